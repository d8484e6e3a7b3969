"""Rendering behaviour on the real GL path (Mesa llvmpipe here): colour output, precision
far from the origin, degenerate cameras and materials, lights without caps, shadows."""
from __future__ import annotations

import numpy as np
import pytest

from scenerender.errors import UserError, Warnings
from scenerender.compare.metrics import absolute_difference

# A camera looking straight down at a plane that fills the view, lit by nothing but the
# material itself when unlit.
FLAT = """
render: {{size: [64, 48], samples: {samples}, output_transform: {transform}, gamma: 2.2}}
camera: {{position: [0, 5, 0], target: [0, 0, 0], fov: 40}}
lights: []
objects:
  - mesh: {{primitive: plane, size: 20}}
    material: {{diffuse: [{c}, {c}, {c}], unlit: true}}
"""


# Linear 0.5 encodes to 187.52 with the exact sRGB curve (pow(1/2.2) would give 186.0),
# to 186.0 with gamma 2.2 and to 127.5 linearly. Encoders may round a value this close to
# a half level either way, so each must land within 0.6 levels of the exact value.
HALF_GREY = [("srgb", 187.52), ("gamma", 186.0), ("linear", 127.5)]


@pytest.mark.parametrize("transform, exact", HALF_GREY)
def test_output_transforms_of_linear_half_grey(render_scene, transform, exact):
    image = render_scene(FLAT.format(samples=1, transform=transform, c=0.5))
    assert np.all(np.abs(image - exact) <= 0.6), np.unique(image)


@pytest.mark.parametrize("transform, exact", HALF_GREY)
def test_output_transforms_after_msaa_resolve(render_scene, transform, exact):
    """The same values through the multisampled paths (sRGB target + blit for srgb, the
    fused resolve and transform pass for the others)."""
    image = render_scene(FLAT.format(samples=4, transform=transform, c=0.5))
    assert np.all(np.abs(image - exact) <= 0.6), np.unique(image)


def test_srgb_encoding_of_several_levels(render_scene):
    for c, expected in ((0.0, 0), (0.002, 7), (0.2, 124), (1.0, 255)):  # 0.002 is in the linear toe
        image = render_scene(FLAT.format(samples=1, transform="srgb", c=c))
        assert image[24, 32, 0] == expected, c


def test_rendering_is_deterministic(gl):
    from conftest import SCENES, render

    a, b = (render(gl, SCENES / "primitives.yaml", ["render.size=[160, 100]"], frames=(10,))[0] for _ in range(2))
    assert np.array_equal(a, b)


OFFSET_SCENE = """
render: {{size: [160, 120], samples: 4}}
camera: {{position: [{x}, {y_cam}, {z_cam}], target: [{x}, {y}, {z}], fov: 45}}
lights:
  - {{type: directional, direction: [-0.5, -1, -0.3], shadows: true}}
  - {{type: point, position: [{px}, {py}, {pz}], color: [1, 0.5, 0.2], attenuation: [1, 0.2, 0.1]}}
  - {{type: ambient, color: [0.2, 0.2, 0.2]}}
objects:
  - mesh: {{primitive: plane, size: 10}}
    position: [{x}, {y}, {z}]
    cast_shadows: false
  - mesh: {{primitive: sphere, radius: 0.6, segments: 48, rings: 24}}
    position: [{x}, {y1}, {z}]
    material: {{diffuse: [0.8, 0.2, 0.2], shininess: 60}}
  - mesh: {{primitive: box, size: 0.5}}
    position: [{bx}, {by}, {bz}]
    rotation: [0, 30, 0]
"""


def _offset_scene(o):
    x, y, z = o
    return OFFSET_SCENE.format(x=x, y=y, z=z, y_cam=y + 2.5, z_cam=z + 4.0, y1=y + 0.6, px=x - 1.5, py=y + 1.5,
                               pz=z + 1.0, bx=x + 1.2, by=y + 0.25, bz=z - 0.4)


