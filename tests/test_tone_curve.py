"""The exposure and tone curve (render.exposure, render.tone_map): the NumPy curves'
shape, the graph a scene gets, the GL output against the NumPy curves on a ramp, exposure
on linear values, EXR staying scene-referred, the reference renderer applying the same
curve, and `tone_map: none` leaving every golden case's bytes as they were."""
from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import scenerender
from golden_cases import CASES, render_case
from scenerender.colorspace import TONE_MAPS, aces_fitted, agx, encode_output, srgb_encode, tone_map
from scenerender.raytrace import render_reference
from scenerender.rendering.passes.output import NO_TONE, OutputTransformPass
from scenerender.rendering.renderer import plan

CURVES = ("aces", "agx")
GREYS = np.concatenate([[0.0], np.logspace(-7, 4, 20001)])


def _grey(values: np.ndarray) -> np.ndarray:
    return np.repeat(values[:, None], 3, axis=1)


# -- the curves ---------------------------------------------------------------------------

@pytest.mark.parametrize("curve", CURVES)
def test_each_curve_maps_black_to_black(curve):
    assert np.array_equal(tone_map(np.zeros((1, 3)), curve), np.zeros((1, 3)))


@pytest.mark.parametrize("curve", CURVES)
def test_each_curve_rises_with_light_and_stays_within_0_and_1(curve):
    """Along a grey ramp from 1e-7 to 1e4 the curve never falls, and rises strictly through
    the image's range; the output stays in [0, 1]."""
    grey = tone_map(_grey(GREYS), curve)
    np.testing.assert_allclose(grey, grey[:, :1].repeat(3, axis=1), atol=1e-3)  # grey stays grey
    assert np.all(np.diff(grey, axis=0) >= 0.0) and grey.min() >= 0.0 and grey.max() <= 1.0
    assert grey[-1, 0] > 0.99  # very bright light reaches white
    # ACES's fit is 0 below 0.0033 and 1 from 25.7; AgX's log range ends at 2^4.03 = 16.3
    rising = (GREYS > 0.004) & (GREYS < 16)
    assert np.all(np.diff(grey[rising, 0]) > 0.0)


@pytest.mark.parametrize("curve", CURVES)
def test_colours_brighten_with_light_within_half_a_level(curve):
    """Along ramps of primaries and random colours, no channel of the sRGB-encoded output
    ever falls by half a level. Both fits mix the channels after the curve (the output or
    outset matrix), so a channel may dip a little while the others rise: ACES by up to
    0.34 of a level, AgX by up to 0.4 on a saturated colour's main channel past the top
    of its log range (docs/scene-notes.md)."""
    colours = np.concatenate([np.eye(3), np.random.default_rng(0).random((60, 3))])
    for colour in colours:
        encoded = srgb_encode(tone_map(GREYS[:, None] * colour, curve)) * 255.0
        fall = np.maximum.accumulate(encoded, axis=0) - encoded
        assert fall.max() < 0.5, (curve, colour, fall.max())


def test_the_published_fits_at_a_few_greys():
    """Where the fits put middle grey and 1.0 (display-linear; docs/scene-notes.md)."""
    greys = _grey(np.array([0.18, 1.0, 16.0]))
    np.testing.assert_allclose(aces_fitted(greys)[:, 0], [0.1056, 0.6191, 0.9899], atol=1e-4)
    np.testing.assert_allclose(agx(greys)[:, 0], [0.2145, 0.5900, 0.9947], atol=1e-4)


def test_none_only_scales_by_the_exposure():
    values = np.random.default_rng(1).random((50, 3)) * 4
    assert np.array_equal(tone_map(values, "none"), values)
    np.testing.assert_allclose(tone_map(values, "none", 1.0), values * 2)
    np.testing.assert_allclose(tone_map(values, "none", -2.5), values * 2 ** -2.5)
    assert set(TONE_MAPS) == {"none", *CURVES}


# -- the graph ----------------------------------------------------------------------------

BOX = "objects:\n  - mesh: {primitive: box}\n"


def _output_pass(text: str, overrides=(), samples=None, want_linear=False):
    world = scenerender.Scene.from_yaml(text, ".", list(overrides)).world
    compiled = plan(world, world.settings.size, samples or world.settings.samples, want_linear=want_linear).compiled
    node = next(n for n in compiled.passes if isinstance(n.render_pass, OutputTransformPass)
                or n.render_pass.name.startswith("resolve"))
    return compiled, node.render_pass


