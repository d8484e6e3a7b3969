"""The pass contract: a pass touches only what its setup declared, and a pass is cached
across frames only when nothing it reads can change.

Every animatable key of the format (found in the schema, not listed here) is animated in
turn; each time, the inputs whose value really changes between two instants must be
dynamic, and so must every pass that reads them. On GL, a few of those scenes are rendered
with and without static-pass caching: the frames must be identical.
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

import scenerender
from scenerender.gpu.depth import depth_convention
from scenerender.gpu.resources import allocate
from scenerender.graph import (
    COLOR_FORMATS, DEPTH_FORMATS, FrameGraph, InputDesc, RenderPass, ResourceDesc, UndeclaredResource,
)
from scenerender.rendering import passes
from scenerender.rendering.features import SHADOW_VIEW_BYTES
from scenerender.rendering.graph_inputs import ObjectsInput, import_inputs, input_values
from scenerender.rendering.light_buffers import pack_lights
from scenerender.rendering.passes import ambient_occlusion, forward, output, shadow, sky, views
from scenerender.rendering.passes.data import ImageData, TargetData
from scenerender.rendering.renderer import GLBackend, plan
from scenerender.scene.reference import scene_tables
from scenerender.world.environment_files import write_hdr
from scenerender.world.frame import FrameEvaluator

BASE = {
    "render": {"size": [32, 24], "samples": 1, "background": [0.1, 0.1, 0.12],
               "fog": {"color": [0.5, 0.5, 0.5], "density": 0.02}},
    "output": {"frames": 3, "fps": 2},
    "camera": {"position": [0, 2, 6], "target": [0, 0.5, 0], "fov": 60},
    "lights": [
        {"type": "directional", "name": "sun", "direction": [-1, -1, -0.5], "shadows": True},
        {"type": "point", "name": "bulb", "position": [0, 3, 0], "shadows": True},
        {"type": "spot", "name": "torch", "position": [2, 3, 2], "direction": [-1, -1.5, -1], "shadows": True},
        {"type": "ambient", "name": "sky", "color": [0.2, 0.2, 0.2]},
    ],
    "materials": {"red": {"diffuse": [0.8, 0.2, 0.2]}},
    "objects": [
        {"name": "ground", "mesh": {"primitive": "plane", "size": 10}},
        {"name": "ball", "mesh": {"primitive": "sphere"}, "position": [0, 1, 0], "material": "red",
         "outline": {"color": [1, 0.6, 0.1], "width": 0.15}},
        {"name": "crates", "mesh": {"primitive": "box"},
         "instances": [{"position": [2, 0.5, 0]}, {"position": [-2, 0.5, 0]}]},
    ],
}

# Two values for each animatable key (by its last name). A key the format gains must get
# its pair here: the test below fails until it has one.
VALUES = {
    "background": ([0.1, 0.1, 0.12], [0.6, 0.3, 0.1]),
    "color": ([1.0, 0.6, 0.1], [0.1, 0.4, 1.0]),
    "density": (0.02, 0.2),
    "exposure": (0.0, 1.0),
    "position": ([0.5, 1.0, 0.5], [-0.5, 1.5, 1.0]),
    "target": ([0.0, 0.5, 0.0], [1.0, 0.0, -1.0]),
    "yaw": (-90.0, -60.0),
    "pitch": (-15.0, -30.0),
    "fov": (60.0, 40.0),
    "height": (5.0, 8.0),
    "focus_distance": (2.0, 6.0),
    "intensity": (1.0, 0.3),
    "enabled": (True, False),
    "direction": ([-1.0, -1.0, -0.5], [0.5, -1.0, 0.2]),
    "inner_angle": (10.0, 2.0),
    "outer_angle": (17.5, 30.0),
    "ambient": ([1.0, 1.0, 1.0], [0.2, 0.2, 0.2]),
    "diffuse": ([0.8, 0.2, 0.2], [0.2, 0.8, 0.2]),
    "specular": ([0.5, 0.5, 0.5], [0.0, 0.0, 0.0]),
    "shininess": (32.0, 4.0),
    "emissive": ([0.0, 0.0, 0.0], [0.5, 0.1, 0.1]),
    "opacity": (1.0, 0.5),
    "base_color": ([0.8, 0.2, 0.2], [0.2, 0.8, 0.2]),
    "metallic": (0.0, 1.0),
    "roughness": (0.5, 0.2),
    "rotation": ([0.0, 0.0, 0.0], [0.0, 45.0, 10.0]),
    "scale": (1.0, 1.5),
    "visible": (True, False),
    # opencv axes looking down -Z from (0, 2, 6), then half a unit to the right
    "camera_to_world": ([[1, 0, 0, 0], [0, -1, 0, 2], [0, 0, -1, 6], [0, 0, 0, 1]],
                        [[1, 0, 0, 0.5], [0, -1, 0, 2], [0, 0, -1, 6], [0, 0, 0, 1]]),
    "world_to_camera": ([[1, 0, 0, 0], [0, -1, 0, 2], [0, 0, -1, 6], [0, 0, 0, 1]],
                        [[1, 0, 0, -0.5], [0, -1, 0, 2], [0, 0, -1, 6], [0, 0, 0, 1]]),
}
# keys whose values differ from another key's of the same last name
PATH_VALUES = {"lights[environment].rotation": (0.0, 90.0)}
ENVIRONMENT = {"type": "environment", "name": "studio", "image": "studio.hdr", "classic": True}
# area lights, added to BASE for their own keys
AREA_LIGHTS = {"rect": {"type": "rect", "name": "panel", "position": [1, 3, -1], "width": 1, "height": 0.5,
                        "shadows": True},
               "disk": {"type": "disk", "name": "lamp", "position": [-1, 3, 1], "radius": 0.4, "shadows": True}}


def animatable_keys() -> list[str]:
    return list(dict.fromkeys(row.path for table in scene_tables() for row in table.rows if row.animatable))


def _locate(scene: dict, path: str) -> tuple[dict, str]:
    """The mapping holding the key ``path`` names in the BASE scene, and the key."""
    *parents, leaf = path.split(".")
    node = scene
    for part in parents:
        if part.startswith("lights["):
            node = next(light for light in node["lights"] if light["type"] == part[len("lights["):-1])
        elif part == "objects[]":
            node = node["objects"][1]
        elif part == "instances[]":
            node = node["instances"][0]
        elif part == "<name>":
            node = node["red"]
        else:
            node = node.setdefault(part, {})
    return node, leaf


def animated_scene(path: str) -> dict:
    """BASE with ``path`` animated from one value to another between t = 0 and t = 1."""
    scene = copy.deepcopy(BASE)
    if path.startswith("objects[].instances[]"):
        scene["objects"][1]["instances"] = [{"position": [0, 0, 0]}, {"position": [0, 0, 2]}]
    if path in ("camera.yaw", "camera.pitch"):
        scene["camera"] = {"position": [0, 2, 6], "yaw": -90, "pitch": -15}
    if path.startswith("camera.pose"):  # a pose places the camera instead of position and target
        scene["camera"] = {"fov": 60}
    if path == "camera.height":
        scene["camera"]["projection"] = "orthographic"
    if path == "camera.focus_distance":  # through a lens (two sub-frames keep it quick)
        scene["camera"]["aperture"] = 1.4
        scene.setdefault("render", {})["film_samples"] = 2
    if path.startswith("lights[environment]"):
        scene["lights"].append(dict(ENVIRONMENT))
    for kind, light in AREA_LIGHTS.items():
        if path.startswith(f"lights[{kind}]"):
            scene["lights"].append(copy.deepcopy(light))
    node, leaf = _locate(scene, path)
    first, second = PATH_VALUES.get(path, VALUES.get(leaf))
    node[leaf] = {"keys": [[0, first], [1, second]]}
    if leaf == "base_color":  # the pbr name of diffuse: one of the two
        node.pop("diffuse", None)
    return scene


def _canonical(value):
    """A comparable form of an input's value: objects in world space and in a fixed order
    (their upload is camera-relative and lists the instances in view first)."""
    if isinstance(value, ObjectsInput):
        out = []
        for frame in value.frames:
            world = frame.models_rel.astype(np.float64)
            world[:, :3, 3] += value.origin
            rows = world.reshape(len(world), -1)
            out.append((frame.visible, rows[np.lexsort(rows.T[::-1])], frame.normals.shape))
        return out
    if dataclasses.is_dataclass(value):
        return [_canonical(getattr(value, f.name)) for f in dataclasses.fields(value)
                if f.name not in ("definition", "definitions", "gpu", "textures")]
    if isinstance(value, dict):
        return {k: _canonical(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_canonical(v) for v in value]
    return value


def _same(a, b) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        return a.shape == b.shape and np.allclose(a, b, rtol=1e-6, atol=1e-5)
    return a == b


def changed_inputs(world, graph_plan) -> set[str]:
    """Names of the inputs whose value differs between t = 0 and t = 1. The ``lights``
    input is compared by the bytes packed for its buffers."""
    evaluator = FrameEvaluator(world, world.settings.size, graph_plan.atlas)
    stub_gpu = SimpleNamespace(textures=None, skybox=None, environment=None)
    names = {h.resource: h.name for h in graph_plan.inputs.all()}
    values = []
    camera = world.spec.camera
    lens_point = (0.5, 0.0) if camera is not None and camera.aperture is not None else None  # off the lens's centre
    for index, time in ((0, 0.0), (2, 1.0)):
        frame = evaluator.evaluate(index, time, lens_point)
        packed = pack_lights(frame, graph_plan.atlas)
        values.append(input_values(graph_plan.inputs, frame, frame.camera, stub_gpu, world, packed))
    return {names[i] for i in values[0] if not _same(_canonical(values[0][i]), _canonical(values[1][i]))}


def _plan(scene: scenerender.Scene):
    world = scene.world
    return world, plan(world, world.settings.size, world.settings.samples)


def test_every_animatable_key_has_test_values():
    missing = [path for path in animatable_keys() if path.split(".")[-1] not in VALUES and path not in PATH_VALUES]
    assert not missing, f"give these keys two values in VALUES: {missing}"
    assert len(animatable_keys()) >= 40


@pytest.mark.parametrize("path", animatable_keys())
def test_animating_a_key_makes_every_pass_reading_it_dynamic(tmp_path, path):
    write_hdr(tmp_path / "studio.hdr", np.ones((8, 16, 3)))
    world, graph_plan = _plan(scenerender.Scene.from_dict(animated_scene(path), base_dir=tmp_path))
    compiled = graph_plan.compiled
    read = {name for _, name, _desc in compiled.inputs()}  # inputs some kept pass reads
    dynamic = {name for _, name, desc in compiled.inputs() if desc.dynamic}
    changed = changed_inputs(world, graph_plan)
    assert changed & read, f"animating {path} changed no input a pass reads: the test scene does not exercise it"
    assert changed & read <= dynamic, f"animating {path} changes {sorted(changed & read - dynamic)}, marked static"
    for name in dynamic:
        for reader in compiled.readers(name):
            assert not compiled.is_static(compiled.node(reader).render_pass), (path, name, reader)


def test_a_still_scene_caches_every_pass_but_the_readback(tmp_path):
    _, graph_plan = _plan(scenerender.Scene.from_dict(BASE, base_dir=tmp_path))
    compiled = graph_plan.compiled
    assert [n.render_pass.name for n in compiled.passes if n.index not in compiled.static] == ["readback"]


def test_a_colour_animation_leaves_shadow_maps_and_geometry_cached(tmp_path):
    _, graph_plan = _plan(scenerender.Scene.from_dict(animated_scene("lights[point].color"), base_dir=tmp_path))
    compiled = graph_plan.compiled
    static = {n.render_pass.name for n in compiled.passes if n.index in compiled.static}
    assert {"shadow:sun", "shadow:bulb", "shadow:torch"} <= static
    assert not compiled.is_static(compiled.node("opaque").render_pass)


@pytest.mark.gl
@pytest.mark.parametrize("path", ["camera.fov", "objects[].visible", "lights[spot].outer_angle",
                                  "materials.<name>.opacity", "render.fog.density", "render.exposure",
                                  "objects[].outline.color",
                                  "lights[directional].direction", "objects[].instances[].position", "lights[rect].position",
                                  "lights[environment].rotation"])
def test_cached_frames_equal_uncached_frames(gl, tmp_path, path):
    """The behaviour the marks stand for: a frame drawn with static passes kept from
    earlier frames is the frame drawn from scratch."""
    write_hdr(tmp_path / "studio.hdr", np.random.default_rng(1).uniform(0, 2, (8, 16, 3)))
    scene = scenerender.Scene.from_dict(animated_scene(path), base_dir=tmp_path)
    frames = {}
    for cache in (True, False):
        with scenerender.Renderer(scene, size=(64, 48), gl=gl, cache_static_passes=cache) as renderer:
            frames[cache] = [renderer.render(i).pixels for i in range(3)]
    assert any(not np.array_equal(frames[True][0], f) for f in frames[True][1:]), f"{path} did not animate"
    for cached, fresh in zip(frames[True], frames[False]):
        assert np.array_equal(cached, fresh), path


# -- a pass touches only what it declared --------------------------------------------------

class _Reads(RenderPass):
    """Declares ``declared``; its execute uses ``used``."""

    def __init__(self, declared, used):
        self.name, self.declared, self.used = "reader", declared, used
        self.side_effect = True

    def setup(self, builder):
        builder.read(*self.declared)

    def execute(self, ctx, data):
        ctx.input(self.used)


def _run_one_frame(graph):
    """Execute ``graph`` once on a backend without GL (the passes here draw nothing)."""
    compiled = graph.compile()
    backend = GLBackend(run=None, images={}, timings=None)
    backend.inputs = {index: f"value of {name}" for index, name, _ in compiled.inputs()}
    compiled.run_frame(backend, frame=0, first=True)


def test_reading_an_undeclared_input_is_an_error():
    graph = FrameGraph()
    camera = graph.import_input("camera", InputDesc(True))
    fog = graph.import_input("fog", InputDesc(False))
    graph.add(_Reads([camera], used=fog))
    with pytest.raises(UndeclaredResource, match="'reader' uses 'fog', which its setup does not declare"):
        _run_one_frame(graph)


def test_reading_a_declared_input_works():
    graph = FrameGraph()
    camera = graph.import_input("camera", InputDesc(True))
    graph.add(_Reads([camera], used=camera))
    _run_one_frame(graph)


def test_an_image_is_not_an_input():
    graph = FrameGraph()

    class MakesImage(RenderPass):
        name = "maker"

        def setup(self, builder):
            return builder.create("color", ResourceDesc("color", (4, 4), "rgba8"))

        def execute(self, ctx, data):
            pass

    image = graph.add(MakesImage())
    graph.add(_Reads([image], used=image))
    with pytest.raises(UndeclaredResource, match="as an input"):
        _run_one_frame(graph)


@pytest.mark.gl
def test_a_real_pass_that_forgets_a_read_fails(gl, tmp_path, monkeypatch):
    """The skybox pass with its setup missing the skybox input: the render stops there."""
    def setup_without_the_sky(self, builder):
        builder.read(self.depth, self.camera)
        return ImageData(builder.write(self.color))

    monkeypatch.setattr(sky.SkyboxPass, "setup", setup_without_the_sky)
    faces = tmp_path / "sky"
    faces.mkdir()
    for face in ("posx", "negx", "posy", "negy", "posz", "negz"):
        Image.new("RGB", (4, 4), (90, 120, 200)).save(faces / f"{face}.png")
    scene = scenerender.Scene.from_dict({**BASE, "render": {**BASE["render"], "skybox": "sky"}}, base_dir=tmp_path)
    with scenerender.Renderer(scene, gl=gl) as renderer:
        with pytest.raises(UndeclaredResource, match="'skybox' uses 'skybox'"):
            renderer.render(0)


def _world_graph(tmp_path, scene: dict = BASE):
    """A graph with the BASE scene's inputs imported, and their handles."""
    graph = FrameGraph()
    return graph, import_inputs(graph, scenerender.Scene.from_dict(scene, base_dir=tmp_path).world)


