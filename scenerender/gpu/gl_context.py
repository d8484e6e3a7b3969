"""Create the one OpenGL context a run uses: moderngl standalone over EGL.

EGL gives a context without a display: Mesa's llvmpipe on a CPU-only machine, the vendor
driver where a GPU is present. ``SCENERENDER_GL_BACKEND`` may name another glcontext
backend (e.g. "x11") for machines without EGL.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from scenerender.errors import EnvironmentProblem
from scenerender.machine import available_cores

REQUIRED_VERSION = 430  # storage buffers for lights and shadow views

# Mesa llvmpipe's rasterizer threads (LP_NUM_THREADS; its default is one per core), as
# cores + this many, unless the user set it. The render thread, the frame encoders and
# ffmpeg share the cores with the rasterizer; with two more threads than cores, tiles
# keep a core busy while another thread waits. Measured on 2 cores (whole commands
# alternated, 3 pairs): the showcase 3.5 % faster, the benchmark scene 1-4 %; pixels
# are the same (each 64 x 64 tile is drawn whole by one thread, in draw order).
EXTRA_RASTERIZER_THREADS = 2

# The libraries glcontext's EGL backend opens, by the names their packages install on Linux.
# Without them glcontext asks ctypes.util.find_library, which runs `ldconfig -p` once for
# each: 3.5 ms of a 0.35 s one-frame render. The loader finds these names where
# find_library would; where it cannot, glcontext's own search is tried before giving up.
EGL_LIBRARIES = {"libgl": "libGL.so.1", "libegl": "libEGL.so.1"}

INSTALL_HINT = ("install an EGL driver: on Debian/Ubuntu 'apt-get install libegl1 libgl1-mesa-dri' "
                "(Mesa, software rendering), or the NVIDIA driver on a GPU machine")


def create_context():
    """A moderngl Context; raises EnvironmentProblem with an install hint if none can be made."""
    import moderngl

    lift_forced_narrow_vectors()
    os.environ.setdefault("LP_NUM_THREADS", str(available_cores() + EXTRA_RASTERIZER_THREADS))
    backend = os.environ.get("SCENERENDER_GL_BACKEND", "egl")
    try:
        ctx = _standalone_context(moderngl, backend)
    except Exception as exc:  # glcontext raises plain Exceptions with driver text
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise EnvironmentProblem(f"cannot create an OpenGL {REQUIRED_VERSION // 100}.{REQUIRED_VERSION % 100 // 10} "
                                 f"context over {backend.upper()} ({reason}); {INSTALL_HINT}") from None
    return ctx


def _standalone_context(moderngl, backend: str):
    if backend == "egl" and sys.platform.startswith("linux"):
        try:
            return moderngl.create_context(standalone=True, backend=backend, require=REQUIRED_VERSION,
                                           **EGL_LIBRARIES)
        except Exception:  # another name, or no EGL at all: glcontext's search says which
            pass
    return moderngl.create_context(standalone=True, backend=backend, require=REQUIRED_VERSION)


def gl_info(ctx) -> dict:
    """Renderer, version and the limits that matter to scenerender."""
    info = ctx.info
    keys = ("GL_VENDOR", "GL_RENDERER", "GL_VERSION", "GL_MAX_SAMPLES", "GL_MAX_TEXTURE_SIZE",
            "GL_MAX_TEXTURE_IMAGE_UNITS", "GL_MAX_SHADER_STORAGE_BLOCK_SIZE", "GL_MAX_UNIFORM_BLOCK_SIZE",
            "GL_MAX_FRAGMENT_UNIFORM_COMPONENTS", "GL_MAX_VIEWPORT_DIMS")
    result = {k: info.get(k) for k in keys if k in info}
    result["max_anisotropy"] = ctx.max_anisotropy
    result["version_code"] = ctx.version_code
    return result



def lift_forced_narrow_vectors(cpuinfo: Path = Path("/proc/cpuinfo")) -> bool:
    """Mesa 22's llvmpipe told to use 4-wide vectors (LP_NATIVE_VECTOR_WIDTH=128) on a CPU
    that has AVX2 writes past a heap buffer while it draws (a ground plane alone is
    enough) and the process dies of heap corruption. On CPUs without AVX llvmpipe picks 128
    bits itself and renders correctly: every example scene under an emulated SSE4.2 CPU
    matches the native render (tests/test_cpu_without_avx2.py). So the forced setting is
    lifted, with a warning, before the driver loads. Returns whether it was."""
    if os.environ.get("LP_NATIVE_VECTOR_WIDTH", "").strip() != "128" or not _has_avx2(cpuinfo):
        return False
    del os.environ["LP_NATIVE_VECTOR_WIDTH"]
    sys.stderr.write("warning: LP_NATIVE_VECTOR_WIDTH=128 ignored: on a CPU with AVX2 it makes Mesa's llvmpipe "
                     "corrupt memory; llvmpipe picks its own width\n")
    return True


def _has_avx2(cpuinfo: Path) -> bool:
    try:
        text = cpuinfo.read_text(encoding="ascii", errors="replace")
    except OSError:
        return False
    return any(line.startswith("flags") and "avx2" in line.split(":", 1)[-1].split() for line in text.splitlines())


# GL_RENDERER names of Mesa's CPU rasterisers: a driver that finds no GPU (or is not allowed
# to use one, as in a container started without it) falls back to one of these silently
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast")

GPU_HINT = ("for a GPU, install its driver with EGL support (NVIDIA: the driver's libEGL_nvidia; AMD and Intel: "
            "Mesa's radeonsi or iris) and, in a container, pass the GPU in (docker run --gpus all with "
            "NVIDIA_DRIVER_CAPABILITIES=graphics); or leave out --require-gpu (and SCENERENDER_REQUIRE_GPU) "
            "to render on the CPU")


def renderer_name(ctx) -> str:
    """The context's GL_RENDERER, e.g. 'llvmpipe (LLVM 15.0.6, 256 bits)'."""
    return str(ctx.info.get("GL_RENDERER", "unknown"))


def is_software(renderer: str) -> bool:
    """Whether GL_RENDERER ``renderer`` names a CPU rasteriser."""
    return any(name in renderer.lower() for name in SOFTWARE_RENDERERS)


def refuse_software(ctx) -> None:
    """EnvironmentProblem (exit 3) when ``ctx`` renders on the CPU: a GPU was required."""
    renderer = renderer_name(ctx)
    if is_software(renderer):
        raise EnvironmentProblem(f"a GPU is required, but the GL renderer is '{renderer}', which draws on the CPU; "
                                 f"{GPU_HINT}")
