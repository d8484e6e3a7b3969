"""A glTF file's own lights (``KHR_lights_punctual``) and cameras, read from its JSON with
the nodes that place them.

Only what the default scene's nodes use is returned: a light or camera no node names is
not in the scene the file describes. Values are glTF's, in its units (candela for point
and spot lights, lux for directional ones; radians; metres); the world turns them into
the scene's (world.file_nodes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from scenerender.mesh.gltf import GltfProblem, file_extension_list, is_index, json_object
from scenerender.mesh.gltf_geometry import placed_nodes

LIGHTS_EXTENSION = "KHR_lights_punctual"
LIGHT_TYPES = ("directional", "point", "spot")


@dataclass(frozen=True)
class GltfLight:
    """One light a node holds. kind: "directional" | "point" | "spot"; color (3,) linear
    RGB; intensity: candela (point, spot) or lux (directional); range: metres or None
    (unbounded); inner_cone, outer_cone: radians from the spot's axis. It shines down its
    node's -Z axis."""

    name: str
    node: int
    kind: str
    color: tuple = (1.0, 1.0, 1.0)
    intensity: float = 1.0
    range: float | None = None
    inner_cone: float = 0.0
    outer_cone: float = math.pi / 4.0


@dataclass(frozen=True)
class GltfCamera:
    """One camera a node holds, looking down the node's -Z with +Y up.

    name: the camera's name, else its node's, else ``camera<index>``. orthographic: its
    type; yfov: the vertical field of view in radians (perspective); aspect: its
    aspectRatio or None; xmag, ymag: half the orthographic view's width and height."""

    name: str
    node: int
    orthographic: bool = False
    yfov: float = math.radians(60.0)
    aspect: float | None = None
    xmag: float = 1.0
    ymag: float = 1.0


def file_lights(header: dict) -> list[GltfLight]:
    """The lights the default scene's nodes hold, in node order (depth first)."""
    lights = file_extension_list(header, LIGHTS_EXTENSION, "lights")
    found = []
    for index, node, _ in placed_nodes(header):
        reference = json_object(node.get("extensions", {}), f"nodes[{index}].extensions").get(LIGHTS_EXTENSION)
        if reference is None:
            continue
        light = json_object(reference, f"nodes[{index}].extensions.{LIGHTS_EXTENSION}").get("light")
        if not (is_index(light) and light < len(lights)):
            raise GltfProblem(f"nodes[{index}] names light {light!r}, the file has {len(lights)}")
        found.append(_light(json_object(lights[light], f"lights[{light}]"), light, index, node))
    return found


def file_cameras(header: dict) -> list[GltfCamera]:
    """The cameras the default scene's nodes hold, in node order (depth first)."""
    cameras = header.get("cameras", [])
    if not isinstance(cameras, list):
        raise GltfProblem("'cameras' is not a list")
    found = []
    for index, node, _ in placed_nodes(header):
        camera = node.get("camera")
        if camera is None:
            continue
        if not (is_index(camera) and camera < len(cameras)):
            raise GltfProblem(f"nodes[{index}] names camera {camera!r}, the file has {len(cameras)}")
        found.append(_camera(json_object(cameras[camera], f"cameras[{camera}]"), camera, index, node))
    return found


def _light(light: dict, index: int, node_index: int, node: dict) -> GltfLight:
    kind = light.get("type")
    where = f"{LIGHTS_EXTENSION}.lights[{index}]"
    if kind not in LIGHT_TYPES:
        raise GltfProblem(f"{where} has type {kind!r}, not one of {', '.join(LIGHT_TYPES)}")
    spot = json_object(light.get("spot", {}), f"{where}.spot")
    light_range = light.get("range")
    outer = _number(spot.get("outerConeAngle", math.pi / 4.0), f"{where}.spot.outerConeAngle", 0.0, math.pi / 2.0)
    inner = _number(spot.get("innerConeAngle", 0.0), f"{where}.spot.innerConeAngle", 0.0, outer)
    return GltfLight(
        name=_name(light.get("name"), node.get("name"), f"light{index}"), node=node_index, kind=kind,
        color=tuple(_number(c, f"{where}.color", 0.0, 1.0) for c in _triple(light.get("color", [1, 1, 1]), where)),
        intensity=_number(light.get("intensity", 1.0), f"{where}.intensity", 0.0, 1e12),
        range=_range(light_range, f"{where}.range"),
        inner_cone=inner, outer_cone=outer)


def _camera(camera: dict, index: int, node_index: int, node: dict) -> GltfCamera:
    kind = camera.get("type")
    where = f"cameras[{index}]"
    name = _name(camera.get("name"), node.get("name"), f"camera{index}")
    if kind == "perspective":
        values = json_object(camera.get("perspective", {}), f"{where}.perspective")
        aspect = values.get("aspectRatio")
        return GltfCamera(name, node_index, yfov=_number(values.get("yfov"), f"{where}.perspective.yfov", 1e-6, math.pi),
                          aspect=None if aspect is None else _number(aspect, f"{where}.perspective.aspectRatio",
                                                                     1e-6, 1e6))
    if kind == "orthographic":
        values = json_object(camera.get("orthographic", {}), f"{where}.orthographic")
        return GltfCamera(name, node_index, orthographic=True,
                          xmag=_magnification(values.get("xmag"), f"{where}.orthographic.xmag"),
                          ymag=_magnification(values.get("ymag"), f"{where}.orthographic.ymag"))
    raise GltfProblem(f"{where} has type {kind!r}, not perspective or orthographic")


def _range(value, what: str) -> float | None:
    """A light's range in metres, or None (unbounded) where the file gives none or 0 (the
    specification asks for more than 0 and bounds a light by a non-zero range only)."""
    if value is None:
        return None
    light_range = _number(value, what, 0.0, math.inf)
    return light_range if light_range > 0.0 else None


def _magnification(value, what: str) -> float:
    """Half the orthographic view's width or height: not zero (the specification); a
    negative one is taken as its size."""
    magnification = abs(_number(value, what, -1e12, 1e12))
    if magnification == 0.0:
        raise GltfProblem(f"{what} is 0")
    return magnification


def _name(*candidates) -> str:
    return next(c for c in candidates if isinstance(c, str) and c.strip())


def _triple(value, where: str) -> list:
    if not isinstance(value, list) or len(value) != 3:
        raise GltfProblem(f"{where}.color is not 3 numbers")
    return value


def _number(value, what: str, lo: float, hi: float) -> float:
    """A finite number clamped to [lo, hi]."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise GltfProblem(f"{what} is {value!r}, not a finite number")
    return min(max(float(value), lo), hi)
