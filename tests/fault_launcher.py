"""Runs the ``scenerender`` command line with frame writes slowed down or stalled, so that
tests can send a signal to a real process at a known point of a render.

    python tests/fault_launcher.py render scene.yaml -o out

Environment (read here only, never by scenerender itself):
  FAULT_WRITE_DELAY   seconds to sleep after each frame is written (default 0)
  FAULT_HANG_AT       frame index whose file is left half-written under its temporary
                      name while the writer sleeps for ever (a SIGKILL then leaves it)
"""
from __future__ import annotations

import os
import sys
import time

from scenerender.sinks import images, video
from scenerender.sinks.base import atomic_path

DELAY = float(os.environ.get("FAULT_WRITE_DELAY", "0"))
HANG_AT = int(os.environ["FAULT_HANG_AT"]) if os.environ.get("FAULT_HANG_AT") else None


def _slowed(write):
    def slow_write(self, frame):
        if frame.index == HANG_AT:
            with atomic_path(self.path_for(frame.index)) as temp:
                temp.write_bytes(b"\x89PNG\r\n\x1a\n half a frame")
                time.sleep(3600)
        write(self, frame)
        time.sleep(DELAY)
    return slow_write


images.ImageSequenceSink.write = _slowed(images.ImageSequenceSink.write)
video.VideoSink.write = _slowed(video.VideoSink.write)

if __name__ == "__main__":
    from scenerender.cli import main

    main(args=sys.argv[1:], prog_name="scenerender")
