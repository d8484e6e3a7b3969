"""A glTF file's own lights (KHR_lights_punctual) and cameras in a scene (``objects[].lights``,
``camera: {from, name}``, world.file_nodes), and a glTF file rendered as it stands
(``scenerender render model.glb``, run.model_scene)."""
from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from click.testing import CliRunner
from PIL import Image

import scenerender
from conftest import render, scene
from gltf_files import GlbBuilder, quad, sphere
from scenerender.animation import Track
from scenerender.cli import main
from scenerender.mesh.gltf_scene import GltfLight
from scenerender.raytrace import render_reference, shading
from scenerender.world.file_nodes import INTENSITY_PER_PHOTOMETRIC_UNIT, file_light, node_placement


def about_x(degrees: float) -> list:
    """The quaternion (x, y, z, w) turning ``degrees`` about +X."""
    half = math.radians(degrees) / 2.0
    return [math.sin(half), 0.0, 0.0, math.cos(half)]


def _still_object():
    constant = Track.constant
    return type("Obj", (), {"position": constant((0.0, 0.0, 0.0), kind="vector"),
                            "rotation": constant((0.0, 0.0, 0.0), kind="vector"), "scale": constant(1.0)})()


# -- the photometric units -------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["point", "spot", "directional"])
def test_candela_and_lux_become_intensity_over_pi_with_inverse_square_falloff(kind):
    light = GltfLight("lamp", 0, kind, color=(1.0, 0.5, 0.25), intensity=100.0, inner_cone=0.2, outer_cone=0.6)
    rest = np.eye(4)
    rest[:3, 3] = (1.0, 2.0, 3.0)
    made = file_light(light, node_placement(_still_object(), rest, 0), "lamp", ("objects", 0, "lights"))
    assert INTENSITY_PER_PHOTOMETRIC_UNIT == pytest.approx(1.0 / math.pi)
    assert made.intensity(0.0) == pytest.approx(100.0 / math.pi)
    assert tuple(made.color(0.0)[:3]) == (1.0, 0.5, 0.25)
    if kind != "directional":
        assert made.attenuation == (0.0, 0.0, 1.0)
        assert np.allclose(made.position(0.0), (1.0, 2.0, 3.0))
    if kind != "point":
        assert np.allclose(made.direction(0.0), (0.0, 0.0, -1.0))  # down the node's -Z
    if kind == "spot":
        assert made.inner_angle(0.0) == pytest.approx(math.degrees(0.2))
        assert made.outer_angle(0.0) == pytest.approx(math.degrees(0.6))


def _lit_quad(path, light: dict, node: dict, roughness: float = 1.0):
    """A white dielectric 2 x 2 quad facing +Z at the origin, and one light on a node."""
    builder = GlbBuilder()
    mesh, _ = quad()
    white = builder.material(pbrMetallicRoughness={"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0,
                                                   "roughnessFactor": roughness})
    builder.node(builder.mesh(builder.primitive(mesh, white)), name="quad")
    builder.node(name="lamp", extensions={"KHR_lights_punctual": {"light": builder.light(**light)}}, **node)
    return builder.write(path)


FACING_QUAD = """
render: {{size: [32, 32], samples: 1, background: [0, 0, 0], shading: pbr}}
camera: {{position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2}}
lights: {lights}
objects:
  - {{name: model, mesh: model.glb, lights: {bring}}}
"""


