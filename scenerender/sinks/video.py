"""Videos: MP4 (H.264) and GIF, streamed frame by frame to an ffmpeg process (the binary
imageio-ffmpeg ships), so a long flythrough never sits in memory. The file appears only
when the video is finished: ffmpeg writes a temporary file, and it is renamed into place
only when ffmpeg exited 0, said nothing alarming, and the container is whole. A full disk
or a read-only folder is a UserError naming the video; the temporary file is removed.
"""
from __future__ import annotations

import collections
import contextlib
import errno
import os
import subprocess
import threading
from fractions import Fraction
from pathlib import Path

import numpy as np

from scenerender.errors import EnvironmentProblem, display_path
from scenerender.sinks.base import (
    FrameSink,
    create_temp,
    make_folders,
    output_errors,
    write_failure,
)

# GIF: a palette per frame (ffmpeg palettegen + paletteuse) looks far better than the
# fixed web palette, and works on a stream because each frame needs only itself.
GIF_FILTER = "split[a][b];[a]palettegen=stats_mode=single:reserve_transparent=0[p];[b][p]paletteuse=new=1"

# What ffmpeg prints for the failures a user can act on (it reports strerror texts).
_FFMPEG_ERRNOS = {os.strerror(code): code for code in
                  (errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EACCES, errno.EPERM, errno.ENAMETOOLONG)}
_STDERR_LINES_KEPT = 20


# x264 preset, by measurement (the showcase's 120 frames at 640x480, CRF 16; CPU the
# better of two runs, PSNR over RGB against the frames):
#   medium 5.18 s, 1520 KB, 39.45 dB;  faster 2.73 s, 1523 KB, 39.27 dB;
#   veryfast 1.84 s, 1565 KB, 39.05 dB;  superfast 1.18 s but 2492 KB.
# ffmpeg shares the machine with the renderer, so its CPU time is the renderer's loss (on
# two cores "faster" took 9 % of a showcase run's CPU): "veryfast" costs a third less than
# "faster" for a file 3 % larger and 0.2 dB.
X264_PRESET = "veryfast"


def _crf(quality: int) -> int:
    """quality 1..100 -> x264 CRF 51..12 (lower CRF is better; 90 gives 16)."""
    return int(round(51 - (quality / 100.0) * 39))


def ffmpeg_exe() -> str:
    try:
        import imageio_ffmpeg
    except ImportError:  # pragma: no cover - a declared dependency
        raise EnvironmentProblem("MP4/GIF output needs imageio-ffmpeg: pip install imageio-ffmpeg") from None
    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError as exc:
        raise EnvironmentProblem(f"MP4/GIF output needs ffmpeg: {exc}") from None


class FfmpegProcess:
    """One ffmpeg encoding raw RGB frames from its stdin (into a temporary file for the
    video ``final``, which errors name). Its stderr is
    drained on a thread (a full pipe would stall ffmpeg) keeping the last lines for the
    error message. ffmpeg runs in its own session: a Ctrl-C on the terminal reaches only
    scenerender, which then stops ffmpeg and removes the file itself."""

    def __init__(self, command: list[str], final: Path):
        self.final = final
        self.stderr_tail: collections.deque = collections.deque(maxlen=_STDERR_LINES_KEPT)
        try:
            self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL,
                                            stderr=subprocess.PIPE, start_new_session=True)
        except OSError as exc:
            raise EnvironmentProblem(f"cannot start ffmpeg ({command[0]}): {exc.strerror}") from None
        self._drain = threading.Thread(target=self._read_stderr, name="ffmpeg-stderr", daemon=True)
        self._drain.start()

    def _read_stderr(self) -> None:
        for raw in self.process.stderr:
            line = raw.decode("utf-8", "replace").strip()
            if line:
                self.stderr_tail.append(line)

    def send(self, data) -> None:
        try:
            self.process.stdin.write(data)
        except OSError:  # a broken pipe: ffmpeg is gone; its exit status says why
            stdin, self.process.stdin = self.process.stdin, None
            with contextlib.suppress(OSError):
                stdin.close()
            raise self._failure(self._wait()) from None

    def finish(self) -> None:
        """Close ffmpeg's input and wait; raise when it failed."""
        with contextlib.suppress(OSError):
            if self.process.stdin is not None:
                self.process.stdin.close()
        returncode = self._wait()
        # some ffmpeg versions exit 0 after failing to write the trailer: a reported
        # write error fails the video whatever the exit status
        if returncode != 0 or self._reported_errno() is not None:
            raise self._failure(returncode)

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
        with contextlib.suppress(OSError):
            if self.process.stdin is not None:
                self.process.stdin.close()
        self._wait()

    def _wait(self) -> int:
        returncode = self.process.wait()
        self._drain.join()
        self.process.stderr.close()
        return returncode

    def _reported_errno(self) -> int | None:
        """The errno of a write failure ffmpeg reported on stderr (by its strerror text)."""
        said = "\n".join(self.stderr_tail).lower()
        return next((code for text, code in _FFMPEG_ERRNOS.items() if text.lower() in said), None)

    def _failure(self, returncode: int) -> Exception:
        """A UserError for a failure the user can act on (disk full, read-only...), else
        an EnvironmentProblem with ffmpeg's last words."""
        code = self._reported_errno()
        if code is not None:
            return write_failure(self.final, code)
        last = self.stderr_tail[-1] if self.stderr_tail else "no message"
        return EnvironmentProblem(f"{display_path(self.final)}: ffmpeg failed (exit status {returncode}): {last}")


