"""The texture images of the example scenes (textures/)."""
from __future__ import annotations

import itertools
import math

import numpy as np

from .common import mix, normalize01, smoothstep, srgb, TEXTURES
from .images import save_image
from .noise import fbm, normal_map_from_height, texture_uv, tiling_fbm, wrapped_distance


def stamp_discs(image: np.ndarray, gen, count: int, radius: tuple, colours: list, softness=0.8):
    """Scatter soft round spots (flowers, pebbles, aggregate) over an image, wrapping at
    the edges so the image still tiles."""
    height, width = image.shape[:2]
    for _ in range(count):
        cx, cy = gen.uniform(0, width), gen.uniform(0, height)
        r = gen.uniform(*radius)
        colour = colours[gen.integers(len(colours))]
        dx, dy = wrapped_distance(width, height, cx, cy)
        cover = 1.0 - smoothstep(r - softness, r + softness, np.hypot(dx, dy))
        image[:] = mix(image, colour, cover)
    return image


def make_checker() -> np.ndarray:
    """8 x 8 grey/white checker for floors: exact 32 px squares, no noise."""
    u, v = texture_uv(256, 256)
    odd = (np.floor(u * 8) + np.floor(v * 8)) % 2
    return mix(srgb("#8c8c8c"), srgb("#f0f0f0"), odd)


def make_garden_grass() -> np.ndarray:
    """Lawn: patchy greens plus short vertical blade streaks."""
    size = 256
    patches = tiling_fbm(size, size, 6, seed=11)
    blades = tiling_fbm(size, size, (96, 24), seed=12, octaves=2)
    specks = tiling_fbm(size, size, 64, seed=13, octaves=1)
    colour = mix(srgb("#2f5a17"), srgb("#6d9a2c"), smoothstep(-0.5, 0.6, patches))
    colour = colour * (0.82 + 0.3 * smoothstep(-0.6, 0.6, blades))[..., None]
    colour = mix(colour, srgb("#a7b248"), 0.6 * smoothstep(0.45, 0.7, specks))
    return colour


def make_island_grass() -> np.ndarray:
    """Brighter, stylised meadow with small white and yellow flowers."""
    size = 256
    patches = tiling_fbm(size, size, 5, seed=21)
    detail = tiling_fbm(size, size, 48, seed=22, octaves=2)
    colour = mix(srgb("#3f7d22"), srgb("#86b83f"), smoothstep(-0.5, 0.5, patches))
    colour = colour * (0.88 + 0.2 * detail)[..., None]
    gen = np.random.default_rng(23)
    stamp_discs(colour, gen, 70, (1.2, 2.2), [srgb("#f4f1e4"), srgb("#f2d33c"), srgb("#e8a1c0")])
    return colour


def make_rock() -> np.ndarray:
    """Grey-brown rock with strata and dark cracks."""
    size = 256
    u, v = texture_uv(size, size)
    body = tiling_fbm(size, size, 6, seed=31)
    cracks = 1.0 - np.abs(tiling_fbm(size, size, 5, seed=32, octaves=4))
    strata = np.sin(2 * np.pi * (6 * v + 0.35 * tiling_fbm(size, size, 3, seed=33, octaves=3)))
    colour = mix(srgb("#5c544b"), srgb("#958b7c"), smoothstep(-0.6, 0.6, body + 0.15 * strata))
    colour = mix(colour, srgb("#2e2a26"), 0.8 * smoothstep(0.9, 0.98, cracks))
    return colour * (0.9 + 0.1 * tiling_fbm(size, size, 64, seed=34, octaves=2))[..., None]