@pytest.mark.parametrize("roughness", [1.0, 0.5])
def test_a_point_light_in_candela_lights_as_the_sample_viewer_does(gl, tmp_path, roughness):
    # the Khronos Sample Viewer's radiance f I / d^2 N.L (f the BRDF, I candela) at its
    # default exposure, worked out with the reference's BRDF at each pixel's centre: the
    # GPU's linear value within 1 %
    intensity, height = 6.0, 1.5
    _lit_quad(tmp_path / "model.glb", {"type": "point", "intensity": intensity}, {"translation": [0, 0, height]},
              roughness)
    loaded = scene(FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        linear = renderer.render(0).linear[..., :3]
    rows, cols = np.mgrid[8:24, 8:24]
    points = np.stack([(cols + 0.5) / 16.0 - 1.0, 1.0 - (rows + 0.5) / 16.0, np.zeros_like(rows, float)], -1)
    points = points.reshape(-1, 3)
    to_light = np.array([0.0, 0.0, height]) - points
    distance = np.linalg.norm(to_light, axis=1)
    l = to_light / distance[:, None]
    n = np.tile([0.0, 0.0, 1.0], (len(points), 1))
    v = np.array([0.0, 0.0, 5.0]) - points  # towards the eye, as the renderer takes it for either projection
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    f = shading.pbr_brdf(n, l, v, np.ones((len(points), 3)), np.zeros(len(points)), np.full(len(points), roughness))
    viewer = f * (intensity / distance ** 2 * l[:, 2])[:, None]
    got = linear[8:24, 8:24].reshape(-1, 3)
    assert np.abs(got / viewer - 1.0).max() < 0.01


# the same lights written as the scene format's: intensity I / pi, attenuation 1 / d^2
YAML_LIGHTS = {
    "point": "[{type: point, position: [0.5, 0.3, 1.2], intensity: %r, attenuation: [0, 0, 1]}]" % (5 / math.pi),
    "spot": "[{type: spot, position: [0.2, 0, 1.5], direction: [0, -0.5, -0.866025], intensity: %r, "
            "attenuation: [0, 0, 1], inner_angle: %r, outer_angle: %r, cone_falloff: gltf}]" % (9 / math.pi, math.degrees(0.2),
                                                                           math.degrees(0.35)),
    "directional": "[{type: directional, direction: [0, -0.5, -0.866025], intensity: %r}]" % (2 / math.pi),
    "point_range": "[{type: point, position: [0.5, 0.3, 1.2], intensity: %r, attenuation: [0, 0, 1], range: 1.8}]"
                   % (5 / math.pi),
}
FILE_LIGHTS = {
    "point": ({"type": "point", "intensity": 5}, {"translation": [0.5, 0.3, 1.2]}),
    "spot": ({"type": "spot", "intensity": 9, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.35}},
             {"translation": [0.2, 0, 1.5], "rotation": about_x(-30)}),
    "directional": ({"type": "directional", "intensity": 2}, {"rotation": about_x(-30)}),
    "point_range": ({"type": "point", "intensity": 5, "range": 1.8}, {"translation": [0.5, 0.3, 1.2]}),
}


@pytest.mark.parametrize("kind", ["point", "spot", "directional", "point_range"])
def test_a_files_light_lights_as_the_same_light_written_in_the_scene(gl, tmp_path, kind):
    light, node = FILE_LIGHTS[kind]
    _lit_quad(tmp_path / "model.glb", light, node, roughness=0.4)
    brought = render(gl, FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)[0]
    written = render(gl, FACING_QUAD.format(lights=YAML_LIGHTS[kind], bring="false"), base_dir=tmp_path)[0]
    assert brought.max() > 60  # lit
    assert np.abs(brought.astype(int) - written).max() <= 1
    # and without lights: true the file's lights are not the scene's (the default rig lights it)
    unlit = render(gl, FACING_QUAD.format(lights="[]", bring="false"), base_dir=tmp_path)[0]
    assert unlit.max() == 0


def _viewer_point_light(points: np.ndarray, light: np.ndarray, intensity: float, roughness: float) -> np.ndarray:
    """(P, 3) the Sample Viewer's radiance f I / d^2 N.L at ``points`` (P, 3) of the white
    quad facing +Z, seen from (0, 0, 5), lit by a point light of ``intensity`` candela at
    ``light`` (3,)."""
    to_light = light - points
    distance = np.linalg.norm(to_light, axis=1)
    l = to_light / distance[:, None]
    n = np.tile([0.0, 0.0, 1.0], (len(points), 1))
    v = np.array([0.0, 0.0, 5.0]) - points
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    f = shading.pbr_brdf(n, l, v, np.ones((len(points), 3)), np.zeros(len(points)), np.full(len(points), roughness))
    return f * (intensity / distance ** 2 * l[:, 2])[:, None]


