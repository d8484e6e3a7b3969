"""KHR_materials_iridescence (docs/scene-notes.md, "Layers of the pbr model"): the thin
film's Fresnel (shaders/lighting/iridescence.glsl, shading.thin_film_fresnel) mixed into
the pbr model's, on the GPU and in the reference; a GLB written here."""
from __future__ import annotations

import numpy as np
import pytest

from conftest import render
from gltf_files import GlbBuilder, sphere
from scenerender.raytrace import render_reference, shading
from scenerender.rendering.features import material_defines
from scenerender.tools.quality import frame_errors
from pbr_glb_scene import glb_scene, render_glb
from white_furnace import white_furnace

SCENE = glb_scene(ambient=0.3)
# a black dielectric under a film of index 1.8, 600 nm: its reflection alone, coloured
SOAP = {"iridescenceFactor": 1.0, "iridescenceIor": 1.8, "iridescenceThicknessMaximum": 600}


def film_glb(path, iridescence: dict | None, metallic: float = 0.0):
    builder = GlbBuilder()
    extensions = {}
    if iridescence is not None:
        extensions["KHR_materials_iridescence"] = iridescence
        builder.uses("KHR_materials_iridescence")
    color = [0.9, 0.9, 0.9, 1] if metallic else [0.02, 0.02, 0.02, 1]
    material = builder.material(name="film", extensions=extensions, pbrMetallicRoughness={
        "baseColorFactor": color, "metallicFactor": metallic, "roughnessFactor": 0.35})
    builder.node(builder.mesh(builder.primitive(sphere(1.0, 4), material)))
    return builder.write(path)


def test_the_film_colours_the_reflection(gl, tmp_path):
    # without the film a black dielectric's highlight is grey (F0 0.04 in every channel);
    # with it, coloured, and its hue changes from the middle to the rim
    film_glb(tmp_path / "model.glb", None)
    plain = render_glb(gl, tmp_path)[1].linear[..., :3]
    film_glb(tmp_path / "model.glb", SOAP)
    loaded, frame = render_glb(gl, tmp_path)
    assert "PBR_IRIDESCENCE" in material_defines(loaded.world.materials()[0], "pbr")
    film = frame.linear[..., :3]
    peak = np.unravel_index(np.argmax(plain.mean(axis=2)), plain.shape[:2])
    assert np.ptp(plain[peak]) < 0.02 * plain[peak].mean()
    assert np.ptp(film[peak]) > 0.2 * film[peak].mean()
    rim = film[36, 21]  # near the outline, grazing
    middle = film[36, 48]
    assert np.argmax(rim) != np.argmax(middle) or np.argmin(rim) != np.argmin(middle)


@pytest.mark.parametrize("metallic", [0.0, 1.0])
def test_gpu_matches_the_reference(gl, tmp_path, metallic):
    # the layers' tolerances (tests/test_pbr_layers.py)
    film_glb(tmp_path / "model.glb", {**SOAP, "iridescenceIor": 1.3, "iridescenceThicknessMaximum": 400}
             if metallic else SOAP, metallic)
    loaded, frame = render_glb(gl, tmp_path)
    errors = frame_errors(render_reference(loaded, 0, spp=3), frame.pixels, frame.linear, with_flip=False)
    assert errors["rmse_linear"] < 1.5, errors
    assert errors["interior_rmse"] < 0.25, errors


def test_factor_0_renders_the_bytes_of_no_extension(gl, tmp_path):
    film_glb(tmp_path / "model.glb", None)
    plain = render(gl, SCENE, base_dir=tmp_path)[0]
    film_glb(tmp_path / "model.glb", {**SOAP, "iridescenceFactor": 0.0})
    assert np.array_equal(render(gl, SCENE, base_dir=tmp_path)[0], plain)


def test_the_film_fresnel_is_bounded_and_tends_to_the_bare_interface():
    # no negative light; at normal incidence and no thickness about the base's F0 (the
    # extension's approximation leaves 0.044 for F0 0.04 under a film of index 1.3);
    # grazing, near 1; and it oscillates with thickness (interference)
    count = 200
    cosines = np.linspace(0.0, 1.0, count)
    film = shading.thin_film_fresnel(cosines, np.full(count, 1.3), np.full(count, 400.0), np.full((count, 3), 0.04))
    assert film.min() >= 0.0 and film[0].min() > 0.9
    bare = shading.thin_film_fresnel(np.ones(1), np.full(1, 1.3), np.zeros(1), np.full((1, 3), 0.04))
    assert np.allclose(bare, 0.04, atol=0.005)
    thickness = np.linspace(100.0, 1000.0, count)
    red = shading.thin_film_fresnel(np.ones(count), np.full(count, 1.8), thickness, np.full((count, 3), 0.04))[:, 0]
    assert np.sum(np.diff(np.sign(np.diff(red))) != 0) >= 3


def test_white_furnace_a_film_over_a_white_base_makes_no_light():
    # the per-direction BRDF's Monte Carlo integral in a white surround: 0.947 (the film
    # takes its reflection from the diffuse part by its largest channel, so a coloured
    # reflection loses a little); the uniform-light formula within 0.02 of it (0.961)
    integral, formula = white_furnace("base_color: [1, 1, 1], metallic: 0, roughness: 0.5, iridescence: 1, "
                                      "iridescence_ior: 1.8, iridescence_thickness: 600")
    assert float(integral.mean()) == pytest.approx(0.95, abs=0.03)
    assert float(integral.mean()) < 1.0
    assert abs(float(formula.mean()) - float(integral.mean())) < 0.02
