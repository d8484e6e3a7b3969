"""Light from the surroundings (``lights: - type: environment``), CPU side. No GL.

The environment is one equirectangular image of linear radiance (``EnvironmentDef.image``):
an ``.hdr``/``.exr``/8-bit file as given, or the skybox's six faces resampled into one.
Direction d (world space, after the rotation) sits at

    u = 1/2 + atan2(d.x, -d.z) / (2 pi),   v = acos(d.y) / pi      (v = 0: the top row, +Y)

so the image's centre column looks down -Z, where the default camera looks. Radiance from
direction d is the image there x colour x intensity; the renderer and the reference
renderer read these same numbers.

Diffuse light: the image projected onto real spherical harmonics up to ``sh_order`` and
convolved with the clamped cosine (Ramamoorthi and Hanrahan 2001: bands scaled by pi,
2 pi / 3, pi / 4, 0, -pi / 24), kept as ``irradiance_map``, the radiance a white Lambert
surface facing each direction reflects (irradiance / pi). The specular part is prefiltered
on the GPU (rendering/passes/environment.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from scenerender.animation import Track
from scenerender.colorspace import srgb_decode
from scenerender.errors import display_path
from scenerender.scene.image_files import ImageError
from scenerender.scene.messages import single_error
from scenerender.scene.model.lights import SKY
from scenerender.world.environment_files import read_linear_image

# the clamped cosine's spherical harmonic bands, over pi: irradiance / pi per band
LAMBERT_BANDS = (1.0, 2.0 / 3.0, 0.25, 0.0, -1.0 / 24.0)
IRRADIANCE_MAP_SIZE = (64, 32)     # (width, height): ample for a function of band 4 at most
SH_PROJECTION_WIDTH = 256          # the image is area-averaged to at most this before projecting
CUBE_TO_EQUIRECT_MAX_WIDTH = 2048  # a skybox becomes an equirectangular image this wide at most


@dataclass(frozen=True)
class EnvironmentDef:
    """The scene's environment light.

    image: (H, W, 3) float32 linear radiance, equirectangular, rows top (+Y) to bottom.
    rotation: Track of degrees about +Y (the image turned counter-clockwise seen from above).
    classic: Phong and Blinn-Phong materials get the diffuse term too (as an ambient).
    prefilter_size: width in pixels of each prefiltered specular level (height half that).
    sh_order: the highest spherical-harmonic band of the diffuse term (0..4).
    samples: GGX samples a texel of each rough prefiltered level.
    footprint: the specular lookup widened to the pixel's spread of reflection directions.
    specular: "split_sum" (the prefiltered image at the reflection direction) or "sampled"
    (``specular_samples`` GGX samples of ``image`` a pixel, at its own normal and view).
    visibility: how many directions the scene's occlusion of the light is sampled in, each
    with a shadow map of ``visibility_map_size`` texels a side (world.environment_visibility);
    0: the scene does not block it. visibility_interleave: pixels a side of the block the
    directions are shared out over (world.environment_visibility.interleave_pattern),
    looked up at half the image's resolution where ``visibility_half_resolution``.
    background: the image is drawn behind the scene (turned by ``rotation``, times colour x
    intensity), in place of the skybox.
    """

    name: str
    path: tuple
    image: np.ndarray = field(repr=False)
    color: Track
    intensity: Track
    enabled: Track
    rotation: Track
    classic: bool = False
    prefilter_size: int = 128
    sh_order: int = 4
    samples: int = 512
    footprint: bool = False
    visibility: int = 0
    visibility_map_size: int = 512
    background: bool = False
    visibility_interleave: int = 1
    visibility_half_resolution: bool = False
    specular: str = "split_sum"
    specular_samples: int = 32

    @cached_property
    def sh(self) -> np.ndarray:
        """((sh_order + 1)^2, 3) radiance coefficients of the image (real SH, ``sh_basis`` order)."""
        return project_sh(self.image, self.sh_order)

    @cached_property
    def irradiance_map(self) -> np.ndarray:
        """(32, 64, 3) float32 equirectangular: irradiance / pi from each direction's hemisphere."""
        width, height = IRRADIANCE_MAP_SIZE
        return diffuse_radiance(self.sh, equirect_directions(height, width)).astype(np.float32)

    def state(self, t: float) -> "EnvironmentState":
        on = 1.0 if self.enabled(t) else 0.0
        scale = np.asarray(self.color(t), dtype=np.float64)[:3] * self.intensity(t) * on
        return EnvironmentState(scale, world_to_image(self.rotation(t)))