@pytest.mark.parametrize("offset", [(1e6, 0.0, 0.0), (-3e5, 2e5, 1e6)])
def test_a_scene_far_from_the_origin_renders_like_the_same_scene_at_it(render_scene, offset):
    at_origin = render_scene(_offset_scene((0.0, 0.0, 0.0)))
    far_away = render_scene(_offset_scene(offset))
    diff = absolute_difference(at_origin, far_away)
    assert diff.mean() < 0.2 and diff.max() <= 8, (diff.mean(), diff.max())


def test_looking_straight_down_along_up_renders(render_scene):
    text = """
render: {size: [96, 96], samples: 1}
camera: {position: [0, 6, 0], target: [0, 0, 0], fov: 50}
lights: [{type: directional, direction: [0, -1, 0]}, {type: ambient, color: [0.2, 0.2, 0.2]}]
objects:
  - mesh: {primitive: plane, size: 4}
    material: {diffuse: [0.2, 0.6, 0.2]}
  - mesh: {primitive: box, size: 0.8}
    position: [0, 0.4, -1.2]
    material: {diffuse: [0.9, 0.1, 0.1]}
"""
    image = render_scene(text)
    assert image[48, 48, 1] > image[48, 48, 0]          # green plane under the camera
    pixels = image.astype(int)
    red = np.argwhere(pixels[:, :, 0] > pixels[:, :, 1] + 80)
    assert len(red) > 50 and red[:, 0].mean() < 40       # the box at -Z is at the top of the image
    nearly = render_scene(text.replace("position: [0, 6, 0]", "position: [0, 6, 0.0001]"))
    assert absolute_difference(image, nearly).mean() < 0.5  # no flip right next to the singularity


def test_a_camera_passing_through_its_target_renders_finite_frames(gl, monkeypatch):
    """At t = 1 the animated position sits on the target, with no direction to look in: that
    frame looks down -Z (the default view direction), and neither the camera, the spot light
    that follows it, nor any pixel is NaN."""
    from conftest import render, scene
    from scenerender.rendering.renderer import ENV_CHECK_FINITE
    from scenerender.world.frame import FrameEvaluator

    text = """
render: {size: [48, 32], samples: 1}
output: {fps: 1, frames: 3}
camera:
  position: {keys: [[0, [0, 1, -3]], [2, [0, 1, 3]]]}
  target: [0, 1, 0]
lights:
  - {type: spot, attach: camera, shadows: true}
  - {type: directional, direction: [-1, -1, -1], shadows: true}
objects:
  - mesh: {primitive: box}
  - mesh: {primitive: plane, size: 10}
"""
    loaded = scene(text)
    camera = FrameEvaluator(loaded.world, (48, 32), None).evaluate(1, 1.0).camera
    assert np.array_equal(camera.rotation, np.eye(3))
    monkeypatch.setenv(ENV_CHECK_FINITE, "1")  # a NaN reaching any pixel fails the frame
    frames = render(gl, text, frames=(0, 1, 2))
    assert all(frame.std() > 0 for frame in frames)


def test_shininess_zero_gives_finite_even_highlights(render_scene):
    text = """
render: {size: [64, 64], samples: 1}
camera: {position: [0, 0, 3], target: [0, 0, 0]}
lights: [{type: directional, direction: [0, 0, -1]}]
objects:
  - mesh: {primitive: sphere, radius: 1, segments: 48, rings: 24}
    material: {diffuse: [0.2, 0.2, 0.2], specular: [0.3, 0.3, 0.3], shininess: 0}
"""
    image = render_scene(text).astype(int)
    center = image[32, 32]
    assert 120 < center[0] < 255                   # lit: base + constant specular lobe
    assert np.all(image[20:44, 20:44] > 60)        # no black (NaN) pixels on the lit face


def _ring_of_lights(count: int) -> str:
    lights = []
    for i in range(count):
        a = 2 * np.pi * i / count
        lights.append(f"  - {{type: point, position: [{3 * np.cos(a):.4f}, 0.3, {3 * np.sin(a):.4f}], "
                      f"color: [1, 1, 1], intensity: 0.8, attenuation: [1, 0, 4]}}")
    return ("render: {size: [96, 96], samples: 1}\ncamera: {position: [0, 9, 0.001], target: [0, 0, 0], fov: 50}\n"
            "lights:\n" + "\n".join(lights) + "\nobjects:\n  - mesh: {primitive: plane, size: 8}\n")


