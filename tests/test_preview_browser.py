"""The preview page in a real browser: headless Chromium (Debian's chromium and
chromium-driver; CI installs both) driven by Selenium opens `scenerender preview`'s page
and uses it as a person would. Screenshots of each step are kept under the test's tmp
folder (pytest prints where) as artefacts to look at."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("watchfiles", reason="the preview extra is not installed (pip install 'scenerender[preview]')")
pytest.importorskip("selenium", reason="selenium is not installed (pip install 'scenerender[test]')")

from preview_helpers import (CHROMEDRIVER, CHROMIUM, FOV_LINE, PIXEL_SCRIPT, ROOT, PreviewProcess,  # noqa: E402
                             chrome, write_paint, write_scene)
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import Select, WebDriverWait  # noqa: E402

pytestmark = [pytest.mark.gl, pytest.mark.xdist_group("preview"),
              pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None,
                                 reason="chromium or chromium-driver is not installed (apt-get install chromium "
                                        "chromium-driver)")]
WAIT = 60  # seconds: a loaded 2-core machine renders slowly
SCREENSHOTS = ROOT / "tests" / "output" / "preview"


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    write_paint(tmp_path)
    write_scene(tmp_path)
    return tmp_path


@pytest.fixture
def page(folder, tmp_path):
    """The page of a running preview, its first frame shown."""
    preview = PreviewProcess(folder / "scene.yaml")
    driver = chrome(tmp_path / "profile")
    try:
        driver.get(preview.url)
        shown(driver, lambda s: s is not None)
        driver.preview = preview
        yield driver
    finally:
        driver.quit()
        preview.stop()


def shown(driver, check, timeout: float = WAIT) -> dict:
    """The page's last shown frame (window.previewShown) once ``check`` holds for it."""
    return WebDriverWait(driver, timeout, poll_frequency=0.05).until(
        lambda d: (lambda s: s if check(s) else False)(d.execute_script("return window.previewShown || null")))


def pixel(driver, x: int, y: int) -> tuple[int, int, int]:
    return tuple(driver.execute_script(PIXEL_SCRIPT, x, y))


def camera_yaml(driver) -> str:
    return driver.find_element(By.ID, "camera-yaml").text


def screenshot(driver, name: str) -> Path:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    path = SCREENSHOTS / f"{name}.png"
    driver.save_screenshot(str(path))
    return path


def test_the_page_shows_the_frame(page):
    image = page.find_element(By.ID, "frame")
    assert page.execute_script("return arguments[0].naturalWidth", image) == 320  # the preview size
    red, green, blue = pixel(page, 3, 3)  # the background: blue
    assert blue > 150 and blue > red + 60, (red, green, blue)
    red, green, blue = pixel(page, 160, 130)  # the box: its orange paint
    assert red > green > blue and red > 120, (red, green, blue)
    assert camera_yaml(page) == "camera: {position: [0, 1.2, 4], target: [0, 0, 0], fov: 50}"
    assert page.find_element(By.ID, "frame-label").text == "frame 0 / 7 · 0.000 s"
    assert page.find_element(By.ID, "scene-size").text == "320x240 of 640x480"
    assert len(page.find_elements(By.CSS_SELECTOR, "#path circle.key")) == 2  # the path's keys, from above
    assert page.find_elements(By.ID, "path-current")
    assert screenshot(page, "loaded").stat().st_size > 10_000


def test_a_saved_scene_shows_the_new_frame(page, folder):
    before = shown(page, bool)
    write_scene(folder, background=(0.9, 0.1, 0.05))
    after = shown(page, lambda s: s["generation"] > before["generation"])
    red, green, blue = pixel(page, 3, 3)
    assert red > 150 and red > blue + 60, (red, green, blue)
    assert after["frame"] == before["frame"] and after["query"] == before["query"]  # the same view
    screenshot(page, "saved")


def test_a_saved_asset_shows_the_new_frame(page, folder):
    before = shown(page, bool)
    write_paint(folder, colour=(20, 200, 60))
    shown(page, lambda s: s["generation"] > before["generation"])
    red, green, blue = pixel(page, 160, 130)
    assert green > red + 60, (red, green, blue)


def test_the_timeline_changes_the_frame(page):
    yaml_before = camera_yaml(page)
    timeline = page.find_element(By.ID, "timeline")
    timeline.click()
    timeline.send_keys(Keys.END)  # the last frame, as a keyboard user scrubs
    after = shown(page, lambda s: s["frame"] == 7)
    assert page.find_element(By.ID, "frame-label").text == "frame 7 / 7 · 0.875 s"
    assert camera_yaml(page) == "camera: {position: [3, 1.2, 2.6], target: [0, 0, 0], fov: 50}" != yaml_before
    assert after["renderSeconds"] > 0
    timeline.send_keys(Keys.ARROW_LEFT)
    shown(page, lambda s: s["frame"] == 6)
    screenshot(page, "timeline")


