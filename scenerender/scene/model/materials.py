"""``materials:``, an object's inline ``material`` and its ``material_overrides``: colours,
shininess, opacity, the pbr model's metallic and roughness, and image maps."""
from __future__ import annotations

from pydantic import model_validator
from pydantic_core import PydanticCustomError

from scenerender.scene.model.paths import ImagePath
from scenerender.scene.model.unions import mapping_or
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import AnimatedColor, Bool, Text, animated_number, choice, number, vector

# the largest index of refraction a material takes (mesh.gltf.MAX_IOR reads a file's alike)
MAX_IOR = 10.0

MATERIAL_SHADINGS = ("phong", "blinn_phong", "pbr", "unlit")
# the pbr names of keys the Phong models already have: one value, two names
ALIASES = {"base_color": "diffuse", "base_color_map": "diffuse_map"}


class MaterialSpec(StrictModel):
    """A material; keys left out keep the MTL value (for overrides) or the default."""

    ambient: AnimatedColor | None = None
    diffuse: AnimatedColor | None = None
    specular: AnimatedColor | None = None
    shininess: animated_number(0, 10000) | None = None
    emissive: AnimatedColor | None = None
    opacity: animated_number(0, 1) | None = None
    diffuse_map: ImagePath | None = None
    specular_map: ImagePath | None = None
    normal_map: ImagePath | None = None
    opacity_map: ImagePath | None = None
    wrap: choice("repeat", "clamp", "mirror") | None = None
    filter: choice("linear", "nearest") | None = None
    unlit: Bool | None = None
    shading: choice(*MATERIAL_SHADINGS) | None = None
    base_color: AnimatedColor | None = None
    base_color_map: ImagePath | None = None
    metallic: animated_number(0, 1) | None = None
    roughness: animated_number(0, 1) | None = None
    metallic_roughness_map: ImagePath | None = None
    normal_scale: number(-100, 100) | None = None
    occlusion_map: ImagePath | None = None
    occlusion_strength: number(0, 1) | None = None
    emissive_map: ImagePath | None = None
    emissive_strength: number(0, 1e6) | None = None
    alpha_mode: choice("opaque", "mask", "blend") | None = None
    alpha_cutoff: number(0, 1) | None = None
    double_sided: Bool | None = None
    # the pbr model's dielectric reflection (KHR_materials_ior, KHR_materials_specular) and
    # clear coat (KHR_materials_clearcoat), sheen (KHR_materials_sheen): docs/scene-notes.md,
    # "Layers of the pbr model"
    ior: number(1, MAX_IOR) | None = None
    specular_factor: number(0, 1) | None = None
    specular_color: vector(3, 0) | None = None
    clearcoat: number(0, 1) | None = None
    clearcoat_roughness: number(0, 1) | None = None
    sheen_color: vector(3, 0, 1) | None = None  # KHR_materials_sheen
    sheen_roughness: number(0, 1) | None = None
    anisotropy: number(0, 1) | None = None  # KHR_materials_anisotropy
    anisotropy_rotation: number(-360, 360) | None = None  # degrees from the tangent
    iridescence: number(0, 1) | None = None  # KHR_materials_iridescence
    iridescence_ior: number(1, MAX_IOR) | None = None
    iridescence_thickness: number(0, 10000) | None = None  # nanometres
    iridescence_thickness_min: number(0, 10000) | None = None  # the thickness map's 0
    # the layers' maps (the extensions' textures): each multiplies its layer's value
    clearcoat_map: ImagePath | None = None
    clearcoat_roughness_map: ImagePath | None = None
    sheen_color_map: ImagePath | None = None
    sheen_roughness_map: ImagePath | None = None
    specular_factor_map: ImagePath | None = None
    specular_color_map: ImagePath | None = None
    anisotropy_map: ImagePath | None = None
    transmission_map: ImagePath | None = None
    thickness_map: ImagePath | None = None
    iridescence_map: ImagePath | None = None
    clearcoat_normal_map: ImagePath | None = None
    iridescence_thickness_map: ImagePath | None = None
    # light through the surface (KHR_materials_transmission) and through its volume
    # (KHR_materials_volume): docs/scene-notes.md, "Transmission and volume"
    transmission: number(0, 1) | None = None
    thickness: number(0, 1e6) | None = None
    attenuation_color: vector(3, 0, 1) | None = None
    attenuation_distance: number(0, None, lo_open=True) | None = None

    @model_validator(mode="after")
    def _one_name_each(self):
        for pbr_name, name in ALIASES.items():
            if getattr(self, pbr_name) is not None and getattr(self, name) is not None:
                raise PydanticCustomError("alias", "{a} and {b} are the same value; give one of them",
                                          {"a": pbr_name, "b": name, "subpath": (pbr_name,)})
        return self


MaterialRef = mapping_or(MaterialSpec, Text)  # a name from `materials`, or inline
