"""Which shader features a scene and its materials need -> GLSL defines.

Features are decided once per run from the scene: light counts per type, shadows, fog
mode, AO; and per material: its shading model (the scene's ``render.shading`` unless the
material names its own), texture maps, vertex colours, alpha mask, mirrored wrap.

Which lights cast shadows, and where their views sit in the shadow-view array, never
changes during a run, so those are compile-time constants too: an unshadowed light has no
shadow code at all, and a shadowed one reads its view at a constant index, from a constant
atlas page.
"""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.scene.model.lights import PREFILTER_LEVELS
from scenerender.world.environment_visibility import interleave_pattern
from scenerender.world.shadows import first_shadow_views, view_count

# Light and shadow data live in uniform blocks (fast on every driver) up to the size every
# OpenGL implementation must offer; beyond that, in storage buffers (no cap on lights).
UNIFORM_BLOCK_BYTES = 16384
SHADOW_VIEW_BYTES = 144  # one ShadowView (shaders/lighting/shadows.glsl)

TEXTURE_UNITS = {
    "u_diffuse_map": 0, "u_specular_map": 1, "u_normal_map": 2, "u_opacity_map": 3,
    "u_shadow_atlas": 4, "u_ao": 5, "u_skybox": 6, "u_gbuffer": 7, "u_noise": 8, "u_color": 9, "u_atlas": 10,
    "u_shadow_atlas_2": 11, "u_metallic_roughness_map": 12, "u_occlusion_map": 13, "u_emissive_map": 14,
    "u_roughness_map": 15, "u_metallic_map": 16, "u_env_diffuse": 17, "u_env_specular": 18, "u_env_source": 19,
    "u_original": 20,
    "u_env_visibility": 21,
    "u_shadow_depth": 22, "u_shadow_depth_2": 23, "u_velocity": 24, "u_velocity_tiles": 25,
    "u_env_vis_samples": 26, "u_env_vis_surfaces": 27, "u_ltc": 28, "u_lens_depth": 29,
    "u_probe_irradiance": 30, "u_probe_depth": 31,
    # past the 32 a shader stage may sample: only the bake's full-screen passes use these
    "u_capture": 32, "u_capture_reflectance": 33, "u_capture_normal": 34,
    # the pbr layers' maps: units past 32, a forward program samples fewer than 32 textures
    "u_clearcoat_map": 35, "u_clearcoat_roughness_map": 36, "u_sheen_color_map": 37, "u_sheen_roughness_map": 38,
    "u_specular_factor_map": 39, "u_specular_color_map": 40, "u_specular_glossiness_map": 41,
    "u_anisotropy_map": 42,
    # the opaque scene behind transmissive surfaces (passes/transmission.py)
    "u_transmission_source": 43,
    "u_transmission_map": 44, "u_thickness_map": 45, "u_iridescence_map": 46, "u_iridescence_thickness_map": 47,
    "u_clearcoat_normal_map": 48,
    # the shadow casters' back faces (render.shadows.casters: solid), plain depth
    "u_shadow_back": 49, "u_shadow_back_2": 50,
}
# maps only the pbr model reads
PBR_MAPS = ("metallic_roughness_map", "roughness_map", "metallic_map", "clearcoat_map", "clearcoat_roughness_map",
            "sheen_color_map", "sheen_roughness_map", "specular_factor_map", "specular_color_map",
            "specular_glossiness_map", "anisotropy_map", "transmission_map", "thickness_map",
            "iridescence_map", "iridescence_thickness_map", "clearcoat_normal_map")