def test_none_and_no_exposure_build_the_graph_of_a_scene_without_the_keys():
    plain, plain_pass = _output_pass(BOX)
    explicit, explicit_pass = _output_pass(BOX, ["render.tone_map=none", "render.exposure=0"])
    assert explicit.pass_names == plain.pass_names == ["opaque", "resolve+output_transform", "readback"]
    assert explicit_pass == plain_pass and explicit_pass.describe() == "resolve; srgb by the target format"
    assert "exposure" not in [name for _, name, _ in explicit.inputs()]
    gamma, gamma_pass = _output_pass(BOX, ["render.output_transform=gamma", "render.tone_map=none"])
    assert gamma_pass.tone is NO_TONE and gamma_pass.defines() == {"OUTPUT_GAMMA": True, "SAMPLES": 4}


@pytest.mark.parametrize("overrides, described, defines", [
    (["render.tone_map=agx"], "4x MSAA, agx tone map, srgb", {"TONE_MAP_AGX": True}),
    (["render.tone_map=aces", "render.exposure=-1.5"], "4x MSAA, exposure -1.5, aces tone map, srgb",
     {"TONE_MAP_ACES": True, "EXPOSURE": True}),
    (["render.exposure=1"], "4x MSAA, exposure +1, srgb", {"EXPOSURE": True}),
    (["render.exposure={keys: [[0, 0], [1, 2]]}", "render.output_transform=gamma"],
     "4x MSAA, animated exposure, gamma 2.2", {"EXPOSURE": True}),
])
def test_a_tone_curve_or_exposure_shades_to_the_float_target_and_shows_in_the_output_pass(
        overrides, described, defines):
    compiled, output = _output_pass(BOX, overrides)
    assert output.describe() == described
    assert {k: v for k, v in output.defines().items() if not k.startswith(("OUTPUT_", "SAMPLES"))} == defines
    opaque = next(n.render_pass for n in compiled.passes if n.render_pass.name == "opaque")
    assert opaque.color_format == "rgba16f"  # the values above 1 reach the curve
    exposure = [(name, desc.dynamic) for _, name, desc in compiled.inputs() if name == "exposure"]
    assert exposure == ([("exposure", "keys" in overrides[0])] if "EXPOSURE" in defines else [])


# -- on GL: the shader's curves against NumPy's on a ramp ------------------------------------

RAMP_WIDTH = 256


def _ramp_scene(tmp_path, render: str) -> scenerender.Scene:
    """An unlit plane filling a 256 x 8 image, textured with a ramp of every 8-bit sRGB
    level (linear 0 to 1, finely spaced in the darks), seen straight down."""
    levels = np.arange(RAMP_WIDTH, dtype=np.uint8)
    rows = np.stack([levels, levels, levels[::-1]], axis=1)[None].repeat(2, axis=0)  # blue runs the other way
    Image.fromarray(rows).save(tmp_path / "ramp.png")
    text = f"""
render: {{size: [{RAMP_WIDTH}, 8], samples: 1, background: [0, 0, 0], {render}}}
camera: {{position: [0, 10, 0], target: [0, 0, 0], up: [0, 0, -1], projection: orthographic, height: 0.25}}
lights: []
objects:
  - mesh: {{primitive: plane, size: [8, 0.25]}}
    material: {{diffuse: [1, 1, 1], diffuse_map: ramp.png, filter: nearest, unlit: true}}
"""
    return scenerender.Scene.from_yaml(text, tmp_path)


def _frame(gl, scene, **options):
    with scenerender.Renderer(scene, gl=gl, **options) as renderer:
        return renderer.render(0)


@pytest.mark.parametrize("curve", CURVES)
@pytest.mark.parametrize("transform", ["srgb", "gamma"])
def test_the_output_shader_applies_the_numpy_curve_within_a_level(gl, tmp_path, curve, transform):
    """The GPU's output of a ramp from 0 to 2^5 (exposure -3 to +5) is the NumPy curve of
    the linear values the GPU read back, within 1 level."""
    for exposure in (-3.0, 0.0, 5.0):
        scene = _ramp_scene(tmp_path, f"tone_map: {curve}, exposure: {exposure}, output_transform: {transform}")
        frame = _frame(gl, scene, want_linear=True)
        assert frame.linear.max() > 0.99 and len(np.unique(frame.linear[..., 0])) > 200  # the ramp is all there
        expected = encode_output(tone_map(frame.linear, curve, exposure), transform, 2.2)
        difference = np.abs(frame.pixels.astype(int) - expected)
        assert difference.max() <= 1, (curve, transform, exposure, difference.max())