def test_no_cap_on_the_number_of_lights(render_scene):
    """40 point lights in a ring: the 40th still lights its own patch of floor."""
    all_lights = render_scene(_ring_of_lights(40))
    without_last = render_scene(_ring_of_lights(40).rsplit("\n  - {type: point", 1)[0] + "\nobjects:\n"
                                "  - mesh: {primitive: plane, size: 8}\n")
    diff = np.abs(all_lights.astype(int) - without_last.astype(int)).sum(axis=2)
    ys, xs = np.nonzero(diff > 10)
    assert len(ys) > 20
    # the changed pixels sit where the last light is (angle just below 2 pi: +X, slightly -Z)
    assert xs.mean() > 60 and abs(ys.mean() - 48) < 15


def test_many_shadowed_lights_each_cast_their_shadow(render_scene):
    """Six shadowed spot lights (more than pyrender's four per type), each behind a post."""
    lights, posts = [], []
    for i in range(6):
        a = 2 * np.pi * i / 6
        lights.append(f"  - {{type: spot, position: [{2.5 * np.cos(a):.3f}, 1.0, {2.5 * np.sin(a):.3f}], "
                      f"direction: [{-np.cos(a):.3f}, -0.35, {-np.sin(a):.3f}], inner_angle: 40, outer_angle: 60, "
                      f"intensity: 0.5, shadows: {{size: 256}}}}")
        posts.append(f"  - {{mesh: {{primitive: cylinder, radius: 0.08, height: 1.2}}, "
                     f"position: [{1.6 * np.cos(a):.3f}, 0.6, {1.6 * np.sin(a):.3f}]}}")
    text = ("render: {size: [128, 128], samples: 1}\ncamera: {position: [0, 7, 0.001], target: [0, 0, 0], fov: 60}\n"
            "lights:\n" + "\n".join(lights) + "\nobjects:\n  - mesh: {primitive: plane, size: 8}\n    cast_shadows: false\n"
            + "\n".join(posts) + "\n")
    lit = render_scene(text)
    unshadowed = render_scene(text.replace("shadows: {size: 256}", "shadows: false"))
    darker = (unshadowed.astype(int) - lit.astype(int)).sum(axis=2) > 15
    # each post's shadow falls towards the centre, on the floor between post and centre
    for i in range(6):
        a = 2 * np.pi * i / 6
        cx, cy = 64 + 0.9 * 64 / 7.0 * 1.0 * np.cos(a) * 1.35, 64 + 0.9 * 64 / 7.0 * np.sin(a) * 1.35
        region = darker[int(cy) - 6:int(cy) + 7, int(cx) - 6:int(cx) + 7]
        assert region.any(), f"no shadow from light {i}"


def test_lights_in_storage_buffers_render_like_uniform_blocks(render_scene, monkeypatch):
    """Light and shadow data beyond a uniform block's guaranteed size go to storage buffers
    (no cap on lights); both layouts must give the same image."""
    from scenerender.rendering import features

    text = """
render: {size: [96, 72], samples: 1}
camera: {position: [0, 4, 5], target: [0, 0, 0], fov: 50}
lights:
  - {type: directional, direction: [-0.4, -1, -0.2], intensity: 0.6, shadows: true}
  - {type: point, position: [1, 1.5, 1], attenuation: [1, 0.3, 0.2], shadows: {size: 128}}
  - {type: spot, position: [-1.5, 2, 0], direction: [0.6, -1, 0], outer_angle: 40, shadows: {size: 128}}
objects:
  - mesh: {primitive: plane, size: 8}
    cast_shadows: false
  - mesh: {primitive: box, size: 0.6}
    position: [0, 0.3, 0]
"""
    in_uniform_blocks = render_scene(text)
    monkeypatch.setattr(features, "UNIFORM_BLOCK_BYTES", 0)
    assert "LIGHTS_IN_UNIFORM_BLOCK" not in features.SceneFeatures(1, 1, 1, True, None, "blinn", False, False,
                                                                    (0,), (1,), (7,), 8).lighting_defines()
    in_storage_buffers = render_scene(text)
    assert in_uniform_blocks.std() > 10  # lit, shadowed, not blank
    assert np.array_equal(in_uniform_blocks, in_storage_buffers)