def _quad_points(rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """(P, 3) the points of the 2 x 2 quad at the centres of pixels (rows, cols) of the 32 x 32
    orthographic view of FACING_QUAD."""
    return np.stack([(cols + 0.5) / 16.0 - 1.0, 1.0 - (rows + 0.5) / 16.0, np.zeros_like(rows, float)],
                    -1).reshape(-1, 3)


def test_a_lights_range_ends_it_with_the_specifications_window(gl, tmp_path):
    # KHR_lights_punctual's recommended attenuation clamp(1 - (d / range)^4, 0, 1) / d^2:
    # the GPU's linear value within 1 % of it where the window is open, exactly black past
    # the range (the quad's corners, d up to 1.73), and the same window in the reference
    intensity, height, light_range = 6.0, 1.0, 1.5
    _lit_quad(tmp_path / "model.glb", {"type": "point", "intensity": intensity, "range": light_range},
              {"translation": [0, 0, height]})
    loaded = scene(FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        linear = renderer.render(0).linear[..., :3]
    rows, cols = np.mgrid[0:32, 0:32]
    points = _quad_points(rows, cols)
    distance = np.linalg.norm(np.array([0.0, 0.0, height]) - points, axis=1)
    window = np.clip(1.0 - (distance / light_range) ** 4, 0.0, 1.0)
    viewer = _viewer_point_light(points, np.array([0.0, 0.0, height]), intensity, 1.0) * window[:, None]
    got = linear.reshape(-1, 3)
    open_window = window > 0.05
    assert np.abs(got[open_window] / viewer[open_window] - 1.0).max() < 0.01
    assert got[distance > light_range].max() == 0.0 and (distance > light_range).sum() > 50
    # the reference takes the same window (its samples lie anywhere in their pixel: black
    # a pixel's half diagonal past the range): its mean against the GPU's within 0.5 %
    reference = render_reference(loaded, 0, spp=1).linear
    assert reference[distance.reshape(32, 32) > light_range + 0.045].max() == 0.0
    assert abs(reference.mean() / linear.mean() - 1.0) < 0.005


def test_a_files_spot_falls_off_as_the_square_of_the_ramp_between_its_cones(gl, tmp_path):
    # KHR_lights_punctual's implementation note: between cos(outer) and cos(inner) the cone
    # is t^2 of the linear ramp t (the Sample Viewer's); a scene's spot keeps smoothstep,
    # 3 t^2 - 2 t^3, unless it sets cone_falloff: gltf. Straight above the quad, inner 0.3
    # and outer 0.7 radians: the penumbra is the ring 0.31 to 0.84 from the centre
    intensity, height, inner, outer = 4.0, 1.0, 0.3, 0.7
    _lit_quad(tmp_path / "model.glb", {"type": "spot", "intensity": intensity,
                                       "spot": {"innerConeAngle": inner, "outerConeAngle": outer}},
              {"translation": [0, 0, height]})
    loaded = scene(FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)
    assert loaded.world.lights[0].cone_falloff == "gltf"
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        linear = renderer.render(0).linear[..., :3].reshape(-1, 3)
    rows, cols = np.mgrid[0:32, 0:32]
    points = _quad_points(rows, cols)
    light = np.array([0.0, 0.0, height])
    cos_angle = (light - points)[:, 2] / np.linalg.norm(light - points, axis=1)
    t = np.clip((cos_angle - math.cos(outer)) / (math.cos(inner) - math.cos(outer)), 0.0, 1.0)
    unconed = _viewer_point_light(points, light, intensity, 1.0)
    penumbra = (t > 0.1) & (t < 0.9)
    assert penumbra.sum() > 100
    assert np.abs(linear[penumbra] / (unconed[penumbra] * (t * t)[penumbra, None]) - 1.0).max() < 0.01
    # smoothstep would be 1.2 to 2.8 times as bright there: the check tells them apart
    assert np.all(3.0 - 2.0 * t[penumbra] > 1.19)
    # the reference takes the same cone: its mean within 0.5 % of the GPU's
    reference = render_reference(loaded, 0, spp=1).linear
    assert abs(reference.mean() / linear.mean() - 1.0) < 0.005
    # the same spot in the scene format keeps smoothstep, and takes t^2 by the key
    yaml_spot = ("[{type: spot, position: [0, 0, %r], direction: [0, 0, -1], intensity: %r, attenuation: [0, 0, 1], "
                 "inner_angle: %r, outer_angle: %r%s}]")
    for falloff, expected in (("", t * t * (3.0 - 2.0 * t)), (", cone_falloff: gltf", t * t)):
        text = FACING_QUAD.format(lights=yaml_spot % (height, intensity / math.pi, math.degrees(inner),
                                                      math.degrees(outer), falloff), bring="false")
        with scenerender.Renderer(scene(text, base_dir=tmp_path), gl=gl, want_linear=True) as renderer:
            got = renderer.render(0).linear[..., :3].reshape(-1, 3)
        assert np.abs(got[penumbra] / (unconed[penumbra] * expected[penumbra, None]) - 1.0).max() < 0.01, falloff


def test_a_range_past_everything_lit_renders_the_bytes_of_no_range(gl, tmp_path):
    # the window's code is in the program once any light has a range; there a window that
    # never closes over the scene (1 - (d / range)^4 rounds to 1) changes no pixel
    light = {"type": "point", "intensity": 6.0}
    _lit_quad(tmp_path / "model.glb", light, {"translation": [0, 0, 1.2]}, roughness=0.5)
    plain = render(gl, FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)[0]
    _lit_quad(tmp_path / "model.glb", {**light, "range": 1e6}, {"translation": [0, 0, 1.2]}, roughness=0.5)
    loaded = scene(FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)
    assert loaded.world.lights[0].range == 1e6
    far = render(gl, FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)[0]
    assert np.array_equal(plain, far)
    # and a range that ends inside the picture does change it
    _lit_quad(tmp_path / "model.glb", {**light, "range": 1.5}, {"translation": [0, 0, 1.2]}, roughness=0.5)
    near = render(gl, FACING_QUAD.format(lights="[]", bring="true"), base_dir=tmp_path)[0]
    assert near.astype(int).sum() < 0.9 * plain.astype(int).sum()


def test_the_lights_move_with_the_object_and_its_clip(tmp_path):
    builder = GlbBuilder()
    mesh, _ = quad()
    builder.node(builder.mesh(builder.primitive(mesh)), name="quad")
    lamp = builder.node(name="lamp", translation=[0, 0, 1],
                        extensions={"KHR_lights_punctual": {"light": builder.light(type="point", intensity=3)}})
    builder.animation("rise", [(lamp, "translation", [0.0, 2.0], [[0, 0, 1], [0, 0, 3]], "LINEAR")])
    builder.write(tmp_path / "model.glb")
    text = """
objects:
  - {name: model, mesh: model.glb, lights: true, position: [10, 0, 0], animation: {clip: rise}}
"""
    world = scenerender.Scene.from_yaml(text, tmp_path).world
    (light,) = world.lights
    assert np.allclose(light.position(0.0), (10, 0, 1))
    assert np.allclose(light.position(1.0), (10, 0, 2))
    assert world.inputs.per_light[0].dynamic  # so its shadow map and packed data follow it
    still = scenerender.Scene.from_yaml(text.replace(", animation: {clip: rise}", ""), tmp_path).world
    assert not still.inputs.per_light[0].dynamic


# -- cameras ---------------------------------------------------------------------------------------

def _camera_file(path, camera: dict, node: dict, clip=None):
    """A coloured box and a camera on a node; ``clip``: (times, translations) of the camera."""
    builder = GlbBuilder()
    orange = builder.material(pbrMetallicRoughness={"baseColorFactor": [0.9, 0.5, 0.1, 1], "metallicFactor": 0})
    builder.node(builder.mesh(builder.primitive(trimesh.creation.box((1, 1, 1)), orange)), name="box",
                 rotation=[0.1, 0.3, 0.0, 0.95])
    holder = builder.node(name="CameraNode", camera=builder.camera(**camera), **node)
    if clip is not None:
        builder.animation("dolly", [(holder, "translation", clip[0], clip[1], "LINEAR")])
    return builder.write(path)


def _camera_scene(camera: str, animation: str = "") -> str:
    return f"""
render: {{size: [64, 48], samples: 1}}
output: {{frames: 5, fps: 4}}
camera: {camera}
lights: [{{type: directional, direction: [-0.3, -1, -0.5]}}, {{type: ambient}}]
objects:
  - {{name: model, mesh: model.glb{animation}}}
"""


PERSPECTIVE = {"type": "perspective", "name": "Lens", "perspective": {"yfov": 0.6, "znear": 0.1}}


def test_a_files_perspective_camera_is_the_view(gl, tmp_path):
    # the camera node at (0.5, 1, 4) turned 12 degrees down: the same as a scene camera there
    _camera_file(tmp_path / "model.glb", PERSPECTIVE, {"translation": [0.5, 1, 4], "rotation": about_x(-12)})
    target = [0.5, 1 - 4 * math.tan(math.radians(12)), 0]
    from_file = render(gl, _camera_scene("{from: model, name: Lens}"), base_dir=tmp_path)[0]
    written = render(gl, _camera_scene(f"{{position: [0.5, 1, 4], target: {target}, fov: {math.degrees(0.6)}}}"),
                     base_dir=tmp_path)[0]
    assert np.abs(from_file.astype(int) - written).max() <= 2
    assert (np.abs(from_file.astype(int) - from_file[0, 0]).max(axis=2) > 30).sum() > 300  # the box is in view
    # name left out: the file's first camera
    first = render(gl, _camera_scene("{from: model}"), base_dir=tmp_path)[0]
    assert np.array_equal(first, from_file)


def test_a_files_orthographic_camera_shows_twice_ymag(gl, tmp_path):
    ortho = {"type": "orthographic", "orthographic": {"xmag": 2, "ymag": 1.5, "znear": 0.1, "zfar": 50}}
    _camera_file(tmp_path / "model.glb", ortho, {"translation": [0, 0, 6]})
    from_file = render(gl, _camera_scene("{from: model}"), base_dir=tmp_path)[0]
    written = render(gl, _camera_scene("{position: [0, 0, 6], target: [0, 0, 0], projection: orthographic, "
                                       "height: 3}"), base_dir=tmp_path)[0]
    assert np.abs(from_file.astype(int) - written).max() <= 2


@pytest.mark.parametrize("frame", [1, 3])
def test_a_files_camera_moves_with_its_node_in_the_objects_clip(gl, tmp_path, frame):
    _camera_file(tmp_path / "model.glb", PERSPECTIVE, {"translation": [0, 0, 4]},
                 clip=([0.0, 1.0], [[0, 0, 4], [1, 0.5, 6]]))
    moving = render(gl, _camera_scene("{from: model}", ", animation: {clip: dolly, loop: false}"), frames=(frame,),
                    base_dir=tmp_path)[0]
    u = min(frame / 4.0, 1.0)
    x, y, z = u, 0.5 * u, 4 + 2 * u
    written = render(gl, _camera_scene(f"{{position: [{x}, {y}, {z}], target: [{x}, {y}, 0], "
                                       f"fov: {math.degrees(0.6)}}}", ", animation: {clip: dolly, loop: false}"),
                     frames=(frame,), base_dir=tmp_path)[0]
    assert np.abs(moving.astype(int) - written).max() <= 2


@pytest.mark.parametrize("camera,message", [
    ("{from: model, name: Wide}", "has no camera named 'Wide' (cameras: 'Lens')"),
    ("{from: crate}", "no object is named 'crate' (objects: 'model')"),
    ("{from: model, fov: 30}", "the file's camera gives its own fov; remove fov or from"),
    ("{name: Lens}", "give from too"),
])
def test_a_camera_the_file_does_not_have_exits_2_naming_what_it_has(tmp_path, camera, message):
    _camera_file(tmp_path / "model.glb", PERSPECTIVE, {"translation": [0, 0, 4]})
    (tmp_path / "scene.yaml").write_text(_camera_scene(camera))
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml")])
    assert result.exit_code == 2
    assert message in result.output
    assert "Traceback" not in result.output


def test_lights_true_needs_a_gltf_file(tmp_path):
    (tmp_path / "scene.yaml").write_text("objects: [{mesh: {primitive: box}, lights: true}]\n")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml")])
    assert result.exit_code == 2
    assert "lights: true brings in the lights of a glTF file" in result.output


# -- a glTF file rendered as it stands -------------------------------------------------------------

def blender_style(path, clip: bool = False):
    """As Blender writes a scene: a floor and a ball, a sun and a point lamp (their nodes
    turned to shine down -Z), and a camera with its aspect ratio."""
    builder = GlbBuilder()
    red = builder.material(name="Red", pbrMetallicRoughness={"baseColorFactor": [0.8, 0.1, 0.1, 1],
                                                             "metallicFactor": 0, "roughnessFactor": 0.5})
    grey = builder.material(name="Floor", pbrMetallicRoughness={"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                                "metallicFactor": 0, "roughnessFactor": 0.9})
    ball = builder.node(builder.mesh(builder.primitive(sphere(0.5), red)), name="Ball", translation=[0, 0.5, 0])
    builder.node(builder.mesh(builder.primitive(trimesh.creation.box((6, 0.1, 6)), grey)), name="Floor",
                 translation=[0, -0.05, 0])
    builder.node(name="Light", translation=[1.5, 2.5, 1],
                 extensions={"KHR_lights_punctual": {"light": builder.light(type="point", intensity=40,
                                                                            color=[1, 0.9, 0.8], name="Light")}})
    builder.node(name="Sun", rotation=about_x(-60),
                 extensions={"KHR_lights_punctual": {"light": builder.light(type="directional", intensity=2,
                                                                            name="Sun")}})
    builder.node(name="Camera", translation=[0, 1.5, 5], rotation=about_x(-12),
                 camera=builder.camera(type="perspective", name="Camera",
                                       perspective={"yfov": 0.6, "aspectRatio": 1.5, "znear": 0.1, "zfar": 100}))
    if clip:
        builder.animation("Roll", [(ball, "translation", [0.0, 0.5], [[0, 0.5, 0], [1, 0.5, 0]], "LINEAR")])
    return builder.write(path)


def test_a_blender_style_glb_renders_framed_and_lit_without_a_scene_file(gl, tmp_path):
    blender_style(tmp_path / "model.glb")
    result = CliRunner().invoke(main, ["render", str(tmp_path / "model.glb"), "-o", str(tmp_path / "out"), "-q"])
    assert result.exit_code == 0, result.output
    frames = sorted((tmp_path / "out").glob("*.png"))
    assert len(frames) == 1
    image = np.asarray(Image.open(frames[0]).convert("RGB")).astype(int)
    assert image.shape == (480, 720, 3)  # the camera's aspect ratio, 480 high
    # framed: the red ball in the middle of the image, through the file's camera
    red = (image[..., 0] > image[..., 1] + 40) & (image[..., 0] > 60)
    rows, cols = np.nonzero(red)
    assert red.sum() > 3000
    assert abs(cols.mean() - 360) < 20 and 180 < rows.mean() < 330
    # lit by the file's lights: the same picture as the scene that names them
    written = """
render: {size: [720, 480], shading: pbr}
camera: {from: model, name: Camera}
lights: []
objects: [{name: model, mesh: model.glb, lights: true}]
"""
    assert np.abs(render(gl, written, base_dir=tmp_path)[0].astype(int) - image).max() <= 1


def test_a_glb_without_camera_or_lights_is_framed_and_lit_by_the_default_rig(gl, tmp_path):
    builder = GlbBuilder()
    builder.node(builder.mesh(builder.primitive(sphere(0.5))), translation=[20, 3, -7])
    builder.write(tmp_path / "ball.glb")
    result = CliRunner().invoke(main, ["render", str(tmp_path / "ball.glb"), "-o", str(tmp_path / "out"), "-q"])
    assert result.exit_code == 0, result.output
    image = np.asarray(Image.open(tmp_path / "out" / "frame_0000.png").convert("L")).astype(int)
    lit = image > image[0, 0] + 30
    rows, cols = np.nonzero(lit)
    assert lit.sum() > 10000  # the default camera frames its bounds, the headlight lights it
    assert abs(rows.mean() - 240) < 30 and abs(cols.mean() - 320) < 30


def test_a_glbs_first_clip_plays_once_over_its_length(tmp_path):
    blender_style(tmp_path / "model.glb", clip=True)
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "model.glb")])
    assert result.exit_code == 0, result.output
    assert "1 objects, 2 lights, 15 frame(s), 720x480" in result.output  # 0.5 s at 30 fps
    assert "clips #0 'Roll' (0.5 s)" in result.output


def test_a_broken_glb_given_as_the_scene_exits_2(tmp_path):
    (tmp_path / "bad.glb").write_bytes(b"glTF\x02\x00\x00\x00garbage")
    result = CliRunner().invoke(main, ["render", str(tmp_path / "bad.glb"), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert "bad.glb" in result.output and "Traceback" not in result.output
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").glob("*.png"))


def test_an_extension_not_read_is_named_in_one_warning(tmp_path):
    builder = GlbBuilder()
    builder.node(builder.mesh(builder.primitive(sphere(0.5), builder.material(
        extensions={"KHR_materials_dispersion": {"dispersion": 1}}))))
    builder.uses("KHR_materials_dispersion")
    builder.uses("KHR_texture_transform")
    builder.write(tmp_path / "shiny.glb")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "shiny.glb")])
    assert result.exit_code == 0, result.output
    lines = [line for line in result.output.splitlines() if line.startswith("warning")]
    assert len(lines) == 1
    assert "shiny.glb" in lines[0] and "extension KHR_materials_dispersion is not supported" in lines[0]


