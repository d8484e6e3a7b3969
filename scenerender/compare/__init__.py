"""Comparing renders with references: ``scenerender diff``, ``render --check`` and the
golden-image tests.

    from scenerender.compare import compare_paths, DEFAULT_RULE, write_html_report
    result = compare_paths(Path("ref/"), Path("out/"))       # images, folders or videos
    result.passed, result.summary_lines(), result.to_json()
    write_html_report(result, Path("report.html"))

Nothing here needs an OpenGL context. The names below are imported on first use, so that
importing ``scenerender.compare.rule`` (the command line's defaults) does not load numpy.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "compare_images": "diff", "compare_paths": "diff",
    "FrameMetrics": "metrics", "measure": "metrics",
    "write_html_report": "report",
    "CompareResult": "result", "FrameComparison": "result",
    "DEFAULT_RULE": "rule", "DiffRule": "rule",
    "Provenance": "sources", "read_image": "sources", "read_provenance": "sources",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'scenerender.compare' has no attribute '{name}'")
    return getattr(importlib.import_module(f"scenerender.compare.{module}"), name)


def __dir__():
    return __all__
