"""The environment light's specular term (``specular: split_sum | sampled`` on
``type: environment``): the three-sphere scene against the reference renderer, each sphere
within 3 % (benchmarks/quality/three_spheres.py), the copper sphere alone (no occlusion, the
specular term by itself) where the sampled term reaches the reference and the split sum
falls short, the key unset rendering what the renderer drew before it existed, and bad
values refused at their key."""
from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

import scenerender
from golden_cases import beyond_cpu_rounding, reference_path, render_case
from quality_benchmarks import QUALITY, quality_module
from scenerender.cli import main

SIZE = (128, 96)
SAMPLED = ["lights[0].specular=sampled", "lights[0].specular_samples=32"]
# the copper sphere by itself: its neighbours and the ground hidden, nothing to block
ALONE = ["objects[0].visible=false", "objects[2].visible=false", "objects[3].visible=false",
         "lights[0].visibility=false"]


spheres = quality_module("three_spheres")


def _reference(overrides: list) -> tuple[np.ndarray, np.ndarray]:
    """((H, W) float64 linear radiance, (H, W) bool mixed pixels) of the three-sphere scene
    with ``overrides`` at SIZE by the reference renderer (2x2 samples a pixel, 24
    directions each, seeded)."""
    scene = scenerender.load(spheres.SCENE, [f"render.size=[{SIZE[0]},{SIZE[1]}]", *overrides])
    return spheres.reference(scene, spp=2, environment_samples=24)


@pytest.fixture(scope="module")
def three_reference():
    """The scene's reference and each sphere's pixels."""
    truth, mixed = _reference([])
    scene = scenerender.load(spheres.SCENE, [f"render.size=[{SIZE[0]},{SIZE[1]}]"])
    return truth, spheres.sphere_masks(spheres.surface_points(scene.world, SIZE), mixed)


@pytest.fixture(scope="module")
def alone_reference():
    """The copper sphere alone: its reference and its pixels (those the reference sees it in)."""
    truth, mixed = _reference(ALONE)
    return truth, (truth > 0.0) & ~mixed


def three_errors(gl, reference, overrides=()) -> dict:
    truth, masks = reference
    return spheres.sphere_errors(spheres.gpu_linear(list(overrides), SIZE, gl), truth, masks)


def alone_error(gl, reference, overrides=()) -> float:
    truth, mask = reference
    linear = spheres.gpu_linear([*ALONE, *overrides], SIZE, gl)
    return float(linear[mask].mean() / truth[mask].mean() - 1.0)


@pytest.mark.gl
@pytest.mark.parametrize("setting", ["split_sum", "sampled"])
def test_three_spheres_under_a_sky_each_within_3_percent_of_the_reference(gl, three_reference, setting):
    # The GPU's mean linear radiance over each sphere against the reference's, the spheres
    # blocking part of each other's sky. split_sum at the light's defaults (32 visibility
    # directions), measured here: grey +0.6, copper +2.9, white +1.1 % (the copper +1.4 %
    # at 256x192 against a finer reference: benchmarks/quality/three_spheres.md). The
    # sampled term is scaled by one specular visibility a pixel, an error the split sum's
    # happens to offset on the copper (+3.7 % at 32 directions), so it is checked at 64
    # directions: +0.8, -0.3, +0.7 %.
    overrides = [] if setting == "split_sum" else [*SAMPLED, "lights[0].visibility_directions=64"]
    errors = three_errors(gl, three_reference, overrides)
    assert all(abs(error) < 0.03 for error in errors.values()), errors


@pytest.mark.gl
def test_the_three_sphere_check_catches_a_coarser_visibility(gl, three_reference):
    # the same bound fails where the sky's occlusion is sampled in 16 directions (the
    # default before 0.7.0; measured: copper +5.6 %, white +5.3 %): the check sees errors
    # of this size
    errors = three_errors(gl, three_reference, ["lights[0].visibility_directions=16"])
    assert max(abs(error) for error in errors.values()) > 0.04, errors


@pytest.mark.gl
def test_the_copper_sphere_alone_within_2_percent_split_sum_and_sampled(gl, alone_reference):
    # The copper sphere alone (nothing blocks its sky), so the specular term is all there is.
    # The split sum looked up at the lobe's dominant direction: -0.7 % here (-1.4 % at
    # 256x192 against a finer reference); looked up at R, as before, it read -2.5 % (-3.2 %),
    # which the bound fails. 64 samples at the pixel's own n and v: -0.03 %; 16 and 32
    # samples: -0.7 and -1.0 %. With Colbert and Krivanek's extra mip level (lod + 1) 64
    # samples came out -1.4 % here: the 1 % bound caught it
    split = alone_error(gl, alone_reference)
    sampled = alone_error(gl, alone_reference, ["lights[0].specular=sampled", "lights[0].specular_samples=64"])
    assert abs(split) < 0.02, split
    assert abs(sampled) < 0.01, sampled


@pytest.mark.gl
def test_the_key_unset_renders_the_bytes_drawn_before_it_existed(gl):
    # unset and split_sum are one path: the same bytes in this run, on any CPU. And that path
    # draws tests/golden/gltf_pbr@visibility_exact.png, drawn before the key existed (drawn
    # again when the opaque pass began writing the sRGB encoding itself, which moved values
    # by a level at most, and when the split sum's lookup moved to the lobe's dominant
    # direction), up to the CPU's rounding (golden_cases.beyond_cpu_rounding); sampled does not
    name = "gltf_pbr@visibility_exact"
    before = np.asarray(Image.open(reference_path(name)))[..., :3]
    unset = render_case(gl, name)
    assert np.array_equal(render_case(gl, name, ["lights[2].specular=split_sum"]), unset)
    assert beyond_cpu_rounding(unset, before) is None, beyond_cpu_rounding(unset, before)
    assert beyond_cpu_rounding(render_case(gl, name, ["lights[2].specular=sampled"]), before)


@pytest.mark.parametrize("value, key", [
    ("specular: exact", "lights[0].specular"),
    ("specular: 1", "lights[0].specular"),
    ("specular_samples: 0", "lights[0].specular_samples"),
    ("specular_samples: 257", "lights[0].specular_samples"),
    ("specular_samples: 2.5", "lights[0].specular_samples"),
])
def test_bad_values_are_refused_at_their_key(tmp_path, value, key):
    (tmp_path / "e.hdr").write_bytes((QUALITY / "scenes" / "contact_sky.hdr").read_bytes())
    (tmp_path / "s.yaml").write_text(f"objects: []\nlights: [{{type: environment, image: e.hdr, {value}}}]\n")
    result = CliRunner().invoke(main, ["validate", str(tmp_path / "s.yaml")])
    assert result.exit_code == 2, result.output
    assert key in result.stderr and "s.yaml:2" in result.stderr, result.stderr
    assert "Traceback" not in result.stderr
