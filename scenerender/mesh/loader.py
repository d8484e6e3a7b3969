"""Load a mesh file into MeshData: OBJ with the built-in reader, glTF's common case with
mesh.gltf_geometry, other formats via trimesh.

trimesh (with SciPy) takes about half a second to import, so it is imported only when a
file needs it.
"""
from __future__ import annotations

import io
import os
import warnings as _pywarnings
from pathlib import Path

import numpy as np

from scenerender.errors import SourceLocation, UserError, Warnings, display_path
from scenerender.mesh.budget import TriangleBudget
from scenerender.mesh.cache import load_obj_cached
from scenerender.mesh.data import MeshData
from scenerender.mesh.data import MeshGroup
from scenerender.mesh.geometry import NORMAL_MODES, apply_normals_mode, normalize_unit
from scenerender.mesh.gltf import (GltfFile, GltfProblem, GltfSource, GltfStructureProblem, read_gltf, split_glb,
                                   variant_names, vertex_colors)
from scenerender.mesh.gltf_animation import read_clips, read_skins
from scenerender.mesh.gltf_geometry import read_parts
from scenerender.mesh.numbers import BEYOND_FLOAT32, fits_float32
from scenerender.scene.assets import AssetPolicy, policy_for
from scenerender.scene.files import read_regular_file

TRIMESH_FORMATS = (".ply", ".stl", ".glb", ".gltf", ".off")
MESH_FORMATS = (".obj",) + TRIMESH_FORMATS


def load_mesh(
    path: Path, *, normals: str = "auto", normalize: bool = False, warnings: Warnings,
    assets: AssetPolicy | None = None, budget: TriangleBudget | None = None, variant: str | None = None,
) -> MeshData:
    """Read a mesh file, give it normals according to ``normals`` (auto | smooth | flat)
    and, with ``normalize``, centre it and scale its bounding-box diagonal to 1.

    ``assets`` confines the files the mesh names (MTL libraries, textures, glTF buffers) and
    records them; without one, the mesh's own folder is the only root. ``budget`` is how
    many triangles the scene may still load; it is charged with this mesh's triangles.
    ``variant``: a glTF file's KHR_materials_variants name (one of ``gltf_variants``) whose
    materials its primitives take.

    The result always has finite unit normals. Raises UserError (naming the file) when the
    file is missing, of an unsupported type, unreadable, malformed, over the triangle
    budget, or holds no triangles.
    """
    if normals not in NORMAL_MODES:
        raise ValueError(f"normals must be one of {', '.join(NORMAL_MODES)}, not {normals!r}")
    path = Path(path)
    shown = display_path(path)
    assets = assets if assets is not None else policy_for(path)
    _check_mesh_file(path, assets, SourceLocation(shown))
    budget = budget if budget is not None else TriangleBudget.unlimited()
    suffix = path.suffix.lower()
    if suffix == ".obj":
        from scenerender.mesh.obj import parse_obj  # the OBJ and MTL readers: only scenes with OBJ files

        def parse(warned: Warnings) -> MeshData:
            return _finished(parse_obj(path, warned, assets=assets, budget=budget), normals, normalize, shown)

        # a cached load is exactly this parse, warnings included (see mesh.cache)
        return load_obj_cached(path, parse, normals=normals, normalize=normalize, warnings=warnings,
                               assets=assets, budget=budget)
    if suffix in TRIMESH_FORMATS:
        mesh = _load_other_format(path, assets, budget, warnings, variant)
        budget.charge(mesh.triangle_count, SourceLocation(shown))
    else:
        raise UserError(
            f"unsupported mesh format '{path.suffix}' (supported: {', '.join(MESH_FORMATS)})",
            SourceLocation(shown),
        )
    return _finished(mesh, normals, normalize, shown)