def test_play_runs_through_the_frames(page):
    page.find_element(By.ID, "play").click()
    seen = set()
    deadline = time.monotonic() + WAIT
    while len(seen) < 4 and time.monotonic() < deadline:
        seen.add(shown(page, bool)["frame"])
        time.sleep(0.05)
    page.find_element(By.ID, "play").click()
    assert len(seen) >= 4, seen


def test_a_drag_changes_the_camera_yaml(page):
    before = camera_yaml(page)
    stage = page.find_element(By.ID, "stage")
    ActionChains(page).click_and_hold(stage).move_by_offset(90, 0).move_by_offset(30, -20).release().perform()
    WebDriverWait(page, WAIT).until(lambda d: camera_yaml(d) != before and "target: [0, 0, 0]" in camera_yaml(d))
    yaml = camera_yaml(page)
    position = [float(v) for v in re.search(r"position: \[([^\]]+)\]", yaml).group(1).split(",")]
    assert abs(sum(v * v for v in position) - (1.2 ** 2 + 4 ** 2)) < 0.05  # orbiting keeps the distance
    assert position[0] < -0.5  # dragged right: the camera went round to the left
    distance = sum(v * v for v in position) ** 0.5
    page.execute_script("arguments[0].dispatchEvent(new WheelEvent('wheel', {deltaY: 100, bubbles: true,"
                        " cancelable: true}))", stage)
    WebDriverWait(page, WAIT).until(lambda d: camera_yaml(d) != yaml)
    farther = [float(v) for v in re.search(r"position: \[([^\]]+)\]", camera_yaml(page)).group(1).split(",")]
    assert sum(v * v for v in farther) ** 0.5 > distance * 1.05  # the wheel dollied out
    yaml = camera_yaml(page)
    ActionChains(page).send_keys("w").perform()  # fly forward: camera and target move together
    WebDriverWait(page, WAIT).until(lambda d: camera_yaml(d) != yaml)
    assert "target: [0, 0, 0]" not in camera_yaml(page)
    screenshot(page, "dragged")


def test_the_mode_switch(page):
    before = shown(page, bool)
    Select(page.find_element(By.ID, "mode")).select_by_value("normals")
    shown(page, lambda s: "mode=normals" in s["query"])
    assert pixel(page, 3, 3) == (0, 0, 0)  # normals mode: no surface, no colour
    assert before["query"] != shown(page, bool)["query"]


def test_a_broken_scene_shows_its_message_and_line_then_a_fixed_one_clears_it(page, folder):
    before = shown(page, bool)
    write_scene(folder, fov="500")
    errors = page.find_element(By.ID, "errors")
    WebDriverWait(page, WAIT).until(lambda d: errors.is_displayed() and f"scene.yaml:{FOV_LINE}" in errors.text)
    assert "camera.fov" in errors.text
    assert pixel(page, 3, 3)[2] > 150  # the last good image stays under the message
    screenshot(page, "broken")
    write_scene(folder, background=(0.1, 0.6, 0.1))
    WebDriverWait(page, WAIT).until(lambda d: not errors.is_displayed())
    shown(page, lambda s: s["generation"] > before["generation"] + 1)
    screenshot(page, "fixed")


def test_check_shows_the_reference_and_the_verdict(folder, tmp_path):
    """`--check REF/`: the reference beside the live frame, and the verdict of that frame
    rendered at the scene's own quality; a change to the scene turns it to CHANGED."""
    render = subprocess.run([sys.executable, "-m", "scenerender", "render", "scene.yaml", "-o", "ref", "-q"],
                            cwd=folder, capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(ROOT)))
    assert render.returncode == 0, render.stderr
    preview = PreviewProcess(folder / "scene.yaml", "--check", "ref")
    driver = chrome(tmp_path / "profile")
    try:
        driver.get(preview.url)
        verdict = driver.find_element(By.ID, "verdict")
        WebDriverWait(driver, WAIT).until(lambda d: verdict.text.startswith("PASS frame_0000"))
        reference = driver.find_element(By.ID, "reference")
        WebDriverWait(driver, WAIT).until(lambda d: d.execute_script("return arguments[0].naturalWidth", reference))
        assert driver.execute_script("return arguments[0].naturalWidth", reference) == 640  # the scene's own size
        screenshot(driver, "check")
        write_scene(folder, background=(0.9, 0.1, 0.05))
        WebDriverWait(driver, WAIT).until(lambda d: verdict.text.startswith("CHANGED frame_0000"))
    finally:
        driver.quit()
        preview.stop()
