"""Progress on stderr for multi-frame runs: a live bar on a terminal, a line every few
seconds in logs (CI), nothing with ``-q``."""
from __future__ import annotations

import sys
import time

from scenerender.gpu.gl_context import is_software


class Progress:
    """Counts frames; ``report`` prints at most every ``interval`` seconds when not a TTY."""

    def __init__(self, total: int, quiet: bool = False, stream=None, interval: float = 5.0):
        self.total = total
        self.done = 0
        self.silent = quiet  # -q: not even the renderer line
        self.quiet = quiet or total <= 1
        self.stream = stream or sys.stderr
        self.interval = interval
        self.started = time.perf_counter()
        self._last_report = self.started
        self._bar = None
        self._task = None
        if not self.quiet and getattr(self.stream, "isatty", lambda: False)():
            self._start_bar()

    def _start_bar(self) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            TextColumn,
            TimeRemainingColumn,
        )
        from rich.progress import Progress as Bar

        self._bar = Bar(TextColumn("rendering"), BarColumn(), MofNCompleteColumn(),
                        TextColumn("{task.fields[fps]:.1f} fps"), TimeRemainingColumn(),
                        console=Console(file=self.stream), transient=True)
        self._task = self._bar.add_task("frames", total=self.total, fps=0.0)
        self._bar.start()

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.started

    @property
    def fps(self) -> float:
        return self.done / self.elapsed if self.elapsed > 0 else 0.0

    def renderer(self, gl_renderer: str) -> None:
        """The first line of a run's progress, also of a one-frame run: which GL renderer
        draws, and whether that is the CPU (a driver that finds no GPU falls back to one
        without a word)."""
        if self.silent:
            return
        where = "software, on the CPU" if is_software(gl_renderer) else "on the GPU"
        line = f"GL renderer: {gl_renderer} ({where})"
        if self._bar is not None:
            self._bar.console.print(line, markup=False, highlight=False)
        else:
            print(line, file=self.stream, flush=True)

    def note(self, line: str) -> None:
        """A line about the run (a bake's time), also in a one-frame run."""
        if self.silent:
            return
        if self._bar is not None:
            self._bar.console.print(line, markup=False, highlight=False)
        else:
            print(line, file=self.stream, flush=True)

    def advance(self) -> None:
        self.done += 1
        if self.quiet:
            return
        if self._bar is not None:
            self._bar.update(self._task, advance=1, fps=self.fps)
            return
        now = time.perf_counter()
        if now - self._last_report >= self.interval and self.done < self.total:
            self._last_report = now
            remaining = (self.total - self.done) / self.fps if self.fps > 0 else 0.0
            print(f"frame {self.done}/{self.total} ({100 * self.done // self.total}%), "
                  f"{self.fps:.1f} fps, about {remaining:.0f} s left", file=self.stream, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.stop()
            self._bar = None
