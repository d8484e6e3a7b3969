"""The comparison scene rendered by scenerender in-process, without writing files: the
render-only figure (frame evaluation, passes and readback). The with-writes figure comes
from the ``scenerender render`` command itself (see run_compare.py)."""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import parse_args, run_frames  # noqa: E402

import scene_def as S  # noqa: E402


def main() -> None:
    args = parse_args(__doc__)
    from scenerender.errors import Warnings
    from scenerender.gpu.gl_context import create_context
    from scenerender.rendering.renderer import GraphRenderer
    from scenerender.scene import load_scene
    from scenerender.world.build import build_world

    overrides = [f"render.size=[{args.width}, {args.height}]", f"render.samples={args.samples}"]
    world = build_world(load_scene(S.SCENE_YAML, overrides), Warnings())
    renderer = GraphRenderer(world, create_context())
    run_frames(args, lambda i: renderer.render(i).pixels)


if __name__ == "__main__":
    main()
