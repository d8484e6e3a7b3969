"""What the page is told about the scene besides its frames: frame count and rate, the
render modes, the camera path seen from above, and the reference frame and verdict that
``--check REF/`` asks for."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from scenerender.compare import compare_images, read_image
from scenerender.compare.sources import is_frame_file
from scenerender.run.references import reference_folder, renderer_key
from scenerender.scene.loading import load_scene
from scenerender.scene.model.render import MODES
from scenerender.sinks.images import frame_name_pattern

MOST_PATH_POINTS = 600  # a long animation's path is sampled this often, evenly


def scene_facts(scene_path: Path, overrides: list[str], asset_roots=()) -> tuple[dict, dict | None]:
    """The scene file as saved, validated again without loading its assets (a few ms):
    the timeline's and the mode switch's facts, and its camera path (``camera_path``)."""
    loaded = load_scene(scene_path, overrides, asset_roots=tuple(asset_roots))
    spec = loaded.spec
    summary = {"name": loaded.path.name, "frame_count": spec.output.frame_count, "fps": float(spec.output.fps),
               "size": [int(v) for v in spec.render.size], "mode": spec.render.mode, "modes": list(MODES),
               "name_pattern": spec.output.name}
    return summary, camera_path(spec.camera, spec.output.frame_count, float(spec.output.fps))


def camera_path(camera, frame_count: int, fps: float) -> dict | None:
    """A scene's own camera positions over its frames, for the page's view from above:
    ``{"frames": [frame index], "points": [[x, y, z]], "keys": [[x, y, z]]}`` (float lists),
    or None when the camera (a ``CameraSpec`` or None) does not move along a position track."""
    track = None if camera is None else camera.position
    if track is None or track.is_constant:
        return None
    frames = np.unique(np.linspace(0, max(frame_count - 1, 0), min(frame_count, MOST_PATH_POINTS)).round().astype(int))
    points = [_rounded(track(index / fps)) for index in frames]
    keys = [_rounded(value) for value in track.values]
    return {"frames": frames.tolist(), "points": points, "keys": keys}


def _rounded(values) -> list[float]:
    return [round(float(v), 4) for v in np.asarray(values, dtype=np.float64).reshape(-1)[:3]]


@dataclass(frozen=True)
class ReferenceFrames:
    """The reference frames of ``--check REF/``: ``root``, or ``root/<renderer>/`` (ref/llvmpipe/)
    where that exists for the GL renderer drawing the preview, as ``render --check`` picks."""

    root: Path

    def frame_path(self, index: int, name_pattern: str | None, frame_count: int, gl_renderer: str | None
                   ) -> Path | None:
        """The reference file of frame ``index`` (any image format a frame folder may hold), or None."""
        folder = reference_folder(self.root, renderer_key(gl_renderer))
        stem = frame_name_pattern(name_pattern, frame_count).format(frame=index)
        found = sorted(path for path in folder.glob(f"{stem}.*") if is_frame_file(path))
        return found[0] if found else None

    @staticmethod
    def verdict(reference: Path, pixels: np.ndarray) -> dict:
        """``pixels`` ((H, W, 3) uint8, rendered at the scene's own size and samples)
        judged against ``reference`` by the diff rule, on colour alone: ``{"passed": bool,
        "line": the diff's summary line}``."""
        result = compare_images(reference.stem, read_image(reference), pixels, keep_images=False)
        line = result.summary_line() if not result.passed else (result.excused_line() or f"PASS {reference.stem}")
        return {"passed": result.passed, "line": line}