def make_bark() -> np.ndarray:
    """Bark of vertical plates split by dark, wandering fissures (where warped noise
    crosses zero); 128 x 256 so one repeat covers about a metre of trunk."""
    width, height = 128, 256
    u, v = texture_uv(width, height)
    warp = tiling_fbm(width, height, (2, 4), seed=43, octaves=3)
    n = fbm(np.stack([u * 6 + warp, v * 2], axis=-1), 41, octaves=4, period=(6, 2))
    plates = smoothstep(0.02, 0.12, np.abs(n))
    fine = tiling_fbm(width, height, (24, 12), seed=42, octaves=3)
    colour = mix(srgb("#1e140d"), srgb("#7a5a3e"), plates * (0.7 + 0.3 * smoothstep(-0.5, 0.5, fine)))
    return colour * (0.85 + 0.2 * tiling_fbm(width, height, (4, 8), seed=44, octaves=2))[..., None]


def make_leaves() -> np.ndarray:
    """Foliage: hundreds of small overlapping leaves in varied greens on dark shade."""
    size = 256
    colour = mix(srgb("#14300e"), srgb("#24501a"), normalize01(tiling_fbm(size, size, 6, seed=51)))
    gen = np.random.default_rng(52)
    shades = [srgb(c) for c in ("#3d7a25", "#4f8f2c", "#2f6a20", "#6aa336", "#558a30")]
    for _ in range(520):
        cx, cy = gen.uniform(0, size, 2)
        angle = gen.uniform(0, np.pi)
        length, width = gen.uniform(6, 11), gen.uniform(2.5, 4.0)
        dx, dy = wrapped_distance(size, size, cx, cy)
        a = dx * np.cos(angle) + dy * np.sin(angle)
        b = -dx * np.sin(angle) + dy * np.cos(angle)
        shape = (a / length) ** 2 + (b / width) ** 2
        cover = 1.0 - smoothstep(0.75, 1.0, shape)
        # Lighter midrib and darker edge give each leaf a little volume.
        tone = shades[gen.integers(len(shades))] * (1.05 - 0.25 * np.clip(shape, 0, 1))[..., None]
        colour = mix(colour, tone, cover)
    return colour


def make_stone_wall() -> np.ndarray:
    """Castle ashlar: 4 courses of grey blocks of random widths, mortar joints."""
    return ashlar(256, courses=4, seed=61, palette=("#6f6c66", "#a19c92"), mortar="#4a4741")[0]


def ashlar(size: int, courses: int, seed: int, palette, mortar, block_px=(48, 110), joint=3.0):
    """Tiling masonry of staggered blocks. Returns (colour, height, joint mask) so the same
    layout drives diffuse, normal and specular maps."""
    gen = np.random.default_rng(seed)
    rows = np.arange(size) + 0.5
    cols = np.arange(size) + 0.5
    course_h = size / courses
    edge_dist = np.zeros((size, size))
    block_tone = np.zeros((size, size))
    for course in range(courses):
        # Joint positions within this course, wrapping around the image width.
        cuts, x = [], gen.uniform(0, size)
        while True:
            cuts.append(x % size)
            x += gen.uniform(*block_px)
            if x - cuts[0] > size - block_px[0] * 0.6:
                break
        cuts = np.sort(np.array(cuts))
        in_course = (rows >= course * course_h) & (rows < (course + 1) * course_h)
        y0 = course * course_h
        dy = np.minimum(rows[in_course] - y0, y0 + course_h - rows[in_course])
        rel = (cols[None, :] - cuts[:, None]) % size            # distance past each cut
        block = np.argmin(rel, axis=0)                          # block index per column
        dx_left = rel[block, np.arange(size)]
        dx_right = (cuts[(block + 1) % len(cuts)] - cols) % size
        dx = np.minimum(dx_left, dx_right)
        edge_dist[in_course] = np.minimum(dy[:, None], dx[None, :])
        tones = gen.uniform(0, 1, len(cuts))
        block_tone[in_course] = tones[block][None, :]
    grain = tiling_fbm(size, size, 16, seed=seed + 1, octaves=4)
    joints = 1.0 - smoothstep(joint * 0.5, joint * 0.5 + 1.5, edge_dist)
    base = mix(srgb(palette[0]), srgb(palette[1]), np.clip(0.25 + 0.5 * block_tone + 0.35 * grain, 0, 1))
    colour = mix(base, srgb(mortar), joints)
    # Blocks are slightly pillowed: flat faces whose edges round down into the joint.
    height = smoothstep(joint * 0.5, joint * 0.5 + 5.0, edge_dist) * 0.8 + 0.2 + 0.06 * grain
    return colour, height, joints


