"""The GLB files compared with the Khronos glTF Sample Viewer: one row of spheres per
material extension, built to the recipe of the Khronos sample models that exercise it
(ClearCoatTest, SheenChair's swatches, IORTestGrid, SpecularTest: a parameter swept across
a row), written here in code so that nothing of unknown licence is needed.

Every file carries its own camera and KHR_lights_punctual lights, so that both renderers
take the view and the light from the file alone (``scenerender render model.glb`` and the
Sample Viewer's ``cameraIndex = 0``). The GLBs are written by tests/gltf_files.py's builder.

A model whose extensions scenerender does not read yet (``READ_EXTENSIONS``) is skipped
with a line saying so: transmission and volume join the table by themselves once
scenerender/mesh/gltf.py lists them; another model is one ``Model(...)`` line in MODELS.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import trimesh

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "tests"))
from gltf_files import GlbBuilder  # noqa: E402  (the tests' GLB writer, one way to write a GLB)

ASPECT = 2.0          # the file camera's aspectRatio: the image is twice as wide as high
CAMERA_Z = 5.0
YFOV = 0.45           # radians: four spheres of radius 0.42 one metre apart fill the width
SPHERE_X = (-1.5, -0.5, 0.5, 1.5)
RADIUS = 0.42

RED = [0.6, 0.05, 0.03, 1.0]
GOLD = [1.0, 0.71, 0.29, 1.0]
BLUE = [0.03, 0.05, 0.25, 1.0]
GREY = [0.18, 0.2, 0.24, 1.0]


@dataclass(frozen=True)
class Model:
    """A row of spheres, left to right, each with one glTF material (its JSON fields).

    name: the file's stem; title: what the row shows; materials: up to four dicts as
    glTF writes a material (``pbrMetallicRoughness``, ``extensions``); backdrop: coloured
    bars behind the row (what a transmissive sphere shows through itself); rig: the lights,
    "three" (``three_lights``) or "spot" (``spot_light``); tangents: write each sphere's
    tangent frame (``sphere_tangents``), so that both renderers turn the same one."""

    name: str
    title: str
    materials: tuple
    backdrop: bool = False
    labels: tuple = field(default=())
    rig: str = "three"
    tangents: bool = False  # the spheres carry a TANGENT (what KHR_materials_anisotropy turns in)

    def extensions(self) -> set[str]:
        return {name for material in self.materials for name in material.get("extensions", {})}


def pbr(base=GREY, metallic=0.0, roughness=0.5, **extensions) -> dict:
    """A glTF material: metallic-roughness factors and ``extensions`` (name -> fields)."""
    material = {"pbrMetallicRoughness": {"baseColorFactor": list(base), "metallicFactor": metallic,
                                         "roughnessFactor": roughness}}
    if extensions:
        material["extensions"] = extensions
    return material


MODELS = (
    Model("metal_rough", "plain metallic-roughness: red dielectric at roughness 0.25 and 0.7, "
                         "gold metal at 0.25 and 0.6",
          (pbr(RED, 0.0, 0.25), pbr(RED, 0.0, 0.7), pbr(GOLD, 1.0, 0.25), pbr(GOLD, 1.0, 0.6)),
          labels=("rough 0.25", "rough 0.7", "metal 0.25", "metal 0.6")),
    Model("clearcoat", "KHR_materials_clearcoat over a rough red base (roughness 0.8)",
          (pbr(RED, 0.0, 0.8),
           pbr(RED, 0.0, 0.8, KHR_materials_clearcoat={"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05}),
           pbr(RED, 0.0, 0.8, KHR_materials_clearcoat={"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.3}),
           pbr(RED, 0.0, 0.8, KHR_materials_clearcoat={"clearcoatFactor": 0.5, "clearcoatRoughnessFactor": 0.1})),
          labels=("no coat", "coat 1 @ 0.05", "coat 1 @ 0.3", "coat 0.5 @ 0.1")),
    Model("sheen", "KHR_materials_sheen over a dark blue rough base (roughness 0.8)",
          (pbr(BLUE, 0.0, 0.8),
           pbr(BLUE, 0.0, 0.8, KHR_materials_sheen={"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.3}),
           pbr(BLUE, 0.0, 0.8, KHR_materials_sheen={"sheenColorFactor": [1.0, 0.4, 0.6], "sheenRoughnessFactor": 0.6}),
           pbr(BLUE, 0.0, 0.8, KHR_materials_sheen={"sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 1.0})),
          labels=("no sheen", "white @ 0.3", "pink @ 0.6", "white @ 1.0")),
    Model("ior", "KHR_materials_ior on a grey dielectric at roughness 0.3: ior 1.0, 1.33, 1.5, 2.5",
          tuple(pbr(GREY, 0.0, 0.3, KHR_materials_ior={"ior": ior}) for ior in (1.0, 1.33, 1.5, 2.5)),
          labels=("ior 1.0", "ior 1.33", "ior 1.5", "ior 2.5")),
    Model("specular", "KHR_materials_specular on a grey dielectric at roughness 0.3",
          (pbr(GREY, 0.0, 0.3, KHR_materials_specular={"specularFactor": 0.0}),
           pbr(GREY, 0.0, 0.3, KHR_materials_specular={"specularFactor": 0.5}),
           pbr(GREY, 0.0, 0.3, KHR_materials_specular={"specularColorFactor": [1.0, 0.5, 0.2]}),
           pbr(GREY, 0.0, 0.3, KHR_materials_specular={"specularColorFactor": [2.0, 2.0, 2.0]})),
          labels=("factor 0", "factor 0.5", "colour (1, 0.5, 0.2)", "colour 2")),
    Model("spot", "KHR_lights_punctual's spot cone (inner 10, outer 25 degrees) across grey rough spheres",
          tuple(pbr([0.5, 0.5, 0.5, 1.0], 0.0, 0.6) for _ in SPHERE_X),
          labels=("in the penumbra", "inside the inner cone", "inside the inner cone", "in the penumbra"),
          rig="spot"),
    Model("transmission", "KHR_materials_transmission: factor 0, 0.5, 1 at roughness 0, 1 at roughness 0.4",
          tuple(pbr([0.9, 0.9, 0.9, 1.0], 0.0, roughness, KHR_materials_transmission={"transmissionFactor": factor})
                for factor, roughness in ((0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 0.4))),
          backdrop=True, labels=("factor 0", "factor 0.5", "factor 1", "factor 1 @ 0.4")),
    Model("volume", "KHR_materials_volume in a transmissive sphere: thickness 0, 0.3, 0.8, 0.8 with a short distance",
          tuple(pbr([1, 1, 1, 1], 0.0, 0.05, KHR_materials_transmission={"transmissionFactor": 1.0},
                    KHR_materials_volume={"thicknessFactor": thickness, "attenuationColor": [0.9, 0.4, 0.1],
                                          "attenuationDistance": distance})
                for thickness, distance in ((0.0, 1.0), (0.3, 1.0), (0.8, 1.0), (0.8, 0.25))),
          backdrop=True, labels=("thickness 0", "0.3", "0.8", "0.8, distance 0.25")),
    Model("iridescence", "KHR_materials_iridescence: a film of ior 1.3 over a dark dielectric at roughness 0.25, "
                         "200, 400 and 600 nm thick, and 400 nm over gold metal",
          tuple(pbr(base, metallic, 0.25, KHR_materials_iridescence={
                    "iridescenceFactor": 1.0, "iridescenceIor": 1.3, "iridescenceThicknessMaximum": thickness})
                for base, metallic, thickness in ((BLUE, 0.0, 200.0), (BLUE, 0.0, 400.0), (BLUE, 0.0, 600.0),
                                                  (GOLD, 1.0, 400.0))),
          labels=("200 nm", "400 nm", "600 nm", "gold, 400 nm")),
    Model("specular_glossiness", "KHR_materials_pbrSpecularGlossiness (no metallic-roughness block): a red "
                                 "diffuse under grey specular 0.04 at glossiness 0.3 and 0.75, gold specular, "
                                 "a coloured specular",
          tuple({"extensions": {"KHR_materials_pbrSpecularGlossiness": {
                    "diffuseFactor": diffuse, "specularFactor": specular, "glossinessFactor": gloss}}}
                for diffuse, specular, gloss in (([0.6, 0.05, 0.03, 1.0], [0.04, 0.04, 0.04], 0.3),
                                                 ([0.6, 0.05, 0.03, 1.0], [0.04, 0.04, 0.04], 0.75),
                                                 ([0.0, 0.0, 0.0, 1.0], [1.0, 0.71, 0.29], 0.75),
                                                 ([0.1, 0.1, 0.3, 1.0], [0.3, 0.5, 0.2], 0.6))),
          labels=("gloss 0.3", "gloss 0.75", "gold specular", "coloured specular")),
    Model("anisotropy", "KHR_materials_anisotropy on gold metal at roughness 0.3: strength 0, 0.5 and 0.9 "
                        "along the spheres' circles of latitude, 0.9 turned 90 degrees",
          tuple(pbr(GOLD, 1.0, 0.3, KHR_materials_anisotropy={"anisotropyStrength": strength,
                                                              "anisotropyRotation": rotation})
                for strength, rotation in ((0.0, 0.0), (0.5, 0.0), (0.9, 0.0), (0.9, math.pi / 2))),
          labels=("strength 0", "0.5", "0.9", "0.9 turned 90 degrees"), tangents=True),
)


def look_rotation(direction) -> list[float]:
    """The unit quaternion [x, y, z, w] turning a node's -Z onto ``direction`` (glTF's
    lights and cameras look down their node's -Z)."""
    d = np.asarray(direction, dtype=np.float64)
    d /= np.linalg.norm(d)
    forward = np.array([0.0, 0.0, -1.0])
    axis = np.cross(forward, d)
    cosine = float(np.dot(forward, d))
    if np.linalg.norm(axis) < 1e-9:
        return [0.0, 0.0, 0.0, 1.0] if cosine > 0 else [0.0, 1.0, 0.0, 0.0]
    half = np.arccos(np.clip(cosine, -1.0, 1.0)) / 2.0
    axis = axis / np.linalg.norm(axis) * np.sin(half)
    return [float(axis[0]), float(axis[1]), float(axis[2]), float(np.cos(half))]


