"""The viewer modes scene's models (seed 003)."""
from __future__ import annotations

import math

import numpy as np

from .geometry import bevelled_box, box, lathe
from .obj_files import Material, Model, tex, WHITE


def make_column() -> Model:
    """Stone column, 3.1 m: square plinth, moulded base, a shaft with entasis, a capital
    and abacus. UVs keep texels square everywhere so the block pattern and its normal map
    read right; u runs around each lathe piece (twice), v up it."""
    stone = "column_stone"
    shaft_v = 2 * math.pi * 0.32 / 2      # metres per texture repeat: matches u_repeat = 2
    common = dict(segments=32, uv=True, u_repeat=2, v_scale=shaft_v, material=stone)

    def bulge(r0, r1, y0, y1, amount, steps=5):
        """A torus-like moulding from (r0, y0) to (r1, y1) swelling outwards by `amount`."""
        t = np.linspace(0, 1, steps)
        return [(r0 + (r1 - r0) * s + amount * math.sin(math.pi * s), y0 + (y1 - y0) * s) for s in t]

    plinth = box((1.0, 0.25, 1.0), (0, 0.125, 0), uv_scale=shaft_v, name="plinth", material=stone)
    base_profile = [(0, 0.25)] + bulge(0.44, 0.42, 0.25, 0.35, 0.04) + [(0.39, 0.37)] + \
        bulge(0.39, 0.37, 0.39, 0.46, 0.03)[1:] + [(0.34, 0.47)]
    base = lathe(base_profile, name="base", **common)
    y = np.linspace(0.47, 2.77, 9)
    entasis = 0.34 - 0.05 * ((y - 0.47) / 2.3) ** 1.6 + 0.008 * np.sin(np.pi * (y - 0.47) / 2.3)
    shaft = lathe(list(zip(entasis, y)), name="shaft", **common)
    echinus = [(0.3 + 0.16 * (1 - math.cos(a)), 2.84 + 0.11 * math.sin(a)) for a in np.linspace(0.2, np.pi / 2, 5)]
    capital = lathe([(0.29, 2.77)] + bulge(0.29, 0.3, 2.78, 2.84, 0.02, 4) + echinus + [(0.46, 2.96), (0, 2.96)],
                    name="capital", **common)
    abacus = box((0.98, 0.14, 0.98), (0, 3.03, 0), uv_scale=shaft_v, name="abacus", material=stone)
    materials = {stone: Material(WHITE, ka=(0.9, 0.9, 0.9), ks=(0.6, 0.6, 0.6), ns=40,
                                 map_kd=tex("column_diffuse.tga"), map_ks=tex("column_specular.tga"),
                                 map_bump=tex("column_normal.tga"), bump_scale=1.0)}
    return Model("column", [plinth, base, shaft, capital, abacus], materials,
                 description="Stone column, 3.1 m tall, 1 m square plinth; diffuse, normal and specular maps (TGA).")


def make_crate() -> Model:
    """Wooden crate, 1 m cube with 4 cm chamfered edges; each face shows the whole
    crate texture, so the normal map's frame and brace line up with the bevels."""
    crate = bevelled_box(1.0, 0.04, name="crate", material="crate_wood").moved(0, 0.5, 0)
    materials = {"crate_wood": Material(WHITE, ka=(0.9, 0.9, 0.9), ks=(0.25, 0.25, 0.25), ns=20,
                                        map_kd=tex("crate_diffuse.tga"), map_bump=tex("crate_normal.tga"))}
    return Model("crate", [crate], materials, description="Crate, 1 m cube standing on y = 0, chamfered edges.")
