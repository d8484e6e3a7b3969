"""Python's cycle collector, paused while a render starts.

A render's start-up (imports, the scene model's validator, the render graph, the GL
resources) makes 80,000-100,000 objects the collector tracks, nearly all of which live as
long as the process. Collecting while they are made walks them again and again for almost
nothing: 11 ms of a 0.35 s one-frame render even at the command's raised threshold
(cli.COMMAND_GC_THRESHOLD). So the ``render`` command pauses collections, and the frame
loop ends the pause once the first frame is out (``startup_done``): what start-up made is
frozen (later collections do not walk it again; about 300 of those objects are garbage
in cycles then, frozen with the rest) and collections run as before, so a long render's
garbage cycles are still freed. Whatever ends a command ends the pause too
(``end_pause``), which also gives a caller in the same process (a test's CliRunner) its
collector back as it was.
"""
from __future__ import annotations

import gc

_paused = False
_froze = False


def pause_until_started() -> None:
    """Stop automatic collections until ``startup_done`` or ``end_pause``; nothing when the
    caller has them off already."""
    global _paused
    if gc.isenabled():
        gc.disable()
        _paused = True


def startup_done() -> None:
    """The run's long-lived objects exist: freeze them and collect again. Nothing unless
    ``pause_until_started`` paused collections."""
    global _paused, _froze
    if _paused:
        gc.freeze()
        _paused, _froze = False, True
        gc.enable()


def end_pause() -> None:
    """Collections as they were before ``pause_until_started``, whether or not start-up
    finished."""
    global _paused, _froze
    if _froze:
        gc.unfreeze()
        _froze = False
    if _paused:
        _paused = False
        gc.enable()
