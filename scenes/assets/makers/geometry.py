"""Parts, transforms and parametric surfaces the models are built from."""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace

import numpy as np

from .noise import fbm


@dataclass
class Part:
    """One piece of a model: polygons with one material. Faces are tuples of vertex indices
    (3 or more), counter-clockwise seen from outside."""
    name: str
    v: np.ndarray
    faces: list
    material: str = "default"
    uv: np.ndarray | None = None
    smooth_angle: float = 50.0        # neighbouring faces closer than this share normals
    relative_indices: bool = False    # write faces with negative (relative) OBJ indices

    def _apply(self, matrix: np.ndarray) -> "Part":
        moved = self.v @ matrix[:3, :3].T + matrix[:3, 3]
        faces = self.faces
        if np.linalg.det(matrix[:3, :3]) < 0:          # a mirror flips the winding
            faces = [tuple(reversed(f)) for f in faces]
        return replace(self, v=moved, faces=faces)

    def moved(self, x=0.0, y=0.0, z=0.0) -> "Part":
        m = np.eye(4)
        m[:3, 3] = (x, y, z)
        return self._apply(m)

    def scaled(self, x, y=None, z=None) -> "Part":
        y = x if y is None else y
        z = x if z is None else z
        return self._apply(np.diag([x, y, z, 1.0]))

    def rotated(self, axis: str, degrees: float) -> "Part":
        return self._apply(rotation(axis, degrees))

    def named(self, name: str, material: str | None = None, **changes) -> "Part":
        return replace(self, name=name, material=material or self.material, **changes)

    def warped(self, fn) -> "Part":
        """Move every vertex by fn(positions) -> new positions (for bends and noise)."""
        return replace(self, v=np.asarray(fn(self.v.copy()), dtype=float))

    @property
    def triangle_count(self) -> int:
        return sum(len(f) - 2 for f in self.faces)