def add_camera(builder: GlbBuilder) -> None:
    """The file's camera, looking down -Z from z = CAMERA_Z."""
    builder.node(camera=builder.camera(type="perspective", perspective={
        "yfov": YFOV, "aspectRatio": ASPECT, "znear": 0.1, "zfar": 50.0}), translation=[0.0, 0.0, CAMERA_Z])


def three_lights(builder: GlbBuilder) -> None:
    """A key sun from the upper left, a point light at the upper right front, a rim sun from
    behind (what shows a sheen and a coat's Fresnel at the outline). Photometric units: lux
    and candela."""
    key = builder.light(type="directional", intensity=2.5, color=[1.0, 0.97, 0.92], name="key")
    builder.node(extensions={"KHR_lights_punctual": {"light": key}}, rotation=look_rotation([0.5, -0.6, -0.62]))
    point = builder.light(type="point", intensity=12.0, color=[0.9, 0.95, 1.0], name="fill")
    builder.node(extensions={"KHR_lights_punctual": {"light": point}}, translation=[2.0, 1.5, 2.5])
    rim = builder.light(type="directional", intensity=2.0, name="rim")
    builder.node(extensions={"KHR_lights_punctual": {"light": rim}}, rotation=look_rotation([-0.3, -0.35, 0.89]))


