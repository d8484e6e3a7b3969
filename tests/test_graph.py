"""The render graph without GL: culling, resource versions, static-pass caching, dumps,
and the graphs real scenes compile to (checked against a do-nothing backend)."""
from __future__ import annotations

from pathlib import Path

import pytest

from scenerender.errors import Warnings
from scenerender.graph import FrameGraph, InputDesc, RenderPass, ResourceDesc
from scenerender.rendering.renderer import plan
from scenerender.scene import load_scene
from scenerender.scene.loading import load_scene_text
from scenerender.world.build import build_world

SCENES = Path(__file__).resolve().parent.parent / "scenes"
COLOR = ResourceDesc("color", (8, 8), "rgba8")


class NullBackend:
    """Executes nothing; records which pass ran on which frame."""

    def __init__(self):
        self.log = []

    def execute(self, node, frame, written=frozenset()):
        self.log.append((frame, node.render_pass.name))

    def ran(self, frame):
        return [name for f, name in self.log if f == frame]


class Use(RenderPass):
    """Reads ``inputs``; writes ``target`` (a new version) or creates its own output."""

    def __init__(self, name, inputs=(), target=None, side_effect=False):
        self.name, self.inputs, self.target, self.side_effect = name, inputs, target, side_effect

    def setup(self, builder):
        builder.read(*self.inputs)
        if self.target is not None:
            return builder.write(self.target)
        return builder.create(self.name + "_out", COLOR)


def Make(name, *inputs):
    return Use(name, inputs)


def _inputs(graph):
    """A static and a dynamic world input."""
    return graph.import_input("still", InputDesc(False)), graph.import_input("moving", InputDesc(True))


def test_passes_no_output_needs_are_culled():
    g = FrameGraph()
    a = g.add(Make("a"))
    g.add(Make("unused"))
    b = g.add(Use("b", [a]))
    g.add(Use("present", [b], side_effect=True))
    compiled = g.compile()
    assert compiled.pass_names == ["a", "b", "present"]
    assert compiled.culled_names == ["unused"]
    assert {name for _, name, _ in compiled.resources()} == {"a_out", "b_out", "present_out"}


def test_writing_creates_a_new_version_and_readers_see_the_right_one():
    g = FrameGraph()
    color = g.add(Make("clear"))
    drawn = g.add(Use("draw", target=color))
    assert (color.version, drawn.version) == (1, 2) and color.resource == drawn.resource
    g.add(Use("present", [color], side_effect=True))  # reads version 1 only
    compiled = g.compile()
    assert compiled.pass_names == ["clear", "present"]  # the later write is not needed
    assert compiled.culled_names == ["draw"]


def test_writing_an_old_version_is_an_error():
    g = FrameGraph()
    color = g.add(Make("clear"))
    g.add(Use("first", target=color))
    with pytest.raises(ValueError, match="latest version"):
        g.add(Use("second", target=color))


def test_static_passes_run_once_and_dynamic_ones_every_frame():
    g = FrameGraph()
    still, moving = _inputs(g)
    shadow = g.add(Make("shadow", still))
    sky = g.add(Make("sky", still))
    lit = g.add(Use("forward", [shadow, sky, moving]))
    g.add(Use("present", [lit], side_effect=True))
    compiled = g.compile()
    backend = NullBackend()
    for frame in range(3):
        compiled.run_frame(backend, frame, first=frame == 0)
    assert backend.ran(0) == ["shadow", "sky", "forward", "present"]
    assert backend.ran(1) == ["forward", "present"] == backend.ran(2)


def test_a_pass_reading_a_dynamic_pass_is_not_static():
    g = FrameGraph()
    still, moving = _inputs(g)
    shadow = g.add(Make("moving_shadow", moving))
    post = g.add(Use("post", [shadow, still]))
    g.add(Use("present", [post], side_effect=True))
    compiled = g.compile()
    assert not compiled.is_static(compiled.passes[1].render_pass)