def rotation(axis: str, degrees: float) -> np.ndarray:
    """4x4 right-handed rotation about a coordinate axis (counter-clockwise looking down it)."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    m = np.eye(4)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def grid_part(points: np.ndarray, uv: np.ndarray | None = None, name="grid", material="default",
              closed: bool = True, smooth_angle: float = 50.0) -> Part:
    """Quad mesh over a (rows, cols, 3) grid. Rows advance along the surface's v direction
    and columns along u, with u x v pointing outwards (so faces come out counter-clockwise).

    With `uv`, the grid carries its own seam column (cols = segments + 1) and no wrapping.
    Without, a `closed` grid wraps its last column to the first, so no vertex is duplicated
    and smooth normals computed from the file have no seam. Rows whose points coincide are
    poles: they become one vertex (without uv) and their neighbours become triangles."""
    rows, cols = points.shape[:2]
    wrap = closed and uv is None
    pole = [np.ptp(points[r], axis=0).max() < 1e-9 for r in range(rows)]
    index = np.zeros((rows, cols), dtype=np.int64)
    verts, uvs = [], []
    for r in range(rows):
        if pole[r] and uv is None:
            index[r, :] = len(verts)
            verts.append(points[r, 0])
            continue
        for c in range(cols):
            index[r, c] = len(verts)
            verts.append(points[r, c])
            if uv is not None:
                uvs.append(uv[r, c])
    faces = []
    span = cols if wrap else cols - 1
    for r in range(rows - 1):
        for c in range(span):
            c1 = (c + 1) % cols
            a, b, cc, d = index[r, c], index[r, c1], index[r + 1, c1], index[r + 1, c]
            if pole[r]:
                faces.append((int(a), int(cc), int(d)))
            elif pole[r + 1]:
                faces.append((int(a), int(b), int(cc)))
            else:
                faces.append((int(a), int(b), int(cc), int(d)))
    return Part(name, np.array(verts, dtype=float), faces, material,
                np.array(uvs, dtype=float) if uv is not None else None, smooth_angle)


def pole_uv_fix(uv: np.ndarray, points: np.ndarray) -> np.ndarray:
    """At a pole every column meets one point; centring each pole texel on its triangle
    avoids a visible swirl in the texture there."""
    rows, cols = points.shape[:2]
    for r in range(rows):
        if np.ptp(points[r], axis=0).max() < 1e-9:
            uv[r, :-1, 0] = (uv[r, :-1, 0] + uv[r, 1:, 0]) * 0.5
    return uv


def ellipsoid(radii, center=(0.0, 0.0, 0.0), segments=24, rings=12, uv=False,
              u_repeat=1.0, v_range=(0.0, 1.0), name="ellipsoid", material="default") -> Part:
    """Latitude/longitude ellipsoid with its poles on Y. u runs once around (times
    u_repeat), v from the bottom pole to the top pole mapped onto v_range."""
    phi = np.linspace(-np.pi / 2, np.pi / 2, rings + 1)
    cols = segments + 1 if uv else segments
    theta = np.arange(cols) * (2 * np.pi / segments)
    unit = np.stack([
        np.cos(phi)[:, None] * np.sin(theta)[None, :],
        np.repeat(np.sin(phi)[:, None], cols, axis=1),
        np.cos(phi)[:, None] * np.cos(theta)[None, :],
    ], axis=-1)
    unit[0], unit[-1] = (0.0, -1.0, 0.0), (0.0, 1.0, 0.0)     # exact poles
    points = unit * np.asarray(radii) + np.asarray(center)
    tex = None
    if uv:
        uu, vv = np.meshgrid(theta / (2 * np.pi) * u_repeat, np.linspace(*v_range, rings + 1))
        tex = pole_uv_fix(np.stack([uu, vv], axis=-1), points)
    return grid_part(points, tex, name, material)


def lathe(profile, segments=24, uv=False, u_repeat=1.0, v_scale=1.0, phase=0.0,
          radius_fn=None, cap_bottom=None, cap_top=None, name="lathe", material="default",
          smooth_angle=50.0) -> Part:
    """Surface of revolution about +Y. `profile` lists (radius, y) from the bottom up the
    outside to the top (radius 0 closes the end in a point). `radius_fn(theta)` may scale
    the radius per angle (flutes, ragged pine skirts). Caps close open ends: 'fan' (a
    centre vertex) or 'ngon' (one polygon face). With uv: u goes once around (times
    u_repeat), v is the distance along the profile divided by v_scale (world texel scale)."""
    profile = np.asarray(profile, dtype=float)
    cols = segments + 1 if uv else segments
    theta = np.arange(cols) * (2 * np.pi / segments) + math.radians(phase)
    factor = np.ones(cols) if radius_fn is None else radius_fn(theta)
    r = profile[:, 0:1] * factor[None, :]
    points = np.stack([r * np.sin(theta), np.repeat(profile[:, 1:2], cols, axis=1), r * np.cos(theta)], axis=-1)
    tex = None
    if uv:
        along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(profile, axis=0), axis=1))])
        uu, vv = np.meshgrid((theta - math.radians(phase)) / (2 * np.pi) * u_repeat, along / v_scale)
        tex = pole_uv_fix(np.stack([uu, vv], axis=-1), points)
    part = grid_part(points, tex, name, material, smooth_angle=smooth_angle)
    ring_of = {"bottom": points[0, :segments], "top": points[-1, :segments]}
    for end, kind in (("bottom", cap_bottom), ("top", cap_top)):
        if kind:
            part = merge([part, disc_cap(ring_of[end], end == "top", kind, uv, v_scale)], name)
    return part


def disc_cap(ring: np.ndarray, facing_up: bool, kind: str, uv: bool, uv_scale: float) -> Part:
    """Flat cap over a ring listed in increasing angle (counter-clockwise seen from +Y).
    Own vertices keep the rim edge sharp; planar UVs follow the box convention."""
    ring = ring if facing_up else ring[::-1]
    n = len(ring)
    verts = np.array(ring, dtype=float)
    if kind == "ngon":
        faces = [tuple(range(n))]
    else:
        center = ring.mean(axis=0)
        verts = np.vstack([verts, center])
        faces = [(n, i, (i + 1) % n) for i in range(n)]
    tex = None
    if uv:
        tex = np.stack([verts[:, 0], -verts[:, 2] if facing_up else verts[:, 2]], axis=-1) / uv_scale
    return Part("cap", verts, faces, "default", tex)


def merge(parts: list, name: str | None = None) -> Part:
    """Concatenate parts that share a material into one part."""
    verts, faces, uvs, offset = [], [], [], 0
    for p in parts:
        verts.append(p.v)
        faces.extend(tuple(i + offset for i in f) for f in p.faces)
        if p.uv is not None:
            uvs.append(p.uv)
        offset += len(p.v)
    first = parts[0]
    uv = np.vstack(uvs) if len(uvs) == len(parts) else None
    return replace(first, name=name or first.name, v=np.vstack(verts), faces=faces, uv=uv)


def smooth_path(control, samples: int) -> np.ndarray:
    """Catmull-Rom curve through control points, `samples` points in all."""
    p = np.asarray(control, dtype=float)
    p = np.vstack([2 * p[0] - p[1], p, 2 * p[-1] - p[-2]])
    out = []
    segments = len(p) - 3
    for t in np.linspace(0, segments, samples):
        i = min(int(t), segments - 1)
        u = t - i
        a, b, c, d = p[i:i + 4]
        out.append(0.5 * ((2 * b) + (-a + c) * u + (2 * a - 5 * b + 4 * c - d) * u ** 2
                          + (-a + 3 * b - 3 * c + d) * u ** 3))
    return np.array(out)


def tube(path, radii, segments=12, uv=False, u_repeat=1.0, v_range=(0.0, 1.0), phase=0.0,
         cap_start=False, cap_end=False, name="tube", material="default", smooth_angle=50.0) -> Part:
    """A tube swept along `path` ((n, 3) points) with a radius per point: a number, or
    (r1, r2) for an elliptical section. A radius of 0 closes that end in a point; caps
    close the ends flat. Frames are parallel-transported so the tube does not twist."""
    path = np.asarray(path, dtype=float)
    radii = np.asarray(radii, dtype=float)
    if radii.ndim == 1:
        radii = np.stack([radii, radii], axis=-1)
    tangents = np.gradient(path, axis=0)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    seed_dir = np.array([0.0, 1.0, 0.0]) if abs(tangents[0, 1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    normal = seed_dir - tangents[0] * np.dot(seed_dir, tangents[0])
    frames = []
    for t in tangents:
        normal = normal - t * np.dot(normal, t)
        normal /= np.linalg.norm(normal)
        frames.append((normal, np.cross(t, normal)))
    cols = segments + 1 if uv else segments
    theta = np.arange(cols) * (2 * np.pi / segments) + math.radians(phase)
    rows = []
    for point, (n, b), (r1, r2) in zip(path, frames, radii):
        rows.append(point + np.outer(r1 * np.cos(theta), n) + np.outer(r2 * np.sin(theta), b))
    points = np.array(rows)
    if cap_start:
        points = np.vstack([np.repeat(path[None, :1], cols, axis=1), points])
    if cap_end:
        points = np.vstack([points, np.repeat(path[None, -1:], cols, axis=1)])
    tex = None
    if uv:
        uu, vv = np.meshgrid((theta - math.radians(phase)) / (2 * np.pi) * u_repeat,
                             np.linspace(*v_range, len(points)))
        tex = pole_uv_fix(np.stack([uu, vv], axis=-1), points)
    return grid_part(points, tex, name, material, smooth_angle=smooth_angle)


# Box faces as (outward normal, u axis, v axis) with u x v = normal, so textures read
# the right way round from outside and tangent frames agree across the model.
BOX_FACES = (
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
)


def box(size, center=(0.0, 0.0, 0.0), uv_scale: float | None = None, unit_uv=False,
        name="box", material="default", skip_bottom=False) -> Part:
    """Axis-aligned box with four vertices per face (sharp edges). UVs are either world
    projections (one texture repeat per `uv_scale` units) or [0, 1] on every face."""
    half = np.asarray(size, dtype=float) / 2.0
    center = np.asarray(center, dtype=float)
    verts, uvs, faces = [], [], []
    for normal, u_axis, v_axis in BOX_FACES:
        if skip_bottom and normal == (0, -1, 0):
            continue
        n, u, v = (np.array(a, dtype=float) for a in (normal, u_axis, v_axis))
        start = len(verts)
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = center + half * (n + su * u + sv * v)
            verts.append(p)
            if unit_uv:
                uvs.append(((su + 1) / 2, (sv + 1) / 2))
            elif uv_scale:
                uvs.append((np.dot(p, u) / uv_scale, np.dot(p, v) / uv_scale))
        faces.append(tuple(range(start, start + 4)))
    tex = np.array(uvs, dtype=float) if uvs else None
    return Part(name, np.array(verts), faces, material, tex, smooth_angle=20.0)


def ordered_polygon(points: np.ndarray, outward) -> list:
    """Order a convex polygon's points counter-clockwise as seen from the `outward` side."""
    points = np.asarray(points, dtype=float)
    n = np.asarray(outward, dtype=float)
    n /= np.linalg.norm(n)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a = np.cross(helper, n)
    a /= np.linalg.norm(a)
    b = np.cross(n, a)                               # (a, b, n) right-handed
    rel = points - points.mean(axis=0)
    return list(np.argsort(np.arctan2(rel @ b, rel @ a), kind="stable"))


