"""The second pass over a validated scene: the files it names.

Validation (``scene/model/``) checks what a scene says and opens nothing: a path there is
the text the scene wrote. This pass looks each one up through the run's ``AssetPolicy``
(relative to the scene file, inside the allowed folders, symlinks followed, a regular file
whose real name still has a suffix of its kind), reads the headers of the images the scene
names (readable, within ``--limit texture_pixels``; skybox faces square and of one size)
and finds the six faces in a skybox folder. It returns the model with every path replaced
by the resolved ``Path``, each file recorded in ``assets.files_read`` in the model's order.

Problems are reported like validation's own: one line each, at the key that names the
file, through ``messages.to_user_errors``. The pass runs only on a scene that validated, so
a scene with problems of both kinds shows the validation problems first.
"""
from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError
from pydantic_core import PydanticCustomError

from scenerender.errors import UserError
from scenerender.limits import Limits
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.image_files import ImageError, image_size
from scenerender.scene.messages import to_user_errors
from scenerender.scene.model.lights import SKY
from scenerender.scene.model.materials import MaterialSpec
from scenerender.scene.model.meshes import MESH_FILE
from scenerender.scene.model.objects import ObjectSpec
from scenerender.scene.model.paths import ENVIRONMENT_FILE, IMAGE_FILE, IMAGE_SUFFIXES, FileKind, keys_holding
from scenerender.scene.model.render import SKY_FACES, RenderSpec, SkyboxFaces
from scenerender.scene.model.scene import SceneSpec
from scenerender.scene.yaml_source import SourceMap

# the image keys of a material: diffuse_map, specular_map, normal_map, opacity_map
MAP_KEYS = keys_holding(MaterialSpec, IMAGE_FILE)


def check_files(spec: SceneSpec, data: dict, source: SourceMap, assets: AssetPolicy, limits: Limits) -> SceneSpec:
    """``spec`` with each file it names looked up and checked; raises ``SceneErrors``
    located in the scene file through ``data`` (the document ``spec`` was validated from)
    and ``source``."""
    checks = _FileChecks(assets, limits)
    resolved = checks.scene(spec)
    if checks.problems:
        raise to_user_errors(ValidationError.from_exception_data("scene files", checks.problems), data, source)
    return resolved