def test_point_light_cube_shadows_fall_away_from_the_light(render_scene):
    text = """
render: {size: [128, 128], samples: 1}
camera: {position: [0, 8, 0.001], target: [0, 0, 0], fov: 50}
lights:
  - {type: point, position: [0, 1.2, 0], attenuation: [1, 0, 0], shadows: {size: 256}}
objects:
  - mesh: {primitive: plane, size: 8}
    cast_shadows: false
  - mesh: {primitive: box, size: [0.4, 0.8, 0.4]}
    position: [1.2, 0.4, 0]
  - mesh: {primitive: box, size: [0.4, 0.8, 0.4]}
    position: [-1.2, 0.4, 0]
"""
    image = render_scene(text)[:, :, 0].astype(int)
    row = image[64]
    # beyond each box (further from the light, which is at the centre) the floor is dark
    assert row[64 + 40] < row[64 + 12] - 40 and row[64 - 40] < row[64 - 12] - 40


def test_spot_with_equal_inner_and_outer_angle_has_a_hard_edge(render_scene):
    text = """
render: {size: [128, 128], samples: 1}
camera: {position: [0, 6, 0.001], target: [0, 0, 0], fov: 50}
lights: [{type: spot, position: [0, 3, 0], direction: [0, -1, 0], inner_angle: 20, outer_angle: 20}]
objects:
  - mesh: {primitive: plane, size: 8}
"""
    row = render_scene(text)[64, :, 0].astype(int)
    inside = row > 30
    edges = np.nonzero(np.diff(inside.astype(int)))[0]
    assert len(edges) == 2
    for e in edges:  # full brightness to nothing between two neighbouring pixels
        assert abs(row[e] - row[e + 1]) > 100


def test_device_samples_are_powers_of_two_within_the_device():
    from scenerender.rendering.renderer import device_samples

    assert [device_samples(n, 8) for n in (1, 2, 3, 4, 5, 7, 8, 16, 64)] == [1, 2, 2, 4, 4, 4, 8, 8, 8]
    assert device_samples(8, 6) == 4  # a device maximum that is no power of two
    assert device_samples(0, 4) == 1


def test_msaa_off_gives_only_the_two_colours_of_a_mask(render_scene):
    text = """
render: {{size: [80, 60], samples: {samples}, background: [0, 0, 0]}}
camera: {{position: [0, 0, 4], target: [0, 0, 0]}}
lights: []
objects:
  - mesh: {{primitive: sphere, radius: 1}}
    material: {{diffuse: [1, 0, 0], unlit: true}}
"""
    hard = render_scene(text.format(samples=1))
    assert set(np.unique(hard[:, :, 0])) == {0, 255}
    smooth = render_scene(text.format(samples=4))
    assert len(np.unique(smooth[:, :, 0])) > 2  # anti-aliased edge pixels


def test_view_culling_never_changes_the_image(gl, monkeypatch):
    from conftest import SCENES, render
    from scenerender.world import frame as frame_module

    culled = render(gl, SCENES / "foggy_road.yaml", ["render.size=[200, 112]"], frames=(40,))[0]
    monkeypatch.setattr(frame_module, "instances_in_view", lambda b, m, p: np.ones(len(m), dtype=bool))
    everything = render(gl, SCENES / "foggy_road.yaml", ["render.size=[200, 112]"], frames=(40,))[0]
    assert np.array_equal(culled, everything)