def bevelled_box(size: float, bevel: float, name="crate", material="default") -> Part:
    """Cube with chamfered edges: 6 faces, 12 edge strips, 8 corner triangles, each with
    its own vertices. Every face carries the whole texture; strips and corners take the
    texture's border, projected from the face they lean on most."""
    h, inner = size / 2.0, size / 2.0 - bevel
    # The point each cube corner contributes to the face of each axis.
    def corner_point(signs, axis):
        p = np.array(signs, dtype=float) * inner
        p[axis] = signs[axis] * h
        return p

    polygons = []   # (points, outward)
    for axis in range(3):
        for sign in (1, -1):
            pts = [corner_point(s, axis) for s in itertools.product((1, -1), repeat=3) if s[axis] == sign]
            normal = np.zeros(3)
            normal[axis] = sign
            polygons.append((pts, normal))
    for a1, a2 in ((0, 1), (1, 2), (2, 0)):
        for s1, s2 in itertools.product((1, -1), repeat=2):
            corners = [s for s in itertools.product((1, -1), repeat=3) if s[a1] == s1 and s[a2] == s2]
            pts = [corner_point(s, a) for s in corners for a in (a1, a2)]
            normal = np.zeros(3)
            normal[a1], normal[a2] = s1, s2
            polygons.append((pts, normal))
    for s in itertools.product((1, -1), repeat=3):
        polygons.append(([corner_point(s, a) for a in range(3)], np.array(s, dtype=float)))

    verts, uvs, faces = [], [], []
    for pts, normal in polygons:
        pts = np.array(pts)
        order = ordered_polygon(pts, normal)
        axis = int(np.argmax(np.abs(normal) + np.array([3e-3, 2e-3, 1e-3])))  # deterministic tie-break
        face = next(f for f in BOX_FACES if f[0][axis] == np.sign(normal[axis]) and abs(f[0][axis]) == 1)
        u_axis, v_axis = np.array(face[1], dtype=float), np.array(face[2], dtype=float)
        start = len(verts)
        for i in order:
            verts.append(pts[i])
            uvs.append((np.dot(pts[i], u_axis) / size + 0.5, np.dot(pts[i], v_axis) / size + 0.5))
        faces.append(tuple(range(start, start + len(order))))
    return Part(name, np.array(verts), faces, material, np.array(uvs), smooth_angle=20.0)


