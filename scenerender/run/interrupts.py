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