class VideoSink(FrameSink):
    """Encodes frames into ``path`` (.mp4 or .gif) at ``fps``."""

    def __init__(self, path: Path, fmt: str, fps: float, size: tuple, quality: int = 90):
        self.path = self.target = Path(path)
        self.fmt = fmt
        self.fps = fps
        self.size = tuple(size)
        # H.264 in yuv420p needs even sizes: odd frames get one edge row/column repeated
        # (never rescaled, so pixels stay where they were rendered)
        self.encoded_size = tuple(v + v % 2 for v in size) if fmt == "mp4" else self.size
        self.quality = quality
        self.frames = 0
        self._temp: Path | None = None
        self._ffmpeg: FfmpegProcess | None = None

    def command(self, temp: Path) -> list[str]:
        """The ffmpeg command line encoding raw rgb24 frames from stdin into ``temp``."""
        fps = Fraction(self.fps).limit_denominator()
        width, height = self.encoded_size
        if self.fmt == "mp4":
            encode = ["-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", str(_crf(self.quality)),
                      "-preset", X264_PRESET, "-movflags", "+faststart", "-f", "mp4"]
        else:
            encode = ["-filter_complex", GIF_FILTER, "-c:v", "gif", "-loop", "0", "-f", "gif"]
        return [ffmpeg_exe(), "-nostdin", "-hide_banner", "-loglevel", "error", "-y",
                "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}", "-r", str(fps), "-i", "pipe:0",
                *encode, str(temp)]

    def _open(self) -> None:
        with output_errors(self.path):
            make_folders(self.path.parent)
            # reserve the temporary name (and find out early whether the folder is
            # writable); ffmpeg then writes over this empty file
            self._temp = create_temp(self.path)
        self._ffmpeg = FfmpegProcess(self.command(self._temp), self.path)

    def write(self, frame) -> None:
        pixels = frame.pixels
        if pixels.shape[1] != self.size[0] or pixels.shape[0] != self.size[1]:
            raise ValueError(f"frame size {pixels.shape[1]}x{pixels.shape[0]} differs from the video's {self.size}")
        if self._ffmpeg is None:
            self._open()
        pad_h, pad_w = self.encoded_size[1] - pixels.shape[0], self.encoded_size[0] - pixels.shape[1]
        if pad_h or pad_w:
            pixels = np.pad(pixels, ((0, pad_h), (0, pad_w), (0, 0)), mode="edge")
        try:
            self._ffmpeg.send(np.ascontiguousarray(pixels, dtype=np.uint8))
        except BaseException:
            self.abort()
            raise
        self.frames += 1

    def is_complete(self, index: int = 0) -> bool:
        """True when the video file exists whole (every frame is in it, or none is)."""
        return self.path.is_file() and container_is_whole(self.path, self.fmt)

    def close(self) -> None:
        if self._ffmpeg is None:
            return
        try:
            self._ffmpeg.finish()
            if not container_is_whole(self._temp, self.fmt):
                raise EnvironmentProblem(f"{display_path(self.path)}: ffmpeg exited 0 but the {self.fmt.upper()} "
                                         "it wrote is incomplete")
            with output_errors(self.path):
                os.replace(self._temp, self.path)
        except BaseException:
            self.abort()
            raise
        self._ffmpeg = None
        self._temp = None

    def abort(self) -> None:
        if self._ffmpeg is not None:
            self._ffmpeg.kill()
            self._ffmpeg = None
        if self._temp is not None:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(self._temp)
            self._temp = None

    def describe(self) -> str:
        return str(self.path)


def container_is_whole(path: Path, fmt: str) -> bool:
    """A cheap structural check that ffmpeg finished ``path``: an MP4's top-level boxes
    span the file exactly and include 'moov' (the index, written last; a cut-off file
    lacks it: "moov atom not found"); a GIF ends with its trailer byte."""
    try:
        with open(path, "rb") as handle:
            if fmt == "gif":
                handle.seek(0, os.SEEK_END)
                if handle.tell() < 14:
                    return False
                handle.seek(-1, os.SEEK_END)
                return handle.read(1) == b";"
            return _mp4_has_index(handle)
    except OSError:
        return False


def _mp4_has_index(handle) -> bool:
    size = os.fstat(handle.fileno()).st_size
    offset, seen = 0, set()
    while offset < size:
        handle.seek(offset)
        header = handle.read(8)
        if len(header) < 8:
            return False
        length, kind = int.from_bytes(header[:4], "big"), header[4:8]
        if length == 1:  # a 64-bit size follows
            extended = handle.read(8)
            if len(extended) < 8:
                return False
            length = int.from_bytes(extended, "big")
        elif length == 0:  # the box runs to the end of the file
            length = size - offset
        if length < 8 or offset + length > size:
            return False
        seen.add(kind)
        offset += length
    return b"moov" in seen and b"mdat" in seen

