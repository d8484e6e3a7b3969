"""The garden scene's models (seed 000)."""
from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np

from .common import linear
from .geometry import box, ellipsoid, lathe, smooth_path, tube
from .obj_files import Material, Model, tex, WHITE


def make_duck() -> Model:
    """Duck, 0.36 m long, facing +X. No normals in the file: loaders compute smooth ones."""
    def body_shape(p):
        back = np.clip(-p[:, 0] / 0.17, 0.0, 1.0)
        p[:, 1] += 0.06 * back ** 2.5                                   # tail end sweeps up
        p[:, 1] = np.where(p[:, 1] < 0.03, 0.03 - (0.03 - p[:, 1]) * 0.35, p[:, 1])  # flat belly
        return p

    body = ellipsoid((0.17, 0.1, 0.12), (0.0, 0.11, 0.0), 32, 16, name="body", material="duck_body")
    body = body.warped(body_shape)
    tail_path = smooth_path([(-0.12, 0.15, 0.0), (-0.17, 0.18, 0.0), (-0.215, 0.215, 0.0)], 6)
    tail_r = np.linspace(1.0, 0.0, 6)[:, None] * np.array([0.035, 0.055])
    tail = tube(tail_path, tail_r, 14, cap_start=True, name="tail", material="duck_body")
    neck = tube([(0.075, 0.14, 0.0), (0.09, 0.2, 0.0), (0.1, 0.25, 0.0)], [0.06, 0.055, 0.05], 16,
                cap_start=True, cap_end=True, name="neck", material="duck_body")
    head_c = np.array([0.1, 0.275, 0.0])
    head = ellipsoid((0.075, 0.072, 0.07), head_c, 24, 12, name="head", material="duck_body")
    beak = ellipsoid((0.06, 0.017, 0.038), (0.0, 0.0, 0.0), 16, 8, name="beak", material="duck_beak")
    beak = beak.warped(lambda p: p + np.c_[np.zeros(len(p)), -0.15 * np.clip(p[:, 0], 0, None), np.zeros(len(p))])
    beak = beak.rotated("z", -8).moved(0.175, 0.262, 0.0)
    parts = [body, tail, neck, head, beak]
    for side in (1, -1):
        wing = ellipsoid((0.11, 0.045, 0.024), (0, 0, 0), 20, 10, name="wing", material="duck_body")
        wing = wing.rotated("z", -14).rotated("y", -9 * side).moved(-0.025, 0.145, 0.105 * side)
        direction = np.array([0.55, 0.32, 0.77 * side])
        direction /= np.linalg.norm(direction)
        eye_c = head_c + direction * 0.066
        eye = ellipsoid((0.012, 0.013, 0.012), eye_c, 10, 6, name="eye", material="duck_eye")
        parts += [wing.named("wing_left" if side > 0 else "wing_right"),
                  eye.named("eye_left" if side > 0 else "eye_right")]
    parts.sort(key=lambda p: ["duck_body", "duck_beak", "duck_eye"].index(p.material))
    materials = {
        "duck_body": Material(linear("#f5c518"), ks=(0.25, 0.25, 0.2), ns=10),
        "duck_beak": Material(linear("#f07818"), ks=(0.2, 0.2, 0.2), ns=10),
        "duck_eye": Material(linear("#0a0a0a"), ks=(0.8, 0.8, 0.8), ns=80),
    }
    return Model("duck", parts, materials, normals=False, triangles_only=True,
                 description="Duck, 0.36 m long, facing +X; three materials; no normals (computed smooth).")


