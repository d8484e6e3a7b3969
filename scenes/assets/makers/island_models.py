"""The floating island's models (seed 001)."""
from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np

from .common import linear
from .geometry import box, ellipsoid, extruded_polygon, grid_part, lathe, noise_displace, pole_uv_fix, smooth_path, tube
from .noise import fbm
from .obj_files import Material, Model, tex, vertex_normals, WHITE


def make_island() -> Model:
    """Floating island, 30 m across: a gently domed grassy top and a rough inverted cone
    of rock below, sharing one rim so there is no crack."""
    segments, top_rings, under_rows = 48, 10, 12
    radius, depth = 15.0, 13.0
    theta = np.arange(segments + 1) * (2 * np.pi / segments)
    # Rim radius wobbles with angle (1D noise around a circle; wraps by construction).
    ring = np.stack([np.cos(theta), np.sin(theta)], axis=-1) * 1.2
    rim_r = radius * (1.0 + 0.09 * fbm(ring + 5.0, seed=401, octaves=3))
    rim_y = -0.25 + 0.2 * fbm(ring + 9.0, seed=402, octaves=2)

    # Top: rows from the rim inwards to the centre (u x v points up).
    s = np.linspace(1.0, 0.0, top_rings + 1)[:, None]
    r_top = rim_r[None, :] * s
    x, z = r_top * np.sin(theta), r_top * np.cos(theta)
    bumps = 0.35 * fbm(np.stack([x, z], axis=-1) / 5.0, seed=403, octaves=3)
    y = 0.8 * (1.0 - s ** 2) + bumps * (1.0 - s ** 4) + rim_y[None, :] * s ** 6
    y[0] = rim_y
    top_pts = np.stack([x, y, z], axis=-1)
    top_pts[-1] = top_pts[-1].mean(axis=0)
    top_uv = np.stack([top_pts[..., 0], -top_pts[..., 2]], axis=-1) / 4.0
    top = grid_part(top_pts, pole_uv_fix(top_uv, top_pts), "grass_top", "island_grass", smooth_angle=60)

    # Underside: rows from the tip up to the rim (u x v points outwards).
    t = np.linspace(1.0, 0.0, under_rows + 1)[:, None]                 # 1 = tip, 0 = rim
    r_under = rim_r[None, :] * (1.0 - t) ** 0.75
    y_under = rim_y[None, :] - depth * t ** 1.3 - 0.6 * (1 - t) * t
    pts = np.stack([r_under * np.sin(theta), y_under, r_under * np.cos(theta)], axis=-1)
    pts[0] = (0.0, -depth - 0.4, 0.0)
    rough = fbm(pts / 3.5, seed=404, octaves=4)
    ledges = 0.5 * np.sin(pts[..., 1] * 1.7 + 2.0 * fbm(pts / 8.0, seed=405, octaves=2))
    push = (1.6 * rough + ledges) * np.sin(np.pi * np.clip(1 - t, 0, 1)) ** 0.7
    horizontal = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)[None, :, :]
    pts = pts + horizontal * push[..., None]
    pts[:, -1] = pts[:, 0]                                           # seam column identical
    pts[-1] = top_pts[0]                                             # same rim as the top
    v_dist = -pts[..., 1] / 4.0
    under_uv = np.stack([np.repeat(theta[None, :] / (2 * np.pi) * 12, under_rows + 1, axis=0), -v_dist], axis=-1)
    under = grid_part(pts, pole_uv_fix(under_uv, pts), "rock_underside", "island_rock", smooth_angle=45)
    materials = {
        "island_grass": Material(WHITE, ka=(0.9, 0.9, 0.9), ks=(0.05, 0.05, 0.05), ns=8,
                                 map_kd=tex("island_grass.png")),
        "island_rock": Material(WHITE, ka=(0.8, 0.8, 0.8), ks=(0.15, 0.15, 0.15), ns=12, map_kd=tex("rock.png")),
    }
    return Model("island", [top, under], materials,
                 description="Floating island, 30 m across, top at y ~ 0.8, rock tip at y = -13.4.")


