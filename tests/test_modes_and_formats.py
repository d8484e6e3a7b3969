"""Every render mode in every output format renders: the shaded modes' colour, and the data
modes' values (depth, normals, ambient occlusion, shadow, light depth), which EXR keeps in
32-bit float rather than 8 bits."""
from __future__ import annotations

import itertools

import numpy as np
import OpenEXR
import pytest
from click.testing import CliRunner

from conftest import SCENES
from scenerender.cli import main
from scenerender.scene.model.output import FORMATS, VIDEO_FORMATS
from scenerender.scene.model.render import MODES

pytestmark = pytest.mark.gl

CASES = list(itertools.product(MODES, FORMATS))


def _render(tmp_path, mode, fmt, frames="0:1"):
    out = tmp_path / ("clip." + fmt if fmt in VIDEO_FORMATS else "out")
    result = CliRunner().invoke(main, ["render", str(SCENES / "viewer_modes.yaml"), "-o", str(out), "--format", fmt,
                                       "--set", f"render.mode={mode}", "--size", "48x32", "--frames", frames])
    return result, out


@pytest.mark.parametrize("mode, fmt", CASES, ids=[f"{m}-{f}" for m, f in CASES])
def test_every_mode_renders_in_every_format(tmp_path, mode, fmt):
    frames = "0:2" if fmt in VIDEO_FORMATS else "0:1"
    result, out = _render(tmp_path, mode, fmt, frames)
    assert result.exit_code == 0, result.output
    written = [out] if fmt in VIDEO_FORMATS else sorted(out.glob(f"*.{fmt}"))
    assert written and all(path.stat().st_size > 0 for path in written)


@pytest.mark.parametrize("mode", ["depth", "normals"])
def test_exr_keeps_data_modes_in_float(tmp_path, mode):
    result, out = _render(tmp_path, mode, "exr")
    assert result.exit_code == 0, result.output
    with OpenEXR.File(str(next(out.glob("*.exr")))) as exr:
        values = exr.channels()["RGB"].pixels
    assert values.dtype == np.float32
    fractions = values * 255.0 - np.round(values * 255.0)
    assert np.abs(fractions).max() > 0.01  # not 8-bit levels stored as floats


LIGHT_MODES = ("shaded", "wireframe", "points")


@pytest.mark.parametrize("mode", MODES)
def test_only_the_data_modes_are_written_without_the_output_transform(gl, mode):
    """What docs/scene-format.md and docs/scene-notes.md say: shaded, wireframe and points are
    light, encoded by ``output_transform``; the data modes are written as they are."""
    from conftest import render_one
    from scenerender.rendering.pipeline import DATA_MODES

    srgb, linear = (render_one(gl, SCENES / "viewer_modes.yaml",
                               [f"render.mode={mode}", "render.size=[48, 32]", "render.samples=1",
                                f"render.output_transform={transform}"]) for transform in ("srgb", "linear"))
    assert (mode in DATA_MODES) == np.array_equal(srgb, linear)
    assert (mode in LIGHT_MODES) != (mode in DATA_MODES)


def test_the_format_reference_names_the_data_modes_the_renderer_has():
    import re

    from scenerender.rendering.pipeline import DATA_MODES
    from scenerender.scene.reference_text import RENDER_MODES

    light, data = RENDER_MODES.split("The data modes", 1)
    data = data.split(":", 1)[0]
    assert tuple(re.findall(r"`(\w+)`", data)) == DATA_MODES
    assert [m for m in re.findall(r"`(\w+)`", light) if m in MODES] == list(LIGHT_MODES)
