"""Frame sinks: where rendered frames go. No rendering here, so sinks are tested with
synthetic frames. Every file is written whole (temporary file, then rename) or not at all.

The names below are imported on first use, so that ``scenerender diff``, which reads object
ids through ``scenerender.sinks.object_ids``, does not load the image and video writers.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "FrameSink": "base", "atomic_path": "base", "output_errors": "base", "remove_stale_partials": "base",
    "IMAGE_SUFFIX_FORMATS": "images", "ImageSequenceSink": "images", "SingleImageSink": "images",
    "frame_name_pattern": "images",
    "ThreadedSink": "threaded",
    "VideoSink": "video",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'scenerender.sinks' has no attribute '{name}'")
    return getattr(importlib.import_module(f"scenerender.sinks.{module}"), name)


def __dir__():
    return __all__
