"""The scene's render settings as plain frozen values: what the renderer needs of
``render:`` without the validated scene model (which stays in scene/ and world/)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from scenerender.scene.model.render import SKY_FACES, AmbientOcclusion

# The render modes that show values rather than light (no tone curve, no bloom, no sub-frames).
DATA_MODES = ("depth", "normals", "ambient_occlusion", "shadow", "light_depth")


@dataclass(frozen=True)
class FogSettings:
    """mode: "exp" | "exp2" | "linear"; start, end: distances of linear fog."""

    mode: str
    start: float
    end: float


@dataclass(frozen=True)
class AmbientOcclusionSettings:
    radius: float
    samples: int
    strength: float

    @classmethod
    def of(cls, spec) -> "AmbientOcclusionSettings":
        return cls(spec.radius, spec.samples, spec.strength)

    @classmethod
    def default(cls) -> "AmbientOcclusionSettings":
        """The format's defaults (what `mode: ambient_occlusion` shows without settings)."""
        return cls.of(AmbientOcclusion())


@dataclass(frozen=True)
class ShadowMapSettings:
    """One light's shadow map: size in texels, pcf taps across, biases in extra texels."""

    size: int
    pcf: int
    bias: float
    slope_bias: float
    # soft shadows of lights with a size (percentage-closer soft shadows): depth reads of
    # the blocker search, comparison reads of the filter
    blocker_samples: int = 16
    filter_samples: int = 32
    # "solid": a second map holds the casters' back faces, and a soft shadow's rays are
    # blocked only inside a caster (shaders/lighting/soft_shadows.glsl, solid_fraction)
    casters: str = "surface"


@dataclass(frozen=True)
class IndirectSettings:
    """render.indirect: light bounced between surfaces (rendering/passes/indirect.py).

    bounces: how many times light bounces; probe_spacing: the probe grid's spacing in
    scene units, None for probe_grid.default_spacing;
    capture_size: the side in texels of each cube face a probe sees the scene through;
    probe_budget: the most probes drawn again in a frame where the scene moved
    (world.probe_updates)."""

    bounces: int
    probe_spacing: float | None
    capture_size: int
    probe_budget: int = 32

    @classmethod
    def of(cls, spec) -> "IndirectSettings":
        return cls(spec.bounces, spec.probe_spacing, spec.capture_size, spec.probe_budget)


@dataclass(frozen=True)
class OutlineSettings:
    """An object's selection outline: colour (an RGBA Track) and width in world units."""

    color: object
    width: float


@dataclass(frozen=True)
class BloomSettings:
    """strength: the fraction of light spread into the glow; radius: the Gaussian's
    standard deviation as a fraction of the image height (rendering/passes/bloom.py)."""

    strength: float
    radius: float


@dataclass(frozen=True)
class RenderSettings:
    """size: (width, height); skybox: the six face paths (+x -x +y -y +z -z) or None;
    tone_map: "none" | "aces" | "agx" (the exposure, a Track, is an input: world.inputs)."""

    size: tuple
    samples: int
    shading: str
    mode: str
    tone_map: str
    output_transform: str
    gamma: float
    wireframe_overlay: bool
    line_width: float
    point_size: float
    fog: FogSettings | None
    ambient_occlusion: AmbientOcclusionSettings | None
    skybox: tuple[Path, ...] | None
    bloom: BloomSettings | None = None
    film_samples: int = 16
    depth_of_field: str = "sub_frames"
    motion_blur: str = "sub_frames"
    indirect: IndirectSettings | None = None

    @classmethod
    def of(cls, render) -> "RenderSettings":
        """From the validated ``render:`` section (``scene.model.render.RenderSpec``)."""
        fog = render.fog
        ao = render.ambient_occlusion
        sky = render.skybox
        return cls(
            size=tuple(render.size), samples=render.samples, shading=render.shading, mode=render.mode,
            tone_map=render.tone_map, output_transform=render.output_transform, gamma=render.gamma,
            wireframe_overlay=render.wireframe_overlay, line_width=render.line_width, point_size=render.point_size,
            fog=FogSettings(fog.mode, fog.start, fog.end) if fog is not None else None,
            ambient_occlusion=AmbientOcclusionSettings.of(ao) if ao is not None else None,
            skybox=tuple(Path(getattr(sky, face)) for face in SKY_FACES) if sky is not None else None,
            bloom=BloomSettings(render.bloom.strength, render.bloom.radius) if render.bloom is not None else None,
            film_samples=render.film_samples, depth_of_field=render.depth_of_field,
            motion_blur=render.motion_blur,
            indirect=IndirectSettings.of(render.indirect) if render.indirect is not None else None,
        )
