"""How the camera passes store depth: reversed-Z in a 32-bit float buffer where the device
can map clip depth to [0, 1] (glClipControl: GL 4.5 or ARB_clip_control), otherwise the
classic -1..1 mapping into a 24-bit fixed-point buffer.

Why reversed-Z: a perspective projection spends its depth values as 1/distance. Stored
as 1 at the near plane falling to 0 at the far plane, that hyperbola meets float32's
exponent, which is densest near 0, and the two roughly cancel: relative depth precision is
about 1e-7 at every distance, so near can be tiny and far huge. With fixed-point depth the
precision near the far plane is ~ distance^2 / (near * 2^24), hence the fallback's cap on
far / near.

The convention is fixed per renderer. Clip control is GL state, so the renderer switches
it on around each frame's passes and back off after (other users of the context, and the
shadow passes' own matrices, see the default mapping only through ``clip_projection``).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import os
from dataclasses import dataclass

import numpy as np

GL_LOWER_LEFT = 0x8CA1
GL_NEGATIVE_ONE_TO_ONE = 0x935E
GL_ZERO_TO_ONE = 0x935F
GL_RENDERBUFFER = 0x8D41
GL_DEPTH_COMPONENT32F = 0x8CAC

# Far / near of `near/far: auto` in the fallback: keeps a 24-bit buffer precise.
FIXED_POINT_DEPTH_RATIO = 1e4
# "0" forces the fallback (to test it, or for a driver whose clip control misbehaves).
ENV_REVERSED_Z = "SCENERENDER_REVERSED_Z"


@dataclass(frozen=True)
class DepthConvention:
    """reversed: reversed-Z float depth (clip z in [0, 1], 1 at near, cleared to 0)."""

    reversed: bool
    gl_calls: object = None  # _GLCalls where reversed

    @property
    def clear_value(self) -> float:
        return 0.0 if self.reversed else 1.0

    @property
    def nearer(self) -> str:
        """The depth test that lets nearer fragments win."""
        return ">" if self.reversed else "<"

    @property
    def farther(self) -> str:
        """The depth test that passes fragments strictly behind what is stored."""
        return "<" if self.reversed else ">"

    @property
    def nearer_or_equal(self) -> str:
        return ">=" if self.reversed else "<="

    @property
    def ndc_near_far(self) -> tuple[float, float]:
        """Normalised-device z of the near and the far plane."""
        return (1.0, 0.0) if self.reversed else (-1.0, 1.0)

    @property
    def depth_format(self) -> str:
        """The ResourceDesc format of camera depth targets."""
        return "depth32f" if self.reversed else "depth24"

    @property
    def max_depth_ratio(self) -> float | None:
        """The cap on far / near that `near/far: auto` keeps; None: no cap needed."""
        return None if self.reversed else FIXED_POINT_DEPTH_RATIO

    def camera_projection(self, projection: np.ndarray) -> np.ndarray:
        """(4, 4) float64: an OpenGL (-1..1) projection remapped to this convention's clip
        depth. Reversed: z' = (w - z) / 2, so near -> 1 and far -> 0; exact for
        perspective and orthographic alike."""
        if not self.reversed:
            return projection
        result = projection.copy()
        result[2] = 0.5 * (projection[3] - projection[2])
        return result

    def clip_projection(self, projection: np.ndarray) -> np.ndarray:
        """(4, 4) float64: a projection whose depth is written by the fragment shader
        (shadow maps) remapped so clipping keeps the same volume: z' = (z + w) / 2."""
        if not self.reversed:
            return projection
        result = projection.copy()
        result[2] = 0.5 * (projection[2] + projection[3])
        return result

    def begin_frame(self) -> None:
        if self.reversed:
            self.gl_calls.clip_control(GL_LOWER_LEFT, GL_ZERO_TO_ONE)

    def end_frame(self) -> None:
        if self.reversed:
            self.gl_calls.clip_control(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE)

    def make_float_depth(self, renderbuffer, size: tuple, samples: int) -> None:
        """Re-specify a moderngl depth renderbuffer's storage as 32-bit float in place
        (moderngl makes only 24-bit depth buffers)."""
        calls = self.gl_calls
        calls.bind_renderbuffer(GL_RENDERBUFFER, renderbuffer.glo)
        calls.renderbuffer_storage(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT32F, int(size[0]), int(size[1]))
        calls.bind_renderbuffer(GL_RENDERBUFFER, 0)


class _GLCalls:
    """The three GL entry points moderngl does not wrap, resolved for the current context."""

    def __init__(self, lookup):
        uint, sizei = ctypes.c_uint, ctypes.c_int
        self.clip_control = _function(lookup, b"glClipControl", uint, uint)
        self.bind_renderbuffer = _function(lookup, b"glBindRenderbuffer", uint, uint)
        self.renderbuffer_storage = _function(lookup, b"glRenderbufferStorageMultisample",
                                              uint, sizei, uint, sizei, sizei)


def _function(lookup, name: bytes, *argtypes):
    address = lookup(name)
    if not address:
        raise OSError(f"no {name.decode()}")
    return ctypes.CFUNCTYPE(None, *argtypes)(address)


def _proc_address_lookup(backend: str):
    """The context's own loader (eglGetProcAddress for the EGL backend, glXGetProcAddress
    for X11), else the other; None if neither loads."""
    loaders = [("EGL", "eglGetProcAddress"), ("GL", "glXGetProcAddress")]
    if backend == "x11":
        loaders.reverse()
    for library, symbol in loaders:
        path = ctypes.util.find_library(library)
        if path is None:
            continue
        try:
            function = getattr(ctypes.CDLL(path), symbol)
        except (OSError, AttributeError):
            continue
        function.restype = ctypes.c_void_p
        function.argtypes = [ctypes.c_char_p]
        return function
    return None


def has_clip_control(gl) -> bool:
    return gl.version_code >= 450 or "GL_ARB_clip_control" in gl.extensions


def depth_convention(gl) -> DepthConvention:
    """Reversed-Z where the device has clip control and it is not switched off by
    ``SCENERENDER_REVERSED_Z=0``; the fixed-point fallback otherwise."""
    if os.environ.get(ENV_REVERSED_Z, "1") == "0" or not has_clip_control(gl):
        return DepthConvention(False)
    backend = os.environ.get("SCENERENDER_GL_BACKEND", "egl")
    lookup = _proc_address_lookup(backend) if backend in ("egl", "x11") else None
    if lookup is None:
        return DepthConvention(False)
    try:
        return DepthConvention(True, _GLCalls(lookup))
    except OSError:
        return DepthConvention(False)