@dataclass(frozen=True)
class SceneFeatures:
    n_dir: int
    n_point: int
    n_spot: int
    shadows: bool
    fog_mode: str | None
    specular: str  # render.shading: the model of materials that name none
    unlit: bool
    ambient_occlusion: bool
    # per light type, in light order: index of the light's first shadow view, or -1
    dir_shadow_views: tuple = ()
    point_shadow_views: tuple = ()
    spot_shadow_views: tuple = ()
    n_shadow_views: int = 0
    shadow_footprint_samples: int = 1  # points a pixel's shadow is averaged over (MSAA samples)
    # per light type, in light order: hardware-filtered taps per side of the light's "pcf"
    # filter (max(pcf - 1, 1)), or 0: compile-time, so the shader's tap loops unroll
    dir_shadow_taps: tuple = ()
    point_shadow_taps: tuple = ()
    spot_shadow_taps: tuple = ()
    # per light type, in light order: the atlas page holding the light's maps (0 unshadowed)
    dir_shadow_pages: tuple = ()
    point_shadow_pages: tuple = ()
    spot_shadow_pages: tuple = ()
    shadow_pages: int = 1
    # per light type, in light order: whether the light has a size (lighting/sized.glsl),
    # and its soft shadow's blocker-search and filter reads (0: no soft shadow)
    dir_sized: tuple = ()
    point_sized: tuple = ()
    spot_sized: tuple = ()
    dir_soft: tuple = ()
    point_soft: tuple = ()
    spot_soft: tuple = ()
    # rectangle and disk lights (lighting/area.glsl): their count, shadow views, taps,
    # pages and soft-shadow reads, in light order
    n_area: int = 0
    area_shadow_views: tuple = ()
    area_shadow_taps: tuple = ()
    area_shadow_pages: tuple = ()
    area_soft: tuple = ()
    # per light type, in light order: whether a soft shadow's casters are solid (a second
    # map of their back faces; render.shadows.casters)
    dir_solid: tuple = ()
    point_solid: tuple = ()
    spot_solid: tuple = ()
    area_solid: tuple = ()
    # the environment light's prefiltered image, (levels, strip width, strip height), or
    # None; ``environment_classic``: Phong and Blinn-Phong materials get its diffuse term
    environment: tuple | None = None
    environment_classic: bool = False
    environment_footprint: bool = False
    environment_specular_samples: int = 0  # GGX samples a pixel of the sampled specular term; 0: the split sum
    environment_visibility: int = 0  # directions the scene's occlusion of it is sampled in
    # (N, lookups a pixel) of the blocks the directions are shared out over; N 1: every
    # pixel looks up all of them as it shades (environment_visibility.interleave_pattern)
    environment_interleave: tuple = (1, 0)
    light_range: bool = False  # a point or spot light has a range (lighting/lights.glsl, range_window)
    environment_halves: int = 1  # maps a direction (environment_visibility.region_halves)

    @classmethod
    def of(cls, world, samples: int = 1, atlas=None) -> "SceneFeatures":
        """samples: the MSAA samples the run renders with (the device may give fewer than
        the scene asks for); atlas: the run's world.shadows.AtlasLayout (None: one page)."""
        kinds = [light.kind for light in world.lights]
        render = world.settings
        first_views = _first_shadow_views(world.lights, atlas)
        return cls(
            n_dir=kinds.count("directional"), n_point=kinds.count("point"), n_spot=kinds.count("spot"),
            n_area=kinds.count("rect") + kinds.count("disk"),
            shadows=any(light.shadow is not None for light in world.lights),
            fog_mode=render.fog.mode if render.fog is not None else None,
            specular=render.shading, unlit=render.shading == "unlit",
            ambient_occlusion=render.ambient_occlusion is not None,
            shadow_footprint_samples=_footprint_samples(samples),
            **first_views,
            **_sized_lights(world.lights),
            **_environment_features(world.environment, world.environment_halves),
            light_range=any(light.range is not None for light in world.lights),
        )

    @property
    def soft_shadows(self) -> bool:
        """Whether a shadowed light has a size: then the shaders read the atlas as plain
        depth too (lighting/soft_shadows.glsl)."""
        return any(blockers for blockers, _ in self.dir_soft + self.point_soft + self.spot_soft + self.area_soft)

    @property
    def solid_casters(self) -> bool:
        """Whether a soft shadow reads its casters' back faces too (render.shadows.casters:
        solid): then the shaders bind the back-face pages (lighting/soft_shadows.glsl)."""
        return any(self.dir_solid + self.point_solid + self.spot_solid + self.area_solid)

    def lighting_defines(self) -> dict:
        defines = {"N_DIR_LIGHTS": self.n_dir, "N_POINT_LIGHTS": self.n_point, "N_SPOT_LIGHTS": self.n_spot}
        if self.n_area:
            defines["N_AREA_LIGHTS"] = self.n_area
        if self.specular == "phong":
            defines["SPECULAR_PHONG"] = True
        if self.shadows:
            defines["HAS_SHADOWS"] = True
            for kind in ("dir", "point", "spot", "area"):
                for what in ("views", "taps", "pages"):
                    values = getattr(self, f"{kind}_shadow_{what}")
                    if values:
                        defines[f"{kind.upper()}_SHADOW_{what.upper()}"] = ", ".join(str(v) for v in values)
            defines["SHADOW_PAGES"] = self.shadow_pages
            if self.shadow_footprint_samples > 1:
                defines["SHADOW_FOOTPRINT_SAMPLES"] = self.shadow_footprint_samples
            if self.n_shadow_views * SHADOW_VIEW_BYTES <= UNIFORM_BLOCK_BYTES:
                defines["N_SHADOW_VIEWS"] = self.n_shadow_views
            if self.soft_shadows:
                defines.update(self._soft_shadow_defines())
        defines.update(self._sized_defines())
        if self.light_range:
            defines["LIGHT_RANGE"] = True
        if self.light_bytes <= UNIFORM_BLOCK_BYTES:
            defines["LIGHTS_IN_UNIFORM_BLOCK"] = True
        return defines

    def _sized_defines(self) -> dict:
        """Which lights of each type have a size, where any has (none in a scene of points)."""
        defines = {}
        for kind in ("dir", "point", "spot"):
            sized = getattr(self, f"{kind}_sized")
            if any(sized):
                defines[f"{kind.upper()}_LIGHT_SIZED"] = ", ".join("true" if v else "false" for v in sized)
        return defines

    def _soft_shadow_defines(self) -> dict:
        defines = {"SOFT_SHADOWS": True}
        for kind in ("dir", "point", "spot", "area"):
            soft = getattr(self, f"{kind}_soft")
            if any(blockers for blockers, _ in soft):
                defines[f"{kind.upper()}_SOFT_BLOCKERS"] = ", ".join(str(b) for b, _ in soft)
                defines[f"{kind.upper()}_SOFT_FILTER"] = ", ".join(str(f) for _, f in soft)
            solid = getattr(self, f"{kind}_solid")
            if any(solid):
                defines["SOLID_CASTERS"] = True
                defines[f"{kind.upper()}_SOFT_SOLID"] = ", ".join("true" if v else "false" for v in solid)
        return defines

    @property
    def light_bytes(self) -> int:
        """Size of the light block (see shaders/lighting/lights.glsl)."""
        return 48 * self.n_dir + 64 * self.n_point + 96 * self.n_spot + 96 * self.n_area + 16

    def forward_defines(self, material, with_ao: bool) -> dict:
        defines = {}
        if self.fog_mode is not None:
            defines["HAS_FOG"] = True
            defines[f"FOG_{self.fog_mode.upper()}"] = True
        model = material.model(self.specular)
        if model == "unlit":
            defines["UNLIT"] = True
        else:
            defines.update(self.lighting_defines())
            defines.pop("SPECULAR_PHONG", None)
            if model == "phong":
                defines["SPECULAR_PHONG"] = True
            elif model == "pbr":
                defines["SHADING_PBR"] = True
            if with_ao:
                defines["HAS_AO"] = True
            if self.environment is not None and environment_shades(self.environment_classic, model):
                defines.update(self.environment_defines())
                if self.environment_visibility and not material.transparent:
                    defines.update(self.interleave_defines())
        defines.update(material_defines(material, model))
        return defines

    def environment_defines(self) -> dict:
        """The prefiltered image's layout (shaders/lighting/environment_map.glsl)."""
        defines = {"HAS_ENVIRONMENT": True, **specular_layout_defines(self.environment)}
        if self.environment_footprint:
            defines["ENV_FOOTPRINT"] = True
        if self.environment_specular_samples:
            defines["ENV_SPECULAR_SAMPLES"] = self.environment_specular_samples
        if self.environment_visibility:
            # the maps' count (both halves of each direction's region, where it has two)
            defines["ENV_VISIBILITY"] = self.environment_visibility * self.environment_halves
            defines["ENV_VIS_MIN_ALPHA"] = visibility_min_alpha(self.environment_visibility)
        return defines

    def interleave_defines(self) -> dict:
        """Opaque surfaces read the visibility pass's lookups, where it shares the
        directions out (passes/environment.py EnvironmentVisibilityPass); transparent ones,
        which it does not draw, look every direction up themselves."""
        interleave, per_pixel = self.environment_interleave
        if interleave == 1:
            return {}
        return {"ENV_VIS_INTERLEAVE": interleave, "ENV_VIS_PER_PIXEL": per_pixel}