def load_gltf_nodes(path: Path, *, normals: str = "auto", warnings: Warnings, assets: AssetPolicy,
                    budget: TriangleBudget, variant: str | None = None) -> list[tuple[int, MeshData, dict | None]]:
    """A glTF file for its animations: [(node index, the node's mesh at rest, its
    deformation or None)], one mesh per node that holds one, so that each can move with its
    node. A node whose vertices move themselves (a skin, morph targets: see _deformation)
    keeps its mesh in the mesh's own space: a skin places it (the node's transform is
    ignored, as the specification says), else the node's transform after the morph. The
    others are where the file puts them at rest. Raises UserError where the file needs
    trimesh (which keeps no nodes)."""
    path = Path(path)
    shown = display_path(path)
    _check_mesh_file(path, assets, SourceLocation(shown))
    raw = read_regular_file(path, "mesh file")
    read_file = _policy_reader(path, assets)
    source = _gltf_json(raw, path)
    gltf = _read_gltf(source, path, read_file, warnings, variant)
    parts = _gltf_parts_here(source, read_file, gltf, deformations=True, variant=variant)
    if parts is None:
        raise UserError("cannot play its animations: its geometry is stored in a way only trimesh reads "
                        "(sparse, compressed or non-triangle primitives), and trimesh keeps no nodes",
                        SourceLocation(shown))
    nodes: dict = {}
    for part in parts:
        nodes.setdefault(part["node"], []).append(part)
    meshes = []
    for node, node_parts in nodes.items():
        deform = _deformation(node_parts)
        if deform:  # the mesh's own space: the joints, or the node's transform after the morph, place it
            node_parts = [{**p, "transform": np.eye(4)} for p in node_parts]
        mesh = _finished(_joined(node_parts, gltf, shown), normals, False, shown)
        budget.charge(mesh.triangle_count, SourceLocation(shown))
        if deform and len(node_parts) and sum(len(p["vertices"]) for p in node_parts) != mesh.vertex_count:
            raise UserError("cannot play its skin or morph targets: the normals mode changed the vertices; use "
                            "normals: auto with a file that stores normals", SourceLocation(shown))
        meshes.append((node, mesh, deform or None))
    return meshes


def _deformation(parts: list[dict]) -> dict:
    """What moves a node's vertices themselves: {"skin", "joints" (N, 4), "weights" (N, 4)}
    where the node has a skin and every primitive JOINTS_0 and WEIGHTS_0; {"morph":
    {"positions", "normals": (T, N, 3), "weights": (T,)}} where every primitive has the same
    number T of morph targets; both, or {} (a rigid part)."""
    deform: dict = {}
    if parts[0]["skin"] is not None and all("joints" in p for p in parts):
        deform.update(skin=parts[0]["skin"], joints=np.concatenate([p["joints"] for p in parts]),
                      weights=np.concatenate([p["weights"] for p in parts]))
    counts = {len(p.get("targets") or ()) for p in parts}
    if len(counts) == 1 and counts != {0}:
        count = counts.pop()
        defaults = parts[0].get("morph_weights")
        defaults = np.asarray(defaults, dtype=np.float64) if defaults is not None else np.zeros(count)
        if defaults.shape != (count,):
            defaults = np.zeros(count)
        deform["morph"] = {key: np.stack([np.concatenate([p["targets"][t][key] for p in parts]) for t in range(count)])
                           for key in ("positions", "normals")}
        deform["morph"]["weights"] = defaults
    return deform


def read_gltf_clips(path: Path, assets: AssetPolicy) -> tuple[dict, list, list]:
    """(the glTF JSON, its animation clips, its skins: mesh.gltf_animation.Clip, Skin) of
    the file ``path``, its buffers read through ``assets``. Raises UserError naming the file
    where they are malformed."""
    path = Path(path)
    shown = display_path(path)
    _check_mesh_file(path, assets, SourceLocation(shown))
    raw = read_regular_file(path, "mesh file")
    source = _gltf_json(raw, path)
    try:
        read_file = _policy_reader(path, assets)
        return source.header, read_clips(source, read_file), read_skins(source, read_file)
    except UserError:
        raise  # a buffer outside the allowed folders
    except GltfProblem as exc:
        raise UserError(f"cannot read its animations: {exc}", SourceLocation(shown)) from None
    except Exception as exc:  # noqa: BLE001 - values NumPy cannot shape (a weights channel of no targets...)
        raise UserError(f"cannot read its animations: {_short(exc)}", SourceLocation(shown)) from None


