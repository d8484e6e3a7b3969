"""Writes the hard-case assets in this folder (run it here; numpy and Pillow):
checker.png (a one-texel 64x64 checker), quad_uv_near.obj / quad_uv_far.obj (a 2x2 quad
with texture coordinates 0..0.25 and 10000..10000.25), degenerate.obj (a pyramid with
zero-length normals and zero-area triangles)."""
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent

DEGENERATE = """# a pyramid with zero-length normals on two corners, a zero-area triangle (a repeated
# vertex) and a sliver whose three corners lie on one line
v -0.5 0 -0.5
v 0.5 0 -0.5
v 0.5 0 0.5
v -0.5 0 0.5
v 0 0.6 0
v 0.25 0 -0.5
vn 0 0 0
vn 0 -1 0
vn 0.7 0.7 0
vn -0.7 0.7 0
vn 0 0 0
f 1//2 2//2 3//2
f 1//2 3//2 4//2
f 1//1 5//5 2//3
f 2//3 5//5 3//3
f 3//4 5//5 4//4
f 4//4 5//5 1//1
f 1//1 1//1 5//5
f 1//2 6//2 2//2
"""


def quad(base: float) -> str:
    lines = [f"# a 2x2 quad facing +Z, texture coordinates {base:.2f}..{base + 0.25:.2f}: "
             "16 texels of a 64-texel checker"]
    lines += [f"v {x} {y} 0" for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    lines += [f"vt {base + u:.2f} {base + v:.2f}" for u, v in ((0, 0), (0.25, 0), (0.25, 0.25), (0, 0.25))]
    lines += ["vn 0 0 1", "f 1/1/1 2/2/1 3/3/1", "f 1/1/1 3/3/1 4/4/1"]
    return "\n".join(lines) + "\n"


def main() -> None:
    checker = ((np.add.outer(np.arange(64), np.arange(64)) % 2) * 255).astype(np.uint8)
    Image.fromarray(np.stack([checker] * 3, axis=2)).save(HERE / "checker.png")
    (HERE / "quad_uv_near.obj").write_text(quad(0.0))
    (HERE / "quad_uv_far.obj").write_text(quad(10000.0))
    (HERE / "degenerate.obj").write_text(DEGENERATE)


if __name__ == "__main__":
    main()