def make_tree() -> Model:
    """Broadleaf tree, 5 m: flared, slightly bent trunk with two branches and three lumpy
    foliage clumps."""
    bend = lambda p: p + np.c_[0.04 * p[:, 1] ** 2, np.zeros(len(p)), np.zeros(len(p))]
    trunk = lathe([(0, 0), (0.42, 0), (0.3, 0.12), (0.24, 0.45), (0.2, 1.5), (0.16, 2.6), (0.12, 3.2), (0, 3.35)],
                  14, uv=True, u_repeat=2, v_scale=1.0, name="trunk", material="bark").warped(bend)
    parts = [trunk]
    for direction, top in (((1, 0.2), (0.85, 3.1, 0.3)), ((-0.8, -0.5), (-0.75, 3.25, -0.4))):
        start = np.array([0.04 * 2.0 ** 2, 2.0, 0.0])
        mid = start + np.array([direction[0] * 0.3, 0.45, direction[1] * 0.3])
        path = smooth_path([start, mid, top], 6)
        parts.append(tube(path, np.linspace(0.08, 0.035, 6), 8, uv=True, v_range=(0, 1.5), cap_end=True,
                          name="branch", material="bark"))
    clumps = (((0.15, 3.75, 0.0), 1.5, 0.85), ((0.95, 3.15, 0.35), 1.05, 0.8), ((-0.75, 3.3, -0.4), 1.1, 0.85))
    for i, (center, r, squash) in enumerate(clumps):
        clump = ellipsoid((r, r * squash, r), center, 22, 12, uv=True, u_repeat=3.0, v_range=(0, 2),
                          name=f"foliage{i}", material="leaves")
        parts.append(noise_displace(clump, 0.22 * r, 1.6, seed=410 + i, center=center))
    materials = {
        "bark": Material(WHITE, ka=(0.8, 0.8, 0.8), ks=(0.05, 0.05, 0.05), ns=6, map_kd=tex("bark.png")),
        "leaves": Material(WHITE, ka=(0.8, 0.8, 0.8), ks=(0.12, 0.12, 0.12), ns=14, map_kd=tex("leaves.png")),
    }
    return Model("tree", parts, materials, description="Broadleaf tree, 5 m tall, 3 m crown.")


def make_cloud() -> Model:
    """Cumulus puff, 8 m wide: overlapping flattened spheres with flat-ish bottoms."""
    gen = np.random.default_rng(420)
    puffs = [((0.0, 0.0, 0.0), 2.0)]
    for angle in np.linspace(0, 2 * np.pi, 7)[:-1] + gen.uniform(-0.3, 0.3, 6):
        dist = gen.uniform(1.6, 2.6)
        r = gen.uniform(1.0, 1.6)
        puffs.append(((dist * np.cos(angle) * 1.2, gen.uniform(-0.2, 0.4), dist * np.sin(angle) * 0.7), r))
    parts = []
    for i, (c, r) in enumerate(puffs):
        puff = ellipsoid((r, r * 0.75, r), c, 18, 9, name=f"puff{i}", material="cloud")
        flat_bottom = lambda p: np.column_stack([p[:, 0], np.maximum(p[:, 1], -0.6 + 0.15 * (p[:, 1] + 0.6)), p[:, 2]])
        parts.append(puff.warped(flat_bottom))
    materials = {"cloud": Material((0.95, 0.95, 0.97), ka=WHITE, ks=(0.0, 0.0, 0.0), ns=1)}
    return Model("cloud", parts, materials, description="Cloud, about 8 x 3 x 5 m, centred on the origin.")