def gltf_header(path: Path, assets: AssetPolicy) -> dict:
    """The glTF JSON of the file ``path`` (through the root guard, mesh.gltf.split_glb),
    for what needs only the JSON: its cameras, lights and variants. Raises UserError naming
    the file where it cannot be read."""
    path = Path(path)
    _check_mesh_file(path, assets, SourceLocation(display_path(path)))
    return _gltf_json(read_regular_file(path, "mesh file"), path).header


def gltf_variants(path: Path, assets: AssetPolicy) -> list[str]:
    """The KHR_materials_variants names of the glTF file ``path`` (empty without any).
    Raises UserError naming the file where it cannot be read."""
    header = gltf_header(path, assets)
    try:
        return variant_names(header)
    except GltfProblem as exc:
        raise UserError(f"cannot read its variants: {exc}", SourceLocation(display_path(path))) from None


def _gltf_json(raw: bytes, path: Path) -> GltfSource:
    """The glTF file ``raw`` read from ``path``, split and checked once for all its readers
    by the root guard (mesh.gltf.split_glb): a file whose JSON is no glTF document is a UserError
    naming the file and the key, whatever would read it next."""
    try:
        return split_glb(raw)
    except GltfStructureProblem as exc:
        raise UserError(f"not a usable glTF file: {exc.message}", SourceLocation(display_path(path)),
                        exc.key) from None


def _check_mesh_file(path: Path, assets: AssetPolicy, where: SourceLocation) -> None:
    """Raise unless ``path`` is a regular file inside the folders ``assets`` allows. Whether
    it lies inside is decided first: nothing outside is looked at."""
    lookup = assets.lookup(os.path.abspath(path), path.parent)
    if lookup.problem == "missing":
        raise UserError("mesh file not found", where)
    if not lookup.found:
        raise UserError(lookup.message, where)


def _finished(mesh: MeshData, normals: str, normalize: bool, shown: str) -> MeshData:
    """``mesh`` as read, given its normals mode and, with ``normalize``, unit size."""
    if mesh.triangle_count == 0:
        raise UserError("the file contains no triangles", SourceLocation(shown))
    mesh = apply_normals_mode(mesh, normals)
    if normalize:
        mesh = normalize_unit(mesh)
    return mesh


def _load_other_format(path: Path, assets: AssetPolicy, budget: TriangleBudget, warnings: Warnings,
                       variant: str | None = None) -> MeshData:
    """Read ``path`` (not an OBJ) and flatten the scene it describes into one mesh.

    Node transforms are applied; UVs are kept when any part has them (parts without get
    (0, 0)); normals are kept only when the file stored them, else left None for the
    normals mode to compute. Files the mesh refers to (glTF buffers and images, a PLY's
    texture) are read through ``assets``. Where the header declares the face count (PLY,
    binary STL, OFF), ``budget`` is checked before anything is allocated.

    A glTF file also gives its materials (mesh.gltf: one group per run of triangles with
    one material, the images they use, ``COLOR_0``). Materials that cannot be read are one
    warning, and the file is drawn with the scene's material. Its geometry is read by
    mesh.gltf_geometry where that can (no trimesh import), else, as every other format,
    by trimesh.
    """
    shown = display_path(path)
    raw = read_regular_file(path, "mesh file")
    declared = declared_faces(raw, path.suffix.lower())
    if declared is not None:
        budget.check(declared, SourceLocation(shown))
    read_file = _policy_reader(path, assets)
    gltf = None
    if path.suffix.lower() in (".glb", ".gltf"):
        source = _gltf_json(raw, path)
        gltf = _read_gltf(source, path, read_file, warnings, variant)
        parts = _gltf_parts_here(source, read_file, gltf, variant=variant)
        if parts is not None:
            return _joined(parts, gltf, shown)
    return _joined(_trimesh_parts(path, raw, assets, gltf, warnings), gltf, shown)