def test_static_ness_follows_only_from_what_a_pass_reads():
    g = FrameGraph()
    still, moving = _inputs(g)
    a = g.add(Make("reads_still", still))
    b = g.add(Make("reads_moving", moving))
    c = g.add(Make("reads_nothing"))
    g.add(Use("present", [a, b, c], side_effect=True))
    compiled = g.compile()
    assert [compiled.is_static(n.render_pass) for n in compiled.passes] == [True, False, True, False]
    assert compiled.readers("moving") == ["reads_moving"]


def test_a_pass_drawn_over_by_a_dynamic_pass_is_not_static():
    """The outline (dynamic) draws over the opaque image in place: were the opaque pass
    cached, the outline would draw over its own last frame."""
    g = FrameGraph()
    still, moving = _inputs(g)
    opaque = g.add(Make("opaque", still))
    outlined = g.add(Use("outline", [moving], target=opaque))
    g.add(Use("present", [outlined], side_effect=True))
    compiled = g.compile()
    assert [compiled.is_static(n.render_pass) for n in compiled.passes] == [False, False, False]


def test_writes_to_a_pass_own_region_leave_earlier_results_cached():
    """Shadow passes share one atlas, each writing only its own tiles."""
    g = FrameGraph()
    still, moving = _inputs(g)
    fixed_light = g.add(Make("shadow:fixed", still))

    class OwnTiles(Use):
        def setup(self, builder):
            builder.read(*self.inputs)
            return builder.write(self.target, own_region=True)

    atlas = g.add(OwnTiles("shadow:moving", [moving], target=fixed_light))
    g.add(Use("present", [atlas], side_effect=True))
    compiled = g.compile()
    assert [compiled.is_static(n.render_pass) for n in compiled.passes] == [True, False, False]


class _Keeps(Use):
    """A pass whose result depends only on what it reads (like a shadow map)."""

    keeps_unchanged = True


class _OwnTilesKeeps(_Keeps):
    def setup(self, builder):
        builder.read(*self.inputs)
        return builder.write(self.target, own_region=True)


class _ValueBackend(NullBackend):
    """NullBackend with input values: ``values[frame][input name]``; an input is the same
    for a pass when its value equals the one the pass last ran with."""

    def __init__(self, values):
        super().__init__()
        self.values, self.frame, self.last = values, None, {}

    def same_input(self, node, handle):
        return self.last.get((node.index, handle.name)) == self.values[self.frame][handle.name]

    def execute(self, node, frame, written=frozenset()):
        super().execute(node, frame, written)
        for handle in node.reads:
            if handle.version == 0:
                self.last[(node.index, handle.name)] = self.values[frame][handle.name]


def _run(compiled, backend, frames):
    for frame in range(frames):
        backend.frame = frame
        compiled.run_frame(backend, frame, first=frame == 0)


def test_a_pass_that_keeps_unchanged_results_runs_only_when_what_it_reads_changes():
    g = FrameGraph()
    still, moving = _inputs(g)
    views = g.import_input("views", InputDesc(True))
    sun = g.add(_Keeps("shadow:sun", [views, still]))
    g.add(Use("present", [g.add(Use("opaque", [sun, moving]))], side_effect=True))
    compiled = g.compile()
    values = [{"views": v, "moving": f, "still": 0} for f, v in enumerate("aabbb")]
    backend = _ValueBackend(values)
    _run(compiled, backend, 5)
    assert [backend.ran(f)[0] for f in range(5)] == ["shadow:sun", "opaque", "shadow:sun", "opaque", "opaque"]


