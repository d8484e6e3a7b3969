"""Set uniforms by name, skipping the ones a program variant does not use."""
from __future__ import annotations

import numpy as np


def matrix_bytes(m: np.ndarray) -> bytes:
    """A NumPy (row-major) matrix as the column-major float32 bytes GLSL expects."""
    return np.ascontiguousarray(np.asarray(m, dtype=np.float64).T, dtype=np.float32).tobytes()


def set_uniforms(program, **values) -> None:
    """program[name] = value for each name the program has.

    2-D arrays are matrices; 1-D arrays vectors; an array of vectors can be given as
    bytes. Names the compiler removed (unused in this variant) are skipped.
    """
    for name, value in values.items():
        member = program.get(name, None)
        if member is None:
            continue
        if isinstance(value, bytes):
            member.write(value)
        elif isinstance(value, np.ndarray) and value.ndim == 2:
            member.write(matrix_bytes(value))
        elif isinstance(value, (np.ndarray, list, tuple)):
            member.value = tuple(float(v) for v in np.asarray(value).reshape(-1))
        else:
            member.value = value