def make_cat() -> Model:
    """Sitting cat, 0.48 m to the ear tips, facing +Z; one material, no normals."""
    m = "cat_fur"
    parts = [
        ellipsoid((0.1, 0.15, 0.11), (0, 0, 0), 28, 14, name="torso").rotated("x", -12).moved(0, 0.17, -0.02),
        ellipsoid((0.075, 0.09, 0.07), (0, 0.2, 0.055), 20, 10, name="chest"),
        ellipsoid((0.085, 0.075, 0.075), (0, 0.37, 0.03), 24, 12, name="head"),
        ellipsoid((0.042, 0.028, 0.03), (0, 0.345, 0.088), 14, 7, name="muzzle"),
    ]
    for side in (1, -1):
        parts.append(ellipsoid((0.062, 0.08, 0.11), (0.075 * side, 0.08, -0.035), 20, 10, name="haunch"))
        parts.append(ellipsoid((0.03, 0.02, 0.05), (0.095 * side, 0.02, 0.045), 12, 6, name="hind_paw"))
        leg = tube([(0.038 * side, 0.2, 0.06), (0.04 * side, 0.11, 0.075), (0.042 * side, 0.03, 0.09)],
                   [0.026, 0.024, 0.022], 12, cap_start=True, cap_end=True, name="front_leg")
        parts.append(leg)
        parts.append(ellipsoid((0.027, 0.018, 0.036), (0.043 * side, 0.018, 0.105), 12, 6, name="front_paw"))
        ear = lathe([(0, 0), (0.034, 0), (0, 0.072)], 12, name="ear")
        ear = ear.scaled(1.0, 1.0, 0.45).rotated("z", -22 * side).moved(0.046 * side, 0.415, 0.025)
        parts.append(ear)
        eye = ellipsoid((0.014, 0.012, 0.008), (0.032 * side, 0.385, 0.095), 10, 6, name="eye")
        parts.append(eye)
    tail_path = smooth_path([(0.0, 0.05, -0.125), (0.09, 0.025, -0.13), (0.155, 0.022, -0.04),
                             (0.15, 0.022, 0.06), (0.11, 0.035, 0.125)], 18)
    t = np.linspace(0, 1, 18)
    tail_r = 0.019 * np.sqrt(np.clip((1 - t) / 0.08, 0, 1)) * (1 - 0.2 * t)   # rounded tip
    parts.append(tube(tail_path, tail_r, 12, cap_start=True, name="tail"))
    parts = [p.named(p.name, m) for p in parts]
    materials = {m: Material(linear("#c98a4b"), ks=(0.15, 0.15, 0.15), ns=5)}
    return Model("cat", parts, materials, normals=False,
                 description="Sitting cat, 0.48 m tall, facing +Z; one material; no normals (computed smooth).")


def make_lamp() -> Model:
    """Garden street lamp, 2.55 m: octagonal post, bracket arm, hanging lantern. Written
    with per-face normals (flat look) and quads/fans as they come."""
    metal, glass = "lamp_metal", "lamp_glass"
    flat = 1.0   # degrees: every face keeps its own normal
    octagon = dict(segments=8, phase=22.5, smooth_angle=flat, material=metal)
    parts = [
        lathe([(0, 0), (0.2, 0), (0.2, 0.1), (0.14, 0.16), (0.11, 0.32), (0.075, 0.36)], cap_top="ngon",
              name="base", **octagon),
        lathe([(0.065, 0.36), (0.05, 2.3)], cap_top="ngon", name="post", **octagon),
        lathe([(0, 2.2), (0.075, 2.2), (0.075, 2.3), (0.06, 2.33), (0.03, 2.36), (0.03, 2.42),
               (0.05, 2.46), (0, 2.55)], name="finial", **octagon),
    ]
    square = dict(segments=4, phase=45.0, smooth_angle=flat, material=metal, cap_start=True, cap_end=True)
    bar = 0.02 * math.sqrt(2)
    parts.append(tube([(0.0, 2.12, 0.0), (0.62, 2.12, 0.0)], [bar, bar], name="arm", **square))
    parts.append(tube(smooth_path([(0.02, 1.8, 0), (0.15, 1.9, 0), (0.3, 2.02, 0), (0.45, 2.1, 0)], 6),
                      [bar * 0.7] * 6, name="brace", **square))
    # Lantern hanging from the arm's end, classic shape: wider at the top.
    lx = 0.55
    pyramid = dict(segments=4, phase=45.0, smooth_angle=flat)
    lantern = [
        lathe([(0.012, 2.05), (0.012, 2.12)], name="hanger", material=metal, segments=6, smooth_angle=flat),
        lathe([(0, 1.92), (0.2, 1.92), (0.2, 1.95), (0, 2.07)], name="roof", material=metal, **pyramid),
        lathe([(0, 1.6), (0.08, 1.62), (0.11, 1.66)], cap_top="ngon", name="bottom", material=metal, **pyramid),
        lathe([(0.11, 1.66), (0.16, 1.92)], name="glass", material=glass, **pyramid),
    ]
    for sx, sz in itertools.product((1, -1), repeat=2):
        lantern.append(tube([(0.078 * sx, 1.66, 0.078 * sz), (0.113 * sx, 1.92, 0.113 * sz)],
                            [0.012, 0.012], name="frame_edge", **square))
    parts += [p.moved(lx, 0, 0) for p in lantern]
    parts.sort(key=lambda p: p.material == glass)
    materials = {
        metal: Material(linear("#1f2a24"), ks=(0.4, 0.4, 0.4), ns=30, comment="dark green painted iron"),
        glass: Material(linear("#fff1c4"), ks=(0.8, 0.8, 0.8), ns=90, ke=linear("#ffd27a"),
                        comment="lit lantern glass (emissive)"),
    }
    return Model("lamp", parts, materials,
                 description="Garden street lamp, 2.55 m, arm towards +X; per-face normals (flat).")


