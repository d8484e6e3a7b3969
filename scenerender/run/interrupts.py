"""SIGINT, SIGTERM and SIGHUP during a render: turned into an exception in the main
thread, so the render stops the way it stops on any error (the writer thread finishes or
discards its frame, the video's temporary file is removed) and the command exits with
128 + the signal number and one line, instead of dying with partial files behind.
"""
from __future__ import annotations

import contextlib
import signal
import threading

HANDLED = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


class Interrupted(KeyboardInterrupt):
    """A render stopped by a signal. A KeyboardInterrupt, so code that cleans up on
    Ctrl-C cleans up on SIGTERM and SIGHUP too."""

    def __init__(self, signum: int):
        self.signum = signum
        self.signal_name = signal.Signals(signum).name
        self.exit_code = 128 + signum
        super().__init__(f"interrupted by {self.signal_name}")

    def __reduce__(self):
        # a worker's chunk stopped by a signal comes back to the parent pickled
        return Interrupted, (self.signum,)


def _ours_to_replace(signum: int) -> bool:
    """Only default dispositions are replaced: a signal the program running us ignores
    (SIGHUP under nohup, SIGINT of a background job) stays ignored, and a handler
    someone else installed stays theirs."""
    current = signal.getsignal(signum)
    return current is signal.SIG_DFL or current is signal.default_int_handler


@contextlib.contextmanager
def signals_as_exceptions(signals=HANDLED):
    """While the block runs, the first of ``signals`` raises ``Interrupted`` in the main
    thread; later ones are ignored so the cleanup it starts runs to its end. Does
    nothing outside the main thread (Python delivers signals only there)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    raised = False

    def handler(signum, _frame):
        nonlocal raised
        if not raised:
            raised = True
            raise Interrupted(signum)

    previous = {}
    try:
        for signum in signals:
            if _ours_to_replace(signum):
                previous[signum] = signal.signal(signum, handler)
        yield
    finally:
        for signum, old in previous.items():
            signal.signal(signum, old)


# A pool worker's signal state (``worker_signals``): whether a chunk is rendering, and the
# signal that stopped one (then every later chunk of the run stops at once too).
_worker = {"busy": False, "stopped_by": None}


def worker_signals() -> None:
    """A worker process's initializer (run/workers.py): for its whole life, a signal the
    parent passes on raises Interrupted while a chunk renders (``interruptible_chunk``), so
    the chunk stops within a step and leaves nothing partial, and is ignored while the
    worker waits for a chunk: the pool's shutdown then ends it, where a worker killed while
    idle would break the pool (the parent would then wait on the busy one for ever)."""
    for signum in HANDLED:
        if _ours_to_replace(signum):
            signal.signal(signum, _worker_handler)


def _worker_handler(signum, _frame):
    if _worker["stopped_by"] is None:
        _worker["stopped_by"] = signum
        if _worker["busy"]:
            raise Interrupted(signum)


@contextlib.contextmanager
def interruptible_chunk():
    """A worker's chunk: stopped by the first signal (``worker_signals``), at once where
    one came before it (a chunk the pool had queued before the parent stopped it)."""
    if _worker["stopped_by"] is not None:
        raise Interrupted(_worker["stopped_by"])
    _worker["busy"] = True
    try:
        yield
    finally:
        _worker["busy"] = False

