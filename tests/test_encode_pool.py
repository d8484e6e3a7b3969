"""The encoder pool of ThreadedSink: frames encoded on several threads, written whole,
in order, by one writer; errors come back to the caller with their class."""
from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np
import pytest
from PIL import Image

from scenerender.sinks import ImageSequenceSink, ThreadedSink
from scenerender.sinks.threaded import encode_workers, find_encoder


@dataclass
class Frame:
    index: int
    pixels: np.ndarray
    linear: np.ndarray | None = None


def frame(index: int) -> Frame:
    pixels = np.zeros((24, 32, 3), np.uint8)
    pixels[..., 0] = index
    pixels[:, :16, 1] = 200
    return Frame(index, pixels)


class EncodingSink:
    """Encodes on any thread (records which), writes on one (records the order)."""

    needs_linear = False

    def __init__(self, fail_at=None, gate: threading.Event | None = None):
        self.fail_at, self.gate = fail_at, gate
        self.encoder_threads, self.writer_threads = set(), set()
        self.written, self.encoded = [], []
        self.closed = self.aborted = False

    def encode_frame(self, frame):
        if self.gate is not None:
            self.gate.wait(10)
        self.encoder_threads.add(threading.get_ident())
        self.encoded.append(frame.index)
        if frame.index == self.fail_at:
            raise KeyError(f"cannot encode frame {frame.index}")
        return b"%d" % frame.index

    def write(self, frame):
        self.writer_threads.add(threading.get_ident())
        assert frame.encoded == b"%d" % frame.index
        self.written.append(frame.index)

    def close(self):
        self.closed = True

    def abort(self):
        self.aborted = True


@pytest.mark.parametrize("cores, expected", [(1, 1), (2, 1), (3, 2), (5, 4), (64, 4)])
def test_encoder_count_leaves_a_core_to_the_renderer(cores, expected):
    assert encode_workers(cores) == expected


def test_pool_encodes_on_several_threads_and_writes_in_order_on_one():
    inner = EncodingSink()
    sink = ThreadedSink(inner, encoders=3)
    for i in range(40):
        sink.write(frame(i))
    sink.close()
    assert inner.written == list(range(40)) and inner.closed
    assert len(inner.writer_threads) == 1
    assert threading.get_ident() not in inner.encoder_threads | inner.writer_threads


def test_an_encoding_error_resurfaces_with_its_class_and_stops_writing():
    inner = EncodingSink(fail_at=3)
    sink = ThreadedSink(inner, encoders=2)
    with pytest.raises(KeyError, match="cannot encode frame 3"):
        for i in range(20):
            sink.write(frame(i))
        sink.close()
    sink.abort()
    assert inner.written == [0, 1, 2]  # nothing after the failed frame
    assert inner.aborted and not inner.closed


def test_queue_is_bounded_while_encoders_are_stuck():
    gate = threading.Event()
    inner = EncodingSink(gate=gate)
    sink = ThreadedSink(inner, depth=3, encoders=2)
    submitted = []

    def producer():
        for i in range(50):
            sink.write(frame(i))
            submitted.append(i)

    thread = threading.Thread(target=producer, daemon=True)
    thread.start()
    thread.join(0.5)  # the producer must be held back by the full queue
    held_back = len(submitted)
    gate.set()
    thread.join(10)
    sink.close()
    assert held_back <= 3 + 2 + 1  # queued + in the writer's hand + one being put
    assert inner.written == list(range(50))


def test_sink_without_encoder_gets_the_writer_thread_only():
    class Video:
        needs_linear = False

        def __init__(self):
            self.written = []

        def write(self, frame):
            assert not hasattr(frame, "encoded")
            self.written.append(frame.index)

        def close(self):
            pass

    inner = Video()
    sink = ThreadedSink(inner, encoders=4)
    for i in range(10):
        sink.write(frame(i))
    sink.close()
    assert sink.encoders == 0 and inner.written == list(range(10))


def test_encoder_found_through_a_wrapping_sink(tmp_path):
    images = ImageSequenceSink(tmp_path, "png", "f{frame:03d}")

    class Wrapper:  # as the manifest's recording sink wraps the image sink
        needs_linear = False

        def __init__(self, sink):
            self.sink = sink

        def write(self, frame):
            self.sink.write(frame)

        def close(self):
            self.sink.close()

    assert find_encoder(Wrapper(images)) == images.encode_frame
    sink = ThreadedSink(Wrapper(images), encoders=3)
    frames = [frame(i) for i in range(12)]
    for f in frames:
        sink.write(f)
    sink.close()
    for f in frames:
        with Image.open(images.path_for(f.index)) as image:
            assert np.array_equal(np.asarray(image), f.pixels)
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"f{i:03d}.png" for i in range(12)]
