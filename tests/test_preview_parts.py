"""The preview's parts on their own: the page's camera as overrides and back, the path seen
from above, and the throttle that makes a burst of saves two renders."""
from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest

pytest.importorskip("watchfiles", reason="the preview extra is not installed (pip install 'scenerender[preview]')")

from preview_helpers import write_paint, write_scene  # noqa: E402

from scenerender.preview.scene_info import scene_facts  # noqa: E402
from scenerender.preview.views import PlacedCamera, View, camera_from_record, camera_yaml, PreviewQuality  # noqa: E402
from scenerender.preview.watcher import SaveThrottle  # noqa: E402
from scenerender.scene.loading import load_scene  # noqa: E402


def test_a_placed_camera_parses_and_refuses_what_is_not_one():
    camera = PlacedCamera.parse("1,2,3,0,0.5,0,45")
    assert camera == PlacedCamera((1.0, 2.0, 3.0), (0.0, 0.5, 0.0), 45.0)
    for text in ("1,2,3", "1,2,3,4,5,6,7,8", "1,2,3,nan,0,0,50", "1,2,3,0,0,0,inf", "1,2,3,0,0,0,180", "a,b,c,d,e,f,g"):
        with pytest.raises(ValueError):
            PlacedCamera.parse(text)


def test_a_placed_camera_replaces_an_aim_by_yaw_and_pitch(tmp_path: Path):
    """The overrides clear yaw/pitch, which would otherwise fight the placed target."""
    scene = tmp_path / "scene.yaml"
    scene.write_text("camera: {position: [0, 1, 5], yaw: -90, pitch: -10, fov: 70}\nobjects: []\n")
    view = View(frame=0, mode="depth", camera=PlacedCamera((4.0, 2.0, 0.0), (0.0, 0.0, 0.0), 35.0))
    spec = load_scene(scene, view.overrides()).spec
    assert spec.camera.yaw is None and spec.camera.pitch is None
    assert tuple(spec.camera.position(0.0)) == (4.0, 2.0, 0.0) and spec.camera.fov(0.0) == 35.0
    assert spec.render.mode == "depth"


def test_the_preview_size_keeps_the_scenes_shape_and_the_users_own_choice():
    quality = PreviewQuality.for_options(size_given=False, samples_given=False)
    assert quality.samples == 1
    assert quality.size_for((800, 600)) == (320, 240)
    assert quality.size_for((960, 540)) == (320, 180)
    assert quality.size_for((480, 320)) == (320, 213)
    assert quality.size_for((600, 1200)) == (120, 240)
    assert quality.size_for((160, 120)) == (160, 120)  # never enlarged
    assert PreviewQuality.for_options(size_given=True, samples_given=True) == PreviewQuality(None, None)
    assert PreviewQuality(None, None).size_for((960, 540)) is None


def test_the_camera_yaml_is_a_scene_files_camera(tmp_path: Path):
    text = camera_yaml({"position": [1.23456, -0.0, 4.0], "target": [0.0, 0.2, 0.0], "fov": 49.99999})
    assert text == "camera: {position: [1.235, 0, 4], target: [0, 0.2, 0], fov: 50}"
    scene = tmp_path / "scene.yaml"
    scene.write_text(text + "\nobjects: []\n")
    assert tuple(load_scene(scene).spec.camera.position(0.0)) == (1.235, 0.0, 4.0)


@pytest.mark.gl
def test_the_camera_read_back_from_a_frame_is_the_scenes(tmp_path: Path, gl):
    import scenerender

    write_paint(tmp_path)
    scene = scenerender.load(write_scene(tmp_path), ["render.size=[64, 48]"])
    with scenerender.Renderer(scene, gl=gl) as renderer:
        first = camera_from_record(renderer.camera_record(0), (0.0, 0.0, 0.0))
        last = camera_from_record(renderer.camera_record(7))  # no target known: one step ahead along the view
    assert first == {"position": [0.0, 1.2, 4.0], "target": [0.0, 0.0, 0.0], "fov": 50.0}
    assert last["position"] == [3.0, 1.2, 2.6] and last["fov"] == 50.0
    ahead = [t - p for t, p in zip(last["target"], last["position"])]
    assert ahead[0] < 0 and ahead[2] < 0  # looking back towards the origin


def test_the_path_from_above_has_the_keys_and_one_point_a_frame(tmp_path: Path):
    write_paint(tmp_path)
    summary, path = scene_facts(write_scene(tmp_path), [])
    assert summary["frame_count"] == 8 and summary["fps"] == 8.0 and summary["mode"] == "shaded"
    assert path["frames"] == list(range(8)) and path["keys"] == [[0.0, 1.2, 4.0], [3.0, 1.2, 2.6]]
    assert path["points"][0] == [0.0, 1.2, 4.0] and path["points"][-1] == [3.0, 1.2, 2.6]
    still = tmp_path / "still.yaml"
    still.write_text("camera: {position: [0, 1, 5]}\nobjects: []\n")
    assert scene_facts(still, [])[1] is None  # a camera that does not move has no path


class Counter:
    def __init__(self):
        self.count = 0
        self.lock = threading.Lock()

    def __call__(self):
        with self.lock:
            self.count += 1


def test_a_lone_save_fires_at_once():
    fired = Counter()
    throttle = SaveThrottle(fired, burst_seconds=0.2)
    throttle.saved()
    assert fired.count == 1  # synchronously: a single save waits for nothing
    throttle.stop()


def test_a_burst_fires_twice_and_two_bursts_four_times():
    fired = Counter()
    throttle = SaveThrottle(fired, burst_seconds=0.2)
    for _ in range(2):
        for _ in range(8):
            throttle.saved()
            time.sleep(0.01)
        time.sleep(0.6)
    throttle.stop()
    assert fired.count == 4


def test_stopping_cancels_the_burst_still_open():
    fired = Counter()
    throttle = SaveThrottle(fired, burst_seconds=0.2)
    throttle.saved()
    throttle.saved()
    throttle.stop()
    time.sleep(0.4)
    assert fired.count == 1