def castle_merlons(start, end, height, thickness, outward, count_step=1.4, size=0.7) -> list:
    """Battlement teeth along a wall top from start to end (x, z), set to the outer edge."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    length = np.linalg.norm(end - start)
    along = (end - start) / length
    count = int(length // count_step)
    parts = []
    for k in range(count):
        c2 = start + along * (length - (count - 1) * count_step) / 2 + along * k * count_step
        c2 = c2 + np.asarray(outward) * (thickness / 2 - 0.2)
        size3 = (size, 0.7, 0.4) if abs(along[0]) > 0.5 else (0.4, 0.7, size)
        parts.append(box(size3, (c2[0], height + 0.35, c2[1]), uv_scale=3.0, name="merlon",
                         material="castle_stone", skip_bottom=True))
    return parts


def make_castle() -> Model:
    """Small castle, 17 m square: four curtain walls with battlements, four round corner
    towers with cone roofs, a gate, and a square keep with an octagonal turret.

    Loader exercise: the towers and roofs are written with negative (relative) indices;
    tower caps are 12-gon faces, the turret's cap an octagon and the gate an arched n-gon."""
    stone = "castle_stone"
    half, wall_h, wall_t = 6.0, 4.5, 1.2
    parts = []
    for axis in ("x", "z"):
        for sign in (1, -1):
            if axis == "x":
                size, center = (2 * half, wall_h, wall_t), (0, wall_h / 2, sign * half)
                a, b, outward = (-half + 2, sign * half), (half - 2, sign * half), (0, sign)
            else:
                size, center = (wall_t, wall_h, 2 * half), (sign * half, wall_h / 2, 0)
                a, b, outward = (sign * half, -half + 2), (sign * half, half - 2), (sign, 0)
            parts.append(box(size, center, uv_scale=3.0, name=f"wall_{axis}{'+' if sign > 0 else '-'}",
                             material=stone))
            parts += castle_merlons(a, b, wall_h, wall_t, outward)
    # Gate: an arched door slab on the front (+Z) wall, one convex n-gon face per side.
    arch = [(1.1 * math.cos(a), 2.0 + 1.1 * math.sin(a)) for a in np.linspace(0, np.pi, 9)]
    door = extruded_polygon([(1.1, 0.0)] + arch + [(-1.1, 0.0)], 0.12, uv_scale=3.0, name="gate",
                            material="castle_wood").moved(0, 0, half + wall_t / 2)
    parts.append(door)
    # Keep with battlements and windows; turret with an octagonal cap on one corner.
    parts.append(box((5.0, 9.0, 5.0), (0, 4.5, -0.5), uv_scale=3.0, name="keep", material=stone))
    for a, b, outward in (((-2.5, 2.0), (2.5, 2.0), (0, 1)), ((-2.5, -3.0), (2.5, -3.0), (0, -1)),
                          ((2.0, -3.0), (2.0, 2.0), (1, 0)), ((-2.0, -3.0), (-2.0, 2.0), (-1, 0))):
        parts += castle_merlons(a, b, 9.0, 1.0, outward, count_step=1.2, size=0.6)
    parts.append(lathe([(0.9, 9.0), (0.9, 11.0), (1.15, 11.3), (1.15, 11.7)], 8, uv=True, u_repeat=2,
                       v_scale=3.0, phase=22.5, cap_top="ngon", name="turret", material=stone,
                       smooth_angle=30).moved(1.6, 0, -2.1))
    for k in range(4):
        for x in (-1.2, 1.2):
            # Placed on the keep's +Z face around the keep's own axis, then turned to each face.
            window = box((0.5, 1.0, 0.12), (x, 6.5, 2.5), uv_scale=3.0, name="keep_window",
                         material="castle_window")
            parts.append(window.rotated("y", 90 * k).moved(0, 0, -0.5))
    roof_parts = []
    for sx, sz in itertools.product((1, -1), repeat=2):
        cx, cz = sx * half, sz * half
        tower = lathe([(2.1, 0.0), (1.85, 1.0), (1.8, 7.0), (2.15, 7.35), (2.15, 7.6)], 12, uv=True,
                      u_repeat=4, v_scale=3.0, cap_bottom="ngon", cap_top="ngon", name="tower",
                      material=stone, smooth_angle=35)
        roof = lathe([(0, 7.5), (2.45, 7.5), (1.2, 9.6), (0, 11.4)], 12, uv=True, u_repeat=4, v_scale=3.0,
                     name="roof", material="castle_roof", smooth_angle=35)
        tag = f"{'e' if sx > 0 else 'w'}{'s' if sz > 0 else 'n'}"
        parts.append(tower.moved(cx, 0, cz).named(f"tower_{tag}", relative_indices=True))
        roof_parts.append(roof.moved(cx, 0, cz).named(f"roof_{tag}", relative_indices=True))
        facing = math.degrees(math.atan2(sx, sz))
        for height in (3.0, 5.5):
            w = box((0.45, 0.9, 0.3), (0, height, 1.78), uv_scale=3.0, name="tower_window",
                    material="castle_window")
            parts.append(w.rotated("y", facing + (25 if height > 4 else -25)).moved(cx, 0, cz))
    parts += roof_parts
    order = [stone, "castle_roof", "castle_wood", "castle_window"]
    parts.sort(key=lambda p: order.index(p.material))
    materials = {
        stone: Material(WHITE, ka=(0.85, 0.85, 0.85), ks=(0.08, 0.08, 0.08), ns=10, map_kd=tex("stone.png")),
        "castle_roof": Material(linear("#7a2e26"), ks=(0.25, 0.25, 0.25), ns=24, comment="slate-red roof"),
        "castle_wood": Material(linear("#5a3b22"), ks=(0.1, 0.1, 0.1), ns=8),
        "castle_window": Material(linear("#151515"), ks=(0.5, 0.5, 0.5), ns=60),
    }
    return Model("castle", parts, materials,
                 description="Castle, 16.9 m square, 11.7 m tall, gate towards +Z.",
                 extra_header=["Towers and roofs use negative (relative) indices; caps are n-gons."])


