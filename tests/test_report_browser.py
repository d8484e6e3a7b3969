"""The HTML report in a real browser: headless Chromium (Debian's `chromium` package; CI
installs it) opens a report of a changed frame, runs its script and takes a screenshot,
which must show the layout: the red verdict banner, the heatmap's red, the yellow
outlines of the changed region and the dashed cyan outline of the close-up's window."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from scenerender.compare import compare_paths, write_html_report
from test_compare import PROVENANCE, drawn, make_folder

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (apt-get install chromium)")
WINDOW = (1280, 1500)


def chromium(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               f"--user-data-dir={tmp_path / 'profile'}", f"--window-size={WINDOW[0]},{WINDOW[1]}", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("report")
    ref = make_folder(folder / "ref", {"frame_0000.png": drawn(), "frame_0001.png": drawn(),
                                       "frame_0002.png": drawn()}, PROVENANCE)
    out = make_folder(folder / "out", {"frame_0000.png": drawn(shift=(0.25, 0)),
                                       "frame_0001.png": drawn(drop_disc=True)})
    path = folder / "report.html"
    write_html_report(compare_paths(ref, out), path)
    return path


def colour_share(pixels: np.ndarray, colour, tolerance=30) -> float:
    """Fraction of (H, W, 3) pixels within ``tolerance`` levels of ``colour`` per channel."""
    return float(np.all(np.abs(pixels.astype(int) - colour) <= tolerance, axis=2).mean())


def test_screenshot_shows_the_report(report, tmp_path):
    shot = tmp_path / "report.png"
    result = chromium(tmp_path, f"--screenshot={shot}", report.as_uri())
    assert shot.exists(), result.stderr[-2000:]
    pixels = np.asarray(Image.open(shot).convert("RGB"))
    assert pixels.shape[:2] == (WINDOW[1], WINDOW[0])
    assert pixels.std() > 20, "the screenshot is blank"
    banner = pixels[:40]
    assert colour_share(banner, (0xb3, 0x26, 0x1e), 12) > 0.5, "no red CHANGED banner at the top"
    body = pixels[80:]
    assert colour_share(body, (0xff, 0xd4, 0x00), 40) > 0.0005, "no yellow outline of the changed region"
    red = (body[..., 0] > 150) & (body[..., 1] < 40) & (body[..., 2] < 40)
    assert red.mean() > 0.0005, "no red in the heatmap"
    assert colour_share(body, (0x00, 0xe5, 0xff), 40) > 0.0005, "no dashed outline of the close-up's window"


def test_the_script_runs(report, tmp_path):
    """The slider's script sets the reference's clip on load; a script error would leave it unset."""
    dom = chromium(tmp_path, "--dump-dom", report.as_uri()).stdout
    assert "clip-path: inset(0px 50% 0px 0px)" in dom or "clip-path: inset(0 50% 0 0)" in dom, dom[-500:]