def _gltf_parts_here(source: GltfSource, read_file, gltf: GltfFile | None, deformations: bool = False,
                     variant: str | None = None) -> list[dict] | None:
    """The glTF file's parts read without trimesh, or None where trimesh must read it
    (what mesh.gltf_geometry leaves to it, or a file it finds malformed: trimesh then
    gives the reason the user sees, as for every other format)."""
    names = [material.name for material in gltf.materials] if gltf is not None else []
    try:
        with np.errstate(all="ignore"):
            return read_parts(source, read_file, names, deformations, variant)
    except UserError:
        raise  # a file it names outside the allowed folders
    except Exception:  # noqa: BLE001 - NotReadHere, GltfProblem, or malformed JSON values
        return None


def _joined(raw_parts: list[dict], gltf: GltfFile | None, shown: str) -> MeshData:
    """The parts checked, joined into one mesh, with the glTF materials they use."""
    parts = [_part_arrays(raw, shown) for raw in raw_parts]
    if not parts:
        raise UserError("the file contains no triangles", SourceLocation(shown))
    mesh = _concatenate(parts, shown)
    if gltf is not None:
        used = {group.material for group in mesh.groups if group.material is not None}
        mesh.materials = {m.name: m for m in gltf.materials if m.name in used}
        mesh.images = {key: data for key, data in gltf.images.items()
                       if any(t.image == key for m in mesh.materials.values() for t in m.textures().values())}
    return mesh


def _trimesh_parts(path: Path, raw: bytes, assets: AssetPolicy, gltf: GltfFile | None,
                   warnings: Warnings) -> list[dict]:
    """The parts of the file as trimesh reads it (see _raw_parts)."""
    import trimesh  # deliberately lazy: see the module docstring

    shown = display_path(path)
    data = io.BytesIO(raw)
    resolver = _policy_resolver(trimesh, path, assets)
    try:
        with _pywarnings.catch_warnings(), np.errstate(all="ignore"):
            # Pillow's decompression-bomb (a RuntimeWarning), NumPy's overflow and the readers'
            # complaints (UserWarning) on hostile files would otherwise print multi-line text;
            # the outcome is judged below instead. A DeprecationWarning still shows.
            _pywarnings.simplefilter("ignore", RuntimeWarning)
            _pywarnings.simplefilter("ignore", UserWarning)
            if hasattr(trimesh, "load_scene"):
                scene = trimesh.load_scene(data, file_type=path.suffix.lower()[1:], resolver=resolver, process=False)
            else:  # trimesh < 4.5
                scene = trimesh.load(data, file_type=path.suffix.lower()[1:], resolver=resolver,
                                     force="scene", process=False)
            return _raw_parts(scene, trimesh, _gltf_slots(scene, gltf, warnings, shown))
    except UserError:
        raise  # a referenced file outside the allowed folders, already explained
    except MemoryError:
        raise UserError("cannot read mesh: its header claims more data than fits in memory",
                        SourceLocation(shown)) from None
    except Exception as exc:  # trimesh raises many types for malformed files
        raise UserError(f"cannot read mesh: {_short(exc)}", SourceLocation(shown)) from None


def _read_gltf(source: GltfSource, path: Path, read_file, warnings: Warnings, variant: str | None = None) -> GltfFile | None:
    """The file's own glTF materials (mesh.gltf), or None with a warning where they cannot
    be read (the geometry may still be fine: trimesh judges it)."""
    shown = display_path(path)
    try:
        gltf = read_gltf(source, str(path), read_file, variant)
    except GltfProblem as exc:
        warnings.warn(f"materials not read ({exc}); drawn with the scene's material", SourceLocation(shown))
        return None
    except UserError:
        raise  # a file it names outside the allowed folders
    except (ValueError, OSError, RecursionError) as exc:
        warnings.warn(f"materials not read ({_short(exc)}); drawn with the scene's material", SourceLocation(shown))
        return None
    for note in gltf.unsupported:
        warnings.warn(f"{note}", SourceLocation(shown))
    return gltf


