"""What the comparison runners share: arguments, the PNG writer thread, the report line."""
from __future__ import annotations

import argparse
import json
import queue
import threading
import time
from pathlib import Path

STARTED = time.perf_counter()  # as early as the runner's imports allow


def parse_args(description: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--size", default="640x480", help="WxH")
    parser.add_argument("--samples", type=int, default=4, help="MSAA samples (1 = off)")
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--out", type=Path, help="write frame_NNNN.png here; without it, render only")
    args = parser.parse_args()
    args.width, args.height = (int(v) for v in args.size.lower().split("x"))
    return args


class PngWriter:
    """Encodes PNGs (zlib level 1) on one background thread while the next frame renders.

    write(index, pixels): pixels (H, W, 3) uint8, top row first.
    """

    def __init__(self, folder: Path):
        from PIL import Image

        self._image = Image
        self.folder = folder
        folder.mkdir(parents=True, exist_ok=True)
        self._queue: queue.Queue = queue.Queue(maxsize=4)
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while (item := self._queue.get()) is not None:
            index, pixels = item
            self._image.fromarray(pixels).save(self.folder / f"frame_{index:04d}.png", compress_level=1)

    def write(self, index: int, pixels) -> None:
        self._queue.put((index, pixels))

    def close(self) -> None:
        self._queue.put(None)
        self._thread.join()


def run_frames(args, render_frame) -> None:
    """Render args.frames frames with ``render_frame(i) -> (H, W, 3) uint8`` and print one
    JSON line: seconds to the first frame, steady frames/s (frames 1..N-1) and the total."""
    writer = PngWriter(args.out) if args.out else None
    first_done = None
    for i in range(args.frames):
        pixels = render_frame(i)
        if writer is not None:
            writer.write(i, pixels)
        if i == 0:
            first_done = time.perf_counter()
    if writer is not None:
        writer.close()
    ended = time.perf_counter()
    steady = (args.frames - 1) / (ended - first_done) if args.frames > 1 else 0.0
    print(json.dumps({"first_frame_s": first_done - STARTED, "fps": steady, "seconds": ended - STARTED}))