def test_a_kept_page_makes_its_later_passes_clear_their_own_tiles_and_a_redrawn_one_redraws_them():
    """Two maps on one page: the first pass clears the page. When it runs, the second must
    too (its tiles were cleared); when it keeps its map, the second may keep its own or
    redraw it alone."""
    g = FrameGraph()
    first_views, second_views = g.import_input("a", InputDesc(True)), g.import_input("b", InputDesc(True))
    page = g.add(_Keeps("shadow:a", [first_views]))
    page = g.add(_OwnTilesKeeps("shadow:b", [second_views], target=page))
    g.add(Use("present", [page], side_effect=True))
    compiled = g.compile()
    backend = _ValueBackend([{"a": 0, "b": 0}, {"a": 1, "b": 0}, {"a": 1, "b": 1}, {"a": 1, "b": 1}])
    _run(compiled, backend, 4)
    assert [backend.ran(f) for f in range(4)] == [["shadow:a", "shadow:b", "present"],
                                                  ["shadow:a", "shadow:b", "present"],  # b's tiles were cleared
                                                  ["shadow:b", "present"],
                                                  ["present"]]


def test_inputs_cannot_be_written_and_images_must_be_known_formats():
    g = FrameGraph()
    still, _ = _inputs(g)
    with pytest.raises(ValueError, match="read-only"):
        g.add(Use("bad", target=still))
    with pytest.raises(ValueError, match="depth32f"):
        ResourceDesc("depth", (8, 8), "depth32f")


def test_dump_and_dot_name_every_pass():
    g = FrameGraph()
    a = g.add(Make("a"))
    g.add(Make("unused"))
    g.add(Use("present", [a], side_effect=True))
    compiled = g.compile()
    text = compiled.dump()
    assert "a " in text and "culled (no output needs them): unused" in text
    dot = compiled.dot()
    assert dot.startswith("digraph") and '"unused"' in dot and "style=dashed" in dot


# -- graphs of real scenes -------------------------------------------------------------

def _world(path_or_text, overrides=(), tmp_path=None):
    if tmp_path is not None:
        return build_world(load_scene_text(path_or_text, tmp_path, overrides), Warnings())
    return build_world(load_scene(path_or_text, list(overrides)), Warnings())


def _compiled(path_or_text, overrides=(), tmp_path=None):
    world = _world(path_or_text, overrides, tmp_path)
    return plan(world, world.settings.size, world.settings.samples).compiled


def test_showcase_graph_has_every_feature_pass_and_caches_shadows():
    compiled = _compiled(SCENES / "showcase.yaml")
    names = compiled.pass_names
    for name in ("shadow:sun", "shadow:lantern", "gbuffer", "ssao", "ssao_blur", "opaque",
                 "outline", "transparent", "resolve+output_transform", "readback"):
        assert name in names
    assert compiled.culled_names == []
    # 4x MSAA: the resolve adds the sky behind the samples; no skybox pass (passes/sky.py)
    assert "skybox" not in names
    assert compiled.node("resolve+output_transform").render_pass.sky.skybox is not None
    # the camera orbits, nothing else moves: both shadow maps render once for all 120
    # frames, the sun's over the casters' whole footprint (world.directional_views)
    inputs = {name: desc.dynamic for _, name, desc in compiled.inputs()}
    assert not inputs["objects"] and inputs["camera"] and not inputs["shadow_views:sun"]
    static = {n.render_pass.name: compiled.is_static(n.render_pass) for n in compiled.passes
              if n.render_pass.name.startswith("shadow:")}
    assert static == {"shadow:lantern": True, "shadow:sun": True}
    assert not compiled.is_static(compiled.passes[names.index("opaque")].render_pass)


def test_maps_drawn_once_and_maps_redrawn_each_frame_live_on_separate_pages():
    """The sun's map follows the camera (a pine moved 60 m out spreads the casters too far
    for one fixed map); the lantern's is drawn once. Each page is one texture, cleared
    whole by its first pass, so the sun's redraw never touches the lantern's tiles and
    never pays for a clear of part of a texture."""
    world = _world(SCENES / "showcase.yaml", ["objects[9].instances[0].position=[60, 0, 0]"])
    showcase = plan(world, world.settings.size, world.settings.samples)
    compiled, atlas = showcase.compiled, showcase.atlas
    shadow = {n.render_pass.name: n for n in compiled.passes if n.render_pass.name.startswith("shadow:")}
    pages = {name: node.render_pass.page for name, node in shadow.items()}
    assert pages == {"shadow:lantern": 0, "shadow:sun": 1}
    assert atlas.pages == ((1024, 1536), (2048, 2048))  # six 512px cube faces; one 2048px tile
    read = [str(h) for h in compiled.node("opaque").reads if h.name.startswith("shadow_atlas")]
    assert read == ["shadow_atlas#1", "shadow_atlas_2#1"]