def test_transparent_objects_blend_over_what_is_behind(render_scene):
    text = """
render: {size: [64, 64], samples: 1, background: [0, 0, 0]}
camera: {position: [0, 0, 5], target: [0, 0, 0], fov: 30}
lights: []
objects:
  - mesh: {primitive: box, size: [2, 2, 0.1]}
    position: [0, 0, -1]
    material: {diffuse: [0, 0, 1], unlit: true}
  - mesh: {primitive: plane, size: 1}
    rotation: [90, 0, 0]
    material: {diffuse: [1, 0, 0], opacity: 0.5, unlit: true}
"""
    center = render_scene(text)[32, 32].astype(int)
    # one layer of 0.5 red over blue, in linear light: (0.5, 0, 0.5) -> sRGB 188 each
    assert abs(center[0] - 188) <= 1 and center[1] == 0 and abs(center[2] - 188) <= 1
    # a box has two surfaces on the way through: 0.5 red over (0.5 red over blue)
    boxed = render_scene(text.replace("mesh: {primitive: plane, size: 1}\n    rotation: [90, 0, 0]",
                                      "mesh: {primitive: box, size: [1, 1, 0.1]}"))[32, 32].astype(int)
    assert abs(boxed[0] - 225) <= 1 and abs(boxed[2] - 137) <= 1  # (0.75, 0, 0.25) in sRGB


def test_missing_mtl_texture_is_a_warning_and_a_magenta_placeholder(gl, tmp_path):
    from conftest import render

    (tmp_path / "quad.obj").write_text("mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl painted\nf 1/1 2/2 3/3 4/4\n")
    (tmp_path / "quad.mtl").write_text("newmtl painted\nKd 1 1 1\nmap_Kd missing.png\n")
    scene = ("render: {size: [64, 64], samples: 1}\ncamera: {position: [0, 0, 2.2], target: [0, 0, 0]}\n"
             "lights: []\nobjects:\n  - mesh: quad.obj\n    material_overrides: {painted: {unlit: true}}\n")
    warnings = Warnings()
    image = render(gl, scene, base_dir=tmp_path, warnings=warnings)[0]
    assert any("missing.png" in w and "quad.mtl:3" in w for w in warnings.items)
    colours = {tuple(c) for c in image[8:56, 8:56].reshape(-1, 3)}
    assert (255, 0, 255) in colours and (0, 0, 0) in colours  # the checker's two colours
    with pytest.raises(UserError, match="--strict"):
        render(gl, scene, base_dir=tmp_path, warnings=Warnings(strict=True))


def test_a_texture_used_twice_is_loaded_once(gl):
    from conftest import SCENES, load
    from scenerender.rendering.renderer import GraphRenderer
    from scenerender.world.build import build_world

    world = build_world(load(SCENES / "foggy_road.yaml", ["render.size=[64, 36]"]), Warnings())
    renderer = GraphRenderer(world, gl)
    try:
        renderer.render(0)
        # road.png and dirt.png (sRGB) and the streetlight/pine MTL textures: each file once
        paths = [key[0] for key in renderer.scene.textures._textures]
        assert len(paths) == len(set(paths))
    finally:
        renderer.release()


def test_fog_turns_distant_objects_into_the_fog_colour(render_scene):
    text = """
render: {size: [64, 64], samples: 1, background: [0, 0, 0], fog: {mode: exp2, density: 0.5, color: [0.5, 0.5, 0.5]}}
camera: {position: [0, 0, 0], target: [0, 0, -1], fov: 20}
lights: []
objects:
  - mesh: {primitive: box, size: [4, 4, 0.1]}
    position: [0, 0, -30]
    material: {diffuse: [1, 0, 0], unlit: true}
"""
    assert np.all(np.abs(render_scene(text)[32, 32] - 187.52) <= 0.6)  # all fog: 0.5 grey
    near = render_scene(text.replace("position: [0, 0, -30]", "position: [0, 0, -1]"))[32, 32]
    assert near[0] > 230 and near[1] < 160  # exp(-(0.5 * 1)^2) = 0.78 of the red remains


def test_orthographic_camera_keeps_true_sizes(render_scene):
    text = """
render: {{size: [64, 64], samples: 1, background: [0, 0, 0]}}
camera: {{position: [0, 0, {z}], target: [0, 0, 0], projection: orthographic, height: 4}}
lights: []
objects:
  - mesh: {{primitive: sphere, radius: 1, segments: 64, rings: 32}}
    material: {{diffuse: [1, 1, 1], unlit: true}}
"""
    for distance in (3, 30):
        row = render_scene(text.format(z=distance))[32, :, 0]
        assert abs(int((row > 128).sum()) - 32) <= 1  # diameter 2 of a 4-unit view: half of 64


