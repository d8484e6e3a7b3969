"""``materials:``, an object's inline ``material`` and its ``material_overrides``: colours,
shininess, opacity and image maps."""
from __future__ import annotations

from scenerender.scene.model.paths import ImagePath
from scenerender.scene.model.unions import mapping_or
from scenerender.scene.strict import StrictModel
from scenerender.scene.values import AnimatedColor, Bool, Text, animated_number, choice


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


MaterialRef = mapping_or(MaterialSpec, Text)  # a name from `materials`, or inline
