"""The names object ids are matched by (``objects.json``, ``diff``): an object's own name,
or, for an object the scene does not name, one made from what it is, so that inserting,
dropping or reordering objects renames none of the others.

An unnamed object is called by its mesh (a primitive's kind, a mesh file's stem, ``mesh``
and a digest of its vertices for a mesh handed over by code), its material (a named one's
name, ``inline``, or nothing where the mesh's MTL files give them) and its position at
t = 0 rounded to 1 cm: ``sphere steel at (3, 0.5, -2.2)``. Objects that share such a name
are told apart by a counter in scene order (``#2``, ``#3``), the first keeping the plain
name, so only an object identical to others in all three can be renamed by an insertion.
Moving an unnamed object in the scene renames it: ``diff`` reports it gone and new.
"""
from __future__ import annotations

import hashlib

from scenerender.mesh.data import MeshData


def id_names(world) -> dict:
    """id -> name of every object of ``world`` (a world.build.World): its index + 1 (its id
    in the object-id pass) -> its own name, or the content name above."""
    specs = world.scene.spec.objects
    names = [spec.name or content_name(obj, spec) for obj, spec in zip(world.objects, specs)]
    return {index + 1: name for index, name in enumerate(_counted(names, [bool(s.name) for s in specs]))}


def content_name(obj, spec) -> str:
    """``obj`` (a RenderObject) by its mesh, material and position at t = 0, for ``spec``
    (its scene entry)."""
    material = spec.material if isinstance(spec.material, str) else ("inline" if spec.material is not None else "")
    position = ", ".join(_rounded(v) for v in obj.position(0.0))
    return " ".join(part for part in (_mesh_label(spec), material) if part) + f" at ({position})"


def _mesh_label(spec) -> str:
    if isinstance(spec.mesh, MeshData):
        return "mesh " + hashlib.sha1(spec.mesh.positions.tobytes()).hexdigest()[:6]
    if hasattr(spec.mesh, "primitive"):
        return spec.mesh.primitive
    return spec.mesh.stem


def _rounded(value: float) -> str:
    """A coordinate to 1 cm, without a sign on zero: 3.0 -> '3', -0.001 -> '0'."""
    return f"{round(float(value), 2) + 0.0:g}"


def _counted(names: list[str], given: list[bool]) -> list[str]:
    """``names`` with a counter on the second and later of each made-up name that repeats;
    names the scene gave are kept as they are (diff tells repeats of those apart by index)."""
    seen: dict = {}
    out = []
    for name, own in zip(names, given):
        if own:
            out.append(name)
            continue
        seen[name] = seen.get(name, 0) + 1
        out.append(name if seen[name] == 1 else f"{name} #{seen[name]}")
    return out
