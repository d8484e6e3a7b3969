"""Frame sinks (image sequences, video, the writer thread), frame ranges and image diffs.
No GL: every frame here is synthetic."""
from __future__ import annotations

import os
import threading
from dataclasses import dataclass

import numpy as np
import pytest
from PIL import Image

from scenerender.errors import UserError
from scenerender.run.output import make_sink
from scenerender.run.plan import parse_frame_range
from scenerender.sinks import ImageSequenceSink, ThreadedSink, VideoSink, frame_name_pattern
from scenerender.sinks import images as images_module

W, H = 32, 24


@dataclass
class Frame:
    index: int
    pixels: np.ndarray
    linear: np.ndarray


def make_frame(index: int, width: int = W, height: int = H) -> Frame:
    """A frame whose left half is green and whose red channel encodes the index."""
    pixels = np.zeros((height, width, 3), np.uint8)
    pixels[..., 0] = (index * 40) % 256
    pixels[:, : width // 2, 1] = 200
    pixels[height // 2:, :, 2] = 90
    return Frame(index, pixels, pixels.astype(np.float32) / 255.0)


def grey_frame(index: int, level: int) -> Frame:
    pixels = np.full((H, W, 3), level, np.uint8)
    return Frame(index, pixels, pixels.astype(np.float32) / 255.0)


def all_entries(folder) -> list[str]:
    """Every name in ``folder``, hidden temporaries included."""
    return sorted(os.listdir(folder)) if folder.exists() else []


# ---------------------------------------------------------------------------------------
# image sequences


def idat_payload(png: bytes) -> bytes:
    """The data of a PNG's single IDAT chunk."""
    start = png.index(b"IDAT")
    length = int.from_bytes(png[start - 4:start], "big")
    return png[start + 4:start + 4 + length]


def test_png_deflate_writes_the_bytes_of_zlib():
    """The encoder's deflate (zlib-ng) writes what Python's zlib writes at the same level
    and strategy, so PNG files are the bytes they were before it; another level or
    strategy would change them."""
    import zlib

    rng = np.random.default_rng(3)
    pixels = (rng.integers(0, 5, (48, 64, 3)) * 50).astype(np.uint8)
    pixels[:, 20:40] = 128  # runs, as flat areas of a frame give
    payload = idat_payload(images_module.encode_png(pixels))
    rows = zlib.decompress(payload)

    def deflated(level: int, strategy: int) -> bytes:
        deflate = zlib.compressobj(level, zlib.DEFLATED, 15, 9, strategy)
        return deflate.compress(rows) + deflate.flush()

    assert payload == deflated(1, zlib.Z_RLE)
    assert payload != deflated(1, zlib.Z_DEFAULT_STRATEGY)


@pytest.mark.parametrize("fmt", ["png", "tga"])
def test_lossless_sequence_reads_back_exactly(tmp_path, fmt):
    sink = ImageSequenceSink(tmp_path / "out", fmt, frame_name_pattern(None, 3))
    frames = [make_frame(i) for i in range(3)]
    for frame in frames:
        sink.write(frame)
    sink.close()
    assert all_entries(tmp_path / "out") == [f"frame_000{i}.{fmt}" for i in range(3)]
    assert sink.written == 3
    for frame in frames:
        with Image.open(sink.path_for(frame.index)) as image:
            assert image.size == (W, H)
            np.testing.assert_array_equal(np.asarray(image.convert("RGB")), frame.pixels)


def test_jpg_sequence_reads_back_close(tmp_path):
    sink = ImageSequenceSink(tmp_path, "jpg", "shot_{frame:03d}", quality=95)
    frame = make_frame(2)
    sink.write(frame)
    assert all_entries(tmp_path) == ["shot_002.jpg"]
    with Image.open(tmp_path / "shot_002.jpg") as image:
        assert image.format == "JPEG"
        assert image.size == (W, H)
        got = np.asarray(image.convert("RGB")).astype(int)
    assert np.abs(got - frame.pixels.astype(int)).mean() < 4


def test_exr_sequence_writes_linear_float(tmp_path):
    OpenEXR = pytest.importorskip("OpenEXR")
    sink = ImageSequenceSink(tmp_path, "exr", "frame_{frame:04d}")
    assert sink.needs_linear
    frame = make_frame(1)
    frame.linear[0, 0] = (2.5, 0.0, 0.125)  # HDR values survive
    sink.write(frame)
    assert all_entries(tmp_path) == ["frame_0001.exr"]
    with OpenEXR.File(str(tmp_path / "frame_0001.exr")) as exr:
        rgb = exr.channels()["RGB"].pixels
    assert rgb.shape == (H, W, 3)
    assert rgb.dtype == np.float32
    np.testing.assert_allclose(rgb, frame.linear)


def test_png_sequence_does_not_need_linear(tmp_path):
    assert not ImageSequenceSink(tmp_path, "png", "f{frame}").needs_linear


@pytest.mark.parametrize("count, expected", [
    (0, "frame_{frame:04d}"), (1, "frame_{frame:04d}"), (10000, "frame_{frame:04d}"),
    (10001, "frame_{frame:05d}"), (12000, "frame_{frame:05d}"), (1_000_001, "frame_{frame:07d}"),
])
def test_default_name_pattern_pads_to_frame_count(count, expected):
    assert frame_name_pattern(None, count) == expected


def test_default_names_sort_in_frame_order(tmp_path):
    pattern = frame_name_pattern(None, 12000)
    sink = ImageSequenceSink(tmp_path, "png", pattern)
    assert sink.path_for(0).name == "frame_00000.png"
    assert sink.path_for(11999).name == "frame_11999.png"
    names = [sink.path_for(i).name for i in (0, 7, 10, 999, 1000, 11999)]
    assert sorted(names) == names


def test_explicit_name_pattern_is_kept():
    assert frame_name_pattern("shot_{frame:02d}", 12000) == "shot_{frame:02d}"


def test_is_complete_after_write(tmp_path):
    sink = ImageSequenceSink(tmp_path, "png", "frame_{frame:04d}")
    assert not sink.is_complete(0)
    sink.write(make_frame(0))
    assert sink.is_complete(0)
    assert not sink.is_complete(1)


@pytest.mark.parametrize("fmt", ["png", "jpg", "tga", "exr"])
@pytest.mark.parametrize("content", [b"", b"garbage" * 40])
def test_is_complete_false_for_empty_or_garbage(tmp_path, fmt, content):
    sink = ImageSequenceSink(tmp_path, fmt, "frame_{frame:04d}")
    sink.path_for(3).write_bytes(content)
    assert not sink.is_complete(3)


def noisy_frame() -> Frame:
    pixels = np.random.default_rng(1).integers(0, 256, (48, 64, 3), dtype=np.uint8)
    return Frame(0, pixels, pixels.astype(np.float32) / 255.0)


@pytest.mark.parametrize("fmt", ["png", "exr"])
def test_is_complete_false_for_truncated_file(tmp_path, fmt):
    sink = ImageSequenceSink(tmp_path, fmt, "frame_{frame:04d}")
    sink.write(noisy_frame())
    path = sink.path_for(0)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    assert not sink.is_complete(0)


@pytest.mark.parametrize("fmt", ["jpg", "tga"])
def test_is_complete_false_for_truncated_jpg_and_tga(tmp_path, fmt):
    sink = ImageSequenceSink(tmp_path, fmt, "frame_{frame:04d}")
    sink.write(noisy_frame())
    path = sink.path_for(0)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    assert not sink.is_complete(0)


def test_failed_write_leaves_no_file(tmp_path, monkeypatch):
    def half_write(path, data):
        path.write_bytes(b"\x89PNG\r\n\x1a\n partial")
        raise OSError("disk full")

    monkeypatch.setattr(images_module, "write_file", half_write)
    sink = ImageSequenceSink(tmp_path / "out", "png", "frame_{frame:04d}")
    with pytest.raises(OSError, match="disk full"):
        sink.write(make_frame(0))
    assert all_entries(tmp_path / "out") == []
    assert not sink.is_complete(0)
    assert sink.written == 0


def test_failed_rewrite_keeps_the_old_complete_file(tmp_path, monkeypatch):
    sink = ImageSequenceSink(tmp_path, "png", "frame_{frame:04d}")
    sink.write(make_frame(0))
    before = sink.path_for(0).read_bytes()

    def half_write(path, data):
        path.write_bytes(b"junk")
        raise RuntimeError("encoder crashed")

    monkeypatch.setattr(images_module, "write_file", half_write)
    with pytest.raises(RuntimeError):
        sink.write(make_frame(0))
    assert all_entries(tmp_path) == ["frame_0000.png"]
    assert sink.path_for(0).read_bytes() == before


def test_failed_exr_write_leaves_no_file(tmp_path, monkeypatch):
    def half_write(path, data):
        path.write_bytes(b"v/1\x01 partial")
        raise OSError("boom")

    monkeypatch.setattr(images_module, "write_file", half_write)
    sink = ImageSequenceSink(tmp_path, "exr", "frame_{frame:04d}")
    with pytest.raises(OSError):
        sink.write(make_frame(0))
    assert all_entries(tmp_path) == []


# ---------------------------------------------------------------------------------------
# video


def read_mp4(path):
    imageio_ffmpeg = pytest.importorskip("imageio_ffmpeg")
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    width, height = meta["size"]
    frames = [np.frombuffer(raw, np.uint8).reshape(height, width, 3) for raw in reader]
    return (width, height), frames


def test_mp4_has_all_frames_and_size(tmp_path):
    levels = [20, 120, 220, 70, 170]
    sink = VideoSink(tmp_path / "v.mp4", "mp4", fps=10, size=(W, H))
    for i, level in enumerate(levels):
        sink.write(grey_frame(i, level))
    assert sink.frames == 5
    assert not (tmp_path / "v.mp4").exists()  # the file appears only when finished
    sink.close()
    assert all_entries(tmp_path) == ["v.mp4"]
    size, frames = read_mp4(tmp_path / "v.mp4")
    assert size == (W, H)
    assert len(frames) == 5
    means = [float(f.mean()) for f in frames]
    assert means == pytest.approx(levels, abs=6)


def test_gif_has_all_frames_and_size(tmp_path):
    from PIL import ImageSequence

    levels = [30, 200, 100]
    sink = VideoSink(tmp_path / "v.gif", "gif", fps=10, size=(W, H))
    for i, level in enumerate(levels):
        sink.write(grey_frame(i, level))
    sink.close()
    assert all_entries(tmp_path) == ["v.gif"]
    with Image.open(tmp_path / "v.gif") as image:
        assert image.format == "GIF"
        assert image.size == (W, H)
        frames = [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(image)]
    assert len(frames) == 3
    assert [float(f.mean()) for f in frames] == pytest.approx(levels, abs=6)


@pytest.mark.parametrize("fmt", ["mp4", "gif"])
def test_video_abort_leaves_no_file(tmp_path, fmt):
    sink = VideoSink(tmp_path / f"v.{fmt}", fmt, fps=10, size=(W, H))
    sink.write(make_frame(0))
    sink.write(make_frame(1))
    sink.abort()
    assert all_entries(tmp_path) == []


def test_video_abort_before_any_frame(tmp_path):
    sink = VideoSink(tmp_path / "v.mp4", "mp4", fps=10, size=(W, H))
    sink.abort()
    sink.close()
    assert all_entries(tmp_path) == []


def test_video_rejects_frame_of_other_size(tmp_path):
    sink = VideoSink(tmp_path / "v.mp4", "mp4", fps=10, size=(W, H))
    try:
        with pytest.raises(ValueError, match="differs"):
            sink.write(make_frame(0, width=W + 2))
    finally:
        sink.abort()
    assert not (tmp_path / "v.mp4").exists()


# ---------------------------------------------------------------------------------------
# the writer thread


class RecordingSink:
    needs_linear = False

    def __init__(self, fail_at=None):
        self.indices = []
        self.closed = False
        self.aborted = False
        self.fail_at = fail_at
        self.threads = set()

    def write(self, frame):
        self.threads.add(threading.get_ident())
        if frame.index == self.fail_at:
            raise RuntimeError(f"cannot write frame {frame.index}")
        self.indices.append(frame.index)

    def close(self):
        self.closed = True

    def abort(self):
        self.aborted = True

    def describe(self):
        return "recording"


def test_threaded_sink_writes_in_order_on_another_thread():
    inner = RecordingSink()
    sink = ThreadedSink(inner, depth=2)
    for i in range(10):
        sink.write(make_frame(i))
    sink.close()
    assert inner.indices == list(range(10))
    assert inner.closed
    assert threading.get_ident() not in inner.threads
    assert sink.describe() == "recording"


def test_threaded_sink_error_surfaces_on_close():
    inner = RecordingSink(fail_at=1)
    sink = ThreadedSink(inner)
    sink.write(make_frame(0))
    sink.write(make_frame(1))  # fails on the worker thread
    with pytest.raises(RuntimeError, match="cannot write frame 1"):
        sink.close()
    assert inner.indices == [0]
    assert not inner.closed


def test_threaded_sink_abort():
    inner = RecordingSink()
    sink = ThreadedSink(inner)
    sink.write(make_frame(0))
    sink.abort()
    assert inner.aborted
    assert not inner.closed


def test_threaded_sink_keeps_needs_linear(tmp_path):
    sink = ThreadedSink(ImageSequenceSink(tmp_path, "exr", "f{frame}"))
    try:
        assert sink.needs_linear
    finally:
        sink.close()


# ---------------------------------------------------------------------------------------
# frame ranges and sink choice


@pytest.mark.parametrize("text, expected", [
    (None, list(range(30))),
    ("10:20", list(range(10, 20))),
    ("5", [5]),
    ("0", [0]),
    ("-1", [29]),
    ("-2", [28]),
    (":3", [0, 1, 2]),
    ("-2:", [28, 29]),
    ("27:", [27, 28, 29]),
    ("25:100", [25, 26, 27, 28, 29]),
    ("0:10:4", [0, 4, 8]),
    (" 2 : 4 ", [2, 3]),
])
def test_parse_frame_range(text, expected):
    assert list(parse_frame_range(text, 30)) == expected


@pytest.mark.parametrize("text", ["5:3", "30", "-31", "40:50", "0:0", "a:b", "1:2:3:4", "0:10:0", "0:10:-1",
                                  "x", ""])
def test_parse_frame_range_rejects(text):
    with pytest.raises(UserError) as info:
        parse_frame_range(text, 30)
    assert str(info.value).startswith("--frames: ")


def test_parse_frame_range_out_of_range_names_the_frames():
    with pytest.raises(UserError, match=r"frames 0\.\.29"):
        parse_frame_range("30", 30)


def loaded_scene(tmp_path, output="", name="shot.yaml"):
    from scenerender.scene.loading import load_scene_text

    text = "objects: [{mesh: {primitive: box}}]\n" + (f"output: {output}\n" if output else "")
    return load_scene_text(text, base_dir=tmp_path, name=name)


def test_make_sink_image_sequence(tmp_path):
    sink = make_sink(loaded_scene(tmp_path, "{frames: 12000, format: jpg, quality: 70}"), "jpg",
                     tmp_path / "out", (W, H))
    assert isinstance(sink, ImageSequenceSink)
    assert sink.path_for(3) == tmp_path / "out" / "frame_00003.jpg"
    assert sink.quality == 70


def test_make_sink_video_in_folder_and_as_file(tmp_path):
    loaded = loaded_scene(tmp_path, "{format: mp4, fps: 24}")
    in_folder = make_sink(loaded, "mp4", tmp_path / "out", (W, H))
    assert isinstance(in_folder, VideoSink)
    assert in_folder.path == tmp_path / "out" / "shot.mp4"
    assert in_folder.fps == 24.0
    as_file = make_sink(loaded, "mp4", tmp_path / "movie.mp4", (W, H))
    assert as_file.path == tmp_path / "movie.mp4"
