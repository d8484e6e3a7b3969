"""The CPU reference renderer for ``render.mode: shaded``.

For each pixel, spp x spp stratified (jittered) primary rays; each hit is shaded with
scenerender.raytrace.shading (the GPU's equations), with exact hard shadows from shadow
rays to every shadowed light; the samples are averaged in linear light (a box filter, what
MSAA converges to), then scaled by the exposure, mapped through the tone curve
(scenerender.colorspace.tone_map: the shaders' curves in NumPy) and encoded like the
output pass. The scene, camera and lights come from the same World and frame evaluator
the GPU path uses.

Diffuse (base colour), specular, metallic-roughness, occlusion and emissive maps are
sampled at the base level, bilinearly, for every sample (scenerender.raytrace.textures);
vertex colours multiply the base colour. Each material is shaded with its own model
(Phong, Blinn-Phong, pbr or unlit). What it leaves out (one warning line names what a
scene has of it): normal and opacity maps, screen-space ambient occlusion, transparency
and alpha masks (every surface is opaque), single-sided materials (both faces are
drawn), outlines, the skybox (the background colour shows), the wireframe overlay.

Ambient light is the GPU's formula by default. With ``ambient_samples`` it is integrated
instead: the ambient lights are a uniform environment of that radiance, and each sample
point gathers it from that many cosine-distributed directions (seeded per frame), each
weighted by the material's BRDF and blocked by any surface in its way. That is the exact
answer the GPU's formula approximates (for a white non-metal in a white environment,
the white furnace, its own energy balance).

An environment light (``lights: - type: environment``) is integrated by Monte Carlo, always:
``environment_samples`` directions a sample point (seeded per frame), drawn by multiple
importance sampling between the image's brightness, the cosine and the GGX lobe
(scenerender.raytrace.environment_sampling), each weighted by the material's BRDF and the image's
radiance in that direction and blocked by any surface in its way. Like the ambient term it
is times Ka and the occlusion map. pbr materials take the whole BRDF; Phong and
Blinn-Phong ones only the diffuse part, and only where the light has ``classic: true``;
unlit ones nothing. Rays that miss the scene still
show the background colour, not the environment (as they do not show the skybox).

With ``bounces`` the reference path-traces (_FrameScene._indirect): from each visible point
a path goes on in directions drawn from the BRDF, and every surface it meets is shaded as a
visible point is (emission, ambient, environment, every light with its shadow ray: next-event
estimation), times the path's throughput; Russian roulette ends paths after ROULETTE_AFTER
bounces. docs/scene-notes.md ("Light that bounces, in the reference") has the details.

Transmissive pbr materials (``transmission``) are not transparency: from each visible point
of one a path goes through the rough glass and its volume (scenerender.raytrace.transmission)
to the surface behind, shaded as a visible point is (_FrameScene._through); a light behind
one shines through it by next-event estimation through its BTDF (_FrameScene._light_through).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scenerender import option_rules
from scenerender.colorspace import encode_output, tone_map
from scenerender.errors import UserError
from scenerender.raytrace import environment_sampling as environment, shading, sized_lights, transmission
from scenerender.raytrace.geometry import Soup, frame_soup
from scenerender.raytrace.rays import TriangleCaster
from scenerender.raytrace.textures import MapSampler
from scenerender.scene.messages import single_error
from scenerender.world.frame import FrameEvaluator
from scenerender.rendering.passes.bloom import bloom_weights
from scenerender.world.lens import lens_radius
from scenerender.world.materials import LAYER_MAP_KEYS

# Samples shaded at once; bounds the memory of one chunk to a few hundred MB.
_CHUNK_SAMPLES = 400_000
# Directions a sample point gathers an environment light from, by default.
ENVIRONMENT_SAMPLES = option_rules.DEFAULT_ENVIRONMENT_SAMPLES
# Instants over an open shutter (camera.shutter), by default.
SHUTTER_SAMPLES = option_rules.DEFAULT_SHUTTER_SAMPLES
# Bounces after which a path is ended at random (Russian roulette), and the most chance
# it then has to go on: below 1, so a path in a closed white room still ends.
ROULETTE_AFTER = 3
MAX_SURVIVAL = 0.95


@dataclass
class ReferenceFrame:
    """One reference frame.

    linear:   (H, W, 3) float32 mean of the samples' linear colour (unclamped; before the
              exposure and tone curve, as EXR output holds it).
    pixels:   (H, W, 3) uint8 display-encoded: exposure, tone curve and output transform.
    shadow:   (H, W, S) float32 per shadowed light (S of them, in scene order), the fraction
              of the pixel's samples blocked from it; samples facing away from the light or
              missing the scene count as not blocked.
    cone:     (H, W, C) float32 per spot light, the mean spot-cone factor of the samples.
    blocked:  (H, W, S) float32 per shadowed light, the linear radiance (mean of the three
              channels, over the pixel's samples) its shadow takes away: what the pixel
              would gain were that light unshadowed.
    object:   (H, W) int32 scene-object index seen by the pixel's middle sample, -1 for none.
    mixed:    (H, W) bool: the pixel's samples see more than one object (or background), or
              surfaces facing more than ~25 degrees apart (an edge of one object).
    spp:      samples per pixel along each axis.
    """

    index: int
    time: float
    linear: np.ndarray
    pixels: np.ndarray
    shadow: np.ndarray
    cone: np.ndarray
    object: np.ndarray
    mixed: np.ndarray
    spp: int
    blocked: np.ndarray | None = None


def unsupported_features(world) -> list[str]:
    """Names of what ``world`` uses that the reference draws without."""
    render = world.render
    found = []
    if any("normal_map" in m.maps for m in world.materials()):
        found.append("normal maps")
    if any("opacity_map" in m.maps for m in world.materials()):
        found.append("opacity maps")
    if render.ambient_occlusion is not None:
        found.append("ambient occlusion")
    if any(m.blended for m in world.materials()):
        found.append("transparency")
    if any(m.masked for m in world.materials()):
        found.append("alpha masks")
    if any(not m.double_sided for m in world.materials()):
        found.append("single-sided materials")
    if any(obj.outline for obj in world.objects):
        found.append("outlines")
    if render.skybox is not None:
        found.append("skybox")
    if render.wireframe_overlay:
        found.append("wireframe overlay")
    return found


def render_reference(world, index: int = 0, *, spp: int = 4, size: tuple | None = None,
                     warn=None, ambient_samples: int = 0,
                     environment_samples: int = ENVIRONMENT_SAMPLES,
                     shutter_samples: int = SHUTTER_SAMPLES, bounces: int = 0) -> ReferenceFrame:
    """Frame ``index`` of ``world`` (a World or a scenerender.Scene), spp x spp rays a pixel.

    size: (width, height), default the scene's render.size. ``warn`` receives one line
    naming what the reference leaves out, when the scene has any of it. ambient_samples:
    0 for the GPU's ambient formula, else the directions per sample point over which
    ambient light is integrated (see the module's docstring). environment_samples: the
    directions per sample point over which an environment light is integrated.
    shutter_samples: with ``camera.shutter``, the instants over the open shutter averaged
    (shutter_offsets); with ``camera.aperture`` every ray starts at its own random point of
    the lens (seeded by the frame). bounces: 0 for direct light only, else the most
    surfaces a path from a visible point bounces off (see _FrameScene._indirect). The five
    counts keep the rules of scenerender.option_rules (SPP, AMBIENT_SAMPLES,
    ENVIRONMENT_SAMPLES, SHUTTER_SAMPLES, BOUNCES)."""
    world = getattr(world, "world", world)
    if world.render.mode != "shaded":
        raise single_error(f"the reference renders mode 'shaded' only, not '{world.render.mode}'",
                           ("render", "mode"), world.scene.source)
    for rule, value in ((option_rules.SPP, spp), (option_rules.AMBIENT_SAMPLES, ambient_samples),
                        (option_rules.ENVIRONMENT_SAMPLES, environment_samples),
                        (option_rules.SHUTTER_SAMPLES, shutter_samples), (option_rules.BOUNCES, bounces)):
        if rule.problem(value) is not None:
            raise UserError(rule.problem(value))
    missing = unsupported_features(world)
    if missing and warn is not None:
        warn(f"the reference renders without {', '.join(missing)}")
    width, height = size or tuple(int(v) for v in world.render.size)
    time = index / float(world.output.fps)
    evaluator = FrameEvaluator(world, (width, height), atlas=None)
    parts = [_render_instant(world, evaluator, index, time + offset, (width, height), spp, warn, ambient_samples,
                             environment_samples, sub_frame, bounces)
             for sub_frame, offset in enumerate(shutter_offsets(world, index, shutter_samples))]
    # the float outputs are means over the sub-frames; which object a pixel shows is the
    # first sub-frame's (the one nearest the frame's time)
    linear, shadow, cone, blocked = (parts[0][k] if len(parts) == 1 else np.mean([part[k] for part in parts], axis=0)
                                     for k in (0, 1, 2, 5))
    objects, mixed = parts[0][3], parts[0][4]
    bloom = world.render.bloom
    if bloom is not None and bloom.strength > 0:
        linear = bloomed(linear, bloom.strength, bloom.radius)
    toned = tone_map(linear, world.render.tone_map, float(world.render.exposure(time)))
    pixels = encode_output(toned, world.render.output_transform, world.render.gamma)
    return ReferenceFrame(index, time, linear.astype(np.float32), pixels, shadow.astype(np.float32),
                          cone.astype(np.float32), objects, mixed, spp, blocked.astype(np.float32))


def bloomed(linear: np.ndarray, strength: float, radius: float) -> np.ndarray:
    """``render.bloom`` in NumPy, as rendering/passes/bloom.py does it: the image mixed with
    its Gaussian blur (standard deviation ``radius`` times the height), the blur reading
    the image mirrored about its edges (np.pad's "symmetric": the texel past the edge is
    the edge's), one direction at a time."""
    height, width = linear.shape[:2]
    weights = bloom_weights(radius * height, min(width, height) - 1).astype(np.float64)
    kernel = np.concatenate([weights[:0:-1], weights])
    taps = len(weights) - 1
    blur = np.asarray(linear, dtype=np.float64)
    for axis in (1, 0):
        padding = [(0, 0)] * blur.ndim
        padding[axis] = (taps, taps)
        padded = np.pad(blur, padding, mode="symmetric")
        size = blur.shape[axis]
        blur = sum(w * np.take(padded, np.arange(k, k + size), axis=axis) for k, w in enumerate(kernel))
    return (1.0 - strength) * linear + strength * blur


def shutter_offsets(world, index: int, count: int) -> list[float]:
    """Seconds from frame ``index``'s time at which the reference looks: [0.0] without
    ``camera.shutter``; else ``count`` times over the open shutter (centred on the frame),
    one drawn at random in each of ``count`` equal slices (seeded by the frame), the one
    nearest the frame's time first."""
    camera = world.spec.camera
    if camera is None or camera.shutter == 0.0:
        return [0.0]
    rng = np.random.Generator(np.random.PCG64([index, 3]))
    open_seconds = camera.shutter / float(world.output.fps)
    offsets = ((np.arange(count) + rng.random(count)) / count - 0.5) * open_seconds
    return sorted(offsets.tolist(), key=abs)


def _render_instant(world, evaluator, index: int, time: float, size: tuple, spp: int, warn, ambient_samples: int,
                    environment_samples: int, sub_frame: int, bounces: int = 0) -> tuple:
    """(linear, shadow, cone, objects, mixed, blocked) of the scene at ``time``, each
    sample's ray from its own point of the lens where the camera has an aperture."""
    width, height = size
    frame = evaluator.evaluate(index, time)
    lens = _lens_of(world, frame)
    later = [sub_frame] if sub_frame else []  # the first sub-frame draws what a frame without a shutter drew
    scene = _FrameScene(world, frame, warn, ambient_samples,
                        np.random.Generator(np.random.PCG64([index, 1, *later])), environment_samples,
                        np.random.Generator(np.random.PCG64([index, 2, *later])),
                        np.random.Generator(np.random.PCG64([index, 3, *later])), lens, bounces,
                        np.random.Generator(np.random.PCG64([index, 4, *later])))
    rng = np.random.Generator(np.random.PCG64([index, *later]) if later else np.random.PCG64(index))
    rows_per_chunk = max(1, _CHUNK_SAMPLES // (width * spp * spp))
    chunks = [scene.render_rows(y0, min(height, y0 + rows_per_chunk), width, height, spp, rng)
              for y0 in range(0, height, rows_per_chunk)]
    return tuple(np.concatenate(part) for part in zip(*chunks))


def _lens_of(world, frame) -> tuple | None:
    """(radius, focus distance) of the camera's thin lens in ``frame``, None for a pinhole."""
    spec = world.spec.camera
    if spec is None or spec.aperture is None:
        return None
    focus = frame.focus_distance
    return lens_radius(frame.camera, spec.aperture, focus, spec.sensor_width), focus


class _FrameScene:
    """One frame's geometry, lights and materials, ready to shade samples."""

    def __init__(self, world, frame, warn, ambient_samples: int = 0, ambient_rng=None,
                 environment_samples: int = ENVIRONMENT_SAMPLES, environment_rng=None, light_rng=None,
                 lens: tuple | None = None, bounces: int = 0, bounce_rng=None):
        """light_rng: draws points of lights with a size; lens: (radius, focus distance) of a
        thin lens, None for a pinhole; bounces: see _indirect, whose paths draw every random
        number from ``bounce_rng`` (so the direct light at visible points draws what it
        draws without bounces)."""
        self.world = world
        self.lens = lens
        self.frame = frame
        self.ambient_samples = ambient_samples
        self.environment_samples = environment_samples
        self.environment_rng = environment_rng
        # what shading a visible point draws from; light_rng: points of lights with a size
        self.draws = _Draws(ambient_rng, environment_rng,
                            light_rng if light_rng is not None else np.random.Generator(np.random.PCG64(3)))
        self.bounces = bounces
        self.bounce_rng = bounce_rng if bounce_rng is not None else np.random.Generator(np.random.PCG64(4))
        self.bounce_draws = _Draws(self.bounce_rng, self.bounce_rng, self.bounce_rng)
        # paths through transmissive surfaces (_through): a generator of their own, so
        # a scene without them draws what it drew
        self.transmission_rng = np.random.Generator(np.random.PCG64([5, frame.index]))
        self.environment_image = _image_sampler(world, frame)
        self.soup: Soup = frame_soup(world, frame)
        self.primary = TriangleCaster(self.soup.corners, warn)
        self.primary_count = self.soup.count
        self.casters = TriangleCaster(self.soup.corners[self.soup.casts], warn)
        self.lights = list(frame.lights)
        self.shadowed = [i for i, light in enumerate(self.lights) if light.definition.shadow is not None]
        self.spots = [i for i, light in enumerate(self.lights) if light.kind == "spot"]
        self.table = _material_table(self.soup.materials, world.render.shading)
        self.maps = _material_maps(self.soup.materials, world.images)
        extent = frame.bounds[1] - frame.bounds[0] if frame.bounds is not None else np.ones(3)
        self.extent = max(float(np.linalg.norm(extent)), 1e-9)
        self.depth_range = _depth_range(world, frame.camera)

    # -- rays -----------------------------------------------------------------------------
    def render_rows(self, y0: int, y1: int, width: int, height: int, spp: int, rng):
        """Rows y0..y1-1: (linear (h, W, 3), shadow (h, W, S), cone (h, W, C), object (h, W),
        mixed (h, W), blocked (h, W, S))."""
        rows = y1 - y0
        sx, sy = _sample_positions(rows, width, spp, rng)          # (rows, W, n) pixel coords
        sy = sy + y0
        ndc_x = 2.0 * sx / width - 1.0
        ndc_y = 1.0 - 2.0 * sy / height
        origins, directions = self._camera_rays(ndc_x.reshape(-1), ndc_y.reshape(-1))
        if self.lens is not None:
            origins, directions = self._through_lens(origins, directions, rng)
        strata = None
        if self.frame.environment is not None:
            strata = environment.pixel_strata(self.environment_rng, rows * width, spp * spp,
                                              self.environment_samples)
        color, shadow, cone, objects, normals, blocked = self._trace(origins, directions, strata)
        n = spp * spp
        shape = (rows, width, n)
        color = color.reshape(shape + (3,)).mean(axis=2)
        shadow = shadow.reshape(shape + (-1,)).mean(axis=2)
        blocked = blocked.reshape(shape + (-1,)).mean(axis=2)
        cone = cone.reshape(shape + (-1,)).mean(axis=2)
        objects = objects.reshape(shape)
        mixed = np.any(objects != objects[:, :, :1], axis=2) | _creased(normals.reshape(shape + (3,)))
        return (color, shadow.astype(np.float32), cone.astype(np.float32), objects[:, :, n // 2], mixed,
                blocked.astype(np.float32))

    def _camera_rays(self, ndc_x: np.ndarray, ndc_y: np.ndarray):
        """Camera-relative (origins (R, 3), directions (R, 3)); a perspective direction has
        view depth 1, so a hit's ray parameter is its view depth."""
        camera = self.frame.camera
        to_world = camera.rotation.T
        p = camera.projection
        if camera.orthographic:
            local = np.stack([ndc_x / p[0, 0], ndc_y / p[1, 1], np.zeros_like(ndc_x)], axis=1)
            directions = np.broadcast_to(to_world @ np.array([0.0, 0.0, -1.0]), local.shape).copy()
            return local @ to_world.T, directions
        # p[0, 2] and p[1, 2] shear the view where the principal point is off centre (intrinsics)
        local = np.stack([(ndc_x + p[0, 2]) / p[0, 0], (ndc_y + p[1, 2]) / p[1, 1], -np.ones_like(ndc_x)], axis=1)
        return np.zeros_like(local), local @ to_world.T

    def _through_lens(self, origins: np.ndarray, directions: np.ndarray, rng):
        """Pinhole rays -> thin-lens rays: each starts at a uniform random point of the lens
        disc and passes through the point its pinhole ray meets on the focus plane (so the
        direction keeps view depth 1)."""
        radius, focus = self.lens
        r = radius * np.sqrt(rng.random(len(origins)))
        angle = 2.0 * np.pi * rng.random(len(origins))
        camera = self.frame.camera
        offsets = (r * np.cos(angle))[:, None] * camera.right + (r * np.sin(angle))[:, None] * camera.up
        return origins + offsets, directions - offsets / focus

    def _trace(self, origins: np.ndarray, directions: np.ndarray, strata: environment.Strata | None = None):
        near, far = self.depth_range
        start = origins + directions * near
        triangles = self.primary.first_hit(start, directions)
        t = np.full(len(origins), np.inf)
        hit = triangles >= 0
        u = v = np.zeros(0)
        if hit.any():
            t_hit, u, v = self.primary.hit_parameters(triangles[hit], origins[hit], directions[hit])
            t[hit] = t_hit
        in_range = hit & (t <= far)
        background = self.frame.background[:3]
        color = np.broadcast_to(background, origins.shape).copy()
        shadow = np.zeros((len(origins), len(self.shadowed)))
        blocked = np.zeros((len(origins), len(self.shadowed)))
        cone = np.zeros((len(origins), len(self.spots)))
        objects = np.full(len(origins), -1, np.int32)
        normals = np.zeros_like(origins)
        keep = in_range[hit]
        rows = np.flatnonzero(in_range)
        if len(rows):
            tri = triangles[rows]
            color[rows], shadow[rows], cone[rows], normals[rows], blocked[rows] = self._shade(
                tri, origins[rows] + directions[rows] * t[rows, None], directions[rows], u[keep], v[keep],
                strata[rows] if strata is not None else None)
            objects[rows] = self.soup.object[tri]
        return color, shadow, cone, objects, normals, blocked

    # -- shading --------------------------------------------------------------------------
    def _shade(self, tri: np.ndarray, p: np.ndarray, ray: np.ndarray, u: np.ndarray, v: np.ndarray,
               strata: environment.Strata | None = None):
        """Colour (P, 3), shadow flags (P, S), cone factors (P, C), shading normals (P, 3)
        and the radiance each shadow takes away (P, S) at hit points ``p``
        (camera-relative (P, 3)) on triangles ``tri`` (P,),
        barycentric (u, v); ``strata``: the environment's directions' strata
        (environment.pixel_strata). With ``bounces`` the colour holds the light that
        reaches the point after bouncing off other surfaces too (``_indirect``)."""
        hit = self._surface(tri, p, ray, u, v)
        color, shadow, cone, taken = self._lit(hit, p, strata, self.draws)
        color = color + self._through(hit, p)
        if self.bounces:
            color = color + self._indirect(hit, p)
        fog = self.world.render.fog
        if fog is not None:
            distance = np.linalg.norm(p, axis=1)
            color = shading.apply_fog(color, distance, self.frame.fog_color, fog.mode,
                                      self.frame.fog_density, fog.start, fog.end)
            taken = taken * shading.fog_visibility(distance, fog.mode, self.frame.fog_density, fog.start,
                                                   fog.end)[:, None]
        return color, shadow, cone, hit.n, taken

    def _surface(self, tri: np.ndarray, p: np.ndarray, ray: np.ndarray, u: np.ndarray, v: np.ndarray,
                 view: np.ndarray | None = None) -> "_Hit":
        """The surface at hit points ``p`` (P, 3) of rays along ``ray`` (P, 3) on triangles
        ``tri`` (P,), barycentric (u, v): normals turned towards the ray's side, the
        material's values with vertex colours and maps applied. ``view`` (P, 3) unit towards
        where the ray came from; default towards the eye (the origin)."""
        soup, table = self.soup, self.table
        corners = soup.corners[tri]
        geometric = shading.safe_normalize(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]))
        vn = soup.normals[tri]
        interpolated = vn[:, 0] * (1.0 - u - v)[:, None] + vn[:, 1] * u[:, None] + vn[:, 2] * v[:, None]
        n = shading.safe_normalize(interpolated, geometric)
        # two-sided, as gl_FrontFacing: a face seen from behind uses the flipped normal
        back = np.sum(geometric * ray, axis=1) > 0.0
        n = np.where(back[:, None], -n, n)
        facing = np.where(back[:, None], -geometric, geometric)
        if view is None:
            view = shading.safe_normalize(-p, n)
        m = soup.material[tri]
        surface = {key: table[key][m] for key in ("diffuse", "ambient", "specular", "emissive", "shininess",
                                                   "metallic", "roughness", "layered", *shading.LAYER_KEYS,
                                                   *transmission.SURFACE_KEYS)}
        surface["occlusion"] = np.ones(len(m))
        colors = soup.colors[tri]
        surface["diffuse"] = surface["diffuse"] * (colors[:, 0] * (1.0 - u - v)[:, None] + colors[:, 1] * u[:, None]
                                                   + colors[:, 2] * v[:, None])[:, :3]
        coat_normals = any("clearcoat_normal_map" in samplers for samplers, _ in self.maps.values())
        if soup.tangents is not None:
            surface["anisotropy"] = table["anisotropy"][m]
            surface["anisotropy_xy"] = table["anisotropy_direction"][m]
        if coat_normals:  # tangent space, flat where a material has no coat normal map
            surface["clearcoat_texel"] = np.tile([0.0, 0.0, 1.0], (len(m), 1))
        if self.maps:
            self._apply_maps(m, soup.uvs[tri], u, v, surface)
        if soup.tangents is not None:
            surface["anisotropy_t"] = _anisotropy_direction(soup.tangents[tri], u, v, n, back,
                                                            surface.pop("anisotropy_xy"))
        if coat_normals:
            surface["clearcoat_normal"] = _tangent_space_normal(soup.tangents[tri], u, v, n, back,
                                                                surface.pop("clearcoat_texel"))
        return _Hit(n, facing, view, surface, table["model"][m])

    def _lit(self, hit: "_Hit", p: np.ndarray, strata, draws: "_Draws"):
        """(colour (P, 3), shadow flags (P, S), cone factors (P, C), radiance each shadow
        takes away (P, S)) of the surface ``hit`` at points ``p`` (P, 3): its emission, the
        ambient and environment terms and every light's direct term, before fog; unlit
        points show base + emission. ``draws`` gives the random numbers."""
        n, facing, view, surface, model = hit.n, hit.facing, hit.view, hit.surface, hit.model
        base, ke = surface["diffuse"], surface["emissive"]
        pbr = model == MODELS.index("pbr")
        ambient = (self._ambient(p, n, facing, view, surface, model, draws.ambient) if self.ambient_samples
                   else self._ambient_formula(n, view, surface, pbr))
        ambient = ambient + self._environment(p, n, facing, view, surface, model, strata, draws.environment)
        color = ambient * surface["occlusion"][:, None] + ke
        shadow = np.zeros((len(p), len(self.shadowed)))
        taken = np.zeros((len(p), len(self.shadowed)))
        cone = np.zeros((len(p), len(self.spots)))
        for light_index, light in enumerate(self.lights):
            l, radiance, in_cone, reach = self._light_at(light, p, n, draws.light)
            if light.kind == "spot":
                cone[:, self.spots.index(light_index)] = in_cone
            term = self._direct(n, l, view, radiance, surface, model)
            color += self._light_through(hit, p, light, l, radiance, reach, light_index in self.shadowed)
            if light_index in self.shadowed:
                blocked = self._blocked(light, p, l, facing, n, reach)
                shadow[:, self.shadowed.index(light_index)] = blocked
                taken[:, self.shadowed.index(light_index)] = np.where(blocked, term.mean(axis=1), 0.0)
                term = term * (~blocked)[:, None]
            color += term
        unlit = model == MODELS.index("unlit")
        color = np.where(unlit[:, None], base + ke, color)
        taken = np.where(unlit[:, None], 0.0, taken)
        return color, shadow, cone, taken

    def _light_through(self, hit: "_Hit", p: np.ndarray, light, l: np.ndarray, radiance: np.ndarray,
                       reach: np.ndarray | None, shadowed: bool) -> np.ndarray:
        """(P, 3) what ``light`` (direction ``l`` (P, 3), ``radiance`` (P, 3) and ``reach``
        from _light_at) gives through the transmissive pbr surfaces among ``hit`` that it lies
        behind: next-event estimation through the BTDF (shading.pbr_through_term). Its shadow
        ray leaves from the surface's far side, so the surface itself never blocks it and
        every other caster does. A volume takes the GPU's approximation
        (shaders/lighting/transmission.glsl, light_through), since no path through it can
        meet a point light: the light's direction from where the view's refracted ray leaves
        it, thickness away, attenuated over the thickness."""
        out = np.zeros_like(p)
        surface = hit.surface
        rows = np.flatnonzero((hit.model == MODELS.index("pbr")) & (surface["transmission"] > 0.0)
                              & (np.sum(hit.n * l, axis=1) < 0.0))
        if not len(rows):
            return out
        n, view, at = hit.n[rows], hit.view[rows], {key: value[rows] for key, value in surface.items()}
        direction = l[rows]
        thickness = at["thickness"]
        volume = thickness > 0.0
        if volume.any() and light.kind != "directional":
            if reach is None:
                to_light = (light.position - self.frame.camera.position)[None, :] - p[rows]
            else:
                to_light = direction * reach[rows][:, None]
            eta = 1.0 / at["ior"]
            cos_i = np.sum(n * view, axis=1)
            cos_t2 = 1.0 - eta * eta * (1.0 - cos_i * cos_i)
            refracted = (-eta[:, None] * view + (eta * cos_i - np.sqrt(np.maximum(cos_t2, 0.0)))[:, None] * n)
            refracted = np.where((cos_t2 < 0.0)[:, None], 0.0, refracted)  # GLSL's refract: 0 past the critical angle
            ray = shading.safe_normalize(refracted, -view) * thickness[:, None]
            direction = np.where(volume[:, None], shading.safe_normalize(to_light - ray, -n), direction)
        term = shading.pbr_through_term(n, direction, view, radiance[rows], at["diffuse"], at["metallic"],
                                        at["roughness"], at["transmission"], at["ior"], at["f0"], at["f90"])
        term = term * np.exp(-at["extinction"] * np.where(volume, thickness, 0.0)[:, None])
        if shadowed:
            blocked = self._blocked(light, p[rows], l[rows], -hit.facing[rows], -n, None if reach is None else reach[rows])
            term = term * (~blocked)[:, None]
        out[rows] = term
        return out

    def _indirect(self, hit: "_Hit", p: np.ndarray) -> np.ndarray:
        """(P, 3) the light leaving points ``p`` (P, 3) of surface ``hit`` towards the eye
        after one to ``bounces`` bounces: from each point a path continues in a direction
        drawn from its BRDF (_continuation); at each surface the path meets, what _lit gives
        there (its emission, and the ambient, environment and every light's term: next-event
        estimation) is added, times the path's throughput. After ROULETTE_AFTER bounces a
        path goes on with the chance of its throughput's largest channel (at most
        MAX_SURVIVAL) and is divided by it (Russian roulette: no bias). Unlit surfaces
        reflect nothing: a path ends there, taking only their emission. Paths that leave the
        scene end; the environment and ambient light reach them by next-event estimation
        only (the background is not a light)."""
        total = np.zeros_like(p)
        rows = np.flatnonzero(hit.model != MODELS.index("unlit"))
        hit, p = hit.take(rows), p[rows]
        throughput = np.ones((len(rows), 3))
        rng = self.bounce_rng
        for bounce in range(1, self.bounces + 1):
            l, weight = self._continuation(hit, rng)
            throughput = throughput * weight
            going = np.any(throughput > 0.0, axis=1)
            if bounce > ROULETTE_AFTER:
                survival = np.minimum(throughput.max(axis=1), MAX_SURVIVAL)
                going &= rng.random(len(rows)) < survival
                throughput = throughput / np.maximum(survival, 1e-300)[:, None]
            epsilon = 1e-6 * self.extent + 2e-6 * np.linalg.norm(p, axis=1)
            origins = p + hit.facing * epsilon[:, None]
            triangles = np.full(len(rows), -1, dtype=np.int64)
            if self.primary_count:
                triangles[going] = self.primary.first_hit(origins[going], l[going])
            met = np.flatnonzero(triangles >= 0)
            if not len(met):
                break
            t, u, v = self.primary.hit_parameters(triangles[met], origins[met], l[met])
            rows, throughput, l = rows[met], throughput[met], l[met]
            p = origins[met] + l * t[:, None]
            hit = self._surface(triangles[met], p, l, u, v, view=-l)
            color = self._lit(hit, p, None, self.bounce_draws)[0]
            unlit = hit.model == MODELS.index("unlit")
            color = np.where(unlit[:, None], hit.surface["emissive"], color)
            total[rows] += throughput * color
            keep = np.flatnonzero(~unlit)
            rows, throughput, hit, p = rows[keep], throughput[keep], hit.take(keep), p[keep]
        return total

    def _through(self, hit: "_Hit", p: np.ndarray) -> np.ndarray:
        """(P, 3) the light that reaches the eye through the transmissive pbr surfaces among
        ``hit`` at points ``p`` (P, 3) (raytrace/transmission.py): one path a point, from
        its surface through every transmissive surface it meets (thin walls and volumes,
        Beer-Lambert inside), to the first other surface, shaded as a visible point is
        (``_lit``: emission, ambient, environment, lights; no bounces), or the background
        where it leaves the scene. A transmissive surface on the way adds its own
        reflection too. Each surface the path enters through (from outside) tints it by
        (1 - metallic) transmission base."""
        out = np.zeros_like(p)
        pbr = hit.model == MODELS.index("pbr")
        rows = np.flatnonzero(pbr & (hit.surface["transmission"] > 0.0))
        if not len(rows) or not self.primary_count:
            return out
        hit, p = hit.take(rows), p[rows]
        inside = np.zeros(len(rows), bool)
        extinction = np.zeros((len(rows), 3))
        throughput = np.ones((len(rows), 3))
        rng = self.transmission_rng
        for _ in range(transmission.MAX_INTERFACES):
            surface = hit.surface
            entering = ~inside
            metallic = surface["metallic"][:, None]
            throughput = throughput * np.where(entering[:, None],
                                               (1.0 - metallic) * surface["transmission"][:, None] * surface["diffuse"],
                                               1.0)
            f90 = surface["f90"] * (1.0 - surface["metallic"]) + surface["metallic"]
            f0 = surface["f0"] * (1.0 - metallic) + surface["diffuse"] * metallic
            went = transmission.scatter(transmission.Interface(
                hit.n, hit.view, shading.pbr_alpha(surface["roughness"]), f0, f90, surface["ior"],
                surface["thickness"] <= 0.0, inside), rng)
            extinction = np.where((entering & went.inside)[:, None], surface["extinction"], extinction)
            throughput = throughput * went.weight
            inside = went.inside
            epsilon = 1e-6 * self.extent + 2e-6 * np.linalg.norm(p, axis=1)
            side = np.sign(np.sum(hit.facing * went.l, axis=1))[:, None]
            origins = p + hit.facing * side * epsilon[:, None]
            going = np.flatnonzero(np.any(throughput > 0.0, axis=1))
            triangles = np.full(len(rows), -1, dtype=np.int64)
            triangles[going] = self.primary.first_hit(origins[going], went.l[going])
            left = np.flatnonzero((triangles < 0) & ~inside)
            out[rows[left]] += throughput[left] * self.frame.background[:3]
            met = np.flatnonzero(triangles >= 0)
            if not len(met):
                break
            t, u, v = self.primary.hit_parameters(triangles[met], origins[met], went.l[met])
            rows, inside, extinction, l = rows[met], inside[met], extinction[met], went.l[met]
            throughput = throughput[met] * np.exp(-extinction * np.where(inside, t, 0.0)[:, None])
            p = origins[met] + l * t[:, None]
            hit = self._surface(triangles[met], p, l, u, v, view=-l)
            # outside a volume, a surface adds what it reflects; an opaque one ends the path
            lit = np.flatnonzero(~inside)
            if len(lit):
                out[rows[lit]] += throughput[lit] * self._lit(hit.take(lit), p[lit], None, self.bounce_draws)[0]
            passes = (hit.model == MODELS.index("pbr")) & (hit.surface["transmission"] > 0.0)
            keep = np.flatnonzero(passes)
            rows, inside, extinction, throughput, hit, p = (rows[keep], inside[keep], extinction[keep],
                                                            throughput[keep], hit.take(keep), p[keep])
            if not len(rows):
                break
        return out

    @staticmethod
    def _continuation(hit: "_Hit", rng) -> tuple[np.ndarray, np.ndarray]:
        """(l (P, 3) unit, weight (P, 3)): the direction each path goes on in from surface
        ``hit``, and f (N.l) / pdf, the BRDF over the density it was drawn with. Phong and
        Blinn-Phong surfaces reflect their diffuse part only (base / pi, drawn
        cosine-weighted: the weight is the base colour); pbr ones their whole BRDF, drawn
        from the mixture of the cosine and GGX's visible normals that the environment light
        uses (environment_sampling.draw_directions, weighted by the mixture's density: the
        balance heuristic). Zero weight for a direction below the surface's own plane."""
        n, view, surface = hit.n, hit.view, hit.surface
        frame = environment.TangentFrame(n)
        local_view = environment.sampling_view(n, frame.tangent, frame.bitangent, view)
        alpha = shading.pbr_alpha(surface["roughness"])
        pbr = hit.model == MODELS.index("pbr")
        choice = np.zeros(len(n))
        if pbr.any():
            choice[pbr] = environment.ggx_choice(np.sum(n[pbr] * view[pbr], axis=1), surface["diffuse"][pbr],
                                                 surface["metallic"][pbr])
        local = environment.draw_directions(rng, local_view, alpha, choice, rng.random(len(n)))
        l = shading.safe_normalize(frame.to_world(local), n)
        weight = surface["diffuse"].copy()  # (base / pi) cos / (cos / pi)
        if pbr.any():
            pdf = environment.mixture_pdf(local[pbr], local_view[pbr], alpha[pbr], choice[pbr])
            reflected = shading.pbr_direct_term(n[pbr], l[pbr], view[pbr], np.ones((int(pbr.sum()), 3)),
                                                surface["diffuse"][pbr], surface["metallic"][pbr],
                                                surface["roughness"][pbr]) / np.pi
            weight[pbr] = np.where((pdf > 0.0)[:, None], reflected / np.maximum(pdf, 1e-300)[:, None], 0.0)
        above = (local[:, 2] > 0.0) & (np.sum(l * hit.facing, axis=1) > 0.0)
        return l, np.where(above[:, None], weight, 0.0)

    @staticmethod
    def _direct(n, l, view, radiance, surface: dict, model: np.ndarray) -> np.ndarray:
        """(P, 3): one light's term under each point's model (unlit points are replaced later)."""
        out = np.zeros_like(n)
        for code, name in enumerate(MODELS):
            rows = np.flatnonzero(model == code)
            if not len(rows) or name == "unlit":
                continue
            part = {key: value[rows] for key, value in surface.items()}
            if name == "pbr":
                out[rows] = shading.pbr_direct_term(n[rows], l[rows], view[rows], radiance[rows], part["diffuse"],
                                                    part["metallic"], part["roughness"], shading.pbr_layers(part))
            else:
                out[rows] = shading.direct_term(n[rows], l[rows], view[rows], radiance[rows], part["diffuse"],
                                                part["specular"], part["shininess"], name)
        return out

    def _ambient_formula(self, n, view, surface: dict, pbr: np.ndarray) -> np.ndarray:
        """(P, 3) La Ka times what the surface reflects of it: base, or the pbr model's
        hemisphere integral (shading.pbr_ambient)."""
        reflected = surface["diffuse"]
        if pbr.any():
            reflected = reflected.copy()
            points = {key: value[pbr] for key, value in surface.items()}
            reflected[pbr] = shading.pbr_ambient(n[pbr], view[pbr], points["diffuse"], points["metallic"],
                                                 points["roughness"], shading.pbr_layers(points))
        return shading.ambient_term(self.frame.ambient, surface["ambient"], reflected)

    def _ambient(self, p, n, facing, view, surface: dict, model: np.ndarray, rng) -> np.ndarray:
        """(P, 3) La Ka times the BRDF integrated over the hemisphere by Monte Carlo:
        ``ambient_samples`` cosine-distributed directions a point (pdf cos / pi, so each
        weighs pi f = the light term over N.L), each blocked by any surface in its way."""
        ambient = np.asarray(self.frame.ambient, dtype=np.float64)
        total = np.zeros_like(n)
        if not np.any(ambient > 0.0):
            return total
        tangent, bitangent = environment.tangent_frame(n)
        epsilon = 1e-6 * self.extent + 2e-6 * np.linalg.norm(p, axis=1)
        for _ in range(self.ambient_samples):
            local = environment.cosine_directions(*rng.random((2, len(p))))
            cos = local[:, 2]
            l = tangent * local[:, :1] + bitangent * local[:, 1:2] + n * local[:, 2:]
            radiance = np.broadcast_to(ambient, n.shape)
            term = self._direct(n, l, view, radiance, surface, model) / np.maximum(cos, 1e-12)[:, None]
            if self.primary_count:
                hits = self.primary.first_hit(p + facing * epsilon[:, None], l)
                term = np.where((hits >= 0)[:, None], 0.0, term)
            total += term
        return total / self.ambient_samples * surface["ambient"]

    def _environment(self, p, n, facing, view, surface: dict, model: np.ndarray, strata, rng) -> np.ndarray:
        """(P, 3) Ka times the environment light's radiance reflected towards the eye, by
        Monte Carlo (scenerender.raytrace.environment_sampling); zero without one."""
        state = self.frame.environment
        out = np.zeros_like(n)
        if state is None or not np.any(state.scale > 0.0):
            return out
        rows = self._environment_rows(model)
        if not len(rows):
            return out
        part = {key: value[rows] for key, value in surface.items()}
        n, view, pbr = n[rows], view[rows], model[rows] == MODELS.index("pbr")
        choice = np.where(pbr, environment.ggx_choice(np.sum(n * view, axis=1), part["diffuse"], part["metallic"]),
                          0.0)
        reflected = _environment_reflection(state, self.world.environment.image, n, view, part, pbr)
        gathered = environment.gather(n, view, shading.pbr_alpha(part["roughness"]), choice, self.environment_samples,
                                      rng, reflected, self._open_sky(p[rows], facing[rows]),
                                      self.environment_image, strata[rows] if strata is not None else None)
        out[rows] = gathered * part["ambient"]
        return out

    def _environment_rows(self, model: np.ndarray) -> np.ndarray:
        """(R,) the points an environment light reaches: pbr ones, and Phong and
        Blinn-Phong ones where the light is ``classic``."""
        lit = model == MODELS.index("pbr")
        if self.world.environment.classic:
            lit |= np.isin(model, [MODELS.index("phong"), MODELS.index("blinn_phong")])
        return np.flatnonzero(lit)

    def _open_sky(self, p: np.ndarray, facing: np.ndarray):
        """visible(rows, l) for environment.gather: no surface lies along l from points
        ``p`` (P, 3) of those rows, leaving on the ``facing`` side (the epsilon of _ambient)."""
        epsilon = 1e-6 * self.extent + 2e-6 * np.linalg.norm(p, axis=1)

        def visible(rows: np.ndarray, l: np.ndarray) -> np.ndarray:
            if not self.primary_count:
                return np.ones(len(rows), bool)
            return self.primary.first_hit(p[rows] + facing[rows] * epsilon[rows, None], l) < 0
        return visible

    def _apply_maps(self, m: np.ndarray, corner_uvs: np.ndarray, u: np.ndarray, v: np.ndarray, surface: dict) -> None:
        """The maps of each point's material applied to ``surface`` (arrays per point, in
        place): base and Ks times the diffuse and specular maps, metallic and roughness
        times theirs, emission times the emissive map, occlusion from its map."""
        uv = corner_uvs[:, 0] * (1.0 - u - v)[:, None] + corner_uvs[:, 1] * u[:, None] + corner_uvs[:, 2] * v[:, None]
        for key in ("diffuse", "specular", "emissive", "metallic", "roughness", "thickness", *shading.LAYER_KEYS):
            surface[key] = surface[key].copy()
        for material_index, (samplers, material) in self.maps.items():
            rows = np.flatnonzero(m == material_index)
            if not len(rows):
                continue
            sample = {key: sampler.sample(uv[rows, 2:] if sampler.uv_set == 1 else uv[rows, :2])
                      for key, sampler in samplers.items()}
            if "diffuse_map" in sample:
                surface["diffuse"][rows] *= sample["diffuse_map"][:, :3]
            if "specular_map" in sample:
                surface["specular"][rows] *= sample["specular_map"][:, :3]
            if "emissive_map" in sample:
                surface["emissive"][rows] *= sample["emissive_map"][:, :3]
            if "metallic_roughness_map" in sample:
                surface["metallic"][rows] *= sample["metallic_roughness_map"][:, 2]
                surface["roughness"][rows] *= sample["metallic_roughness_map"][:, 1]
            if "roughness_map" in sample:
                surface["roughness"][rows] *= sample["roughness_map"][:, 0]
            if "metallic_map" in sample:
                surface["metallic"][rows] *= sample["metallic_map"][:, 0]
            if "occlusion_map" in sample:
                surface["occlusion"][rows] = 1.0 + material.occlusion_strength * (sample["occlusion_map"][:, 0] - 1.0)
            _apply_layer_maps(rows, sample, material, surface)

    def _light_at(self, light, p: np.ndarray, n: np.ndarray, rng):
        """(l (P, 3) unit towards the light, radiance (P, 3), cone factor (P,), reach (P,):
        how far along l the light is, inf for a directional light, None for a point one:
        its position). A light with a size
        gives each point one direction drawn over it (sized_lights); attenuation and the
        spot cone are taken at its centre, as on the GPU."""
        size = light.definition.size
        if light.definition.area:
            centre = light.position - self.frame.camera.position
            l, weight, reach = sized_lights.area_directions(centre, light.direction, light.kind,
                                                            light.definition.extent, p, rng)
            return l, light.color[None, :] * weight[:, None], np.ones(len(p)), reach
        if light.kind == "directional":
            l = np.broadcast_to(-light.direction, p.shape)
            radiance = np.broadcast_to(light.color, p.shape)
            if size > 0.0:
                l, weight = sized_lights.disc_directions(light.direction, size, len(p), rng)
                radiance = radiance * weight[:, None]
            return l, radiance, np.ones(len(p)), np.full(len(p), np.inf)
        to_light = (light.position - self.frame.camera.position)[None, :] - p
        distance = np.linalg.norm(to_light, axis=1)
        l = shading.safe_normalize(to_light, n)
        falloff = shading.attenuation(light.definition.attenuation, distance)
        radiance = light.color[None, :] * (falloff * shading.range_window(light.definition.range, distance))[:, None]
        cone = np.ones(len(p))
        if light.kind == "spot":
            cone = shading.spot_cone(light.cos_inner, light.cos_outer, np.sum(-l * light.direction, axis=1),
                                     light.definition.cone_falloff)
            radiance = radiance * cone[:, None]
        if size > 0.0:
            l, weight, reach = sized_lights.sphere_directions(to_light, size, rng)
            return l, radiance * weight[:, None], cone, reach
        return l, radiance, cone, None

    def _blocked(self, light, p: np.ndarray, l: np.ndarray, facing: np.ndarray, n: np.ndarray,
                 reach: np.ndarray | None = None) -> np.ndarray:
        """(P,) bool: a shadow caster lies between each lit point and ``light``, ``reach``
        (P,) away along ``l`` (None: at the light's position). Points not facing the light (N.L <= 0) get no light anyway
        and count as not blocked."""
        lit = np.sum(n * l, axis=1) > 0.0
        blocked = np.zeros(len(p), bool)
        rows = np.flatnonzero(lit)
        if not len(rows):
            return blocked
        # leave the surface on the light's side: float32 in the engine must not re-hit it
        side = np.sign(np.sum(facing[rows] * l[rows], axis=1))[:, None]
        epsilon = 1e-6 * self.extent + 2e-6 * np.linalg.norm(p[rows], axis=1)
        origins = p[rows] + facing[rows] * side * epsilon[:, None]
        directions = l[rows]
        triangles = self.casters.first_hit(origins, directions)
        hits = triangles >= 0
        if light.kind == "directional":
            blocked[rows[hits]] = True
            return blocked
        if reach is None:
            reach = np.linalg.norm((light.position - self.frame.camera.position)[None, :] - origins, axis=1)
        else:
            reach = reach[rows] - epsilon
        t = np.full(len(rows), np.inf)
        if hits.any():
            t[hits] = self.casters.hit_parameters(triangles[hits], origins[hits], directions[hits])[0]
        blocked[rows] = t < reach
        return blocked


MODELS = ("phong", "blinn_phong", "pbr", "unlit")


@dataclass
class _Hit:
    """Surface points ready to shade, one row each: n (P, 3) shading normal and facing
    (P, 3) geometric normal, both on the side the ray came from; view (P, 3) unit towards
    where it came from; surface: the material's values per point ({key: (P, ...)});
    model (P,) index into MODELS."""

    n: np.ndarray
    facing: np.ndarray
    view: np.ndarray
    surface: dict
    model: np.ndarray

    def take(self, rows: np.ndarray) -> "_Hit":
        return _Hit(self.n[rows], self.facing[rows], self.view[rows],
                    {key: value[rows] for key, value in self.surface.items()}, self.model[rows])


@dataclass(frozen=True)
class _Draws:
    """The generators one shading of points draws from: ambient and environment
    directions, points of lights with a size."""

    ambient: np.random.Generator | None
    environment: np.random.Generator | None
    light: np.random.Generator
# maps the reference samples (only the pbr model reads the metallic and roughness ones)
SAMPLED_MAPS = ("diffuse_map", "specular_map", "emissive_map", "occlusion_map", "metallic_roughness_map",
                "roughness_map", "metallic_map", *LAYER_MAP_KEYS)


def _material_table(materials: list, scene_shading: str = "blinn_phong") -> dict:
    """Per-material arrays gathered by triangle: (K, 3) colours (emission times its
    strength), (K,) shininess, metallic, roughness and the shading model (an index into
    MODELS; ``scene_shading`` for materials that name none)."""
    if not materials:
        materials = [(None, {"ambient": np.ones(3), "diffuse": np.ones(4), "specular": np.zeros(3),
                             "emissive": np.zeros(3), "shininess": 1.0, "metallic": 0.0, "roughness": 0.5})]
    values = [v for _, v in materials]
    return {
        "ambient": np.array([v["ambient"][:3] for v in values], dtype=np.float64),
        "diffuse": np.array([v["diffuse"][:3] for v in values], dtype=np.float64),
        "specular": np.array([v["specular"][:3] for v in values], dtype=np.float64),
        "emissive": np.array([np.asarray(v["emissive"][:3]) * getattr(m, "emissive_strength", 1.0)
                              for m, v in materials], dtype=np.float64),
        "shininess": np.array([v["shininess"] for v in values], dtype=np.float64),
        "metallic": np.array([v.get("metallic", 0.0) for v in values], dtype=np.float64),
        "roughness": np.array([v.get("roughness", 0.5) for v in values], dtype=np.float64),
        "model": np.array([MODELS.index(m.model(scene_shading) if m is not None else scene_shading)
                           for m, _ in materials]),
        **_layer_table([m for m, _ in materials]),
        **transmission.transmission_table([m for m, _ in materials]),
    }


def _layer_table(materials: list) -> dict:
    """Per-material arrays of the pbr model's layers (shading.pbr_layers): whether it has
    any, the dielectric's F0 (K, 3) and F90, the clear coat's weight and roughness (K,), the
    sheen's colour (K, 3) and roughness (K,)."""
    default = (np.full(3, 0.04), 1.0)
    pairs = [m.dielectric_f0_f90() if m is not None else default for m in materials]
    return {
        "layered": np.array([m is not None and m.layered for m in materials]),
        "f0": np.array([f0 for f0, _ in pairs], dtype=np.float64).reshape(-1, 3),
        "f90": np.array([f90 for _, f90 in pairs], dtype=np.float64),
        "clearcoat": np.array([m.clearcoat if m is not None else 0.0 for m in materials], dtype=np.float64),
        "clearcoat_roughness": np.array([m.clearcoat_roughness if m is not None else 0.0 for m in materials],
                                        dtype=np.float64),
        "sheen_color": np.array([m.sheen_color if m is not None else (0.0, 0.0, 0.0) for m in materials],
                                dtype=np.float64).reshape(-1, 3),
        "sheen_roughness": np.array([m.sheen_roughness if m is not None else 0.0 for m in materials],
                                    dtype=np.float64),
        "transmission": np.array([m.transmission if m is not None else 0.0 for m in materials], dtype=np.float64),
        "iridescence": np.array([m.iridescence if m is not None else 0.0 for m in materials], dtype=np.float64),
        "iridescence_ior": np.array([m.iridescence_ior if m is not None else 1.3 for m in materials],
                                    dtype=np.float64),
        "iridescence_thickness": np.array([m.iridescence_thickness if m is not None else 400.0 for m in materials],
                                          dtype=np.float64),
        "anisotropy": np.array([m.anisotropy if m is not None else 0.0 for m in materials], dtype=np.float64),
        "anisotropy_direction": np.array([m.anisotropy_direction() if m is not None else (1.0, 0.0)
                                          for m in materials], dtype=np.float64).reshape(-1, 2),
    }


def _anisotropy_direction(frames: np.ndarray, u: np.ndarray, v: np.ndarray, n: np.ndarray, back: np.ndarray,
                          direction: np.ndarray) -> np.ndarray:
    """(P, 3) unit world directions of the anisotropy at hit points, as lighting/material.glsl's
    anisotropy_direction: the corners' tangents ``frames`` (P, 3, 4) interpolated by
    barycentric (u, v), turned for a face seen from behind (``back``), made orthogonal to the
    shading normal ``n``; then (cos, sin) ``direction`` (P, 2) in the frame of that tangent
    and the bitangent cross(n, t) w."""
    tangent = frames[:, 0] * (1.0 - u - v)[:, None] + frames[:, 1] * u[:, None] + frames[:, 2] * v[:, None]
    xyz = np.where(back[:, None], -tangent[:, :3], tangent[:, :3])
    t = shading.safe_normalize(xyz - n * np.sum(n * xyz, axis=1, keepdims=True), np.array([1.0, 0.0, 0.0]))
    b = np.cross(n, t) * np.where(frames[:, 0, 3:] < 0.0, -1.0, 1.0)
    return shading.safe_normalize(t * direction[:, :1] + b * direction[:, 1:], t)


def _tangent_space_normal(frames: np.ndarray, u: np.ndarray, v: np.ndarray, n: np.ndarray, back: np.ndarray,
                          texel: np.ndarray) -> np.ndarray:
    """(P, 3) unit world normals from tangent-space ``texel`` (P, 3) (already * 2 - 1, xy
    scaled) over normals ``n`` (P, 3), as lighting/material.glsl's coat_mapped_normal: the
    tangent frame as _anisotropy_direction takes it."""
    tangent = frames[:, 0] * (1.0 - u - v)[:, None] + frames[:, 1] * u[:, None] + frames[:, 2] * v[:, None]
    xyz = np.where(back[:, None], -tangent[:, :3], tangent[:, :3])
    t = shading.safe_normalize(xyz - n * np.sum(n * xyz, axis=1, keepdims=True), np.array([1.0, 0.0, 0.0]))
    b = np.cross(n, t) * np.where(frames[:, 0, 3:] < 0.0, -1.0, 1.0)
    return shading.safe_normalize(t * texel[:, :1] + b * texel[:, 1:2] + n * texel[:, 2:], n)


def _apply_layer_maps(rows: np.ndarray, sample: dict, material, surface: dict) -> None:
    """The pbr layers' maps (world.materials.LAYER_MAP_KEYS) of ``material`` applied to
    ``surface``'s layer arrays at ``rows``, as lighting/material.glsl's sample_layers: a
    specular colour map multiplies F0 before its clamp, the specular map F0 and F90; the
    specular-glossiness map sets F0, roughness and the diffuse colour's share; the
    transmission and thickness maps multiply theirs (red, green), the iridescence map its
    weight (red); the iridescence thickness map mixes the film's thickness from its minimum
    to its maximum by its green."""
    if "specular_color_map" in sample:
        f0 = np.minimum(material.dielectric_reflectance() * sample["specular_color_map"][:, :3], 1.0)
        surface["f0"][rows] = f0 * material.specular_factor
    if "specular_glossiness_map" in sample:  # KHR_materials_pbrSpecularGlossiness's texture (mesh.gltf)
        texels = sample["specular_glossiness_map"]
        f0 = np.minimum(material.dielectric_reflectance() * texels[:, :3], 1.0) * material.specular_factor
        surface["f0"][rows] = f0
        surface["roughness"][rows] = 1.0 - (1.0 - surface["roughness"][rows]) * texels[:, 3]
        surface["diffuse"][rows] *= 1.0 - f0.max(axis=1)[:, None]
    if "specular_factor_map" in sample:
        surface["f0"][rows] *= sample["specular_factor_map"][:, 3:4]
        surface["f90"][rows] *= sample["specular_factor_map"][:, 3]
    if "anisotropy_map" in sample and "anisotropy_xy" in surface:  # (no anisotropy: nothing to turn)
        # its direction turned by the rotation, its strength times the factor
        texels = sample["anisotropy_map"]
        xy = shading.safe_normalize(np.column_stack([texels[:, :2] * 2.0 - 1.0, np.zeros(len(rows))]),
                                    np.array([1.0, 0.0, 0.0]))[:, :2]
        c, s = material.anisotropy_direction()
        surface["anisotropy_xy"][rows] = np.column_stack([c * xy[:, 0] - s * xy[:, 1], s * xy[:, 0] + c * xy[:, 1]])
        surface["anisotropy"][rows] *= texels[:, 2]
    if "clearcoat_map" in sample:
        surface["clearcoat"][rows] *= sample["clearcoat_map"][:, 0]
    if "clearcoat_roughness_map" in sample:
        surface["clearcoat_roughness"][rows] *= sample["clearcoat_roughness_map"][:, 1]
    if "clearcoat_normal_map" in sample:
        texel = sample["clearcoat_normal_map"][:, :3] * 2.0 - 1.0
        texel[:, :2] *= material.maps["clearcoat_normal_map"].strength
        surface["clearcoat_texel"][rows] = texel
    if "sheen_color_map" in sample:
        surface["sheen_color"][rows] *= sample["sheen_color_map"][:, :3]
    if "sheen_roughness_map" in sample:
        surface["sheen_roughness"][rows] *= sample["sheen_roughness_map"][:, 3]
    if "iridescence_map" in sample:
        surface["iridescence"][rows] *= sample["iridescence_map"][:, 0]
    if "iridescence_thickness_map" in sample:
        low, high = material.iridescence_thickness_min, material.iridescence_thickness
        surface["iridescence_thickness"][rows] = low + (high - low) * sample["iridescence_thickness_map"][:, 1]
    if "transmission_map" in sample:
        surface["transmission"][rows] *= sample["transmission_map"][:, 0]
    if "thickness_map" in sample:
        surface["thickness"][rows] *= sample["thickness_map"][:, 1]


def _material_maps(materials: list, images) -> dict:
    """{material index: ({map key: MapSampler}, its Material)} for the materials that have
    maps the reference samples."""
    maps = {}
    for index, (material, _) in enumerate(materials):
        samplers = {key: MapSampler.for_source(material.maps[key], material, images) for key in SAMPLED_MAPS
                    if key in material.maps}
        if samplers:
            maps[index] = (samplers, material)
    return maps


def _environment_reflection(state, image: np.ndarray, n: np.ndarray, view: np.ndarray, surface: dict,
                            pbr: np.ndarray):
    """reflected(rows, l) for environment.gather: f L_env(l) (N.l) at those points, f the
    pbr model's BRDF where ``pbr`` (P,), else Lambert's base / pi (light terms over pi)."""
    def reflected(rows: np.ndarray, l: np.ndarray) -> np.ndarray:
        radiance = state.radiance(image, l)
        base = surface["diffuse"][rows]
        term = base * radiance * np.maximum(np.sum(n[rows] * l, axis=1), 0.0)[:, None]
        glossy = np.flatnonzero(pbr[rows])
        at = rows[glossy]
        points = {key: value[at] for key, value in surface.items()}
        term[glossy] = shading.pbr_direct_term(n[at], l[glossy], view[at], radiance[glossy], base[glossy],
                                               points["metallic"], points["roughness"], shading.pbr_layers(points))
        return term / np.pi
    return reflected


def _image_sampler(world, frame) -> environment.ImageSampler | None:
    """Draws directions from the frame's environment image, where it has a lit one."""
    state = frame.environment
    if state is None or not np.any(state.scale > 0.0):
        return None
    return environment.ImageSampler(world.environment.image, state.scale, state.to_image)


def _depth_range(world, camera) -> tuple[float, float]:
    """(near, far) ray-parameter range: the scene's explicit clip planes, else everything in
    front of the camera (an ideal camera has no depth buffer to protect); orthographic
    cameras keep the planes the frame evaluator fitted (they may lie behind the eye)."""
    spec = world.spec.camera
    near = 0.0
    far = np.inf
    if camera.orthographic:
        return camera.near, camera.far
    if spec is not None and spec.near != "auto":
        near = float(spec.near)
    if spec is not None and spec.far != "auto":
        far = float(spec.far)
    return near, far


def _creased(normals: np.ndarray, cos_limit: float = 0.9) -> np.ndarray:
    """(rows, W) bool: a pixel's samples face directions more than ~25 degrees apart (a
    box's edge, a cylinder's rim): a shading discontinuity inside one object.
    normals: (rows, W, n, 3), zero for samples that miss."""
    mean = normals.sum(axis=2, keepdims=True)
    mean = mean / np.maximum(np.linalg.norm(mean, axis=3, keepdims=True), 1e-12)
    cosines = np.sum(normals * mean, axis=3)
    hit = np.any(normals != 0.0, axis=3)
    return np.any(hit & (cosines < cos_limit), axis=2)


def _sample_positions(rows: int, width: int, spp: int, rng):
    """Jittered stratified sample positions in pixel units: two (rows, W, spp*spp) arrays,
    one sample in each cell of an spp x spp grid per pixel."""
    cells = (np.arange(spp * spp) % spp, np.arange(spp * spp) // spp)
    jitter = rng.random((2, rows, width, spp * spp))
    x = np.arange(width)[None, :, None] + (cells[0][None, None, :] + jitter[0]) / spp
    y = np.arange(rows)[:, None, None] + (cells[1][None, None, :] + jitter[1]) / spp
    return x, y