def test_reading_light_data_without_declaring_it_is_an_error(tmp_path):
    """Light data reaches a pass only through the packed ``lights`` input: a pass that
    declares every light and shadow view but not ``lights`` cannot read it."""
    graph, inputs = _world_graph(tmp_path)
    declared = [handle for handle in inputs.shading() if handle != inputs.lights]
    graph.add(_Reads(declared, used=inputs.lights))
    with pytest.raises(UndeclaredResource, match="'reader' uses 'lights', which its setup does not declare"):
        _run_one_frame(graph)


@pytest.mark.parametrize("name", ["light:sun", "shadow_views:torch"])
def test_reading_one_light_without_declaring_it_is_an_error(tmp_path, name):
    graph, inputs = _world_graph(tmp_path)
    wanted = next(handle for handle in inputs.all() if handle.name == name)
    graph.add(_Reads([handle for handle in inputs.shading() if handle != wanted], used=wanted))
    with pytest.raises(UndeclaredResource, match=f"'reader' uses '{name}'"):
        _run_one_frame(graph)


def test_shading_declares_the_light_data_it_reads(tmp_path):
    graph, inputs = _world_graph(tmp_path)
    graph.add(_Reads(inputs.shading(), used=inputs.lights))
    _run_one_frame(graph)
    assert [h.name for h in inputs.per_light] == ["light:sun", "light:bulb", "light:torch"]  # no ambient light


