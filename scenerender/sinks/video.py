"""Videos: MP4 (H.264) and GIF, streamed frame by frame to ffmpeg (imageio-ffmpeg), so a
long flythrough never sits in memory. The file appears only when the video is finished."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from scenerender.errors import EnvironmentProblem
from scenerender.sinks.base import FrameSink

# GIF: a palette per frame (ffmpeg palettegen + paletteuse) looks far better than the
# fixed web palette, and works on a stream because each frame needs only itself.
GIF_FILTER = "split[a][b];[a]palettegen=stats_mode=single:reserve_transparent=0[p];[b][p]paletteuse=new=1"


def _crf(quality: int) -> int:
    """quality 1..100 -> x264 CRF 51..12 (lower CRF is better; 90 gives 16)."""
    return int(round(51 - (quality / 100.0) * 39))


class VideoSink(FrameSink):
    """Encodes frames into ``path`` (.mp4 or .gif) at ``fps``."""

    def __init__(self, path: Path, fmt: str, fps: float, size: tuple, quality: int = 90):
        self.path = Path(path)
        self.fmt = fmt
        self.fps = fps
        self.size = tuple(size)
        # H.264 in yuv420p needs even sizes: odd frames get one edge row/column repeated
        # (never rescaled, so pixels stay where they were rendered)
        self.encoded_size = tuple(v + v % 2 for v in size) if fmt == "mp4" else self.size
        self.quality = quality
        self.frames = 0
        self._temp = self.path.with_name(f".{self.path.name}.partial{self.path.suffix}")
        self._writer = None

    def _open(self):
        try:
            import imageio_ffmpeg
        except ImportError:  # pragma: no cover - a declared dependency
            raise EnvironmentProblem("MP4/GIF output needs imageio-ffmpeg: pip install imageio-ffmpeg") from None
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if self.fmt == "mp4":
            params = dict(codec="libx264", pix_fmt_out="yuv420p", quality=None,
                          output_params=["-crf", str(_crf(self.quality)), "-preset", "medium",
                                         "-movflags", "+faststart"], macro_block_size=1)
        else:
            params = dict(codec="gif", pix_fmt_out="rgb8", quality=None,
                          output_params=["-filter_complex", GIF_FILTER, "-loop", "0"], macro_block_size=1)
        writer = imageio_ffmpeg.write_frames(str(self._temp), self.encoded_size, fps=self.fps,
                                             ffmpeg_log_level="error", **params)
        writer.send(None)  # start ffmpeg
        return writer

    def write(self, frame) -> None:
        if self._writer is None:
            self._writer = self._open()
        pixels = frame.pixels
        if pixels.shape[1] != self.size[0] or pixels.shape[0] != self.size[1]:
            raise ValueError(f"frame size {pixels.shape[1]}x{pixels.shape[0]} differs from the video's {self.size}")
        pad_h, pad_w = self.encoded_size[1] - pixels.shape[0], self.encoded_size[0] - pixels.shape[1]
        if pad_h or pad_w:
            pixels = np.pad(pixels, ((0, pad_h), (0, pad_w), (0, 0)), mode="edge")
        self._writer.send(np.ascontiguousarray(pixels))
        self.frames += 1

    def close(self) -> None:
        if self._writer is None:
            return
        self._writer.close()
        self._writer = None
        os.replace(self._temp, self.path)

    def abort(self) -> None:
        if self._writer is not None:
            try:
                self._writer.close()
            except Exception:  # ffmpeg may already be gone; the file is discarded anyway
                pass
            self._writer = None
        if self._temp.exists():
            self._temp.unlink()

    def describe(self) -> str:
        return str(self.path)