def _gltf_slots(scene, gltf: GltfFile | None, warnings: Warnings, shown: str) -> dict:
    """{geometry name: (GltfMaterial or None, COLOR_0 componentType or None)}: trimesh makes
    one geometry per primitive, in file order; each is matched to its primitive here, its
    vertex count checked against the POSITION accessor's. Empty where they do not match
    (a trimesh that reads the file another way): then no material is applied, with a warning."""
    if gltf is None:
        return {}
    names = list(scene.geometry)
    counts = [len(getattr(scene.geometry[name], "vertices", ())) for name in names]
    if len(names) != len(gltf.slots) or any(c != slot[1] for c, slot in zip(counts, gltf.slots)):
        if gltf.materials:
            warnings.warn("materials not matched to the primitives; drawn with the scene's material",
                          SourceLocation(shown))
        return {}
    return {name: (gltf.materials[slot[0]] if slot[0] is not None else None, slot[2])
            for name, slot in zip(names, gltf.slots)}


def _stored_vertex_normals(geometry) -> np.ndarray | None:
    """Vertex normals the file provided, or None.

    trimesh computes vertex normals on demand; ones read from the file are already in its
    cache, which is the only way to tell the two apart.
    """
    cache = getattr(geometry, "_cache", None)
    try:
        stored = cache["vertex_normals"] if "vertex_normals" in cache else None
    except Exception:  # a trimesh without this cache: compute normals ourselves
        return None
    if stored is None or len(stored) != len(geometry.vertices):
        return None
    return np.asarray(stored, dtype=np.float64)


def _raw_parts(scene, trimesh, slots: dict) -> list[dict]:
    """The arrays of each geometry instance as trimesh read them, not yet trusted:
    vertices (N, 3), faces (M, 3), stored normals or None, uv or None, transform (4, 4);
    and from ``slots`` (see _gltf_slots) the glTF material (or None) and vertex colours."""
    raw = []
    for node in scene.graph.nodes_geometry:
        transform, geometry_name = scene.graph[node]
        geometry = scene.geometry.get(geometry_name)
        if isinstance(geometry, trimesh.Trimesh) and len(geometry.faces):
            material, color_type = slots.get(geometry_name, (None, None))
            visual = getattr(geometry, "visual", None)
            raw.append({
                "vertices": np.asarray(geometry.vertices, dtype=np.float64),
                "faces": np.asarray(geometry.faces, dtype=np.int64),
                "normals": _stored_vertex_normals(geometry),
                "uv": getattr(visual, "uv", None),
                "transform": np.asarray(transform, dtype=np.float64),
                "material": material.name if material is not None else None,
                "colors": vertex_colors(visual, color_type, len(geometry.vertices)) if color_type else None,
            })
    return raw