@dataclass(frozen=True)
class EnvironmentState:
    """The environment at one instant: ``scale`` (3,) colour x intensity (zero while
    disabled); ``to_image`` (3, 3) rotates a world direction into the image's frame."""

    scale: np.ndarray
    to_image: np.ndarray

    def same_as(self, other) -> bool:
        return (isinstance(other, EnvironmentState) and np.array_equal(self.scale, other.scale)
                and np.array_equal(self.to_image, other.to_image))

    def radiance(self, image: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """(N, 3) radiance arriving from world ``directions`` (N, 3), unit."""
        return sample_equirect(image, directions @ self.to_image.T) * self.scale


def world_to_image(degrees: float) -> np.ndarray:
    """(3, 3): a world direction into the frame of an image turned ``degrees`` about +Y."""
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    turn = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # the image's frame into the world
    return turn.T


def environment_def(scene, images, sky_faces) -> EnvironmentDef | None:
    """The scene's environment light, its image read (an unreadable file is an error at its
    key), or None; ``sky_faces``: the skybox's six face paths (world.settings.skybox)."""
    found = [(index, light) for index, light in enumerate(scene.spec.lights or ()) if light.type == "environment"]
    if not found:
        return None
    index, light = found[0]
    path = ("lights", index)
    if light.image == SKY:
        image = skybox_image(sky_faces, images)
    else:
        scene.assets.record(light.image)
        try:
            image = read_linear_image(light.image, images)
        except ImageError as exc:
            raise single_error(f"environment image {display_path(light.image)}: {exc.reason}", path + ("image",),
                               scene.source) from None
    return EnvironmentDef(light.name or f"environment{index}", path, image, light.color, light.intensity,
                          light.enabled, light.rotation, light.classic, light.prefilter_size, light.sh_order,
                          light.samples, light.footprint, light.visibility_directions if light.visibility else 0,
                          light.visibility_map_size, light.background,
                          visibility_blocks(light.visibility_interleave, scene.spec.render.size),
                          light.visibility_half_resolution, light.specular, light.specular_samples)


# 'auto' blocks: 3x3 (3 or 4 of 32 directions a pixel) where the image's shorter side has
# at least this many pixels, 2x2 (8 a pixel) below. On scenes/gltf_pbr.yaml 3x3 blocks
# cost 1.25x a frame without visibility at 960x540 and 1.28x at 640x360, 2x2 blocks 1.31x
# and 1.30x; at 256x192 both keep the contact scene and the three spheres within 2.4 %
# of the reference; at 128x96, where the blur's 5 texels reach 10 pixels, 3x3 blocks let
# the patch's shadow go from +1.4 to +4.4 % and the copper sphere from +2.8 to +3.8 %
# (benchmarks/quality/environment_contact.md).
BLOCKS_3X3_FROM = 240


def visibility_blocks(asked, size) -> int:
    """The visibility's ``interleave`` for an image of ``size`` (width, height): ``asked``,
    or for 'auto' 3 where the shorter side has BLOCKS_3X3_FROM pixels or more, else 2."""
    if asked != "auto":
        return asked
    return 3 if min(size) >= BLOCKS_3X3_FROM else 2


def skybox_image(faces, images) -> np.ndarray:
    """The skybox's faces (decoded already, sRGB) as one linear equirectangular image."""
    stacked = np.stack([images.pixels(face)[..., :3] for face in faces]).astype(np.float32) / 255.0
    return cube_to_equirect(srgb_decode(stacked).astype(np.float32))


# -- the equirectangular mapping -------------------------------------------------------

def equirect_uv(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u, v) in [0, 1] of unit ``directions`` (N, 3); see the module's formula."""
    d = np.asarray(directions, dtype=np.float64)
    u = 0.5 + np.arctan2(d[..., 0], -d[..., 2]) / (2.0 * np.pi)
    v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi
    return u, v


def equirect_directions(height: int, width: int) -> np.ndarray:
    """(H, W, 3) unit directions through the texel centres of an equirectangular image."""
    phi = ((np.arange(width) + 0.5) / width - 0.5) * 2.0 * np.pi
    theta = (np.arange(height) + 0.5) / height * np.pi
    sin_t = np.sin(theta)[:, None]
    return np.stack([sin_t * np.sin(phi)[None, :], np.broadcast_to(np.cos(theta)[:, None], (height, width)),
                     -sin_t * np.cos(phi)[None, :]], axis=-1)


def sample_equirect(image: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """(N, 3) bilinear samples of ``image`` (H, W, 3) in ``directions`` (N, 3): u wraps
    around, v is clamped to the first and last rows' centres (as the GPU samples it)."""
    height, width = image.shape[:2]
    u, v = equirect_uv(directions)
    x = u * width - 0.5
    y = np.clip(v * height - 0.5, 0.0, height - 1.0)
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    y1 = np.minimum(y0 + 1, height - 1)
    x0w, x1w = x0 % width, (x0 + 1) % width
    top = image[y0, x0w] * (1.0 - fx) + image[y0, x1w] * fx
    bottom = image[y1, x0w] * (1.0 - fx) + image[y1, x1w] * fx
    return top * (1.0 - fy) + bottom * fy


def texel_solid_angles(height: int, width: int) -> np.ndarray:
    """(H, 1) solid angle of a texel in each row of an equirectangular image (they sum to 4 pi)."""
    edges = np.arange(height + 1) / height * np.pi
    return ((np.cos(edges[:-1]) - np.cos(edges[1:])) * 2.0 * np.pi / width)[:, None]


def cube_to_equirect(faces: np.ndarray, width: int | None = None) -> np.ndarray:
    """(W / 2, W, 3) equirectangular image of a cube map's ``faces`` (6, S, S, 3) in GL's
    order (+X -X +Y -Y +Z -Z), each face's rows top first as a skybox image holds them;
    ``width`` defaults to 4 S (capped): about one texel per face texel at the equator."""
    size = faces.shape[1]
    width = width or min(4 * size, CUBE_TO_EQUIRECT_MAX_WIDTH)
    directions = equirect_directions(width // 2, width).reshape(-1, 3)
    return sample_cube(faces, directions).reshape(width // 2, width, 3).astype(np.float32)


def sample_cube(faces: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """(N, 3) bilinear samples of a cube map (6, S, S, 3) in GL's face convention (each
    face's edge texels clamped)."""
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    ax, ay, az = np.abs(x), np.abs(y), np.abs(z)
    face = np.where((ax >= ay) & (ax >= az), np.where(x > 0, 0, 1),
                    np.where(ay >= az, np.where(y > 0, 2, 3), np.where(z > 0, 4, 5)))
    # (sc, tc, ma) per face: the GL specification's table of cube-map face selection
    sc = np.choose(face, [-z, z, x, x, x, -x])
    tc = np.choose(face, [-y, -y, z, -z, -y, -y])
    ma = np.choose(face, [ax, ax, ay, ay, az, az])
    size = faces.shape[1]
    s = np.clip(((sc / ma + 1.0) * 0.5) * size - 0.5, 0.0, size - 1.0)
    t = np.clip(((tc / ma + 1.0) * 0.5) * size - 0.5, 0.0, size - 1.0)
    s0, t0 = np.floor(s).astype(np.int64), np.floor(t).astype(np.int64)
    s1, t1 = np.minimum(s0 + 1, size - 1), np.minimum(t0 + 1, size - 1)
    fs, ft = (s - s0)[:, None], (t - t0)[:, None]
    top = faces[face, t0, s0] * (1.0 - fs) + faces[face, t0, s1] * fs
    bottom = faces[face, t1, s0] * (1.0 - fs) + faces[face, t1, s1] * fs
    return top * (1.0 - ft) + bottom * ft


# -- spherical harmonics -----------------------------------------------------------------

def sh_basis(directions: np.ndarray, order: int) -> np.ndarray:
    """(N, (order + 1)^2) real spherical harmonics (orthonormal over the sphere) of unit
    ``directions`` (N, 3), bands 0..order (at most 4), in the order l = 0; l = 1: m = -1,
    0, 1; l = 2: m = -2..2; ..."""
    d = np.asarray(directions, dtype=np.float64).reshape(-1, 3)
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    columns = [np.full(len(d), 0.282094791773878)]
    if order >= 1:
        columns += [0.488602511902920 * y, 0.488602511902920 * z, 0.488602511902920 * x]
    if order >= 2:
        columns += [1.092548430592079 * x * y, 1.092548430592079 * y * z,
                    0.315391565252520 * (3.0 * z * z - 1.0),
                    1.092548430592079 * x * z, 0.546274215296040 * (x * x - y * y)]
    if order >= 3:
        columns += [0.590043589926644 * y * (3.0 * x * x - y * y), 2.890611442640554 * x * y * z,
                    0.457045799464466 * y * (5.0 * z * z - 1.0), 0.373176332590115 * z * (5.0 * z * z - 3.0),
                    0.457045799464466 * x * (5.0 * z * z - 1.0), 1.445305721320277 * z * (x * x - y * y),
                    0.590043589926644 * x * (x * x - 3.0 * y * y)]
    if order >= 4:
        x2, y2, z2 = x * x, y * y, z * z
        columns += [2.503342941796705 * x * y * (x2 - y2), 1.770130769779931 * y * z * (3.0 * x2 - y2),
                    0.946174695757560 * x * y * (7.0 * z2 - 1.0), 0.669046543557289 * y * z * (7.0 * z2 - 3.0),
                    0.105785546915204 * (35.0 * z2 * z2 - 30.0 * z2 + 3.0),
                    0.669046543557289 * x * z * (7.0 * z2 - 3.0), 0.473087347878780 * (x2 - y2) * (7.0 * z2 - 1.0),
                    1.770130769779931 * x * z * (x2 - 3.0 * y2),
                    0.625835735449176 * (x2 * (x2 - 3.0 * y2) - y2 * (3.0 * x2 - y2))]
    return np.stack(columns, axis=1)


def sh_bands(order: int) -> np.ndarray:
    """((order + 1)^2,) the band l of each coefficient."""
    return np.concatenate([np.full(2 * l + 1, l) for l in range(order + 1)])


def project_sh(image: np.ndarray, order: int) -> np.ndarray:
    """((order + 1)^2, 3) coefficients of ``image`` (equirectangular radiance) on
    ``sh_basis``: the integral of radiance x basis over the sphere, texel by texel."""
    small = area_average(image, SH_PROJECTION_WIDTH)
    height, width = small.shape[:2]
    weights = texel_solid_angles(height, width)
    grid = equirect_directions(height, width)
    total = np.zeros(((order + 1) ** 2, 3))
    rows = max(1, 65536 // width)  # a band of rows at a time: the basis of a large image is big
    for top in range(0, height, rows):
        band = slice(top, min(height, top + rows))
        directions = grid[band].reshape(-1, 3)
        weighted = sh_basis(directions, order) * np.repeat(weights[band], width, axis=0)
        total += weighted.T @ small[band].reshape(-1, 3)
    return total


def diffuse_radiance(coefficients: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(..., 3) irradiance / pi at surfaces facing ``normals`` (..., 3): what a white
    Lambert surface reflects, from radiance ``coefficients`` (project_sh)."""
    order = math.isqrt(len(coefficients)) - 1
    shape = normals.shape[:-1]
    bands = np.asarray(LAMBERT_BANDS)[sh_bands(order)][:, None]
    out = sh_basis(normals.reshape(-1, 3), order) @ (coefficients * bands)
    return np.maximum(out, 0.0).reshape(shape + (3,))


def area_average(image: np.ndarray, max_width: int) -> np.ndarray:
    """``image`` shrunk by a whole factor (box filter) to at most ``max_width`` wide."""
    height, width = image.shape[:2]
    factor = 1
    while width // factor > max_width and height % (factor * 2) == 0 and width % (factor * 2) == 0:
        factor *= 2
    if factor == 1:
        return np.asarray(image, dtype=np.float64)
    shaped = np.asarray(image, dtype=np.float64).reshape(height // factor, factor, width // factor, factor, 3)
    return shaped.mean(axis=(1, 3))
