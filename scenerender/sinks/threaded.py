"""Encode frames on a small thread pool while the next frame renders.

Compression (zlib-ng's deflate for PNG, Pillow's encoders for JPG and TGA) and ffmpeg
piping release the GIL, so encoder threads run beside the renderer. Image sequences get
a pool of ``encode_workers()`` encoder threads; the encoded bytes are then written, in
frame order, by one writer thread, so the wrapped sink (and the manifest recording behind
it) is only ever called from one thread. Sinks that cannot encode ahead (a video, fed
strictly in order) get the writer thread alone. A bounded queue keeps memory flat
whatever the frame count.
"""
from __future__ import annotations

import queue
import threading
from concurrent.futures import Future, ThreadPoolExecutor

from scenerender.machine import available_cores

_STOP = object()
MAX_ENCODERS = 4  # beyond this PNG encoding stops being the bottleneck (see docs/performance.md)


def encode_workers(cores: int | None = None) -> int:
    """Encoder threads for ``cores`` cores: one core is left to the renderer, at least one
    encoder and at most MAX_ENCODERS."""
    cores = available_cores() if cores is None else cores
    return max(1, min(cores - 1, MAX_ENCODERS))


def find_encoder(sink):
    """The ``encode_frame`` of ``sink`` or of a sink it wraps (its ``.sink``), or None.
    A sink with ``encode_frame`` accepts frames carrying ready bytes in ``encoded``."""
    seen = 0
    while sink is not None and seen < 8:  # wrappers are shallow; the bound guards cycles
        encode = getattr(sink, "encode_frame", None)
        if callable(encode):
            return encode
        sink, seen = getattr(sink, "sink", None), seen + 1
    return None


class EncodedFrame:
    """A frame plus its encoded file bytes (``encoded``); reads every other attribute
    (``index``, ``pixels``, ``linear``) from the frame."""

    def __init__(self, frame, encoded: bytes):
        self._frame = frame
        self.encoded = encoded

    def __getattr__(self, name):
        return getattr(self._frame, name)


def _done(value) -> Future:
    future: Future = Future()
    future.set_result(value)
    return future


class ThreadedSink:
    """Wraps a FrameSink: ``write`` queues, worker threads encode and write. An error of
    a worker resurfaces, as the same exception object, on the next ``write`` or on
    ``close``; nothing is written after a failed frame. ``abort`` drops the frames still
    queued, waits for the frame being written (so it is whole or removed) and stops.

    ``encoders``: encoder threads (default ``encode_workers()``), used only when the sink
    can encode ahead (``find_encoder``). ``depth``: frames queued at most."""

    def __init__(self, sink, depth: int | None = None, encoders: int | None = None):
        self.sink = sink
        self.needs_linear = sink.needs_linear
        self._encode = find_encoder(sink)
        self.encoders = (encoders or encode_workers()) if self._encode is not None else 0
        self._pool = ThreadPoolExecutor(self.encoders, "frame-encoder") if self.encoders else None
        # each encoder has one frame in hand and one waiting, plus the one being written
        depth = depth if depth is not None else 2 * max(self.encoders, 1) + 1
        self._queue: queue.Queue = queue.Queue(maxsize=depth)
        self._error: BaseException | None = None
        self._abandoned = False  # set by abort or a failure: queued frames are dropped
        self._thread = threading.Thread(target=self._run, name="frame-writer", daemon=True)
        self._thread.start()

    def _encoded(self, frame):
        if self._abandoned:
            return None
        return EncodedFrame(frame, self._encode(frame))

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is _STOP:
                return
            if self._abandoned:
                continue
            try:
                frame = item.result()  # in frame order, though encoders may finish in any
                if frame is not None:  # None: encoded after an abort, dropped
                    self.sink.write(frame)
            except BaseException as exc:  # handed to the main thread
                self._error = exc
                self._abandoned = True  # never write past a failed frame

    def _raise_if_failed(self) -> None:
        if self._error is not None:
            error, self._error = self._error, None
            raise error

    def write(self, frame) -> None:
        self._raise_if_failed()
        item = self._pool.submit(self._encoded, frame) if self._pool is not None else _done(frame)
        self._queue.put(item)

    def close(self) -> None:
        self._queue.put(_STOP)
        self._thread.join()
        self._shutdown_pool()
        self._raise_if_failed()
        self.sink.close()

    def abort(self) -> None:
        self._abandoned = True
        while True:  # empty the queue so that putting _STOP never waits on a full one
            try:
                item = self._queue.get_nowait()
            except queue.Empty:
                break
            if item is not _STOP:
                item.cancel()
        self._queue.put(_STOP)
        self._thread.join()
        self._shutdown_pool()
        self.sink.abort()

    def _shutdown_pool(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)

    def is_complete(self, index: int) -> bool:
        return self.sink.is_complete(index)

    def describe(self) -> str:
        return self.sink.describe()