def make_flag() -> Model:
    """Flag on a 6 m pole: a waving 2.4 x 1.5 m cloth, two-sided (two sheets 1 cm apart with
    opposite winding) so it shows with back-face culling from either side."""
    pole = lathe([(0, 0), (0.09, 0), (0.09, 0.06), (0.05, 0.1), (0.045, 6.0), (0, 6.0)], 12, uv=True,
                 name="pole", material="flag_pole")
    ball = ellipsoid((0.09, 0.09, 0.09), (0, 6.08, 0), 12, 6, uv=True, name="finial", material="flag_gold")
    cols, rows = 25, 13
    width, height = 2.4, 1.5
    s = np.linspace(0, 1, cols)
    t = np.linspace(0, 1, rows)
    ss, tt = np.meshgrid(s, t)
    x = 0.06 + ss * width * (1 - 0.04 * np.sin(np.pi * ss))
    z = 0.18 * ss ** 0.8 * np.sin(2 * np.pi * (1.3 * ss - 0.15 * tt))
    y = 4.4 + tt * height - 0.12 * ss ** 2 * (1 - tt)
    sheet = np.stack([x, y, z], axis=-1)
    uv = np.stack([ss, tt], axis=-1)
    # Rows advance along +v (up), columns along +u (away from the pole): front faces +Z.
    front = grid_part(sheet, uv, "cloth_front", "flag_cloth", closed=False, smooth_angle=80)
    back = replace(front, name="cloth_back", v=front.v - 0.01 * vertex_normals(front),
                   faces=[tuple(reversed(f)) for f in front.faces])
    materials = {
        "flag_cloth": Material(WHITE, ks=(0.05, 0.05, 0.05), ns=6, map_kd=tex("flag.png")),
        "flag_pole": Material(linear("#9aa0a6"), ks=(0.6, 0.6, 0.6), ns=60),
        "flag_gold": Material(linear("#d8a939"), ks=(0.9, 0.8, 0.5), ns=80),
    }
    return Model("flag", [pole, ball, front, back], materials,
                 description="Flag, pole 6.2 m, cloth 2.4 x 1.5 m waving towards +X; two-sided cloth.")
