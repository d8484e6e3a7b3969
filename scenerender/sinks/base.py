"""The sink interface and the write-whole-or-nothing helper."""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path


class FrameSink:
    """Receives frames in order. ``write`` takes a ``render.renderer.FrameResult``-like
    object with ``index``, ``pixels`` ((H, W, 3) uint8) and ``linear`` ((H, W, 3) float32
    or None). ``close`` finishes the output; ``abort`` discards anything unfinished."""

    needs_linear = False

    def write(self, frame) -> None:  # pragma: no cover - interface
        raise NotImplementedError

    def close(self) -> None:
        """Finish: after this every output file is complete."""

    def abort(self) -> None:
        """Stop after an error: leave no partial file behind."""

    def describe(self) -> str:
        return ""


@contextlib.contextmanager
def atomic_path(final: Path):
    """Yield a temporary path beside ``final``; rename it to ``final`` only on success."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    handle, temp_name = tempfile.mkstemp(prefix=f".{final.name}.", suffix=".partial" + final.suffix,
                                         dir=final.parent)
    os.close(handle)
    temp = Path(temp_name)
    try:
        yield temp
        os.replace(temp, final)
    finally:
        if temp.exists():
            temp.unlink()
