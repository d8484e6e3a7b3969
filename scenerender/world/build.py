"""Build the World: the validated scene with its meshes loaded and materials resolved.

Still no GL: the World is CPU data the GPU layer uploads once per run.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, Warnings, display_path
from scenerender.mesh import MeshData, apply_normals_mode, load_mesh, make_primitive, normalize_unit
from scenerender.mesh.budget import TriangleBudget
from scenerender.mesh.gltf import GltfProblem
from scenerender.mesh.gltf_geometry import placed_nodes
from scenerender.mesh.gltf_scene import file_cameras, file_lights
from scenerender.mesh.loader import gltf_header, gltf_variants, load_gltf_nodes, read_gltf_clips
from scenerender.scene import LoadedScene
from scenerender.scene.image_files import DEFAULT_MAX_PIXELS
from scenerender.scene.messages import single_error
from scenerender.world import materials as mats
from scenerender.world import texture_files
from scenerender.world.directional_views import fixed_view_sizes
from scenerender.world.environment_light import EnvironmentDef, environment_def
from scenerender.world.environment_visibility import region_halves
from scenerender.world.file_nodes import FileCamera, file_light, node_placement
from scenerender.world.frame_inputs import AnimatedParts, WorldInputs, animated_parts, world_inputs
from scenerender.world.images import ImageStore
from scenerender.world.light_states import LightDef, light_defs, split_ambient
from scenerender.world.node_animation import (
    ClipPlayer, clip_moves, clips_text, deformation, find_clip, node_motions,
)
from scenerender.world.settings import OutlineSettings, RenderSettings
from scenerender.world.objects import RenderObject, listed_instances, random_instances, single_instance
from scenerender.world.reach import check_placements
from scenerender.world.transforms import union_bounds


@dataclass
class World:
    """Everything a render needs, CPU side.

    scene:   the LoadedScene (spec, path, source map).
    objects: RenderObjects in scene order.
    lights:  LightDefs of the directional, point and spot lights, in scene order, then those
             of the glTF files of objects with ``lights: true`` (the default rig's headlight
             when the scene has neither). Their index is the
             one index of a light everywhere: its state in FrameState.lights, its shadow
             atlas tiles and views, its place in the packed light data.
    ambient: LightDefs of the ambient lights, in scene order; they light as their sum.
    environment: the environment light (world.environment.EnvironmentDef), or None.
    images:  every texture and skybox face, decoded and checked (the GPU upload reuses them).
    """

    scene: LoadedScene
    objects: list
    lights: list
    ambient: list = field(default_factory=list)
    environment: EnvironmentDef | None = None
    warnings: Warnings = field(default_factory=Warnings)
    images: ImageStore = field(default_factory=ImageStore)
    file_camera: FileCamera | None = None  # ``camera: {from: ...}``: a glTF file's camera (world.file_nodes)

    @property
    def spec(self):
        return self.scene.spec

    @property
    def render(self):
        """The validated ``render:`` section; the renderer reads ``settings`` instead."""
        return self.scene.spec.render

    @cached_property
    def settings(self) -> RenderSettings:
        """``render:`` as plain frozen values."""
        return RenderSettings.of(self.scene.spec.render)

    @property
    def output(self):
        return self.scene.spec.output

    @cached_property
    def fixed_shadow_sizes(self) -> dict:
        """{index in ``lights``: map size} of the directional lights whose shadow view stays
        put for the whole run (world.directional_views), judged at ``render.size``."""
        width, height = self.settings.size
        return fixed_view_sizes(self, width / height)

    @cached_property
    def animated_parts(self) -> AnimatedParts:
        """Which keys of its objects and materials animate, looked for once (world.frame_inputs)."""
        return animated_parts(self)

    @cached_property
    def inputs(self) -> WorldInputs:
        """Its per-frame inputs and which of them change (world.frame_inputs.world_inputs)."""
        return world_inputs(self)

    @cached_property
    def environment_halves(self) -> int:
        """The maps each direction of the environment's visibility gets
        (world.environment_visibility.region_halves): 1 where it has none, or where its maps
        are drawn again every frame."""
        environment = self.environment
        if environment is None or not environment.visibility:
            return 1
        return region_halves(environment.visibility, environment.visibility_interleave,
                             self.inputs.environment_views.dynamic)

    @property
    def shadowed_lights(self) -> list[LightDef]:
        return [light for light in self.lights if light.shadow is not None]

    def materials(self) -> list:
        return [m for obj in self.objects for m in obj.materials]


def _start_blas() -> None:
    """Have NumPy's OpenBLAS take its working buffers before the textures are decoded. It
    takes them on its first matrix product, and where memory has run short by then (a large
    texture loaded) it ends the process with exit 1 instead of raising MemoryError."""
    np.ones((2, 2)) @ np.ones((2, 2))


def build_world(scene: LoadedScene, warnings: Warnings | None = None) -> World:
    """Load meshes (each file once per set of options), resolve materials, decode every
    texture and skybox face.

    Every file is read through ``scene.assets``, so afterwards ``scene.assets.files_read``
    lists every file the run reads. Triangles are checked against ``scene.limits.triangles``
    while meshes are read, images against ``scene.limits.texture_pixels`` before decoding.
    A texture an MTL names that cannot be decoded becomes the placeholder with a warning;
    one the scene names is an error at its key. So a scene this accepts does not fail later
    for a reason in its input: ``validate`` runs exactly this.
    """
    _start_blas()
    warnings = warnings or Warnings()
    spec = scene.spec
    loader = _Loader(scene, warnings)
    objects = [part for i, obj in enumerate(spec.objects) for part in loader.build_parts(i, obj)]
    check_placements(objects, scene.source)
    brought = loader.file_lights()
    lights, ambient = split_ambient(light_defs(spec.lights, spec.render.shadows, brought))
    _check_modes(scene, lights)
    _check_focus(scene, objects)
    images = ImageStore(max_pixels=_limit(scene, "texture_pixels", DEFAULT_MAX_PIXELS))
    for mesh in loader.meshes.values():
        for key, data in mesh.images.items():  # held by the mesh file itself (glTF)
            images.add_encoded(Path(key), data)
    texture_files.check_material_textures(objects, scene, images, warnings)
    texture_files.check_skybox(scene, images)
    sky_faces = RenderSettings.of(spec.render).skybox
    environment = environment_def(scene, images, sky_faces)
    return World(scene=scene, objects=objects, lights=lights, ambient=ambient, environment=environment,
                 warnings=warnings, images=images, file_camera=loader.file_camera())


def variant_lines(loaded: LoadedScene) -> list[str]:
    """One line per glTF file the scene's objects use that has KHR_materials_variants: their
    names (what ``scenerender validate`` lists, what ``objects[].variant`` can name)."""
    lines, seen = [], set()
    for obj in loaded.spec.objects:
        mesh = obj.mesh
        if not (isinstance(mesh, Path) and mesh.suffix.lower() in (".gltf", ".glb")) or mesh in seen:
            continue
        seen.add(mesh)
        names = gltf_variants(mesh, loaded.assets)
        if names:
            lines.append(f"  {display_path(mesh)}: variants " + ", ".join(f"'{name}'" for name in names))
    return lines


def _limit(scene: LoadedScene, name: str, default: int) -> int:
    return getattr(getattr(scene, "limits", None), name, default)


def _check_modes(scene: LoadedScene, lights: list[LightDef]) -> None:
    mode = scene.spec.render.mode
    if mode in ("shadow", "light_depth") and not any(light.shadow is not None for light in lights):
        raise single_error(f"mode '{mode}' shows the first shadowed light, but no light has shadows: true",
                           ("render", "mode"), scene.source)


def _check_focus(scene: LoadedScene, objects: list) -> None:
    camera = scene.spec.camera
    if camera is None or camera.focus is None or any(obj.name == camera.focus for obj in objects):
        return
    named = ", ".join(f"'{obj.name}'" for obj in objects[:8]) or "none"
    raise single_error(f"no object is named '{camera.focus}' (objects: {named})", ("camera", "focus"), scene.source)


def _mesh_key(obj) -> tuple:
    if isinstance(obj.mesh, MeshData):  # handed over by code; the object is its identity
        return ("memory", id(obj.mesh), obj.normals, obj.normalize)
    if hasattr(obj.mesh, "primitive"):
        return ("primitive", tuple(sorted(obj.mesh.model_dump().items())), obj.normals, obj.normalize)
    if obj.variant is not None:  # the same file with other materials
        return ("file", str(obj.mesh), obj.normals, obj.normalize, ("variant", obj.variant))
    return ("file", str(obj.mesh), obj.normals, obj.normalize)


class _Loader:
    """Builds RenderObjects for one scene: meshes loaded once per key, one triangle budget
    for all of them, each repeated warning given once."""

    def __init__(self, scene: LoadedScene, warnings: Warnings):
        self.scene = scene
        self.warnings = warnings
        self.meshes: dict = {}
        self.budget = TriangleBudget(limit=_limit(scene, "triangles", TriangleBudget.unlimited().limit))
        self.reported: set = set()
        self.players: dict = {}  # object index -> the ClipPlayer of the clip it plays

    def build_parts(self, index: int, obj) -> list[RenderObject]:
        """The object, or for a glTF file playing a clip, one part per node with a mesh."""
        if obj.animation is None:
            return [self.build_object(index, obj)]
        path = ("objects", index)
        header, clips, skins = read_gltf_clips(obj.mesh, self.scene.assets)
        self._check_variant(index, obj)
        meshes = load_gltf_nodes(obj.mesh, normals=obj.normals, warnings=self.warnings,
                                 assets=self.scene.assets, budget=self.budget, variant=obj.variant)
        clip = find_clip(clips, obj.animation.clip)
        if clip is None:
            have = f"its clips: {clips_text(clips)}" if clips else "it has no animations"
            raise single_error(f"{display_path(obj.mesh)} has no clip {obj.animation.clip!r}; {have}",
                               path + ("animation", "clip"), self.scene.source)
        spec = obj.animation
        player = ClipPlayer(header, clip, spec.speed, spec.offset, spec.loop)
        self.players[index] = player
        motions = node_motions(header, player, [node for node, _, deform in meshes if deform is None],
                               [node for node, _, deform in meshes if deform is not None and "skin" not in deform])
        nodes = header.get("nodes", [])
        name = obj.name or _default_name(obj, index)
        parts = []
        for node, mesh, deform in meshes:
            part = self.build_object(index, obj, (("node", node), mesh), f"{name}/{nodes[node].get('name') or node}",
                                     motions.get(node))
            if deform is not None:
                part.deform = self._deformation(player, skins, node, deform, path)
            parts.append(part)
        return parts

    def _check_variant(self, index: int, obj) -> None:
        """An object's ``variant`` must be one its glTF file has (exit 2 listing them)."""
        if obj.variant is None:
            return
        names = gltf_variants(obj.mesh, self.scene.assets)
        if obj.variant not in names:
            have = "its variants: " + ", ".join(f"'{name}'" for name in names) if names else "it has no variants"
            raise single_error(f"{display_path(obj.mesh)} has no variant '{obj.variant}'; {have}",
                               ("objects", index, "variant"), self.scene.source)

    def file_lights(self) -> list:
        """LightDefs of the glTF files' lights, for each object with ``lights: true`` in
        scene order, placed by the object and its clip (world.file_nodes)."""
        found = []
        for index, obj in enumerate(self.scene.spec.objects):
            if not obj.lights:
                continue
            path = ("objects", index, "lights")
            header = self._header(index, obj)
            lights = self._file_values(file_lights, header, path)
            name = obj.name or _default_name(obj, index)
            for light in lights:
                placement = self._placement(index, obj, header, light.node)
                found.append(file_light(light, placement, f"{name}/{light.name}", path))
        return found

    def file_camera(self) -> FileCamera | None:
        """``camera: {from: OBJECT, name: CAMERA}``: the camera of the object's glTF file
        (its first where ``name`` is not given), placed by the object and its clip."""
        camera = self.scene.spec.camera
        if camera is None or camera.from_object is None:
            return None
        source = self.scene.source
        names = [obj.name or _default_name(obj, i) for i, obj in enumerate(self.scene.spec.objects)]
        if camera.from_object not in names:
            shown = ", ".join(f"'{name}'" for name in names[:8]) or "none"
            raise single_error(f"no object is named '{camera.from_object}' (objects: {shown})", ("camera", "from"),
                               source)
        index = names.index(camera.from_object)
        obj = self.scene.spec.objects[index]
        if not str(obj.mesh).lower().endswith((".gltf", ".glb")):
            raise single_error(f"object '{camera.from_object}' is not drawn from a glTF file (.gltf, .glb), which "
                               "is where a camera comes from", ("camera", "from"), source)
        header = self._header(index, obj)
        cameras = self._file_values(file_cameras, header, ("camera", "from"))
        chosen = [c for c in cameras if camera.name is None or c.name == camera.name]
        if not chosen:
            known = ", ".join(f"'{c.name}'" for c in cameras) if cameras else "it has none"
            key = ("camera", "name") if camera.name is not None else ("camera", "from")
            raise single_error(f"{display_path(obj.mesh)} has no camera{f' named {camera.name!r}' if camera.name else ''}"
                               f" (cameras: {known})", key, source)
        return FileCamera(chosen[0], self._placement(index, obj, header, chosen[0].node))

    def _header(self, index: int, obj) -> dict:
        """The glTF JSON of object ``index``'s file (its clip player's where it plays one)."""
        if index in self.players:
            return self.players[index].header
        return gltf_header(obj.mesh, self.scene.assets)

    def _file_values(self, read, header: dict, path: tuple) -> list:
        try:
            return read(header)
        except GltfProblem as exc:
            raise single_error(f"cannot read the glTF file's lights and cameras: {exc}", path,
                               self.scene.source) from None

    def _placement(self, index: int, obj, header: dict, node: int):
        player = self.players.get(index)
        rest = {i: world for i, _, world in placed_nodes(header)}[node]
        return node_placement(obj, rest, node, player, player is not None and clip_moves(header, player.clip, node))

    def _deformation(self, player, skins: list, node: int, deform: dict, path: tuple):
        try:
            return deformation(player, skins, node, deform)
        except (ValueError, IndexError) as exc:
            raise single_error(f"cannot play the glTF skin: {exc}",
                               path + ("mesh",), self.scene.source) from None

    def build_object(self, index: int, obj, loaded: tuple | None = None, name: str | None = None,
                     motion=None) -> RenderObject:
        """``loaded``: (key, mesh) of a part of an animated glTF file, moved by ``motion``."""
        path = ("objects", index)
        if loaded is None:
            key, mesh = self.load(obj, path)
        else:
            key, mesh = (*_mesh_key(obj), *loaded[0]), loaded[1]
            self.meshes[key] = mesh  # its images join the scene's with every other mesh's
        name = name or obj.name or _default_name(obj, index)
        materials = self.object_materials(obj, mesh, path)
        for material in materials:
            material.vertex_colors = mesh.colors is not None
            self._read_set_zero_without_set_one(material, mesh)
        if obj.instances is None:
            instances = single_instance()
        elif isinstance(obj.instances, list):
            instances = listed_instances(obj.instances)
        else:
            instances = random_instances(obj.instances.random)
        return RenderObject(name=name, path=path, mesh=mesh, mesh_key=key, materials=materials,
                            position=obj.position, rotation=obj.rotation, scale=obj.scale, visible=obj.visible,
                            cast_shadows=obj.cast_shadows, outline=_outline(obj.outline), instances=instances,
                            motion=motion)

    def _read_set_zero_without_set_one(self, material, mesh) -> None:
        """Textures asking for texture coordinate set 1 of a mesh without one read set 0,
        with a warning (once per mesh file)."""
        if mesh.uvs1 is not None or not any(source.uv_set == 1 for source in material.maps.values()):
            return
        material.maps = {key: replace(source, uv_set=0) for key, source in material.maps.items()}
        if (mesh.source, "uv1") not in self.reported:
            self.reported.add((mesh.source, "uv1"))
            self.warnings.warn(f"{mesh.source}: a texture asks for texture coordinate set 1 (texCoord: 1), which "
                               "the mesh does not have; it reads set 0")

    def load(self, obj, path: tuple):
        key = _mesh_key(obj)
        if key not in self.meshes:
            where = self.scene.source.locate(path + ("mesh",))
            if key[0] == "memory":
                mesh = apply_normals_mode(obj.mesh, obj.normals)
                self.budget.charge(mesh.triangle_count, where)
            elif key[0] == "primitive":
                params = obj.mesh.model_dump()
                kind = params.pop("primitive")
                mesh = make_primitive(kind, **params)
                self.budget.charge(mesh.triangle_count, where)
                # primitives carry exact normals; only an explicit "flat" changes them
                if obj.normals == "flat":
                    mesh = apply_normals_mode(mesh, "flat")
            else:
                self._check_variant(path[1], obj)
                mesh = load_mesh(obj.mesh, normals=obj.normals, normalize=False, warnings=self.warnings,
                                 assets=self.scene.assets, budget=self.budget, variant=obj.variant)
            if obj.normalize:
                mesh = normalize_unit(mesh)
            self.meshes[key] = mesh
        return key, self.meshes[key]

    def object_materials(self, obj, mesh, path: tuple) -> list:
        """One Material per mesh group, by the precedence in ``world.materials``."""
        spec = self.scene.spec
        overrides = obj.material_overrides or {}
        unknown = [name for name in overrides if name not in mesh.materials]
        if unknown:
            known = ", ".join(mesh.materials) or "no MTL materials"
            raise single_error(f"'{unknown[0]}' is not a material of {mesh.source} (it has: {known})",
                               path + ("material_overrides", unknown[0]), self.scene.source)
        if obj.material is not None:
            named = isinstance(obj.material, str)
            chosen = spec.materials[obj.material] if named else obj.material
            label = obj.material if named else "inline"
            where = ("materials", obj.material) if named else path + ("material",)
            return [mats.resolve(label, None, [chosen], [where]) for _ in mesh.groups]
        result = []
        for group in mesh.groups:
            mtl = mesh.materials.get(group.material) if group.material else None
            if group.material and mtl is None and (mesh.source, group.material) not in self.reported:
                self.reported.add((mesh.source, group.material))
                self.warnings.warn(f"{mesh.source} uses material '{group.material}' that its MTL files do not "
                                   "define; drawn with the default material")
            where = path + ("material_overrides", group.material)
            result.append(mats.resolve(group.material or "default", mtl, [overrides.get(group.material)], [where],
                                       location=SourceLocation(mesh.source)))
        return result


def _default_name(obj, index: int) -> str:
    if isinstance(obj.mesh, MeshData):
        return f"mesh{index}"
    if hasattr(obj.mesh, "primitive"):
        return f"{obj.mesh.primitive}{index}"
    return f"{obj.mesh.stem}{index}"


def scene_bounds(objects: list, matrices: list, visible: list) -> np.ndarray | None:
    """(2, 3) float64 world AABB of the visible objects, or None when nothing is visible."""
    return union_bounds([obj.world_bounds(m) for obj, m, v in zip(objects, matrices, visible) if v])


def _outline(spec) -> OutlineSettings | None:
    return OutlineSettings(spec.color, spec.width) if spec is not None else None
