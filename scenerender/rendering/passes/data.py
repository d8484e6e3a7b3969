"""What passes' setups return: the handles of the images they made, frozen."""
from __future__ import annotations

from dataclasses import dataclass

from scenerender.graph import Handle


@dataclass(frozen=True)
class ImageData:
    """A pass's one output image (for passes that draw over an image: its new version)."""

    image: Handle


@dataclass(frozen=True)
class TargetData:
    """A colour image and the depth buffer drawn with it."""

    color: Handle
    depth: Handle


@dataclass(frozen=True)
class SurfacesData:
    """What the camera sees at each pixel of the environment visibility's image: the
    camera-relative positions with the normals encoded (shaders/common/surface_normal.glsl)
    and the depth buffer drawn with them."""

    surfaces: Handle
    depth: Handle