def test_lights_and_their_shadows_share_one_index(tmp_path):
    """Ambient lights are World.ambient, not World.lights: light i has atlas tiles i,
    shadow views i, first_view[i] and FrameState.lights[i], wherever the ambient light
    sits in the scene's list."""
    scene = copy.deepcopy(BASE)
    scene["lights"] = [scene["lights"][3], *scene["lights"][:3], {"type": "ambient", "color": [0.1, 0.0, 0.0]}]
    world, graph_plan = _plan(scenerender.Scene.from_dict(scene, base_dir=tmp_path))
    assert [light.name for light in world.lights] == ["sun", "bulb", "torch"]
    assert [light.kind for light in world.ambient] == ["ambient", "ambient"]
    assert sorted(graph_plan.atlas.tiles) == [0, 1, 2]
    frame = FrameEvaluator(world, world.settings.size, graph_plan.atlas).evaluate(0, 0.0)
    np.testing.assert_allclose(frame.ambient, [0.3, 0.2, 0.2])
    assert [state.definition for state in frame.lights] == world.lights
    assert sorted(frame.shadow_views) == [0, 1, 2]
    packed = pack_lights(frame, graph_plan.atlas)
    assert packed.first_view == (0, 1, 7)  # the sun's one view, the bulb's six faces, the torch's
    assert len(packed.views) == 8 * SHADOW_VIEW_BYTES