def _part_arrays(raw: dict, shown: str) -> dict:
    """One geometry instance in world space: positions, normals or None, uvs or None, faces.

    trimesh with ``process=False`` passes on what the file says, so the shapes, the face
    indices and the transform are checked here: a file is malformed when its faces name
    vertices it does not have.
    """
    positions, faces, transform = raw["vertices"], raw["faces"], raw["transform"]
    where = SourceLocation(shown)
    if positions.ndim != 2 or positions.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise UserError("cannot read mesh: malformed file (vertex or face arrays of the wrong shape)", where)
    if faces.size and (faces.min() < 0 or faces.max() >= len(positions)):
        raise UserError(f"cannot read mesh: faces refer to vertex {int(faces.max())} but the file has "
                        f"{len(positions)} vertices", where)
    if transform.shape != (4, 4) or not np.isfinite(transform).all():
        raise UserError("cannot read mesh: a node transform is not a finite 4x4 matrix", where)
    normals = raw["normals"]
    uvs = None
    visual_uv = raw["uv"]
    if visual_uv is not None:
        visual_uv = np.asarray(visual_uv, dtype=np.float64)
        if visual_uv.ndim == 2 and visual_uv.shape[1] >= 2 and len(visual_uv) == len(positions):
            uvs = visual_uv[:, :2]
    _check_float32(positions, "a vertex coordinate", where)
    _check_float32(normals, "a normal component", where)
    _check_float32(uvs, "a texture coordinate", where)
    uvs1 = raw.get("uv1")
    _check_float32(uvs1, "a texture coordinate", where)
    linear = transform[:3, :3]
    determinant = np.linalg.det(linear)
    with np.errstate(all="ignore"):  # judged by the checks below, not by NumPy's warnings
        positions = positions @ linear.T + transform[:3, 3]
        if normals is not None:
            # rows times the inverse transpose; a flattening transform leaves none to keep
            normals = normals @ np.linalg.inv(linear) if determinant != 0 else None
    _check_float32(positions, "a vertex coordinate after the node transform", where)
    _check_float32(normals, "a normal component after the node transform", where)
    if determinant < 0:  # a mirroring transform turns the winding inside out
        faces = faces[:, ::-1]
    tangents = raw.get("tangents")
    if tangents is not None:  # directions in the surface: the transform's linear part; a mirror turns the handedness
        _check_float32(tangents, "a tangent component", where)
        tangents = np.hstack([tangents[:, :3] @ linear.T, tangents[:, 3:] * (-1.0 if determinant < 0 else 1.0)])
    return {"positions": positions, "normals": normals, "uvs": uvs, "faces": faces,
            "material": raw.get("material"), "colors": raw.get("colors"), "tangents": tangents, "uvs1": uvs1}


def _check_float32(values: np.ndarray | None, what: str, where: SourceLocation) -> None:
    """Raise unless every one of ``values`` (or None) is finite and fits a 32-bit float,
    which is what the mesh is stored in."""
    if values is None:
        return
    fits = fits_float32(values).reshape(-1)
    if fits.all():
        return
    value = float(values.reshape(-1)[np.argmin(fits)])
    if not np.isfinite(value):
        raise UserError(f"cannot read mesh: {what} is not a finite number ({value})", where)
    raise UserError(f"cannot read mesh: {what} is {value:g}, {BEYOND_FLOAT32}", where)


def _concatenate(parts: list[dict], shown: str) -> MeshData:
    """Join the parts into one mesh; see _load_with_trimesh for how UVs and normals merge."""
    offsets = np.cumsum([0] + [len(p["positions"]) for p in parts])
    uvs = normals = None
    if any(p["uvs"] is not None for p in parts):
        blank = [np.zeros((len(p["positions"]), 2)) for p in parts]
        uvs = np.concatenate(
            [p["uvs"] if p["uvs"] is not None else zeros for p, zeros in zip(parts, blank)]
        ).astype(np.float32)
    if all(p["normals"] is not None for p in parts):
        normals = np.concatenate([p["normals"] for p in parts]).astype(np.float32)
    colors = None
    if any(p.get("colors") is not None for p in parts):  # parts without are white
        colors = np.concatenate([p["colors"] if p.get("colors") is not None else np.ones((len(p["positions"]), 4))
                                 for p in parts]).astype(np.float32)
    faces = [p["faces"] + offset for p, offset in zip(parts, offsets)]
    uvs1 = None
    if any(p.get("uvs1") is not None for p in parts):  # parts without: (0, 0), as for set 0
        uvs1 = np.concatenate([p["uvs1"] if p.get("uvs1") is not None else np.zeros((len(p["positions"]), 2))
                               for p in parts]).astype(np.float32)
    tangents = None
    if all(p.get("tangents") is not None for p in parts):  # else worked out from the uvs, for all alike
        tangents = np.concatenate([p["tangents"] for p in parts]).astype(np.float32)
    return MeshData(
        positions=np.concatenate([p["positions"] for p in parts]).astype(np.float32),
        normals=normals,
        uvs=uvs,
        indices=np.concatenate(faces).astype(np.uint32),
        groups=_material_groups(parts),
        source=shown,
        colors=colors,
        tangents=tangents,
        uvs1=uvs1,
    )


