"""`scenerender preview`: from saving the scene to the new image on the page, against the
render itself, at the preview's 320x240.

A copy of scenes/ goes to a temporary folder; the preview serves the chosen scene on
127.0.0.1 and headless Chromium (Selenium) opens the page. Each round saves the scene with
one light's intensity nudged (so each save draws new pixels) and waits for the page to
show the frame of that save. Save-to-image is the page's clock when the image has loaded
(``window.previewShown.at``, Date.now) less the clock before the file was written (the
same system clock); the render is what the worker spent on that frame (``X-Render-Seconds``:
loading the saved scene and its assets, building the renderer, drawing and PNG encoding).

    python benchmarks/preview_latency.py [--scene garden] [--saves 12] [--pause 0.5]
"""
from __future__ import annotations

import argparse
import re
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from preview_helpers import PreviewProcess, chrome  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402

INTENSITY = re.compile(r"^(\s*intensity:\s*)([0-9.]+)", re.MULTILINE)


def nudged(text: str, round_index: int) -> str:
    """The scene text with its first light intensity changed by a percent, up or down by round."""
    match = INTENSITY.search(text)
    if match is None:
        raise SystemExit("the scene needs an `intensity:` line to nudge")
    value = float(match.group(2)) * (1.01 if round_index % 2 == 0 else 1.0)
    return text[:match.start(2)] + f"{value:.4f}" + text[match.end(2):]


def shown(driver, generation: int) -> dict:
    return WebDriverWait(driver, 60, poll_frequency=0.01).until(
        lambda d: (lambda s: s if s and s["generation"] >= generation else False)(
            d.execute_script("return window.previewShown || null")))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default="garden", help="a scene of scenes/ (its stem)")
    parser.add_argument("--saves", type=int, default=12)
    parser.add_argument("--pause", type=float, default=0.5, help="seconds between a shown frame and the next save")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="preview-latency-"))
    try:
        shutil.copytree(ROOT / "scenes", work / "scenes")
        scene = work / "scenes" / f"{args.scene}.yaml"
        original = scene.read_text(encoding="utf-8")
        preview = PreviewProcess(scene)
        driver = chrome(work / "profile")
        try:
            driver.get(preview.url)
            last = shown(driver, 0)
            rows = []
            for index in range(args.saves):
                time.sleep(args.pause)
                text = nudged(original, index)
                saved_at = time.time() * 1000.0
                scene.write_text(text, encoding="utf-8")
                last = shown(driver, last["generation"] + 1)
                latency = (last["at"] - saved_at) / 1000.0
                rows.append((latency, last["renderSeconds"]))
                print(f"save {index:2d}: on the page after {latency * 1000:6.0f} ms, render {last['renderSeconds'] * 1000:5.0f} ms, "
                      f"the rest {1000 * (latency - last['renderSeconds']):5.0f} ms")
        finally:
            driver.quit()
            preview.stop()
    finally:
        shutil.rmtree(work, ignore_errors=True)
    latencies, renders = zip(*rows)
    rest = [a - b for a, b in rows]
    print(f"{args.scene}, {len(rows)} saves: save to image median {statistics.median(latencies) * 1000:.0f} ms "
          f"(max {max(latencies) * 1000:.0f}); render median {statistics.median(renders) * 1000:.0f} ms; "
          f"the rest median {statistics.median(rest) * 1000:.0f} ms (max {max(rest) * 1000:.0f})")


if __name__ == "__main__":
    main()
