"""What multisampling costs the device by colour-target format, apart from any scene.

Clears a colour target and a depth renderbuffer and draws a grid of triangles over the
whole image, without MSAA and with 4x, GPU-synchronised, into each of the colour formats
the opaque pass may use. With the default fragment shader, which does almost nothing,
what the 4x column adds is the device's work per sample (coverage, depth test, conversion
and store of every sample). With --heavy (a loop of 48 sines a pixel) and many cells it
shows what small triangles add to the shading itself. Prints a Markdown table.

    python benchmarks/msaa_cost.py
    python benchmarks/msaa_cost.py --heavy --cells 100      # triangles of 15 pixels
    python benchmarks/msaa_cost.py --size 1280x720 --cells 80 --rounds 30

"1x" is a plain texture: a multisampled texture of one sample takes the multisampled
path on Mesa llvmpipe and costs what 4x does.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import moderngl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from scenerender.gpu.gl_context import create_context  # noqa: E402
from scenerender.gpu.resources import GL_FRAMEBUFFER_SRGB, GL_SRGB8_ALPHA8  # noqa: E402

FORMATS = {  # name -> moderngl texture arguments, and whether sRGB encoding is on while drawing
    "rgba8 (linear 8-bit)": ({}, False),
    "srgba8, the device encoding": ({"internal_format": GL_SRGB8_ALPHA8}, True),
    "srgba8, the device encoding off (the opaque pass's with MSAA)": ({"internal_format": GL_SRGB8_ALPHA8}, False),
    "rgba16f (its HDR target)": ({"dtype": "f2"}, False),
}
VERTEX = "#version 430\nin vec2 p; out vec2 v; void main() { gl_Position = vec4(p, 0.0, 1.0); v = p; }"
FRAGMENT = "#version 430\nin vec2 v; out vec4 c; void main() { c = vec4(v, 0.2, 1.0); }"
HEAVY_FRAGMENT = """#version 430
in vec2 v;
out vec4 c;
void main() {
    float a = 0.0;
    for (int i = 0; i < 48; ++i) a += sin(v.x * 3.0 + float(i) * v.y * 0.05);
    c = vec4(a * 0.01, 0.5, 0.2, 1.0);
}"""


def grid(cells: int) -> np.ndarray:
    """(cells * cells * 6, 2) float32: two triangles per cell of a grid over clip space."""
    edges = np.linspace(-1.0, 1.0, cells + 1, dtype=np.float32)
    x0, y0 = np.meshgrid(edges[:-1], edges[:-1])
    x1, y1 = np.meshgrid(edges[1:], edges[1:])
    corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y0), (x1, y1), (x0, y1)]
    return np.stack([np.stack(c, axis=-1).reshape(-1, 2) for c in corners], axis=1).reshape(-1, 2)


def draw_ms(ctx, vao, size: tuple, samples: int, texture_args: dict, srgb: bool, rounds: int) -> float:
    """Median milliseconds of a clear and the grid's draw into one target."""
    multisampled = samples if samples > 1 else 0
    color = ctx.texture(size, 4, samples=multisampled, **texture_args)
    depth = ctx.depth_renderbuffer(size, samples=multisampled)
    fbo = ctx.framebuffer([color], depth)
    fbo.use()
    (ctx.enable_direct if srgb else ctx.disable_direct)(GL_FRAMEBUFFER_SRGB)
    ctx.enable(moderngl.DEPTH_TEST)
    times = []
    for _ in range(rounds + 2):
        ctx.finish()
        started = time.perf_counter()
        fbo.clear(0.5, 0.6, 0.7, 1.0, depth=1.0)
        vao.render()
        ctx.finish()
        times.append(time.perf_counter() - started)
    for thing in (fbo, color, depth):
        thing.release()
    return 1000.0 * statistics.median(times[2:])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", default="640x480", help="WxH (default 640x480)")
    parser.add_argument("--cells", type=int, default=40, help="grid cells a side, two triangles each (default 40)")
    parser.add_argument("--samples", type=int, default=4, help="MSAA samples to compare with none (default 4)")
    parser.add_argument("--rounds", type=int, default=15, help="timed draws per target (default 15)")
    parser.add_argument("--heavy", action="store_true", help="a costly fragment shader (48 sines a pixel)")
    args = parser.parse_args()
    size = tuple(int(v) for v in args.size.lower().split("x"))
    ctx = create_context()
    program = ctx.program(vertex_shader=VERTEX, fragment_shader=HEAVY_FRAGMENT if args.heavy else FRAGMENT)
    vao = ctx.vertex_array(program, [(ctx.buffer(grid(args.cells).tobytes()), "2f", "p")])
    print(f"{ctx.info['GL_RENDERER']}; {size[0]}x{size[1]}, {2 * args.cells ** 2} triangles of "
          f"{size[0] * size[1] / (2 * args.cells ** 2):.1f} pixels over the image, "
          f"{'heavy' if args.heavy else 'cheap'} shading, clear + draw, medians of {args.rounds}")
    draw_ms(ctx, vao, size, 1, {}, False, args.rounds)  # warm-up: the first draws of a process run slower
    print(f"| colour target | 1x ms | {args.samples}x ms | {args.samples}x / 1x |")
    print("|---|---|---|---|")
    for name, (texture_args, srgb) in FORMATS.items():
        single = draw_ms(ctx, vao, size, 1, texture_args, srgb, args.rounds)
        multi = draw_ms(ctx, vao, size, args.samples, texture_args, srgb, args.rounds)
        print(f"| {name} | {single:.2f} | {multi:.2f} | {multi / single:.2f} |")


if __name__ == "__main__":
    main()
