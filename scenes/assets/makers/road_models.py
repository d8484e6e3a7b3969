"""The foggy road's models (seed 002)."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .common import linear
from .geometry import box, ellipsoid, lathe, smooth_path, tube
from .obj_files import Material, Model, tex, WHITE


def make_pine() -> Model:
    """Pine, 8 m: thin trunk and three stacked needle cones whose ragged, drooping skirts
    (a star-shaped radius) read as branch tiers."""
    trunk = lathe([(0, 0), (0.3, 0), (0.2, 0.25), (0.15, 2.0), (0.06, 7.0), (0, 7.2)], 10, uv=True,
                  u_repeat=1, v_scale=1.0, name="trunk", material="pine_bark")
    parts = [trunk]
    tiers = ((1.0, 2.6, 4.6), (2.7, 2.0, 6.1), (4.3, 1.4, 7.9))
    for k, (base, radius, apex) in enumerate(tiers):
        h = apex - base
        ridges = lambda theta, k=k: 1.0 + 0.13 * np.cos(9 * theta + 1.7 * k) + 0.05 * np.cos(23 * theta + k)
        cone = lathe([(0, base + 0.55), (radius * 0.97, base + 0.05), (radius, base), (radius * 0.62, base + 0.3 * h),
                      (radius * 0.3, base + 0.65 * h), (0, apex)], 36, uv=True, u_repeat=4, v_scale=2.0,
                     radius_fn=ridges, name=f"tier{k}", material="pine_needles" if k % 2 == 0 else "pine_needles_dark",
                     smooth_angle=70)
        # Branch tips droop: the further out a rim vertex reaches, the lower it hangs.
        reach = np.hypot(cone.v[:, 0], cone.v[:, 2]) / radius
        droop = 0.25 * np.clip(reach - 0.9, 0, None) * (cone.v[:, 1] < base + 0.1)
        parts.append(replace(cone, v=cone.v - np.c_[np.zeros_like(droop), droop, np.zeros_like(droop)]))
    materials = {
        "pine_bark": Material(WHITE, ka=(0.7, 0.7, 0.7), ks=(0.03, 0.03, 0.03), ns=4, map_kd=tex("bark.png")),
        "pine_needles": Material(linear("#1f4a2a"), ks=(0.08, 0.1, 0.08), ns=10),
        "pine_needles_dark": Material(linear("#173a22"), ks=(0.08, 0.1, 0.08), ns=10),
    }
    return Model("pine", parts, materials, description="Pine tree, 7.9 m tall, 5.2 m wide at the bottom tier.")


def make_streetlight() -> Model:
    """Road street light, 7.4 m: tapered post, curved arm towards +X, a flat lamp head with
    an emissive glass bowl underneath (put a spot light at about (1.77, 7.2, 0))."""
    metal = "streetlight_metal"
    post = lathe([(0, 0), (0.22, 0), (0.22, 0.08), (0.14, 0.13), (0.12, 0.6), (0.09, 0.7), (0.075, 6.8), (0, 6.86)],
                 16, name="post", material=metal, smooth_angle=40)
    arm_path = smooth_path([(0, 6.5, 0), (0.0, 7.05, 0), (0.3, 7.33, 0), (1.0, 7.42, 0), (1.45, 7.4, 0)], 14)
    arm = tube(arm_path, np.linspace(0.055, 0.045, 14), 10, cap_start=True, cap_end=True, name="arm",
               material=metal)
    head = ellipsoid((0.5, 0.12, 0.22), (0, 0, 0), 24, 10, name="head", material=metal)
    head = head.warped(lambda p: np.column_stack([p[:, 0], np.maximum(p[:, 1], -0.04), p[:, 2]]))  # flat underside
    glass = ellipsoid((0.38, 0.06, 0.16), (0, 0, 0), 20, 8, name="glass", material="streetlight_glass")
    glass = glass.warped(lambda p: np.column_stack([p[:, 0], np.minimum(p[:, 1], 0.0), p[:, 2]]))
    parts = [post, arm, head.rotated("z", 4).moved(1.75, 7.38, 0), glass.rotated("z", 4).moved(1.77, 7.345, 0)]
    materials = {
        metal: Material(linear("#50555a"), ks=(0.5, 0.5, 0.5), ns=40),
        "streetlight_glass": Material(linear("#fff0d0"), ks=(0.9, 0.9, 0.9), ns=100, ke=linear("#ffd89a"),
                                      comment="lamp glass (emissive)"),
    }
    return Model("streetlight", parts, materials, description="Street light, 7.5 m tall, arm 2.2 m towards +X.")


def make_fence() -> Model:
    """Rustic fence, 10 m along X: six square posts with pyramid tops and two rails per
    bay, each piece slightly off true (seeded)."""
    gen = np.random.default_rng(450)
    wood = "fence_wood"
    half_diag = 0.06 * math.sqrt(2)
    parts = []
    xs = np.linspace(-5, 5, 6)
    for i, x in enumerate(xs):
        post = lathe([(0, 0), (half_diag, 0), (half_diag, 1.12), (0, 1.26)], 4, phase=45, name=f"post{i}",
                     material=wood, smooth_angle=20)
        parts.append(post.rotated("z", gen.uniform(-2, 2)).rotated("x", gen.uniform(-2, 2)).moved(x, 0, 0))
    for i in range(len(xs) - 1):
        for height in (0.45, 0.92):
            length = xs[i + 1] - xs[i] + 0.16
            y = height + gen.uniform(-0.03, 0.03)
            rail = box((length, 0.1, 0.035), (0, 0, 0), name=f"rail{i}", material=wood)
            parts.append(rail.rotated("z", gen.uniform(-1.2, 1.2)).moved((xs[i] + xs[i + 1]) / 2, y, 0.08))
    materials = {wood: Material(linear("#6b4a2f"), ks=(0.05, 0.05, 0.05), ns=6, comment="weathered wood")}
    return Model("fence", parts, materials, description="Fence, 10.2 m along X, 1.26 m tall, rails on the +Z side.")
