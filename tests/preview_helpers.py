"""Running `scenerender preview` for tests and benchmarks: the command in its own process
on 127.0.0.1 and a free port (--port 0, the address read from its first line), a small
scene it can watch, and headless Chromium driven by Selenium."""
from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
from PIL import Image

ROOT = Path(__file__).resolve().parent.parent
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")

# A box under a camera that moves along two keys over 8 frames; the box wears a texture
# file, so that saving an asset can be tested as well as saving the scene. Line numbers
# matter: the tests break `fov` on FOV_LINE.
SCENE = """\
scenerender: 1
render:
  size: [640, 480]
  background: {background}
output:
  fps: 8
  frames: 8
camera:
  position:
    keys:
      - [0.0, [0, 1.2, 4]]
      - [0.875, [3, 1.2, 2.6]]
  target: [0, 0, 0]
  fov: {fov}
lights:
  - {{type: directional, direction: [-0.5, -1, -0.7]}}
  - {{type: ambient, color: [0.3, 0.3, 0.3]}}
objects:
  - name: box
    mesh: {{primitive: box, size: 1.6}}
    material: {{diffuse: [1, 1, 1], diffuse_map: paint.png}}
"""
FOV_LINE = 14


def write_scene(folder: Path, background=(0.1, 0.2, 0.8), fov="50") -> Path:
    path = folder / "scene.yaml"
    text = SCENE.format(background=json.dumps(list(background)), fov=fov)
    temp = folder / ".scene.yaml.saving"
    temp.write_text(text, encoding="utf-8")
    temp.replace(path)  # as editors save: a new file renamed over the old
    return path


def write_paint(folder: Path, colour=(230, 120, 30)) -> Path:
    path = folder / "paint.png"
    Image.fromarray(np.full((8, 8, 3), colour, dtype=np.uint8)).save(path)
    return path


class PreviewProcess:
    """`scenerender preview SCENE --port 0 --no-open ARGS` until ``stop()``."""

    def __init__(self, scene: Path, *args: str, env: dict | None = None):
        env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=str(ROOT), **(env or {}))
        self.process = subprocess.Popen([sys.executable, "-m", "scenerender", "preview", str(scene.resolve()), "--port", "0",
                                         "--no-open", *args], cwd=scene.parent, env=env, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)
        line = self.process.stdout.readline()
        if "http://" not in line:
            self.process.kill()
            raise RuntimeError(f"no address printed: {line!r} {self.process.stderr.read()[-2000:]}")
        self.url = line[line.index("http://"):].split()[0]

    def get(self, path: str, timeout: float = 60) -> tuple[int, dict, bytes]:
        try:
            with urllib.request.urlopen(self.url.rstrip("/") + path, timeout=timeout) as response:
                return response.status, {k.lower(): v for k, v in response.headers.items()}, response.read()
        except urllib.error.HTTPError as exc:
            return exc.code, {k.lower(): v for k, v in exc.headers.items()}, exc.read()

    def state(self, since: int = -1) -> dict:
        return json.loads(self.get(f"/state?since={since}")[2])

    def wait_for_state(self, check, timeout: float = 60) -> dict:
        """The first state for which ``check(state)`` holds (long polls); AssertionError past ``timeout``."""
        deadline = time.monotonic() + timeout
        state = self.state()
        while not check(state):
            assert time.monotonic() < deadline, f"timed out; last state {state}"
            state = self.state(state["version"])
        return state

    def stop(self, sig=signal.SIGINT, timeout: float = 20) -> tuple[int, str, str]:
        """Interrupt as Ctrl-C does; (exit code, stdout, stderr)."""
        if self.process.poll() is None:
            self.process.send_signal(sig)
        try:
            out, err = self.process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.process.kill()
            out, err = self.process.communicate()
            raise AssertionError(f"the preview did not stop within {timeout} s: {err[-2000:]}")
        return self.process.returncode, out, err


def chrome(profile: Path, size=(1280, 900)):
    """A headless Chromium (Debian's chromium and chromium-driver) under Selenium."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     f"--window-size={size[0]},{size[1]}", f"--user-data-dir={profile}"):
        options.add_argument(argument)
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)


# The shown frame's pixel at (x, y) of the image itself, as the page decoded it.
PIXEL_SCRIPT = """
const img = document.getElementById('frame');
const canvas = document.createElement('canvas');
canvas.width = img.naturalWidth; canvas.height = img.naturalHeight;
const context = canvas.getContext('2d');
context.drawImage(img, 0, 0);
return Array.from(context.getImageData(arguments[0], arguments[1], 1, 1).data.slice(0, 3));
"""
