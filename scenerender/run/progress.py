"""Progress on stderr for multi-frame runs: a live bar on a terminal, a line every few
seconds in logs (CI), nothing with ``-q``."""
from __future__ import annotations

import sys
import time

from scenerender.gpu.gl_context import is_software

# Long work (rendering.steps) whose first second's pace says it takes this long or more
# says so, with its estimate, then how much is left every ``interval`` seconds.
LONG_WORK_SECONDS = 5.0
ESTIMATE_AFTER_SECONDS = 1.0  # its pace measured over this much work (the first draw compiles the shader)


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
        self._work = None  # the long work under way: [what, started, told, last line's time]
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
        self._line(f"GL renderer: {gl_renderer} ({where})")

    def work(self, what: str, fraction: float) -> None:
        """Long work ``what`` has ``fraction`` (0 at its start, 1 at its end) done. Work
        that its pace says takes LONG_WORK_SECONDS or more says so once with its estimate,
        then its share done and time left every ``interval`` seconds; also in a one-frame
        run (a prefilter can take minutes before the only frame)."""
        if self.silent:
            return
        now = time.perf_counter()
        if self._work is None or self._work[0] != what or fraction <= 0.0:
            self._work = [what, now, False, now]
            return
        _, started, told, last = self._work
        elapsed = now - started
        if fraction >= 1.0 or elapsed < ESTIMATE_AFTER_SECONDS:
            return
        left = elapsed * (1.0 - fraction) / fraction
        if not told and elapsed + left >= LONG_WORK_SECONDS:
            self._line(f"{what}: about {elapsed + left:.0f} s on this renderer")
            self._work[2:] = [True, now]
        elif told and now - last >= self.interval:
            self._line(f"{what}: {100 * fraction:.0f}% done, about {left:.0f} s left")
            self._work[3] = now

    def _line(self, line: str) -> None:
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
