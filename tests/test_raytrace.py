"""The CPU reference renderer against analytic answers: a lit plane's radiance, a sphere's
silhouette area, a spot cone's edge, a box's shadow outline. Small images (64x64), an
orthographic camera looking straight down, so pixel (x, y) sees world point
(x_world, 0, z_world) with x_world, z_world linear in the pixel centre."""
from __future__ import annotations

import math

import numpy as np
import pytest

import scenerender
from scenerender.raytrace import render_reference, write_reference
from scenerender.raytrace import shading

SIZE = 64
VIEW = 4.0  # world units the image spans, both ways

TOP_DOWN = f"""
render: {{size: [{SIZE}, {SIZE}], background: [0, 0, 0]}}
camera: {{position: [0, 10, 0], target: [0, 0, 0], up: [0, 0, -1], projection: orthographic, height: {VIEW}}}
"""


def load(text: str) -> scenerender.Scene:
    return scenerender.Scene.from_yaml(TOP_DOWN + text, ".")


def pixel_world(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """World (x, z) at the centres of pixels (x, y) of the top-down camera."""
    scale = VIEW / SIZE
    return (x + 0.5) * scale - VIEW / 2, (y + 0.5) * scale - VIEW / 2


def test_lit_plane_radiance_matches_the_formula():
    light, att = np.array([0.4, 1.5, -0.3]), (1.0, 0.3, 0.2)
    scene = load(f"""
lights:
  - {{type: point, position: {light.tolist()}, attenuation: {list(att)}, intensity: 1.0}}
  - {{type: ambient, color: [0.1, 0.1, 0.1]}}
objects:
  - mesh: {{primitive: plane, size: 8}}
    material: {{diffuse: [0.7, 0.6, 0.5], specular: [0, 0, 0]}}
""")
    ref = render_reference(scene, 0, spp=4)
    kd = scene.world.objects[0].materials[0].diffuse(0.0)[:3]
    ys, xs = np.mgrid[0:SIZE, 0:SIZE]
    wx, wz = pixel_world(xs.ravel().astype(float), ys.ravel().astype(float))
    to_light = light[None, :] - np.stack([wx, np.zeros_like(wx), wz], axis=1)
    d = np.linalg.norm(to_light, axis=1)
    cos = to_light[:, 1] / d
    expected = 0.1 * kd[None, :] + (kd[None, :] * (cos / (att[0] + att[1] * d + att[2] * d * d))[:, None])
    # a pixel is the mean over its area; the formula at its centre is within second order
    np.testing.assert_allclose(ref.linear.reshape(-1, 3), expected, rtol=2e-3, atol=1e-4)


def test_sphere_silhouette_area_is_pi_r_squared():
    radius = 1.1
    scene = load(f"""
lights: [{{type: ambient, color: [1, 1, 1]}}]
objects:
  - mesh: {{primitive: sphere, radius: {radius}, segments: 256}}
    material: {{diffuse: [1, 1, 1], unlit: true}}
""")
    ref = render_reference(scene, 0, spp=4)
    area = float(ref.linear[:, :, 0].sum()) * (VIEW / SIZE) ** 2
    # the tessellated outline: a 256-gon inscribed in the circle
    polygon = 0.5 * 256 * math.sin(2 * math.pi / 256) * radius ** 2
    assert area == pytest.approx(polygon, rel=2e-3)
    assert area == pytest.approx(math.pi * radius ** 2, rel=2e-3)


def test_hard_spot_cone_edge_where_the_cone_meets_the_plane():
    height, angle = 2.0, 30.0
    scene = load(f"""
lights:
  - {{type: spot, position: [0, {height}, 0], direction: [0, -1, 0], inner_angle: {angle}, outer_angle: {angle},
     attenuation: [1, 0, 0]}}
objects:
  - mesh: {{primitive: plane, size: 8}}
    material: {{diffuse: [1, 1, 1], specular: [0, 0, 0]}}
""")
    ref = render_reference(scene, 0, spp=4)
    edge_radius = height * math.tan(math.radians(angle))
    lit_area = float(ref.cone[:, :, 0].sum()) * (VIEW / SIZE) ** 2
    assert lit_area == pytest.approx(math.pi * edge_radius ** 2, rel=5e-3)
    # the centre row: lit exactly out to the edge radius (to a tenth of a pixel)
    row = ref.cone[SIZE // 2 - 1:SIZE // 2 + 1, :, 0].mean(axis=0)   # straddles z = 0
    lit_width = float(row.sum()) * VIEW / SIZE
    assert lit_width == pytest.approx(2 * edge_radius, abs=0.1 * VIEW / SIZE)
    outside = ref.cone[:, :, 0] == 0
    assert np.all(ref.linear[outside] == 0.0)


def test_box_shadow_outline_where_geometry_puts_it():
    # a unit box floating over x = -1.5..-0.5, y = 1..2, a sun travelling along (1, -1, 0):
    # its shadow on the ground covers x in [-0.5, 1.5], z in [-0.5, 0.5] (a corner at
    # height y lands y further along x)
    scene = load("""
lights:
  - {type: directional, direction: [1, -1, 0], shadows: true}
  - {type: ambient, color: [0.2, 0.2, 0.2]}
objects:
  - mesh: {primitive: plane, size: 8}
    material: {diffuse: [1, 1, 1], specular: [0, 0, 0]}
  - mesh: {primitive: box, size: 1}
    position: [-1, 1.5, 0]
""")
    ref = render_reference(scene, 0, spp=4)
    pixel = VIEW / SIZE
    shadow = ref.shadow[:, :, 0]
    assert float(shadow.sum()) * pixel ** 2 == pytest.approx(2.0, rel=5e-3)
    ys, xs = np.nonzero(shadow > 0.5)
    wx, wz = pixel_world(xs.astype(float), ys.astype(float))
    assert wx.min() == pytest.approx(-0.5, abs=pixel) and wx.max() == pytest.approx(1.5, abs=pixel)
    assert wz.min() == pytest.approx(-0.5, abs=pixel) and wz.max() == pytest.approx(0.5, abs=pixel)
    # in the shadow only the ambient term is left: 0.2 * Kd; the shadow took Kd cos 45
    inside = shadow == 1.0
    np.testing.assert_allclose(ref.linear[inside], 0.2, rtol=1e-6)
    np.testing.assert_allclose(ref.blocked[:, :, 0][inside], math.sqrt(0.5), rtol=1e-6)
    assert not ref.blocked[:, :, 0][shadow == 0.0].any()


def test_scene_far_from_the_origin_renders_like_at_it():
    text = """
lights:
  - {{type: point, position: [{x}, 1.5, 0.3], attenuation: [1, 0.2, 0.1], shadows: true}}
objects:
  - mesh: {{primitive: plane, size: 8}}
    position: [{x}, 0, 0]
  - mesh: {{primitive: sphere, radius: 0.5}}
    position: [{x}, 0.6, 0]
"""
    near = render_reference(scenerender.Scene.from_yaml(TOP_DOWN + text.format(x=0.0), "."), 0, spp=2)
    moved = TOP_DOWN.replace("[0, 10, 0], target: [0, 0, 0]", "[1e7, 10, 0], target: [1e7, 0, 0]")
    far = render_reference(scenerender.Scene.from_yaml(moved + text.format(x=1e7), "."), 0, spp=2)
    assert np.abs(near.pixels.astype(int) - far.pixels.astype(int)).max() <= 1


def test_reference_writes_exr_and_png(tmp_path):
    import OpenEXR
    from PIL import Image

    scene = load("objects: [{mesh: {primitive: box}}]")
    ref = render_reference(scene, 0, spp=1)
    paths = write_reference(ref, tmp_path / "ref")
    assert [p.name for p in paths] == ["frame_0000.exr", "frame_0000.png"]
    assert np.array_equal(np.asarray(Image.open(paths[1])), ref.pixels)
    with OpenEXR.File(str(paths[0])) as exr:
        assert np.allclose(exr.channels()["RGB"].pixels, ref.linear)
    assert sorted(p.name for p in (tmp_path / "ref").iterdir()) == ["frame_0000.exr", "frame_0000.png"]


def test_reference_names_what_it_leaves_out():
    top_down_with_ao = TOP_DOWN.replace("background: [0, 0, 0]}", "background: [0, 0, 0], ambient_occlusion: {}}")
    scene = scenerender.Scene.from_yaml(
        top_down_with_ao + "objects: [{mesh: {primitive: box}, material: {opacity: 0.5}}]\n", ".")
    lines = []
    render_reference(scene, 0, spp=1, warn=lines.append)
    assert lines == ["the reference renders without ambient occlusion, transparency"]


def test_reference_is_deterministic_and_finite():
    scene = load("objects: [{mesh: {primitive: sphere}}, {mesh: {primitive: plane, size: 4}}]")
    a, b = (render_reference(scene, 0, spp=2) for _ in range(2))
    assert np.array_equal(a.linear, b.linear)
    assert np.isfinite(a.linear).all()


def test_shading_helpers_never_give_nan():
    n = np.array([[0.0, 1.0, 0.0]] * 3)
    l = np.array([[0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 0.0]])
    v = np.array([[0.0, -1.0, 0.0]] * 3)   # l + v = 0 for the first: the half vector falls back
    for model in ("phong", "blinn_phong"):
        lobe = shading.specular_lobe(n, shading.safe_normalize(l), v, np.array([0.0, 32.0, 1.0]), model)
        assert np.isfinite(lobe).all()
    assert np.isfinite(shading.attenuation((0, 0, 0), np.array([0.0]))).all()
    assert shading.spot_cone(0.9, 0.9, np.array([0.9, 0.8999]))[0] == 1.0