def make_flag_texture() -> np.ndarray:
    """Flag cloth: vertical blue/black stripes with a faint weave (256 x 128)."""
    width, height = 256, 128
    u, _ = texture_uv(width, height)
    stripe = np.floor(u * 5) % 2
    colour = mix(srgb("#1c4fb8"), srgb("#141414"), stripe)
    weave = tiling_fbm(width, height, (64, 32), seed=71, octaves=1)
    return colour * (0.93 + 0.07 * weave)[..., None]


def make_road() -> np.ndarray:
    """Asphalt lane seen from above, the road running along v: solid edge lines and one
    dash of the centre line per tile, so it tiles along the road's length."""
    size = 256
    u, v = texture_uv(size, size)
    grain = tiling_fbm(size, size, 32, seed=81, octaves=3)
    stains = tiling_fbm(size, size, (3, 3), seed=82, octaves=3)
    colour = mix(srgb("#2a2a2c"), srgb("#4a4a4c"), smoothstep(-0.6, 0.7, grain))
    colour = colour * (0.9 + 0.12 * stains)[..., None]
    gen = np.random.default_rng(83)
    stamp_discs(colour, gen, 260, (0.4, 1.0), [srgb("#6b6b6b"), srgb("#1c1c1c")], softness=0.5)
    wear = smoothstep(-0.3, 0.4, tiling_fbm(size, size, 24, seed=84, octaves=3))
    paint = np.zeros_like(u)
    for edge in (0.07, 0.93):
        paint = np.maximum(paint, 1.0 - smoothstep(0.012, 0.018, np.abs(u - edge)))
    dash = (1.0 - smoothstep(0.012, 0.018, np.abs(u - 0.5))) * (1.0 - smoothstep(0.245, 0.25, np.abs(v - 0.5)))
    colour = mix(colour, srgb("#d8d2bd"), paint * (0.55 + 0.4 * wear))
    colour = mix(colour, srgb("#e2b93b"), dash * (0.55 + 0.4 * wear))
    return colour


def make_dirt() -> np.ndarray:
    """Bare earth with damp patches and small pebbles."""
    size = 256
    earth = tiling_fbm(size, size, 5, seed=91)
    damp = tiling_fbm(size, size, 3, seed=92, octaves=3)
    colour = mix(srgb("#4b3626"), srgb("#7f6245"), smoothstep(-0.6, 0.6, earth))
    colour = mix(colour, srgb("#35261b"), 0.5 * smoothstep(0.1, 0.5, damp))
    colour = colour * (0.88 + 0.14 * tiling_fbm(size, size, 64, seed=93, octaves=2))[..., None]
    gen = np.random.default_rng(94)
    stamp_discs(colour, gen, 120, (1.0, 3.0), [srgb("#8d8073"), srgb("#6e655c"), srgb("#a39685")])
    return colour


def make_marble() -> np.ndarray:
    """White marble: soft grey veins plus a web of thin ones. Each vein follows a wave of
    whole periods across the tile, bent by tiling noise, so the image tiles."""
    size = 256
    u, v = texture_uv(size, size)
    wave = np.sin(2 * np.pi * (u + v) + 3.5 * tiling_fbm(size, size, 3, seed=101, octaves=5))
    veins = 1.0 - smoothstep(0.0, 0.25, np.abs(wave))
    thin_wave = np.sin(2 * np.pi * (3 * u - v) + 5.0 * tiling_fbm(size, size, 5, seed=102, octaves=5))
    thin = 1.0 - smoothstep(0.0, 0.08, np.abs(thin_wave))
    clouds = tiling_fbm(size, size, 3, seed=103, octaves=4)
    colour = mix(srgb("#efece6"), srgb("#d3cec6"), smoothstep(-0.5, 0.5, clouds))
    colour = mix(colour, srgb("#8a8783"), 0.55 * veins * (0.6 + 0.4 * smoothstep(-0.3, 0.3, clouds)))
    return mix(colour, srgb("#77746f"), 0.4 * thin)


