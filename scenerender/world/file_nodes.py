"""A glTF file's own lights and cameras as lights and the camera of the scene, placed by
their nodes: an object's ``lights: true`` brings the lights of its file in, ``camera: {from:
OBJECT, name: CAMERA}`` looks through one of its cameras. Both move with the object and,
where it plays a clip, with their nodes.

Units (docs/scene-notes.md, "A glTF file's lights and cameras"). KHR_lights_punctual gives
point and spot lights in candela and directional ones in lux, and the Khronos Sample Viewer
lights a surface with radiance f * I * colour * attenuation * N.L (f the BRDF, with its
1 / pi; I / d^2 for a point or spot light, I alone for a directional one) at its default
exposure. scenerender's pbr radiance is pi * f * intensity * colour * attenuation * N.L,
so the same picture needs intensity = I / pi, with attenuation [0, 0, 1] (1 / d^2) for
point and spot lights. Between the cosines of its outer and inner angles the spot's cone
is the square of the linear ramp, as the specification's implementation note and the
Sample Viewer have it (``cone_falloff: gltf``; a scene's spots take smoothstep). A light's ``range`` is the scene light's ``range``: the
specification's recommended window clamp(1 - (d / range)^4, 0, 1) times 1 / d^2.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from scenerender.animation import Track
from scenerender.mesh.gltf_scene import GltfCamera, GltfLight
from scenerender.world.camera import look_rotation, unit_direction
from scenerender.world.light_states import LightDef
from scenerender.world.transforms import model_matrix

# scenerender intensity per candela (point, spot) or per lux (directional): see the module docstring
INTENSITY_PER_PHOTOMETRIC_UNIT = 1.0 / math.pi
INVERSE_SQUARE = (0.0, 0.0, 1.0)
# the widest spot cone the scene format takes (lights[].outer_angle), degrees
_WIDEST_CONE = 89.9
_STILL = Track.constant(0.0)
# Marks a placement as moving for everything that asks which inputs animate (animated_keys)
_MOVING = Track([0.0, 1.0], [0.0, 1.0], ["linear", "linear"])


@dataclass
class NodePlacement:
    """Where a node of an object's glTF file is at time t: (4, 4) float64 M_object(t) W(t),
    W the node's world transform in the file (``node_worlds(t)``: the object's clip player's,
    or None for the file at rest, ``rest``)."""

    position: Track
    rotation: Track
    scale: Track
    rest: np.ndarray
    node: int = 0
    node_worlds: object = None
    moving: Track = field(default=_STILL)

    def __call__(self, t: float) -> np.ndarray:
        node = self.node_worlds(t)[self.node] if self.node_worlds is not None else self.rest
        return model_matrix(self.position(t), self.rotation(t), self.scale(t)) @ node


def node_placement(obj, rest: np.ndarray, node: int, player=None, moved: bool = False) -> NodePlacement:
    """The placement of ``node`` of the scene object ``obj`` (its ``ObjectSpec``): ``rest``
    (4, 4) its world transform in the file at rest; ``player`` the object's ClipPlayer or
    None; ``moved``: the clip moves it."""
    return NodePlacement(obj.position, obj.rotation, obj.scale, rest, node,
                         player.node_worlds if player is not None else None, _MOVING if moved else _STILL)


@dataclass
class _PlacedPoint:
    """The node's origin in the world, (3,) float64: a light's position."""

    placement: NodePlacement

    def __call__(self, t: float) -> np.ndarray:
        return self.placement(t)[:3, 3].copy()


@dataclass
class _PlacedAxis:
    """The node's -Z axis in the world, (3,) float64 unit: where a light shines."""

    placement: NodePlacement

    def __call__(self, t: float) -> np.ndarray:
        return unit_direction(-self.placement(t)[:3, 2], np.array([0.0, -1.0, 0.0]))


def file_light(light: GltfLight, placement: NodePlacement, name: str, path: tuple) -> LightDef:
    """A LightDef of the file's ``light`` placed by ``placement`` (photometric units
    converted: see the module docstring)."""
    common = dict(kind=light.kind, name=name, path=path,
                  color=Track.constant((*light.color, 1.0), kind="vector"),
                  intensity=Track.constant(light.intensity * INTENSITY_PER_PHOTOMETRIC_UNIT),
                  enabled=Track.constant(True, kind="bool"))
    if light.kind == "directional":
        return LightDef(**common, direction=_PlacedAxis(placement))
    if light.kind == "point":
        return LightDef(**common, position=_PlacedPoint(placement), attenuation=INVERSE_SQUARE, range=light.range)
    outer = min(math.degrees(light.outer_cone), _WIDEST_CONE)
    inner = min(math.degrees(light.inner_cone), outer)
    return LightDef(**common, position=_PlacedPoint(placement), direction=_PlacedAxis(placement),
                    attenuation=INVERSE_SQUARE, inner_angle=Track.constant(inner), outer_angle=Track.constant(outer),
                    range=light.range, cone_falloff="gltf")


@dataclass
class FileCamera:
    """The camera of a glTF file the scene looks through: its lens and where its node is.

    fov: the vertical field of view in degrees (perspective); height: the orthographic
    view's height in world units, 2 ymag (the node's scale does not change it: glTF's
    cameras ignore their node's scale)."""

    camera: GltfCamera
    placement: NodePlacement

    @property
    def orthographic(self) -> bool:
        return self.camera.orthographic

    @property
    def fov(self) -> float:
        return min(max(math.degrees(self.camera.yfov), 0.1), 179.0)

    @property
    def height(self) -> float:
        return 2.0 * self.camera.ymag

    def place(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """(position (3,), world -> view rotation (3, 3), rows right, up, back) at ``t``,
        float64: the node's origin, looking down its -Z with its +Y up (its scale dropped)."""
        world = self.placement(t)
        return world[:3, 3].copy(), look_rotation(-world[:3, 2], world[:3, 1])