# -- TANGENT ---------------------------------------------------------------------------------------

def _normal_mapped_quad(path, tangent=None):
    """The quad, its normal map tilting every normal towards +u and +v (red and green above
    0.5), and, where given, its TANGENT (one (4,) value for every vertex)."""
    builder = GlbBuilder()
    mesh, uv = quad()
    tilt = np.full((4, 4, 3), (190, 190, 200), np.uint8)
    material = builder.material(pbrMetallicRoughness={"metallicFactor": 0.0, "roughnessFactor": 1.0},
                                normalTexture={"index": builder.texture(tilt)})
    primitive = builder.primitive(mesh, material, uv=uv)
    if tangent is not None:
        primitive["attributes"]["TANGENT"] = builder.accessor(np.tile(tangent, (4, 1)), "VEC4")
    builder.node(builder.mesh(primitive))
    return builder.write(path)


TILTED = """
render: {size: [24, 24], samples: 1, background: [0, 0, 0], shading: pbr}
camera: {position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2}
lights: [{type: directional, direction: [-0.5, -0.5, -0.7]}]
objects: [{mesh: model.glb}]
"""


def test_a_files_tangents_are_read_as_the_specification_says(gl, tmp_path):
    # the quad's u runs along +x and its v (up the image) along +y: the tangent the
    # renderer works out is (1, 0, 0) with handedness +1; the file saying so draws the same,
    # the file saying otherwise turns the mapped normals with it
    _normal_mapped_quad(tmp_path / "model.glb")
    computed = render(gl, TILTED, base_dir=tmp_path)[0].astype(int)
    _normal_mapped_quad(tmp_path / "model.glb", (1.0, 0.0, 0.0, 1.0))
    stored = render(gl, TILTED, base_dir=tmp_path)[0].astype(int)
    assert np.array_equal(stored, computed)
    # handedness -1: the bitangent cross(n, t) w runs down, the green tilt away from the light
    _normal_mapped_quad(tmp_path / "model.glb", (1.0, 0.0, 0.0, -1.0))
    mirrored = render(gl, TILTED, base_dir=tmp_path)[0].astype(int)
    # the tangent along -x with handedness +1: both tilts away from it
    _normal_mapped_quad(tmp_path / "model.glb", (-1.0, 0.0, 0.0, 1.0))
    turned = render(gl, TILTED, base_dir=tmp_path)[0].astype(int)
    assert computed.mean() > mirrored.mean() + 5 > turned.mean() + 10


