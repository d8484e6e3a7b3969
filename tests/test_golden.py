"""Golden images: every scene in scenes/ (and the seed scenes' other render modes) rendered
small and compared with a committed reference, within the tolerance stated in
golden_cases.py. The second half shows that tolerance catching real regressions."""
from __future__ import annotations

import shutil

import numpy as np
import pytest
from PIL import Image

from golden_cases import CASES, SCENES, beyond_cpu_rounding, reference_ids, reference_path, render_case, render_case_with_ids
from scenerender.compare import DEFAULT_RULE, compare_images


def matches(reference: np.ndarray, candidate: np.ndarray, ids=None):
    """The verdict of `scenerender diff` and `render --check`: one rule everywhere, by
    object too where ``ids`` (both sides' IdMaps) are given, as --check keeps them."""
    frame = compare_images("golden", reference, candidate, DEFAULT_RULE, keep_images=False, object_ids=ids)
    return frame.passed, frame


def reference(name: str) -> np.ndarray:
    return np.asarray(Image.open(reference_path(name)).convert("RGB"))


@pytest.mark.parametrize("name", sorted(CASES))
def test_render_matches_reference(gl, name, tmp_path):
    image, ids = render_case_with_ids(gl, name)
    ok, report = matches(reference(name), image, (reference_ids(name), ids))
    assert report.objects is not None, f"{name}: judged by colour alone ({report.colour_only})"
    if not ok:  # keep what was rendered next to the report, for a look
        Image.fromarray(image).save(tmp_path / f"{name}.png")
    assert ok, f"{name}: {report.summary_line()} (rendered image in {tmp_path})"


def test_references_are_not_blank():
    """A black or single-colour reference would let a broken renderer pass."""
    for name in CASES:
        image = reference(name)
        assert image.std() > 10, name
        assert len(np.unique(image.reshape(-1, 3), axis=0)) > 10, name


def test_every_golden_case_keeps_its_object_ids():
    for name in CASES:
        ids = reference_ids(name)
        assert ids is not None and ids.behind is not None, name
        assert ids.ids.shape == reference(name).shape[:2] and ids.ids.any(), name


def test_a_shininess_halved_fails_and_is_named_by_object(gl):
    """A regression the colours alone passed before the still region limit (at 160x120 the
    spheres are too small for an interior): the frame did not move, so the brighter rings
    fail the still region (417 levels x px against 100), and the ids name the steel spheres."""
    image, ids = render_case_with_ids(gl, "primitives", ["materials.steel.shininess=80"])
    ok, report = matches(reference("primitives"), image, (reference_ids("primitives"), ids))
    assert not ok and "nothing moved, yet a region changed one way" in report.reason, report.summary_line()
    assert "sphere steel at" in report.attribution()


def test_every_scene_file_has_a_golden_case():
    covered = {scene for scene, _, _ in CASES.values()}
    assert covered == {p.name for p in SCENES.glob("*.yaml")}


# -- the tolerance catches real changes ------------------------------------------------
# Each regression is a small, plausible bug: the render must FAIL the comparison.

REGRESSIONS = {
    "a moved object": ("showcase", ["objects[6].position=[-0.15, 0.35, -0.1]"]),   # the vase, 0.2 m
    "a wrong colour": ("showcase", ["objects[6].material=ceramic",
                                    "materials.ceramic.diffuse=[0.22, 0.22, 0.82]"]),
    "a turned light": ("garden", ["lights[0].position.keys[0]=[0.0, [-8, 4.5, 1]]"]),
    "missing shadows": ("primitives", ["lights[0].shadows=false"]),
    "a wrong output transform": ("viewer_modes", ["render.output_transform=gamma"]),
    "a changed fog density": ("foggy_road", ["render.fog.density=0.035"]),
}


@pytest.mark.parametrize("what", sorted(REGRESSIONS))
def test_tolerance_catches(gl, what):
    name, change = REGRESSIONS[what]
    image, ids = render_case_with_ids(gl, name, change)
    ok, report = matches(reference(name), image, (reference_ids(name), ids))
    assert not ok, f"{what} slipped through the tolerance: {report.summary_line()}"


def test_tolerance_accepts_driver_level_noise(gl):
    """One 8-bit level of noise on a quarter of the pixels, as rounding between drivers
    gives, stays within tolerance."""
    image = reference("showcase").astype(int)
    rng = np.random.default_rng(0)
    noise = rng.integers(-1, 2, size=image.shape) * (rng.random(image.shape[:2]) < 0.25)[..., None]
    ok, report = matches(reference("showcase"), np.clip(image + noise, 0, 255).astype(np.uint8))
    assert ok, report.summary_line()


# -- the CPU-rounding bound of the "renders the bytes it drew before" claims -----------------
# (golden_cases.beyond_cpu_rounding) passes another CPU's rounding, and fails a shader changed
# on purpose: each edit is a plausible slip in the environment light's GLSL

SHADER_SLIPS = {
    "a diffuse 1 % too bright": ("return u_env_scale * textureLod(u_env_diffuse",
                                 "return 1.01 * u_env_scale * textureLod(u_env_diffuse"),
    "a specular level a tenth off": ("level - below);", "min(level - below + 0.1, 1.0));"),
}


def _render_with_environment_glsl(gl, tmp_path, monkeypatch, old: str, new: str):
    """gltf_pbr@visibility_off drawn with ``old`` replaced by ``new`` in a copy of
    shaders/lighting/environment.glsl -> (H, W, 3) uint8."""
    import scenerender.gpu.shaders as shaders

    changed = tmp_path / "shaders"
    shutil.copytree(shaders.shader_dir(), changed)
    source = changed / "lighting" / "environment.glsl"
    text = source.read_text(encoding="utf-8")
    assert old in text
    source.write_text(text.replace(old, new), encoding="utf-8")
    monkeypatch.setattr(shaders, "shader_dir", lambda: changed)
    return render_case(gl, "gltf_pbr@visibility_off")


@pytest.mark.gl
@pytest.mark.parametrize("slip", sorted(SHADER_SLIPS))
def test_the_cpu_rounding_bound_fails_a_changed_shader(gl, tmp_path, monkeypatch, slip):
    image = _render_with_environment_glsl(gl, tmp_path, monkeypatch, *SHADER_SLIPS[slip])
    assert beyond_cpu_rounding(image, reference("gltf_pbr@visibility_off")), slip


@pytest.mark.gl
def test_the_copied_shaders_unchanged_pass_the_bound(gl, tmp_path, monkeypatch):
    """The control of the test above: the copy itself changes nothing."""
    line = SHADER_SLIPS["a diffuse 1 % too bright"][0]
    image = _render_with_environment_glsl(gl, tmp_path, monkeypatch, line, line)
    assert beyond_cpu_rounding(image, reference("gltf_pbr@visibility_off")) is None
