"""Encode on a worker thread while the next frame renders.

PNG compression and ffmpeg piping release the GIL, so with two cores the encoder of frame
i runs beside the rendering of frame i + 1. A small bounded queue keeps memory flat.
"""
from __future__ import annotations

import queue
import threading

_STOP = object()


class ThreadedSink:
    """Wraps a FrameSink: ``write`` queues, a worker thread writes. Errors resurface on the
    next ``write`` or on ``close``."""

    def __init__(self, sink, depth: int = 3):
        self.sink = sink
        self.needs_linear = sink.needs_linear
        self._queue: queue.Queue = queue.Queue(maxsize=depth)
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._run, name="frame-writer", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while True:
            frame = self._queue.get()
            if frame is _STOP:
                return
            if self._error is None:
                try:
                    self.sink.write(frame)
                except BaseException as exc:  # handed to the main thread
                    self._error = exc

    def _raise_if_failed(self) -> None:
        if self._error is not None:
            error, self._error = self._error, None
            raise error

    def write(self, frame) -> None:
        self._raise_if_failed()
        self._queue.put(frame)

    def close(self) -> None:
        self._queue.put(_STOP)
        self._thread.join()
        self._raise_if_failed()
        self.sink.close()

    def abort(self) -> None:
        self._queue.put(_STOP)
        self._thread.join()
        self.sink.abort()

    def describe(self) -> str:
        return self.sink.describe()