# -- KHR_materials_variants ------------------------------------------------------------------------

def _variants_file(path):
    """Two spheres: the left's material switches red / green / blue with the variants
    'red', 'green' (and 'blue' lists it); the right's is grey in every variant."""
    builder = GlbBuilder()
    colours = {name: builder.material(name=name, pbrMetallicRoughness={"baseColorFactor": rgba, "metallicFactor": 0})
               for name, rgba in (("red", [0.9, 0.1, 0.1, 1]), ("green", [0.1, 0.9, 0.1, 1]),
                                  ("blue", [0.1, 0.1, 0.9, 1]), ("grey", [0.5, 0.5, 0.5, 1]))}
    builder.uses("KHR_materials_variants")
    builder.json.setdefault("extensions", {})["KHR_materials_variants"] = {
        "variants": [{"name": "red"}, {"name": "green"}, {"name": "blue"}]}
    left = builder.primitive(sphere(0.8), colours["red"])
    left["extensions"] = {"KHR_materials_variants": {"mappings": [
        {"material": colours["green"], "variants": [1]}, {"material": colours["blue"], "variants": [2]}]}}
    builder.node(builder.mesh(left), translation=[-1, 0, 0])
    builder.node(builder.mesh(builder.primitive(sphere(0.8), colours["grey"])), translation=[1, 0, 0])
    return builder.write(path)


