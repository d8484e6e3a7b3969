"""The one frame loop: every way of rendering frames into a sink goes through ``render_into``."""
from __future__ import annotations

from collections.abc import Iterable

from scenerender.run.collection import startup_done
from scenerender.sinks import ThreadedSink


def render_into(renderer, sink, frames: Iterable[int], progress=None) -> None:
    """Render ``frames`` with ``renderer`` (anything with ``render(index) -> Frame``) into
    ``sink``, encoding on threads while the next frame renders. ``sink`` is closed when every
    frame is written and aborted on any error or interrupt, so no partial file is left.
    ``progress`` (a ``Progress``, optional) advances once per frame written."""
    writer = ThreadedSink(sink)
    try:
        for index in frames:
            writer.write(renderer.render(index))
            startup_done()  # collections resume once the first frame is out (run/collection.py)
            if progress is not None:
                for line in renderer.take_notes():
                    progress.note(line)
                progress.advance()
        writer.close()
    except BaseException:
        writer.abort()
        raise
