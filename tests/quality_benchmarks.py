"""The scripts of benchmarks/quality/ as modules, for tests that measure against the
reference the way those tables do (their scenes, regions and error measures)."""
from __future__ import annotations

import importlib.util
from pathlib import Path

QUALITY = Path(__file__).resolve().parent.parent / "benchmarks" / "quality"


def quality_module(name: str):
    """benchmarks/quality/<name>.py, loaded as a module (the folder is not a package)."""
    spec = importlib.util.spec_from_file_location(name, QUALITY / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