def spot_light(builder: GlbBuilder) -> None:
    """One spot, 5 m from the middle of the row, aimed at it: the outer spheres in its
    penumbra (between the 10 and 25 degree cones), the inner ones inside its inner cone."""
    spot = builder.light(type="spot", intensity=60.0, name="spot",
                         spot={"innerConeAngle": np.radians(10.0), "outerConeAngle": np.radians(25.0)})
    builder.node(extensions={"KHR_lights_punctual": {"light": spot}}, translation=[0.0, 3.0, 4.0],
                 rotation=look_rotation([0.0, -3.0, -4.0]))


RIGS = {"three": three_lights, "spot": spot_light}


def add_backdrop(builder: GlbBuilder) -> None:
    """Three upright coloured bars one metre behind the row, lit by the same lights."""
    colours = ([0.8, 0.1, 0.1, 1.0], [0.1, 0.6, 0.1, 1.0], [0.1, 0.2, 0.8, 1.0])
    bar = trimesh.creation.box(extents=[0.35, 2.4, 0.1])
    for x, colour in zip((-1.0, 0.0, 1.0), colours):
        material = builder.material(**pbr(colour, 0.0, 0.6))
        builder.node(builder.mesh(builder.primitive(bar, material)), translation=[x, 0.0, -1.0])


def sphere_columns(width: int) -> list[tuple[int, int]]:
    """The pixel columns [x0, x1) of an image ``width`` wide through the file's camera, one
    a sphere, split halfway between neighbouring spheres' centres."""
    half_width = CAMERA_Z * np.tan(YFOV / 2.0) * ASPECT
    centres = [(x / half_width + 1.0) / 2.0 * width for x in SPHERE_X]
    cuts = [0] + [round((a + b) / 2.0) for a, b in zip(centres, centres[1:])] + [width]
    return list(zip(cuts, cuts[1:]))


def sphere_tangents(sphere: trimesh.Trimesh) -> np.ndarray:
    """(N, 4) float64 unit tangents along the circles of latitude about +y (w = 1), and +x at
    the poles, where those circles shrink to a point."""
    normals = np.asarray(sphere.vertex_normals, dtype=np.float64)
    along = np.cross([0.0, 1.0, 0.0], normals)
    length = np.linalg.norm(along, axis=1, keepdims=True)
    along = np.where(length > 1e-6, along / np.maximum(length, 1e-12), [1.0, 0.0, 0.0])
    return np.hstack([along, np.ones((len(along), 1))])


def write_model(model: Model, path: Path) -> Path:
    """``model`` as a GLB at ``path``: its spheres (icospheres, 2,562 vertices each, smooth
    normals), backdrop, camera and lights."""
    builder = GlbBuilder()
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=RADIUS)
    for x, fields in zip(SPHERE_X, model.materials):
        for extension in fields.get("extensions", {}):
            builder.uses(extension)
        material = builder.material(**fields)
        primitive = builder.primitive(sphere, material)
        if model.tangents:
            primitive["attributes"]["TANGENT"] = builder.accessor(sphere_tangents(sphere), "VEC4")
        builder.node(builder.mesh(primitive), translation=[x, 0.0, 0.0])
    if model.backdrop:
        add_backdrop(builder)
    add_camera(builder)
    RIGS[model.rig](builder)
    return builder.write(path)