def make_fox_atlas() -> np.ndarray:
    """Fox fur atlas (256 px). Regions by v (bottom = 0):
       v 0.5-1   body fur for ellipsoids: cream belly (low v) to orange to dark back, with
                 darker tiger-like stripes around the body,
       v 0.25-.5 tail: orange base (low v) to a white tip (high v),
       v 0-.25   u < .5: legs/ears, orange at the top to dark brown 'socks' at the bottom;
                 u > .5: near-black for the nose and eyes."""
    size = 256
    u, v = texture_uv(size, size)
    streaks = tiling_fbm(size, size, (48, 6), seed=111, octaves=3)
    orange, dark_orange, cream = srgb("#d8661e"), srgb("#8e3a12"), srgb("#f3e6cf")
    colour = np.zeros((size, size, 3))
    # Body: latitude t runs 0 (belly) to 1 (spine).
    t = np.clip((v - 0.5) / 0.5, 0, 1)
    body = mix(cream, orange, smoothstep(0.25, 0.45, t + 0.04 * streaks))
    body = mix(body, dark_orange, smoothstep(0.7, 1.0, t))
    stripes = smoothstep(0.55, 0.85, np.sin(2 * np.pi * 14 * u + 2.5 * streaks)) * smoothstep(0.35, 0.6, t)
    body = mix(body, srgb("#4a1f0b"), 0.55 * stripes)
    colour[v >= 0.5] = body[v >= 0.5]
    # Tail: length l runs 0 (base) to 1 (tip).
    length = np.clip((v - 0.25) / 0.25, 0, 1)
    tail = mix(orange, dark_orange, 0.35 * smoothstep(0.2, 0.6, streaks + 0.3))
    tail = mix(tail, cream, smoothstep(0.72, 0.86, length + 0.03 * streaks))
    band = (v >= 0.25) & (v < 0.5)
    colour[band] = tail[band]
    # Legs: orange high, dark socks low.
    legs = mix(srgb("#2b160c"), orange, smoothstep(0.08, 0.16, v + 0.01 * streaks))
    leg_zone = (v < 0.25) & (u < 0.5)
    colour[leg_zone] = legs[leg_zone]
    colour[(v < 0.25) & (u >= 0.5)] = srgb("#151010")
    return colour * (0.92 + 0.1 * streaks)[..., None]


def make_column_maps():
    """Limestone blocks for the column: diffuse, normal (from the block height field, so
    joints read as real grooves) and specular (dull joints, shinier polished stone)."""
    colour, height, joints = ashlar(256, courses=4, seed=121, palette=("#b9a98a", "#e2d6bb"),
                                    mortar="#6f6453", block_px=(70, 140), joint=4.0)
    chisel = tiling_fbm(256, 256, 24, seed=122, octaves=3)
    height = height + 0.04 * chisel
    normal = normal_map_from_height(height * 12.0, strength=0.5)
    specular = np.clip(0.55 + 0.2 * chisel - 0.5 * joints, 0.05, 1.0)
    return colour, normal, specular