def visibility_min_alpha(directions: int) -> str:
    """GGX alpha no narrower than the directions' spacing where the light is: the median
    cut's power half crowds them into the sky (24 of 32 above the horizon in both quality
    skies), so about the angular radius of one direction's share of a hemisphere,
    sqrt(2 pi / K / pi) (a define's text). A sphere's share, sqrt(4 / K), weighed
    directions outside a copper sphere's lobe (roughness 0.5) and left it 3-5 % bright
    among neighbours that block part of its sky (benchmarks/quality/three_spheres.md)."""
    return f"{min(1.0, (2.0 / directions) ** 0.5):.6f}"


def _sized_lights(lights) -> dict:
    """Per light type, in light order: whether each light has a size, and (blocker reads,
    filter reads) of its soft shadow, (0, 0) unless it is shadowed and has a size."""
    key = {"directional": "dir", "point": "point", "spot": "spot", "rect": "area", "disk": "area"}
    found = {f"{kind}_{what}": [] for kind in ("dir", "point", "spot") for what in ("sized", "soft", "solid")}
    found["area_soft"] = []
    found["area_solid"] = []
    for light in lights:
        kind = key[light.kind]
        if kind != "area":
            found[f"{kind}_sized"].append(light.sized)
        soft = light.sized and light.shadow is not None
        found[f"{kind}_soft"].append((light.shadow.blocker_samples, light.shadow.filter_samples) if soft else (0, 0))
        found[f"{kind}_solid"].append(light.solid_casters)
    return {name: tuple(values) for name, values in found.items()}