def test_one_page_when_every_map_is_drawn_alike(tmp_path):
    from scenerender.world.shadows import plan_atlas

    text = ("lights:\n  - {type: directional, shadows: true}\n  - {type: point, shadows: {size: 256}}\n"
            "objects:\n  - mesh: {primitive: box}\n")
    world = _world(text, tmp_path=tmp_path)
    assert plan_atlas(world.lights).pages == ((2048, 2048 + 256),)  # 2048 + a row of six 256px faces
    redrawn = plan_atlas(world.lights, redrawn=frozenset({0, 1}))
    assert redrawn.pages == ((2048, 2048 + 256),)
    apart = plan_atlas(world.lights, redrawn=frozenset({1}))
    assert apart.pages == ((2048, 2048), (512, 768)) and apart.page_of(0) == 0 and apart.page_of(1) == 1
    small = plan_atlas(world.lights, max_size=1024, redrawn=frozenset({1}))
    assert small.pages == ((1024, 1024), (256, 384))  # every page halved alike to fit


def test_a_plain_scene_gets_only_what_it_uses(tmp_path):
    text = "objects:\n  - mesh: {primitive: box}\n"
    compiled = _compiled(text, tmp_path=tmp_path)
    assert compiled.pass_names == ["opaque", "resolve+output_transform", "readback"]


def test_samples_1_drops_the_resolve(tmp_path):
    text = "render: {samples: 1}\nobjects:\n  - mesh: {primitive: box}\n"
    compiled = _compiled(text, tmp_path=tmp_path)
    assert compiled.pass_names == ["opaque", "readback"]  # the sRGB target holds the output values


def test_gamma_output_resolves_and_transforms_in_one_pass(tmp_path):
    from scenerender.rendering.passes.output import ResolveOutputPass

    text = "render: {output_transform: gamma}\nobjects:\n  - mesh: {primitive: box}\n"
    compiled = _compiled(text, tmp_path=tmp_path)
    assert compiled.pass_names == ["opaque", "resolve+output_transform", "readback"]
    assert isinstance(compiled.passes[1].render_pass, ResolveOutputPass)


def test_linear_output_keeps_the_resolved_hdr_image(tmp_path):
    """EXR reads the resolved linear image, so resolve and output transform stay apart."""
    loaded = load_scene_text("objects:\n  - mesh: {primitive: box}\n", tmp_path, [])
    world = build_world(loaded, Warnings())
    compiled = plan(world, world.render.size, 4, want_linear=True).compiled
    assert compiled.pass_names == ["opaque", "resolve", "output_transform", "readback"]


def _opaque(compiled):
    return next(n.render_pass for n in compiled.passes if n.render_pass.name == "opaque")


def test_depth_prepass_only_where_surfaces_overlap_many_times():
    overdraw = Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "overdraw.yaml"
    assert _opaque(_compiled(overdraw, ["render.samples=1"])).prepass
    # MSAA: hidden fragments are shaded anyway; the prepass stays only for shadows
    unshadowed = ["lights[0].shadows=false", "lights[1].shadows=false"]
    assert not _opaque(_compiled(overdraw, unshadowed)).prepass
    assert not _opaque(_compiled(SCENES / "showcase.yaml", ["render.samples=1"])).prepass
    assert "depth prepass" in _compiled(overdraw, ["render.samples=1"]).dump()