def _variant_scene(variant: str = "") -> str:
    chosen = f", variant: {variant}" if variant else ""
    return f"""
render: {{size: [64, 32], samples: 1, background: [0, 0, 0]}}
camera: {{position: [0, 0, 6], target: [0, 0, 0], fov: 35}}
objects: [{{mesh: model.glb{chosen}}}]
"""


@pytest.mark.parametrize("variant,channel", [("", 0), ("red", 0), ("green", 1), ("blue", 2)])
def test_a_variant_switches_the_materials_it_lists(gl, tmp_path, variant, channel):
    _variants_file(tmp_path / "model.glb")
    image = render(gl, _variant_scene(variant), base_dir=tmp_path)[0].astype(int)
    left, right = image[10:22, 10:22].reshape(-1, 3).mean(axis=0), image[10:22, 42:54].reshape(-1, 3).mean(axis=0)
    assert np.argmax(left) == channel and left[channel] > 2 * np.delete(left, channel).max()
    assert np.ptp(right) < 3  # grey in every variant


def test_validate_lists_the_variants_and_an_unknown_one_exits_2_naming_them(tmp_path):
    _variants_file(tmp_path / "model.glb")
    listed = CliRunner().invoke(main, ["validate", str(tmp_path / "model.glb")])
    assert listed.exit_code == 0, listed.output
    assert "model.glb: variants 'red', 'green', 'blue'" in listed.output
    (tmp_path / "scene.yaml").write_text(_variant_scene("purple"))
    unknown = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml")])
    assert unknown.exit_code == 2
    assert "objects[0].variant" in unknown.output
    assert "has no variant 'purple'; its variants: 'red', 'green', 'blue'" in unknown.output
    assert "Traceback" not in unknown.output