def _environment_features(environment, halves: int) -> dict:
    if environment is None:
        return {}
    return {"environment": specular_layout(environment), "environment_classic": environment.classic,
            "environment_footprint": environment.footprint, "environment_visibility": environment.visibility,
            "environment_specular_samples": environment.specular_samples if environment.specular == "sampled" else 0,
            "environment_interleave": interleave_pattern(environment.visibility, environment.visibility_interleave)
            if environment.visibility else (1, 0),
            "environment_halves": halves}


def environment_shades(classic: bool, model: str) -> bool:
    """Whether the environment light shades a material of shading ``model``: pbr ones
    always, Phong and Blinn-Phong ones (its diffuse term) when the light says ``classic``."""
    return model == "pbr" or (classic and model in ("phong", "blinn_phong"))


def specular_layout(environment) -> tuple:
    """(levels, strip width, strip height) of the environment's prefiltered image."""
    width = environment.prefilter_size
    return PREFILTER_LEVELS, width, max(width // 2, 1)


def specular_layout_defines(layout: tuple) -> dict:
    """The defines that tell the shaders a ``specular_layout`` (GLSL floats)."""
    levels, width, height = layout
    return {"ENV_LEVELS": f"{levels}.0", "ENV_STRIP_WIDTH": f"{width}.0", "ENV_STRIP_HEIGHT": f"{height}.0"}


def _footprint_samples(samples: int) -> int:
    """The largest sample pattern (1, 2, 4, 8, 16) with no more points than ``samples``."""
    count = 1
    while count * 2 <= min(samples, 16):
        count *= 2
    return count


def _first_shadow_views(lights, atlas) -> dict:
    """Where each light's views start in the shadow-view array (world.shadows.
    first_shadow_views: the order rendering.lights packs them in); each light's filter taps
    per side (shaders/lighting/shadows.glsl, filter_taps); and the atlas page holding its
    maps. Each per light type, in light order."""
    firsts = {f"{kind}_shadow_{what}": [] for kind in ("dir", "point", "spot", "area")
              for what in ("views", "taps", "pages")}
    key = {"directional": "dir", "point": "point", "spot": "spot", "rect": "area", "disk": "area"}
    starts = first_shadow_views(lights)
    for index, light in enumerate(lights):
        shadowed = light.shadow is not None
        firsts[f"{key[light.kind]}_shadow_views"].append(starts[index])
        firsts[f"{key[light.kind]}_shadow_taps"].append(max(light.shadow.pcf - 1, 1) if shadowed else 0)
        firsts[f"{key[light.kind]}_shadow_pages"].append(atlas.page_of(index) if shadowed and atlas else 0)
    count = sum(view_count(light) for light in lights if light.shadow is not None)
    pages = len(atlas.pages) if atlas is not None else 1
    return {**{k: tuple(v) for k, v in firsts.items()}, "n_shadow_views": count, "shadow_pages": pages}


def mask_defines(material) -> dict:
    """The defines of an alpha-masked material's program in the passes that draw no colour
    (shaders/lighting/alpha_mask.glsl): what its alpha comes from."""
    defines = {key: value for key, value in material_defines(material, "unlit").items()
               if key in ("HAS_DIFFUSE_MAP", "HAS_OPACITY_MAP", "WRAP_MIRROR", "ALPHA_MASK", "HAS_VERTEX_COLOR",
                          "DIFFUSE_MAP_UV1", "OPACITY_MAP_UV1")}
    if "DIFFUSE_MAP_UV1" in defines or "OPACITY_MAP_UV1" in defines:
        defines["HAS_UV1"] = True
    if any(tuple(material.maps[key].uv_skew) != (0.0, 0.0) for key in ("diffuse_map", "opacity_map")
           if key in material.maps):
        defines["UV_AFFINE"] = True
    return defines


def material_defines(material, model: str = "blinn_phong") -> dict:
    """The defines of ``material`` drawn with shading ``model`` (maps only the pbr model
    reads are left out of the others)."""
    defines = {}
    maps = [key for key in material.maps if model == "pbr" or key not in PBR_MAPS]
    for key in maps:
        defines[f"HAS_{key.upper()}"] = True
    if material.needs_tangents and not material.unlit:
        defines["HAS_TANGENTS"] = True
    if material.wrap == "mirror" and material.maps:
        defines["WRAP_MIRROR"] = True
    if material.blended:  # a transmissive material that is not blended covers what it shows (alpha 1)
        defines["TRANSPARENT"] = True
    if material.masked:
        defines["ALPHA_MASK"] = True
    if material.vertex_colors:
        defines["HAS_VERTEX_COLOR"] = True
    if any(tuple(material.maps[key].uv_skew) != (0.0, 0.0) for key in maps):
        defines["UV_AFFINE"] = True
    for key in maps:
        if material.maps[key].uv_set == 1:  # glTF texCoord: 1 (shaders/lighting/material.glsl)
            defines["HAS_UV1"] = True
            defines[f"{key.upper()}_UV1"] = True
    if model == "pbr" and material.dielectric_specular:
        defines["PBR_DIELECTRIC_SPECULAR"] = True
    if model == "pbr" and material.clearcoat > 0.0:
        defines["PBR_CLEARCOAT"] = True
    if model == "pbr" and material.sheen:
        defines["PBR_SHEEN"] = True
    if model == "pbr" and material.transmissive:
        defines["PBR_TRANSMISSION"] = True
        if material.thickness > 0.0:
            defines["TRANSMISSION_VOLUME"] = True
    if model == "pbr" and material.anisotropy > 0.0:
        defines["PBR_ANISOTROPY"] = True
    if model == "pbr" and material.iridescence > 0.0:
        defines["PBR_IRIDESCENCE"] = True
    return defines
