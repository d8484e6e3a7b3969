"""Sees the scene file and every asset it read saved, with watchfiles (inotify and its
peers through the Rust notify crate; no polling by hand).

The folders holding the files are watched, not the files: an editor that saves by writing
a new file and renaming it over the old one replaces the watched file, and a watch on it
would see nothing after the first save.
"""
from __future__ import annotations

import threading
import time
from pathlib import Path

import watchfiles

# watchfiles hands over a batch of changes once none came for STEP_MS (a save is several
# writes in a few ms), and at the latest after DEBOUNCE_MS.
STEP_MS = 20
DEBOUNCE_MS = 400
# Saves closer together than this are one burst (a save-all, a formatter writing after the
# editor, a script): the first renders at once, the rest once, after the burst.
BURST_SECONDS = 0.15


class SceneWatcher:
    """Calls ``on_change(paths)`` (a set of Path) on its own thread when files in ``files``
    change; ``watch(files)`` replaces the set (the scene may name other assets after a save)."""

    def __init__(self, files, on_change):
        self.on_change = on_change
        self._files = frozenset(Path(f).resolve() for f in files)
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._restart = threading.Event()  # set when the folders to watch changed
        self._thread = threading.Thread(target=self._run, name="scenerender-preview-watch", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        self._restart.set()
        if self._thread.is_alive():
            self._thread.join()

    def watch(self, files) -> None:
        files = frozenset(Path(f).resolve() for f in files)
        with self._lock:
            if files == self._files:
                return
            folders_changed = _folders(files) != _folders(self._files)
            self._files = files
        if folders_changed:
            self._restart.set()

    def _run(self) -> None:
        while not self._stop.is_set():
            with self._lock:
                folders = sorted(str(folder) for folder in _folders(self._files) if folder.is_dir())
            self._restart.clear()
            if not folders:
                self._stop.wait(0.5)
                continue
            for changes in watchfiles.watch(*folders, watch_filter=self._wanted, stop_event=self._restart,
                                            step=STEP_MS, debounce=DEBOUNCE_MS, yield_on_timeout=False,
                                            rust_timeout=500, raise_interrupt=False):
                self.on_change({Path(path) for _, path in changes})

    def _wanted(self, change, path: str) -> bool:
        with self._lock:
            return Path(path) in self._files


def _folders(files) -> set[Path]:
    return {path.parent for path in files}


class SaveThrottle:
    """Turns saves into at most two renders a burst: ``fire()`` at once for a save after a
    quiet spell (no waiting added to a single save), and once more BURST_SECONDS after the
    last of the saves that followed it within BURST_SECONDS of each other."""

    def __init__(self, fire, burst_seconds: float = BURST_SECONDS):
        self.fire = fire
        self.burst_seconds = burst_seconds
        self._lock = threading.Lock()
        self._last_save = -float("inf")
        self._timer: threading.Timer | None = None
        self._armed: object | None = None
        self._stopped = False

    def saved(self) -> None:
        now = time.monotonic()
        with self._lock:
            if self._stopped:
                return
            in_burst = now - self._last_save < self.burst_seconds or self._timer is not None
            self._last_save = now
            if in_burst:
                self._arm()
                return
        self.fire()

    def stop(self) -> None:
        with self._lock:
            self._stopped = True
            timer, self._timer = self._timer, None
        if timer is not None:
            timer.cancel()

    def _arm(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
        self._armed = token = object()  # a timer that fires after another was armed does nothing
        self._timer = threading.Timer(self.burst_seconds, self._burst_over, args=(token,))
        self._timer.daemon = True
        self._timer.start()

    def _burst_over(self, token) -> None:
        with self._lock:
            if self._stopped or self._armed is not token:
                return
            self._timer = self._armed = None
        self.fire()