# -- texCoord: 1 ----------------------------------------------------------------------------------

def _two_uv_sets_quad(path, tex_coord: int, second_set: bool = True):
    """The quad with a left-red, right-blue base colour texture; set 0 maps it as it
    stands, set 1 mirrored left to right; the texture asks for set ``tex_coord``."""
    builder = GlbBuilder()
    mesh, uv = quad()
    pixels = np.zeros((4, 4, 3), np.uint8)
    pixels[:, :2] = (230, 20, 20)
    pixels[:, 2:] = (20, 20, 230)
    material = builder.material(pbrMetallicRoughness={"baseColorTexture": {"index": builder.texture(
        pixels, {"magFilter": 9728, "minFilter": 9728}), "texCoord": tex_coord}, "metallicFactor": 0})
    primitive = builder.primitive(mesh, material, uv=uv)
    if second_set:
        primitive["attributes"]["TEXCOORD_1"] = builder.accessor(np.column_stack([1.0 - uv[:, 0], uv[:, 1]]), "VEC2")
    builder.node(builder.mesh(primitive))
    return builder.write(path)


FLAT_QUAD = """
render: {size: [32, 32], samples: 1, background: [0, 0, 0], shading: unlit}
camera: {position: [0, 0, 5], target: [0, 0, 0], projection: orthographic, height: 2}
objects: [{mesh: model.glb}]
"""


