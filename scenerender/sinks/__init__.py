"""Frame sinks: where rendered frames go. No rendering here, so sinks are tested with
synthetic frames. Every file is written whole (temporary file, then rename) or not at all.
"""
from scenerender.sinks.base import (
           FrameSink,
           atomic_path,
           output_errors,
           remove_stale_partials,
)
from scenerender.sinks.images import (
           IMAGE_SUFFIX_FORMATS,
           ImageSequenceSink,
           SingleImageSink,
           frame_name_pattern,
)
from scenerender.sinks.threaded import ThreadedSink
from scenerender.sinks.video import VideoSink

__all__ = ["FrameSink", "IMAGE_SUFFIX_FORMATS", "ImageSequenceSink", "SingleImageSink", "ThreadedSink", "VideoSink",
           "atomic_path", "frame_name_pattern", "output_errors", "remove_stale_partials"]