def test_texture_wrap_modes(render_scene, tmp_path):
    from PIL import Image

    pixels = np.zeros((1, 2, 3), dtype=np.uint8)
    pixels[0, 0] = (255, 0, 0)   # left half red
    pixels[0, 1] = (0, 0, 255)   # right half blue
    Image.fromarray(pixels).save(tmp_path / "halves.png")
    text = """
render: {{size: [128, 8], samples: 1}}
camera: {{position: [0, 1, 0], target: [0, 0, 0], up: [0, 0, -1], projection: orthographic, height: 0.0625}}
lights: []
objects:
  - mesh: {{primitive: plane, size: [1, 1], uv_repeat: 2}}
    material: {{diffuse_map: halves.png, filter: nearest, wrap: {wrap}, unlit: true, diffuse: [1, 1, 1]}}
"""
    def colours(wrap):
        row = render_scene(text.format(wrap=wrap), base_dir=tmp_path)[4]
        quarters = [row[8 + 32 * i] for i in range(4)]  # centres of u in [0,.5) [.5,1) [1,1.5) [1.5,2)
        return ["r" if q[0] > q[2] else "b" for q in quarters]

    assert colours("repeat") == ["r", "b", "r", "b"]
    assert colours("mirror") == ["r", "b", "b", "r"]
    assert colours("clamp") == ["r", "b", "b", "b"]


@pytest.mark.parametrize("suffix", ["ply", "stl"])
def test_other_mesh_formats_render_like_the_primitive(render_scene, tmp_path, suffix):
    import trimesh

    trimesh.creation.box(extents=(1, 1, 1)).export(tmp_path / f"box.{suffix}")
    text = """
render: {{size: [64, 64], samples: 1, background: [0, 0, 0]}}
camera: {{position: [2, 1.5, 2.5], target: [0, 0, 0]}}
lights: [{{type: directional, direction: [-0.3, -1, -0.5]}}, {{type: ambient}}]
objects:
  - mesh: {mesh}
    normals: flat
"""
    from_file = render_scene(text.format(mesh=f"box.{suffix}"), base_dir=tmp_path)
    primitive = render_scene(text.format(mesh="{primitive: box}"), base_dir=tmp_path)
    assert (from_file.max(axis=2) > 20).sum() > 300
    assert absolute_difference(primitive, from_file).mean() < 1.0


def test_exr_holds_linear_values_before_the_output_transform(tmp_path):
    import OpenEXR

    from scenerender.run.job import RenderOptions, run_render

    scene = tmp_path / "grey.yaml"
    scene.write_text(FLAT.format(samples=4, transform="srgb", c=0.5) + "output: {format: exr}\n")
    run_render(scene, RenderOptions(output=tmp_path / "out", quiet=True), echo=lambda *_: None)
    with OpenEXR.File(str(tmp_path / "out" / "frame_0000.exr")) as exr:
        rgb = exr.channels()["RGB"].pixels
    assert rgb.shape == (48, 64, 3) and rgb.dtype == np.float32
    assert np.allclose(rgb, 0.5, atol=1e-3)  # linear 0.5, not the sRGB-encoded 0.735


def test_linear_fog_mixes_by_distance(render_scene):
    text = """
render: {size: [32, 32], samples: 1, background: [0, 0, 0], fog: {mode: linear, start: 10, end: 30, color: [1, 1, 1]}}
camera: {position: [0, 0, 0], target: [0, 0, -1], fov: 10}
lights: []
objects:
  - mesh: {primitive: plane, size: 4}
    rotation: [90, 0, 0]
    position: [0, 0, -20]
    material: {diffuse: [0, 0, 0], unlit: true}
"""
    # halfway between start and end: 0.5 of the white fog over black -> sRGB 188
    assert abs(int(render_scene(text)[16, 16, 0]) - 188) <= 1