@pytest.mark.gl
def test_shading_that_forgets_the_light_data_fails(gl, tmp_path, monkeypatch):
    """The opaque pass with the ``lights`` input left out of its setup: the render stops
    there, so no light reaches a shader any other way."""
    def declare_without_lights(self, builder):
        builder.read(*(h for h in self.inputs.shading() if h != self.inputs.lights), *self.atlas_pages,
                     *((self.ao,) if self.ao is not None else ()))

    monkeypatch.setattr(forward.Shading, "declare", declare_without_lights)
    scene = scenerender.Scene.from_dict(BASE, base_dir=tmp_path)
    with scenerender.Renderer(scene, gl=gl) as renderer:
        with pytest.raises(UndeclaredResource, match="'opaque' uses 'lights'"):
            renderer.render(0)


@pytest.mark.gl
def test_the_shadow_view_that_forgets_the_light_data_fails(gl, tmp_path, monkeypatch):
    def setup_without_lights(self, builder):
        builder.read(self.atlas, self.camera, self.objects, self.light, self.views)
        return TargetData(builder.create("view", ResourceDesc("color", self.size, self.format)),
                          builder.create("view_depth", ResourceDesc("depth", self.size, "camera_depth")))

    monkeypatch.setattr(views.ShadowFactorViewPass, "setup", setup_without_lights)
    scene = scenerender.Scene.from_dict({**BASE, "render": {**BASE["render"], "mode": "shadow"}}, base_dir=tmp_path)
    with scenerender.Renderer(scene, gl=gl) as renderer:
        with pytest.raises(UndeclaredResource, match="'view:shadow' uses 'lights'"):
            renderer.render(0)


def _pass_classes() -> list[type]:
    modules = (ambient_occlusion, forward, output, shadow, sky, views)
    return [cls for module in modules for _, cls in inspect.getmembers(module, inspect.isclass)
            if issubclass(cls, RenderPass) and cls is not RenderPass and cls.__module__ == module.__name__]


def test_every_pass_is_frozen_configuration():
    """setup cannot store anything on a pass: what it makes goes into its returned data."""
    classes = _pass_classes()
    assert len(classes) >= 15, [c.__name__ for c in classes]
    for cls in classes:
        assert dataclasses.is_dataclass(cls) and cls.__dataclass_params__.frozen, cls.__name__
    assert passes.__doc__


@pytest.mark.gl
def test_the_backend_allocates_every_format_the_graph_offers(gl):
    convention = depth_convention(gl)
    for kind, formats in (("color", COLOR_FORMATS), ("depth", DEPTH_FORMATS)):
        for fmt in formats:
            for samples in (0, 4):
                allocate(gl, ResourceDesc(kind, (8, 8), fmt, samples), convention).release()