def _material_groups(parts: list[dict]) -> list[MeshGroup]:
    """One group per run of consecutive parts with the same material (None: the object's)."""
    groups: list[MeshGroup] = []
    first = 0
    for part in parts:
        count = len(part["faces"])
        material = part.get("material")
        if groups and groups[-1].material == material:
            groups[-1] = MeshGroup(material, groups[-1].first, groups[-1].count + count)
        else:
            groups.append(MeshGroup(material, first, count))
        first += count
    return groups


def _short(exc: BaseException) -> str:
    """An exception as a short one-line reason. trimesh's own messages (ValueError, OSError)
    explain themselves; others (KeyError 'y', IndexError...) need their type to mean anything."""
    text = " ".join(str(exc).split())
    if not isinstance(exc, (ValueError, OSError)) or not text:
        text = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
        text = f"malformed file ({text})"
    return text if len(text) <= 200 else text[:197] + "..."


def _policy_reader(path: Path, assets: AssetPolicy):
    """read(name) -> bytes of a file the mesh ``path`` refers to, through ``assets``:
    inside the allowed folders, regular files only, each recorded as read. A name that is
    not found is tried again as a bare file name beside the mesh."""
    folder = path.parent

    def read(name: str) -> bytes:
        lookup = assets.lookup(name, folder)
        if lookup.problem == "missing":
            bare = assets.lookup(Path(name.replace("\\", "/")).name, folder)
            lookup = bare if bare.found else lookup
        if lookup.problem == "missing":
            raise FileNotFoundError(name)
        if not lookup.found:
            raise UserError(lookup.message, SourceLocation(display_path(path)))
        assets.record(lookup.path)
        return read_regular_file(lookup.path)

    return read


def _policy_resolver(trimesh, path: Path, assets: AssetPolicy):
    """A trimesh resolver reading through ``assets`` (see _policy_reader)."""
    read = _policy_reader(path, assets)

    class PolicyResolver(trimesh.resolvers.Resolver):
        def __init__(self):
            pass

        def get(self, name: str) -> bytes:
            return read(name)

        def keys(self):
            return iter(())

        def write(self, name, data):
            raise PermissionError("meshes are read-only here")

        def namespaced(self, namespace: str):
            return _policy_resolver(trimesh, path.parent / namespace / path.name, assets)

    return PolicyResolver()


def declared_faces(raw: bytes, suffix: str) -> int | None:
    """The face count a PLY, binary STL or OFF header declares (a lower bound on its
    triangles), or None when the format has no such header or it cannot be read here
    (trimesh then reports what is wrong)."""
    try:
        if suffix == ".ply":
            header = raw[: raw.find(b"end_header")] if b"end_header" in raw[:65536] else b""
            for line in header.decode("ascii", "replace").splitlines():
                words = line.split()
                if len(words) == 3 and words[0] == "element" and words[1] == "face":
                    return int(words[2])
        elif suffix == ".stl" and not raw[:5].lower().startswith(b"solid") and len(raw) >= 84:
            return int.from_bytes(raw[80:84], "little")
        elif suffix == ".off":
            lines = [ln.split("#")[0].split() for ln in raw[:4096].decode("ascii", "replace").splitlines()]
            counts = [words for words in lines if words and words[0] != "OFF"]
            if counts and len(counts[0]) >= 2:
                return int(counts[0][1])
    except ValueError:
        return None
    return None
