#!/usr/bin/env python3
"""Generate every model, texture and skybox used by scenerender's example scenes.

All assets are built here from parametric pieces and seeded noise, so running the script
again gives byte-identical files. Only numpy, Pillow and the standard library are used
(the one GLB is written by hand: JSON and binary chunks, PNG images inside).

    python scenes/assets/make_assets.py            # rebuild everything
    python scenes/assets/make_assets.py duck sky   # rebuild assets whose name contains a word

The makers are in makers/, one module per kind of asset: textures.py, skyboxes.py,
environments.py, glb.py (the pbr scene's GLB) and the OBJ models of each example scene
(garden_models.py, island_models.py, road_models.py, viewer_models.py), on top of what they
share: common.py (paths, the file header, colour helpers), noise.py, images.py,
geometry.py (parts and parametric surfaces) and obj_files.py (normals, OBJ and MTL writing).

Conventions (see README.md in this folder):
  * +Y up, about 1 unit per metre, faces counter-clockwise seen from outside.
  * Texture images are stored top row first; OBJ texture coordinate v = 1 is the top row.
  * Normal maps are tangent-space, OpenGL convention (green = +V), stored as linear data.
  * Skybox faces follow the OpenGL cube-map convention (glTexImage2D with
    GL_TEXTURE_CUBE_MAP_POSITIVE_X + i, images uploaded top row first, no flip).
"""
from __future__ import annotations

import sys
import time

from makers.common import ROOT
from makers.environments import write_environments
from makers.garden_models import make_bars, make_cat, make_duck, make_fox, make_lamp
from makers.glb import write_props_glb
from makers.island_models import make_castle, make_cloud, make_flag, make_island, make_tree
from makers.obj_files import write_obj
from makers.road_models import make_fence, make_pine, make_streetlight
from makers.skyboxes import write_skyboxes
from makers.textures import write_textures
from makers.viewer_models import make_column, make_crate

MODEL_BUILDERS = (make_duck, make_cat, make_lamp, make_bars, make_fox, make_island, make_tree, make_cloud,
                  make_castle, make_flag, make_pine, make_streetlight, make_fence, make_column, make_crate)


def main(argv: list[str]) -> int:
    """Build everything (or, with words on the command line, only assets whose name
    contains one of them: 'sky', 'textures', or a model name)."""
    started = time.perf_counter()
    wanted = [w.lower() for w in argv]
    chosen = lambda name: not wanted or any(w in name for w in wanted)
    if chosen("textures"):
        write_textures()
    if chosen("skybox"):
        write_skyboxes()
    if chosen("environments"):
        write_environments()
    for build in MODEL_BUILDERS:
        name = build.__name__.removeprefix("make_")
        if chosen(name):
            model = build()
            write_obj(model)
            print(f"{model.name + '.obj':18} {model.triangle_count:6d} triangles")
    if chosen("pbr_props"):
        print(f"{'pbr_props.glb':18} {write_props_glb():6d} triangles")
    total = sum(p.stat().st_size for p in ROOT.rglob("*") if p.is_file())
    print(f"scenes/assets: {total / 1024:.0f} KiB in all, built in {time.perf_counter() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