@pytest.mark.parametrize("curve", CURVES)
def test_the_fused_msaa_resolve_applies_the_same_curve(gl, tmp_path, curve):
    """With MSAA and no linear readback, the resolve and the output transform are one pass:
    the same curve as the separate passes, within a level."""
    scene = _ramp_scene(tmp_path, f"tone_map: {curve}, exposure: 2")
    fused = _frame(gl, scene, samples=4).pixels
    apart = _frame(gl, scene, samples=4, want_linear=True)
    assert np.abs(fused.astype(int) - apart.pixels).max() <= 1
    expected = encode_output(tone_map(apart.linear, curve, 2.0), "srgb")
    assert np.abs(fused.astype(int) - expected).max() <= 1


def test_exposure_plus_one_doubles_linear_values(gl, tmp_path):
    """tone_map none, linear output: every stored level is twice the level without
    exposure, within rounding, up to where it clips."""
    plain = _frame(gl, _ramp_scene(tmp_path, "output_transform: linear"), want_linear=True)
    brighter = _frame(gl, _ramp_scene(tmp_path, "output_transform: linear, exposure: 1"), want_linear=True)
    assert np.array_equal(plain.linear, brighter.linear)  # the linear (EXR) values stay scene-referred
    doubled = np.clip(2.0 * plain.linear, 0.0, 1.0) * 255.0
    assert np.abs(brighter.pixels - doubled).max() <= 0.51
    below_half = plain.pixels < 127
    assert below_half.sum() > 500
    twice = 2 * plain.pixels[below_half].astype(int)
    assert np.abs(brighter.pixels[below_half] - twice).max() <= 1
    # and through the sRGB curve: decoded, the levels double too
    srgb = _frame(gl, _ramp_scene(tmp_path, "exposure: 1")).pixels
    assert np.abs(srgb.astype(int) - np.rint(srgb_encode(2.0 * plain.linear) * 255)).max() <= 1


def test_an_animated_exposure_changes_the_image_over_time(gl, tmp_path):
    """Exposure from 0 to -1 stop over a second (frame i at i seconds): the second frame
    is the first at half the light, through the same curve."""
    scene = _ramp_scene(tmp_path, "exposure: {keys: [[0, 0], [1, -1]]}, tone_map: agx")
    with scenerender.Renderer(scene, gl=gl, want_linear=True) as renderer:
        first, second = renderer.render(0), renderer.render(int(scene.world.output.fps))
    assert np.array_equal(first.linear, second.linear)
    assert first.pixels.mean() > second.pixels.mean() + 10
    expected = encode_output(tone_map(second.linear, "agx", -1.0), "srgb")
    assert np.abs(second.pixels.astype(int) - expected).max() <= 1


# -- the reference renderer --------------------------------------------------------------

@pytest.mark.parametrize("curve", CURVES)
def test_the_reference_applies_the_same_curve(curve):
    scene = scenerender.Scene.from_yaml(f"""
render: {{size: [32, 24], tone_map: {curve}, exposure: 1.5}}
lights: [{{type: directional, direction: [-1, -2, -1], intensity: 3}}, {{type: ambient, color: [0.2, 0.2, 0.2]}}]
objects:
  - mesh: {{primitive: sphere}}
    material: {{diffuse: [0.9, 0.4, 0.1]}}
""", ".")
    ref = render_reference(scene, 0, spp=2)
    assert ref.linear.max() > 1.0  # the curve has highlights to bring down
    assert np.array_equal(ref.pixels, encode_output(tone_map(ref.linear, curve, 1.5), "srgb"))


# -- tone_map none leaves today's images -----------------------------------------------------

def test_none_leaves_every_golden_case_byte_for_byte(gl):
    """`tone_map: none` with exposure 0, written out, renders each golden case to the same
    bytes as the scene without the keys, in sRGB and through the output shader (gamma)."""
    explicit = ["render.tone_map=none", "render.exposure=0"]
    for name in sorted(CASES):
        assert np.array_equal(render_case(gl, name), render_case(gl, name, explicit)), name
    for name in ("showcase", "foggy_road", "viewer_modes"):
        gamma = ["render.output_transform=gamma"]
        assert np.array_equal(render_case(gl, name, gamma), render_case(gl, name, gamma + explicit)), name
