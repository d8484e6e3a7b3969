"""Memory: a 12,000 x 12,000 texture renders under a 4 GiB address-space limit (before, the
float32 mip chain ran out and ended in an internal error), and running out of memory is one
line and exit 2, naming the texture being loaded, never an internal error."""
from __future__ import annotations

import resource
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from scenerender.world.mipmaps import EXACT_LEVEL_TEXELS, mip_chain

OBJ = ("mtllib big.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
       "usemtl big\nf 1/1 2/2 3/3 4/4\n")
SCENE = ("scenerender: 1\nrender: {size: [160, 120], samples: 1}\ncamera: {position: [0, 2, 2], target: [0, 0, 0]}\n"
         "lights:\n  - {type: directional, direction: [0, -1, -0.3]}\nobjects:\n  - mesh: big.obj\n")


def _big_texture_scene(folder, side: int):
    # a gradient: a few MB of PNG, decoded to side * side RGBA all the same
    row = np.linspace(0, 255, side).astype(np.uint8)
    Image.fromarray(np.broadcast_to(row, (side, side))).convert("RGB").save(folder / "big.png", compress_level=1)
    (folder / "big.mtl").write_text("newmtl big\nKd 1 1 1\nmap_Kd big.png\n")
    (folder / "big.obj").write_text(OBJ)
    (folder / "scene.yaml").write_text(SCENE)
    return folder / "scene.yaml"


def _render_limited(scene, out, address_space: int):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
    return subprocess.run([sys.executable, "-m", "scenerender", "render", str(scene), "-o", str(out)],
                          capture_output=True, text=True, timeout=300, preexec_fn=limit)


@pytest.mark.gl
@pytest.mark.slow
def test_a_12k_texture_renders_under_4_gib(tmp_path):
    scene = _big_texture_scene(tmp_path, 12_000)
    run = _render_limited(scene, tmp_path / "out", 4 * 2**30)
    assert run.returncode == 0, run.stderr[-1000:]
    assert (tmp_path / "out" / "frame_0000.tga").exists() or list((tmp_path / "out").iterdir())


def _render_in_process(scene, out):
    from click.testing import CliRunner

    from scenerender.cli import main

    return CliRunner().invoke(main, ["render", str(scene), "-o", str(out)])


def _out_of_memory(*args, **kwargs):
    raise MemoryError()


@pytest.mark.gl
@pytest.mark.parametrize("step", ["decode", "upload", "elsewhere"])
def test_running_out_of_memory_is_one_line_and_exit_2(tmp_path, monkeypatch, step):
    """Out of memory while decoding or uploading a texture names it; anywhere else, one
    line. (Under a real address-space limit the same lines appear where NumPy or Python
    run short; a native library that fails an allocation itself can still end the process
    without one, which is why this test raises the error where scenerender would meet it.)"""
    from scenerender.gpu import textures
    from scenerender.rendering import renderer
    from scenerender.world import images

    scene = _big_texture_scene(tmp_path, 64)
    target = {"decode": (images, "_rgba"), "upload": (textures.TextureCache, "_upload_2d"),
              "elsewhere": (renderer.GraphRenderer, "render")}[step]
    monkeypatch.setattr(*target, _out_of_memory)
    result = _render_in_process(scene, tmp_path / "out")
    assert result.exit_code == 2, result.output
    # the run's first progress line names the GL renderer; the error is one line after it
    lines = [line for line in result.stderr.strip().splitlines() if not line.startswith("GL renderer: ")]
    assert "internal error" not in result.stderr and len(lines) == 1
    if step == "elsewhere":
        assert lines[0].startswith("error: not enough memory to finish")
    else:
        assert "big.png: not enough memory to" in result.stderr


def test_large_levels_are_made_from_8_bit_levels_within_half_a_level():
    """Above EXACT_LEVEL_TEXELS the chain continues from the rounded level: one more rounding."""
    rng = np.random.default_rng(3)
    side = 2 * int(EXACT_LEVEL_TEXELS ** 0.5) * 2  # level 1 is over the limit, level 2 at it
    image = rng.integers(0, 256, (side, side, 4), dtype=np.uint8)
    levels = mip_chain(image, srgb=False)
    # the exact level k is each 2^k x 2^k block's sum over 4^k: |level - sum / 4^k| <= 1 is
    # |level * 4^k - sum| <= 4^k, in integers (sums of up to 64 texels fit uint16), not over
    # a float64 copy of the 8192 x 8192 image (2 GiB, 12 s)
    sums, texels = image.astype(np.uint16), 1
    for level in levels[:3]:
        sums = sums[0::2, 0::2] + sums[1::2, 0::2] + sums[0::2, 1::2] + sums[1::2, 1::2]
        texels *= 4
        assert np.abs(level.astype(np.int32) * texels - sums).max() <= texels
    assert levels[-1].shape == (1, 1, 4)