def test_shadows_over_the_visible_samples_take_a_prepass_with_msaa_only():
    """With MSAA and shadows, the depth prepass lets the shading pass know which samples
    it shades (GL_ARB_post_depth_coverage), so shadows average over those alone."""
    overdraw = Path(__file__).resolve().parent.parent / "benchmarks" / "scenes" / "overdraw.yaml"
    opaque = _opaque(_compiled(overdraw))
    assert opaque.prepass and opaque.shading.visible_samples
    assert "shadows over the visible samples" in opaque.describe()
    unshadowed = ["lights[0].shadows=false", "lights[1].shadows=false"]
    for overrides in (["render.samples=1"], ["render.samples=2"], unshadowed):
        assert not _opaque(_compiled(overdraw, overrides)).shading.visible_samples
    world = _world(overdraw)
    without = plan(world, world.settings.size, 4, tuning={"post_depth_coverage": False}).compiled
    assert not _opaque(without).prepass and not _opaque(without).shading.visible_samples


def test_shadow_views_are_compile_time_constants(tmp_path):
    """Each light's first shadow view is a constant in the shader; unshadowed lights get -1."""
    from scenerender.rendering.features import SceneFeatures

    text = ("lights:\n  - {type: directional, shadows: true}\n  - {type: point, shadows: true}\n"
            "  - {type: point}\n  - {type: ambient}\n  - {type: spot, position: [0, 3, 0], shadows: true}\n"
            "objects:\n  - mesh: {primitive: box}\n")
    world = build_world(load_scene_text(text, tmp_path, []), Warnings())
    defines = SceneFeatures.of(world).lighting_defines()
    assert defines["DIR_SHADOW_VIEWS"] == "0"
    assert defines["POINT_SHADOW_VIEWS"] == "1, -1"  # six cube faces from view 1
    assert defines["SPOT_SHADOW_VIEWS"] == "7"
    assert defines["N_SHADOW_VIEWS"] == 8 and defines["LIGHTS_IN_UNIFORM_BLOCK"]


def test_depth_mode_culls_shading_shadows_and_sky():
    compiled = _compiled(SCENES / "showcase.yaml", ["render.mode=depth"])
    assert compiled.pass_names == ["gbuffer", "view:depth", "readback"]
    assert {"shadow:sun", "opaque", "transparent", "resolve+output_transform"} <= set(compiled.culled_names)


def test_light_depth_mode_keeps_only_the_first_shadowed_light():
    compiled = _compiled(SCENES / "foggy_road.yaml", ["render.mode=light_depth"])
    assert compiled.pass_names == ["shadow:moon", "view:light_depth", "readback"]
    assert "shadow:streetlight_far" in compiled.culled_names


def test_moving_light_makes_its_shadow_dynamic_but_not_the_others():
    compiled = _compiled(SCENES / "primitives.yaml")
    by_name = {n.render_pass.name: n.render_pass for n in compiled.passes}
    assert compiled.is_static(by_name["shadow:key"])
    assert not compiled.is_static(by_name["shadow:mover"])


def test_static_scene_renders_camera_passes_once_over_many_frames(tmp_path):
    text = ("output: {frames: 5}\nlights: [{type: directional, shadows: true}]\n"
            "objects:\n  - mesh: {primitive: sphere}\n")
    compiled = _compiled(text, tmp_path=tmp_path)
    assert not any(desc.dynamic for _, _, desc in compiled.inputs())
    backend = NullBackend()
    for frame in range(5):
        compiled.run_frame(backend, frame, first=frame == 0)
    assert backend.ran(4) == ["readback"]
    assert backend.ran(0)[0] == "shadow:directional0"


def test_every_scene_compiles_in_every_mode():
    for scene in sorted(SCENES.glob("*.yaml")):
        for mode in ("shaded", "depth", "normals", "wireframe", "points", "ambient_occlusion", "shadow", "light_depth"):
            compiled = _compiled(scene, [f"render.mode={mode}"])
            assert compiled.pass_names[-1] == "readback", (scene.name, mode)
