"""Build the World: the validated scene with its meshes loaded and materials resolved.

Still no GL: the World is CPU data the GPU layer uploads once per run.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from scenerender.errors import Warnings
from scenerender.mesh import apply_normals_mode, load_mesh, make_primitive, normalize_unit
from scenerender.scene import LoadedScene
from scenerender.scene.messages import single_error
from scenerender.world import materials as mats
from scenerender.world.lights import LightDef, light_defs
from scenerender.world.objects import RenderObject, listed_instances, random_instances, single_instance


@dataclass
class World:
    """Everything a render needs, CPU side.

    scene:   the LoadedScene (spec, path, source map).
    objects: RenderObjects in scene order.
    lights:  LightDefs (the default rig when the scene has no ``lights``).
    """

    scene: LoadedScene
    objects: list
    lights: list
    warnings: Warnings = field(default_factory=Warnings)

    @property
    def spec(self):
        return self.scene.spec

    @property
    def render(self):
        return self.scene.spec.render

    @property
    def output(self):
        return self.scene.spec.output

    @property
    def shadowed_lights(self) -> list[LightDef]:
        return [light for light in self.lights if light.shadow is not None]

    def materials(self) -> list:
        return [m for obj in self.objects for m in obj.materials]


def build_world(scene: LoadedScene, warnings: Warnings | None = None) -> World:
    """Load meshes (each file once per set of options) and resolve materials."""
    warnings = warnings or Warnings()
    spec = scene.spec
    meshes: dict = {}
    objects = [_build_object(i, obj, scene, meshes, warnings) for i, obj in enumerate(spec.objects)]
    lights = light_defs(spec.lights, spec.render.shadows)
    _check_modes(scene, lights)
    return World(scene=scene, objects=objects, lights=lights, warnings=warnings)


def _check_modes(scene: LoadedScene, lights: list[LightDef]) -> None:
    mode = scene.spec.render.mode
    if mode in ("shadow", "light_depth") and not any(light.shadow is not None for light in lights):
        raise single_error(f"mode '{mode}' shows the first shadowed light, but no light has shadows: true",
                           ("render", "mode"), scene.source)


def _mesh_key(obj) -> tuple:
    if hasattr(obj.mesh, "primitive"):
        return ("primitive", tuple(sorted(obj.mesh.model_dump().items())), obj.normals, obj.normalize)
    return ("file", str(obj.mesh), obj.normals, obj.normalize)


def _load(obj, path: tuple, meshes: dict, warnings: Warnings):
    key = _mesh_key(obj)
    if key not in meshes:
        if key[0] == "primitive":
            params = obj.mesh.model_dump()
            kind = params.pop("primitive")
            mesh = make_primitive(kind, **params)
            # primitives carry exact normals; only an explicit "flat" changes them
            if obj.normals == "flat":
                mesh = apply_normals_mode(mesh, "flat")
        else:
            mesh = load_mesh(obj.mesh, normals=obj.normals, normalize=False, warnings=warnings)
        if obj.normalize:
            mesh = normalize_unit(mesh)
        meshes[key] = mesh
    return key, meshes[key]


def _build_object(index: int, obj, scene: LoadedScene, meshes: dict, warnings: Warnings) -> RenderObject:
    path = ("objects", index)
    key, mesh = _load(obj, path, meshes, warnings)
    name = obj.name or _default_name(obj, index)
    materials = _object_materials(obj, mesh, path, scene, warnings)
    if obj.instances is None:
        instances = single_instance()
    elif isinstance(obj.instances, list):
        instances = listed_instances(obj.instances)
    else:
        instances = random_instances(obj.instances.random)
    return RenderObject(name=name, path=path, mesh=mesh, mesh_key=key, materials=materials,
                        position=obj.position, rotation=obj.rotation, scale=obj.scale, visible=obj.visible,
                        cast_shadows=obj.cast_shadows, outline=obj.outline, instances=instances)


def _default_name(obj, index: int) -> str:
    if hasattr(obj.mesh, "primitive"):
        return f"{obj.mesh.primitive}{index}"
    return f"{obj.mesh.stem}{index}"


def _object_materials(obj, mesh, path: tuple, scene: LoadedScene, warnings: Warnings) -> list:
    """One Material per mesh group, by the precedence in ``world.materials``."""
    spec = scene.spec
    overrides = obj.material_overrides or {}
    unknown = [name for name in overrides if name not in mesh.materials]
    if unknown:
        known = ", ".join(mesh.materials) or "no MTL materials"
        raise single_error(f"'{unknown[0]}' is not a material of {mesh.source} (it has: {known})",
                           path + ("material_overrides", unknown[0]), scene.source)
    if obj.material is not None:
        chosen = spec.materials[obj.material] if isinstance(obj.material, str) else obj.material
        label = obj.material if isinstance(obj.material, str) else "inline"
        return [mats.resolve(label, None, [chosen]) for _ in mesh.groups]
    result = []
    for group in mesh.groups:
        mtl = mesh.materials.get(group.material) if group.material else None
        if group.material and mtl is None:
            warnings.warn(f"{mesh.source} uses material '{group.material}' that its MTL files do not define; "
                          "drawn with the default material")
        result.append(mats.resolve(group.material or "default", mtl, [overrides.get(group.material)]))
    return result


def scene_bounds(objects: list, matrices: list, visible: list) -> np.ndarray | None:
    """(2, 3) float64 world AABB of the visible objects, or None when nothing is visible."""
    boxes = [obj.world_bounds(m) for obj, m, v in zip(objects, matrices, visible) if v]
    if not boxes:
        return None
    stacked = np.stack(boxes)
    return np.stack([stacked[:, 0].min(axis=0), stacked[:, 1].max(axis=0)])