def extruded_polygon(outline2d, depth: float, uv_scale=1.0, name="slab", material="default") -> Part:
    """Prism from a convex 2D outline (x, y) listed counter-clockwise, extruded from z = 0
    to z = depth. Front and back are single n-gon faces; sides are quads."""
    outline = np.asarray(outline2d, dtype=float)
    n = len(outline)
    front = np.column_stack([outline, np.full(n, depth)])
    back = np.column_stack([outline, np.zeros(n)])
    verts = np.vstack([front, back[::-1]])
    faces = [tuple(range(n)), tuple(range(n, 2 * n))]
    uvs = [tuple(p[:2] / uv_scale) for p in front] + [(-p[0] / uv_scale, p[1] / uv_scale) for p in back[::-1]]
    side_start = len(verts)
    side_verts, side_uvs = [], []
    for i in range(n):
        j = (i + 1) % n
        quad = [back[i], back[j], front[j], front[i]]
        edge = np.linalg.norm(outline[j] - outline[i]) / uv_scale
        side_verts.extend(quad)
        side_uvs.extend([(0, 0), (edge, 0), (edge, depth / uv_scale), (0, depth / uv_scale)])
        faces.append(tuple(range(side_start + 4 * i, side_start + 4 * i + 4)))
    return Part(name, np.vstack([verts, side_verts]), faces, material,
                np.array(uvs + side_uvs, dtype=float), smooth_angle=20.0)


def noise_displace(part: Part, amount: float, frequency: float, seed: int, center=None,
                   octaves: int = 3) -> Part:
    """Push vertices in or out along the direction from `center` by 3D fbm: lumpy
    foliage, rough rock. Coincident vertices (UV seams) move identically."""
    c = part.v.mean(axis=0) if center is None else np.asarray(center, dtype=float)
    rel = part.v - c
    dist = np.linalg.norm(rel, axis=1, keepdims=True)
    direction = np.divide(rel, dist, out=np.zeros_like(rel), where=dist > 1e-12)
    offset = amount * fbm(part.v * frequency, seed, octaves)
    return replace(part, v=part.v + direction * offset[:, None])
