"""Which shader features a scene and its materials need -> GLSL defines.

Features are decided once per run from the scene: light counts per type, shadows, fog
mode, specular model, AO; and per material: texture maps, unlit, mirrored wrap.
"""
from __future__ import annotations

from dataclasses import dataclass

TEXTURE_UNITS = {
    "u_diffuse_map": 0, "u_specular_map": 1, "u_normal_map": 2, "u_opacity_map": 3,
    "u_shadow_atlas": 4, "u_ao": 5, "u_skybox": 6, "u_gbuffer": 7, "u_noise": 8, "u_color": 9, "u_atlas": 10,
}


@dataclass(frozen=True)
class SceneFeatures:
    n_dir: int
    n_point: int
    n_spot: int
    shadows: bool
    fog_mode: str | None
    specular: str
    unlit: bool
    ambient_occlusion: bool

    @classmethod
    def of(cls, world) -> "SceneFeatures":
        kinds = [light.kind for light in world.lights]
        render = world.render
        return cls(
            n_dir=kinds.count("directional"), n_point=kinds.count("point"), n_spot=kinds.count("spot"),
            shadows=any(light.shadow is not None for light in world.lights),
            fog_mode=render.fog.mode if render.fog is not None else None,
            specular=render.shading, unlit=render.shading == "unlit",
            ambient_occlusion=render.ambient_occlusion is not None,
        )

    def lighting_defines(self) -> dict:
        defines = {"N_DIR_LIGHTS": self.n_dir, "N_POINT_LIGHTS": self.n_point, "N_SPOT_LIGHTS": self.n_spot}
        if self.specular == "phong":
            defines["SPECULAR_PHONG"] = True
        if self.shadows:
            defines["HAS_SHADOWS"] = True
        return defines

    def forward_defines(self, material, with_ao: bool) -> dict:
        defines = {}
        if self.fog_mode is not None:
            defines["HAS_FOG"] = True
            defines[f"FOG_{self.fog_mode.upper()}"] = True
        if self.unlit or material.unlit:
            defines["UNLIT"] = True
        else:
            defines.update(self.lighting_defines())
            if with_ao:
                defines["HAS_AO"] = True
        defines.update(material_defines(material))
        return defines


def material_defines(material) -> dict:
    defines = {}
    for key in material.maps:
        defines[f"HAS_{key.upper()}"] = True
    if "normal_map" in material.maps and not material.unlit:
        defines["HAS_TANGENTS"] = True
    if material.wrap == "mirror" and material.maps:
        defines["WRAP_MIRROR"] = True
    return defines