class _FileChecks:
    """One pass: the problems found (as pydantic line errors) and each image's header size,
    read once however many keys name the file."""

    def __init__(self, assets: AssetPolicy, limits: Limits):
        self.assets = assets
        self.base = assets.roots[0]  # relative paths are relative to the scene file
        self.max_pixels = limits.texture_pixels
        self.sizes: dict[Path, tuple[int, int] | ImageError] = {}
        self.problems: list[dict] = []

    # -- the model, in the order of its keys -------------------------------------------
    def scene(self, spec: SceneSpec) -> SceneSpec:
        changes = {}
        render = self.render(spec.render)
        if render is not spec.render:
            changes["render"] = render
        materials = {name: self.material(material, ("materials", name)) for name, material in spec.materials.items()}
        if _changed(materials, spec.materials):
            changes["materials"] = materials
        lights = [self.light(light, ("lights", index)) for index, light in enumerate(spec.lights or ())]
        if any(new is not old for new, old in zip(lights, spec.lights or ())):
            changes["lights"] = lights
        objects = [self.object(obj, ("objects", index)) for index, obj in enumerate(spec.objects)]
        if any(new is not old for new, old in zip(objects, spec.objects)):
            changes["objects"] = objects
        return spec.model_copy(update=changes) if changes else spec

    def render(self, render: RenderSpec) -> RenderSpec:
        if render.skybox is None:
            return render
        return render.model_copy(update={"skybox": self.skybox(render.skybox, ("render", "skybox"))})

    def light(self, light, where: tuple):
        """An environment light's image file looked up (``image: sky`` names none)."""
        if light.type != "environment" or light.image == SKY:
            return light
        written = light.image
        if written.lower().endswith(IMAGE_SUFFIXES):  # 8-bit: its header is read and checked too
            path = self.image(written, where + ("image",))
        else:
            path = self.file(written, where + ("image",), ENVIRONMENT_FILE)
        return light.model_copy(update={"image": path}) if path is not None else light

    def object(self, obj: ObjectSpec, where: tuple) -> ObjectSpec:
        changes = {}
        if isinstance(obj.mesh, str):  # else an inline primitive, or a mesh made in code
            changes["mesh"] = self.file(obj.mesh, where + ("mesh",), MESH_FILE)
        if isinstance(obj.material, MaterialSpec):  # else a name from `materials`, or none
            material = self.material(obj.material, where + ("material",))
            if material is not obj.material:
                changes["material"] = material
        if obj.material_overrides:
            overrides = {name: self.material(material, where + ("material_overrides", name))
                         for name, material in obj.material_overrides.items()}
            if _changed(overrides, obj.material_overrides):
                changes["material_overrides"] = overrides
        return obj.model_copy(update=changes) if changes else obj

    def material(self, material: MaterialSpec, where: tuple) -> MaterialSpec:
        changes = {key: self.image(getattr(material, key), where + (key,))
                   for key in MAP_KEYS if getattr(material, key) is not None}
        return material.model_copy(update=changes) if changes else material

    def skybox(self, sky: SkyboxFaces | str, where: tuple) -> SkyboxFaces | None:
        """The six faces as written, or a folder holding them; each face must be an image,
        all of them square and of one size."""
        written = self.folder_faces(sky, where) if isinstance(sky, str) else {face: getattr(sky, face)
                                                                             for face in SKY_FACES}
        if written is None:
            return None
        faces = {face: self.image(text, where + (face,)) for face, text in written.items()}
        if any(path is None for path in faces.values()):
            return None
        first = self.sizes[faces["posx"]]
        for face in SKY_FACES:
            width, height = self.sizes[faces[face]]
            if width != height or (width, height) != first:
                return self.problem(where, PydanticCustomError(
                    "skybox_size", "skybox faces must be square and all the same size; {face} is {w}x{h}, "
                    "posx {fw}x{fh}", {"face": face, "w": width, "h": height, "fw": first[0], "fh": first[1],
                                       "subpath": (face,)}), sky)
        return SkyboxFaces.model_construct(**faces)

    # -- one path ------------------------------------------------------------------------
    def file(self, written: str, where: tuple, kind: FileKind) -> Path | None:
        """The file ``written`` names, when it exists where the scene may read and its real
        name (symlinks followed) still has a suffix of ``kind``."""
        try:
            path = self.assets.resolve(written, self.base)
        except UserError as exc:
            return self.problem(where, PydanticCustomError("asset_path", "{message}", {"message": exc.message}),
                                written)
        if path.suffix.lower() not in kind.suffixes:
            return self.problem(where, kind.wrong_kind(written), written)
        return path

    def image(self, written: str, where: tuple) -> Path | None:
        """The image file ``written`` names, when its header is readable and within the limit."""
        path = self.file(written, where, IMAGE_FILE)
        if path is None:
            return None
        found = self.sizes.get(path)
        if found is None:
            try:
                found = image_size(path, self.max_pixels)
            except ImageError as exc:
                found = exc
            self.sizes[path] = found
        if isinstance(found, ImageError):
            return self.problem(where, PydanticCustomError("image", "{reason}", {"reason": found.reason}), written)
        return path

    def folder_faces(self, written: str, where: tuple) -> dict[str, str] | None:
        """Face -> file in the folder ``written`` names, found by stem with any image suffix."""
        try:
            folder = self.assets.resolve_folder(written, self.base)
        except UserError as exc:
            return self.problem(where, PydanticCustomError("asset_path", "{message}", {"message": exc.message}),
                                written)
        entries = sorted(folder.iterdir())
        faces = {}
        for face in SKY_FACES:
            found = [p for p in entries if p.stem.lower() == face and p.suffix.lower() in IMAGE_SUFFIXES]
            if not found:
                return self.problem(where, PydanticCustomError(
                    "skybox_face", "skybox folder {value} has no {face} image ({kinds})",
                    {"value": written, "face": face, "kinds": " ".join(IMAGE_SUFFIXES)}), written)
            faces[face] = str(found[0])
        return faces

    def problem(self, where: tuple, error: PydanticCustomError, value) -> None:
        """Record ``error`` at the key path ``where``; returns None, what the check yields."""
        self.problems.append({"type": error, "loc": where, "input": value})
        return None


def _changed(new: dict, old: dict) -> bool:
    return any(new[name] is not value for name, value in old.items())