def contribution_counts() -> np.ndarray:
    """A plausible 7 x 12 'contributions' grid (days x weeks): busier on weekdays, with
    a few streaky weeks and quiet gaps."""
    gen = np.random.default_rng(4)
    weekday = np.array([0.3, 1.0, 1.1, 1.0, 1.2, 0.9, 0.35])[:, None]
    weekly = np.array([0.4, 0.8, 1.4, 1.6, 0.6, 0.1, 0.9, 1.2, 1.8, 1.0, 0.7, 1.3])[None, :]
    counts = gen.poisson(4.2 * weekday * weekly)
    counts[gen.random(counts.shape) < 0.12] = 0
    return counts


def make_bars() -> Model:
    """3D contribution chart: 7 days x 12 weeks of bars on a base plate, GitHub greens
    by level. Boxes with per-face normals in the file."""
    counts = contribution_counts()
    pitch, width = 0.1, 0.08
    levels = np.digitize(counts, [1, 4, 7, 10])          # 0 = none .. 4 = busiest
    parts = [box((12 * pitch + 0.06, 0.03, 7 * pitch + 0.06), (0, 0.015, 0), name="base", material="chart_base")]
    for day, week in itertools.product(range(7), range(12)):
        h = 0.012 + 0.022 * counts[day, week]
        x = (week - 5.5) * pitch
        z = (day - 3) * pitch
        parts.append(box((width, h, width), (x, 0.03 + h / 2, z), name=f"w{week:02d}d{day}",
                         material=f"level{levels[day, week]}", skip_bottom=True))
    parts.sort(key=lambda p: p.material)
    colours = ["#d5d8dc", "#9be9a8", "#40c463", "#30a14e", "#216e39"]
    materials = {"chart_base": Material(linear("#3a3f44"), ks=(0.2, 0.2, 0.2), ns=20)}
    for i, c in enumerate(colours):
        materials[f"level{i}"] = Material(linear(c), ks=(0.3, 0.3, 0.3), ns=20,
                                          comment=f"contribution level {i}")
    return Model("bars", parts, materials,
                 description="Contribution chart, 7 x 12 bars, 1.26 x 0.76 m base; vertex normals (v//vn).")