@pytest.mark.parametrize("tex_coord", [0, 1])
def test_a_texture_reads_the_coordinate_set_it_asks_for(gl, tmp_path, tex_coord):
    _two_uv_sets_quad(tmp_path / "model.glb", tex_coord)
    loaded = scenerender.Scene.from_yaml(FLAT_QUAD, tmp_path)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        image = renderer.render(0).pixels.astype(int)
    left, right = image[8:24, 2:12].reshape(-1, 3).mean(axis=0), image[8:24, 20:30].reshape(-1, 3).mean(axis=0)
    red_left = left[0] > 150 and right[2] > 150
    assert red_left == (tex_coord == 0)
    assert (left[2] > 150 and right[0] > 150) == (tex_coord == 1)
    # the reference reads the same set
    from scenerender.raytrace import render_reference
    reference = render_reference(loaded, 0, spp=1).linear
    assert (reference[16, 4, 0] > reference[16, 4, 2]) == (tex_coord == 0)


def test_a_texture_asking_for_a_set_the_mesh_lacks_reads_set_0_with_a_warning(gl, tmp_path):
    _two_uv_sets_quad(tmp_path / "model.glb", 1, second_set=False)
    image = render(gl, FLAT_QUAD, base_dir=tmp_path)[0].astype(int)
    assert image[16, 4, 0] > 150 and image[16, 28, 2] > 150  # set 0: red left
    loaded = scenerender.Scene.from_yaml(FLAT_QUAD, tmp_path)
    assert any("texture coordinate set 1" in line and "model.glb" in line for line in loaded.warnings)


# -- malformed files -------------------------------------------------------------------------------

JUNK = [None, -1, 0, 1e308, "x", [], {}, [1, 2], {"a": 1}, True, 99, -0.5, [None]]


def _json_paths(value, path=()):
    if isinstance(value, dict):
        items = value.items()
    elif isinstance(value, list):
        items = enumerate(value)
    else:
        return
    for key, child in items:
        yield path + (key,)
        yield from _json_paths(child, path + (key,))


def test_junk_in_a_files_lights_cameras_nodes_and_variants_exits_0_or_2(tmp_path):
    # one or two values of the JSON's lights, cameras, nodes, scenes and variants replaced
    # by junk, 40 files (seeded): each validates or is refused with exit 2, naming the file
    import copy
    import json
    import random
    import struct
    blender_style(tmp_path / "base.glb", clip=True)
    raw = (tmp_path / "base.glb").read_bytes()
    length = struct.unpack_from("<I", raw, 12)[0]
    header, binary = json.loads(raw[20:20 + length]), raw[20 + length:]
    header["extensions"]["KHR_materials_variants"] = {"variants": [{"name": "a"}]}
    header["meshes"][0]["primitives"][0]["extensions"] = {
        "KHR_materials_variants": {"mappings": [{"material": 1, "variants": [0]}]}}
    paths = list(_json_paths({k: header[k] for k in ("extensions", "cameras", "nodes", "scenes", "meshes")}))
    (tmp_path / "scene.yaml").write_text("camera: {from: f}\nobjects: [{name: f, mesh: f.glb, lights: true, "
                                         "variant: a, animation: {clip: 0}}]\n")
    rng = random.Random(7)
    for _ in range(40):
        changed = copy.deepcopy(header)
        for _ in range(rng.randint(1, 2)):
            *parents, last = rng.choice(paths)
            holder = changed
            try:
                for key in parents:
                    holder = holder[key]
                holder[last] = rng.choice(JUNK)
            except (KeyError, IndexError, TypeError):
                continue
        text = json.dumps(changed).encode()
        text += b" " * (-len(text) % 4)
        body = struct.pack("<II", len(text), 0x4E4F534A) + text + binary
        (tmp_path / "f.glb").write_bytes(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)
        for target in ("f.glb", "scene.yaml"):
            result = CliRunner().invoke(main, ["validate", str(tmp_path / target)])
            assert result.exit_code in (0, 2), result.output
            assert "internal error" not in result.output and "Traceback" not in result.output