def make_crate_maps():
    """Wooden crate face: raised frame boards, a diagonal brace, recessed horizontal
    planks with gaps, and nails. Returns (diffuse, normal)."""
    size = 256
    u, v = texture_uv(size, size)
    x, y = u * size, v * size                                     # pixels, y up
    border = 30.0
    grain_h = tiling_fbm(size, size, (4, 48), seed=131, octaves=3)   # grain along u
    grain_v = tiling_fbm(size, size, (48, 4), seed=132, octaves=3)   # grain along v
    # Recessed planks: 4 horizontal boards between the frame, 3 px gaps.
    plank_pitch = (size - 2 * border) / 4.0
    plank_y = (y - border) % plank_pitch
    gap = np.minimum(plank_y, plank_pitch - plank_y)
    plank_height = 0.35 + 0.15 * smoothstep(1.0, 4.0, gap)
    plank_tone = np.floor((y - border) / plank_pitch)
    # Frame: top/bottom boards run along u, side boards along v.
    edge = np.minimum.reduce([x, size - x, y, size - y])
    in_frame = edge < border
    side_board = np.minimum(x, size - x) < border          # left/right boards run full height
    frame_height = 0.95 - 0.25 * (1.0 - smoothstep(0.0, 3.0, border - edge)) - 0.2 * (1 - smoothstep(0, 2.5, edge))
    # Brace from bottom-left to top-right corner of the inner panel.
    brace_dist = np.abs((x - y)) / math.sqrt(2.0)
    in_brace = (brace_dist < 16.0) & ~in_frame
    brace_height = 0.8 - 0.2 * (1.0 - smoothstep(0.0, 3.0, 16.0 - brace_dist))
    height = np.where(in_frame, frame_height, np.where(in_brace, brace_height, plank_height))
    grain = np.where(in_frame & side_board, grain_v, grain_h)
    grain = np.where(in_brace, tiling_fbm(size, size, 24, seed=133, octaves=3), grain)
    height = height + 0.03 * grain
    light_wood, dark_wood = srgb("#b88a55"), srgb("#7a5430")
    tone = np.where(in_frame | in_brace, 0.25, 0.45 + 0.1 * (plank_tone % 2))
    colour = mix(light_wood, dark_wood, np.clip(tone + 0.35 * grain, 0, 1))
    colour = mix(colour, srgb("#3a2714"), 1.0 - smoothstep(0.25, 0.4, height))      # gaps
    # Nails near each frame corner.
    for cx, cy in itertools.product((15.0, size - 15.0), repeat=2):
        d = np.hypot(x - cx, y - cy)
        nail = 1.0 - smoothstep(2.5, 3.5, d)
        colour = mix(colour, srgb("#5b5d60"), nail)
        height = height + 0.08 * nail * np.sqrt(np.clip(1 - (d / 3.5) ** 2, 0, 1))
    normal = normal_map_from_height(height * 10.0, strength=0.6)
    return colour, normal


def write_textures() -> None:
    """Every 2D texture (sizes 128-512 px). Normal and specular maps are linear data."""
    save_image(make_checker(), TEXTURES / "checker.png")
    save_image(make_marble(), TEXTURES / "marble.png")
    save_image(make_garden_grass(), TEXTURES / "grass.bmp")
    save_image(make_fox_atlas(), TEXTURES / "fox.png")
    save_image(make_island_grass(), TEXTURES / "island_grass.png")
    save_image(make_rock(), TEXTURES / "rock.png")
    save_image(make_bark(), TEXTURES / "bark.png")
    save_image(make_leaves(), TEXTURES / "leaves.png")
    save_image(make_stone_wall(), TEXTURES / "stone.png")
    save_image(make_flag_texture(), TEXTURES / "flag.png")
    save_image(make_road(), TEXTURES / "road.png")
    save_image(make_dirt(), TEXTURES / "dirt.png")
    diffuse, normal, specular = make_column_maps()
    save_image(diffuse, TEXTURES / "column_diffuse.tga")
    save_image(normal, TEXTURES / "column_normal.tga")
    save_image(specular, TEXTURES / "column_specular.tga")
    diffuse, normal = make_crate_maps()
    save_image(diffuse, TEXTURES / "crate_diffuse.tga")
    save_image(normal, TEXTURES / "crate_normal.tga")