def make_fox() -> Model:
    """Fox, 1.0 m nose to tail, facing +X, standing; UV-mapped onto the fox.png atlas
    (see make_fox_atlas for its regions)."""
    m = "fox_fur"
    fur = dict(uv=True, material=m, v_range=(0.5, 1.0))
    parts = [
        ellipsoid((0.27, 0.12, 0.115), (0.0, 0.38, 0.0), 24, 12, name="body", **fur),
        ellipsoid((0.13, 0.13, 0.1), (0.17, 0.41, 0.0), 16, 8, name="chest", **fur),
        ellipsoid((0.12, 0.11, 0.105), (-0.19, 0.39, 0.0), 16, 8, name="hips", **fur),
        tube([(0.17, 0.43, 0), (0.24, 0.5, 0), (0.29, 0.56, 0)], [0.075, 0.07, 0.06], 14, uv=True,
             v_range=(0.55, 0.9), cap_start=True, cap_end=True, name="neck", material=m),
        ellipsoid((0.085, 0.075, 0.08), (0.32, 0.6, 0.0), 18, 9, name="head", **fur),
        tube(smooth_path([(0.33, 0.59, 0), (0.42, 0.565, 0), (0.47, 0.55, 0)], 5), [0.055, 0.04, 0.026, 0.015, 0.0],
             14, uv=True, v_range=(0.6, 0.75), cap_start=True, name="snout", material=m),
        ellipsoid((0.014, 0.013, 0.014), (0.47, 0.553, 0), 8, 5, uv=True, v_range=(0.05, 0.2),
                  name="nose", material=m),
    ]
    # Put the nose and eyes into the atlas's black corner.
    black = lambda part: replace(part, uv=np.column_stack([0.6 + 0.3 * part.uv[:, 0], part.uv[:, 1]]))
    parts[-1] = black(parts[-1])
    for side in (1, -1):
        ear = lathe([(0, 0), (0.04, 0), (0.03, 0.05), (0, 0.1)], 12, uv=True, v_scale=0.1,
                    name="ear", material=m)
        # Ears: the leg region turned upside down (not mirrored), so dark tips.
        ear = replace(ear, uv=np.column_stack([0.45 - ear.uv[:, 0] * 0.45, 0.22 - 0.2 * ear.uv[:, 1]]))
        ear = ear.scaled(1.0, 1.0, 0.45).rotated("x", 12 * side).rotated("z", 8).moved(0.305, 0.655, 0.045 * side)
        eye = ellipsoid((0.012, 0.014, 0.01), (0.385, 0.625, 0.045 * side), 8, 5, uv=True, v_range=(0.05, 0.2),
                        name="eye", material=m)
        parts += [ear, black(eye)]
        for x, knee in ((0.17, 0.03), (-0.2, -0.05)):
            # Swept from the paw up, so v (and the atlas's orange-to-sock fade) runs upwards.
            leg_path = smooth_path([(x + 0.01, 0.04, 0.07 * side), (x + knee, 0.2, 0.07 * side),
                                    (x, 0.38, 0.065 * side)], 6)
            leg = tube(leg_path, np.linspace(0.024, 0.045, 6), 10, uv=True, v_range=(0.05, 0.24),
                       cap_start=True, cap_end=True, name="leg", material=m)
            leg = replace(leg, uv=np.column_stack([leg.uv[:, 0] * 0.45, leg.uv[:, 1]]))
            paw = ellipsoid((0.04, 0.022, 0.028), (x + 0.025, 0.022, 0.07 * side), 8, 5, uv=True,
                            v_range=(0.03, 0.08), name="paw", material=m)
            paw = replace(paw, uv=np.column_stack([paw.uv[:, 0] * 0.45, paw.uv[:, 1]]))
            parts += [leg, paw]
    tail_path = smooth_path([(-0.26, 0.42, 0), (-0.38, 0.4, 0), (-0.5, 0.3, 0), (-0.6, 0.22, 0.02),
                             (-0.68, 0.2, 0.04)], 14)
    t = np.linspace(0, 1, 14)
    tail_r = (0.035 + 0.07 * np.sin(np.pi * np.clip(t * 1.1, 0, 1)) ** 0.8) * np.sqrt(np.clip((1 - t) / 0.12, 0, 1))
    parts.append(tube(tail_path, tail_r, 14, uv=True, v_range=(0.26, 0.49), cap_start=True, name="tail", material=m))
    materials = {m: Material(WHITE, ks=(0.08, 0.08, 0.08), ns=8, map_kd=tex("fox.png"))}
    return Model("fox", parts, materials, description="Fox, 1.15 m nose to tail, facing +X; UV atlas fox.png.")
