"""Decode every image a world uses before anything is drawn, so that a scene which builds
also renders: textures an MTL names degrade to the placeholder with one warning per file,
images the scene names (material maps, skybox faces) are errors at their key.

No GL: the decoded pixels stay in the world's ``ImageStore`` for the GPU upload.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

from scenerender.errors import Warnings, display_path
from scenerender.mesh.capped import CappedWarnings
from scenerender.scene.image_files import ImageError
from scenerender.scene.messages import single_error
from scenerender.scene.model.render import SKY_FACES
from scenerender.world.images import ImageStore


def check_material_textures(objects: list, scene, images: ImageStore, warnings: Warnings) -> None:
    """Decode each texture of each object's materials once.

    A texture an MTL file named that cannot be decoded is replaced, in every material using
    it, by the placeholder (``TextureSource.path = None``), with one warning per file at
    the MTL line. One the scene named raises the UserError at that scene key.
    """
    failed: dict[Path, ImageError] = {}
    capped = CappedWarnings(warnings, "textures")  # a few lines, however many files fail
    for obj in objects:
        for material in obj.materials:
            for key, source in list(material.maps.items()):
                if source.path is None:
                    continue
                error = failed.get(source.path) or _decode(source.path, scene, images, source.embedded)
                if error is None:
                    continue
                if source.mtl_location is None:
                    raise single_error(f"{display_path(source.path)}: {error.reason}", source.scene_key or (),
                                       scene.source)
                if source.path not in failed:
                    capped.warn(f"texture {display_path(source.path)}: {error.reason}; "
                                "a placeholder is drawn instead", source.mtl_location)
                failed[source.path] = error
                material.maps[key] = dataclasses.replace(source, path=None)
    capped.finish()


def check_skybox(scene, images: ImageStore) -> None:
    """Decode the six skybox faces; a face that cannot be decoded is an error at its key.
    (Square, equal-sized faces are checked from the headers when the scene is validated.)"""
    faces = scene.spec.render.skybox
    if faces is None:
        return
    render_data = (scene.data or {}).get("render") if isinstance(scene.data, dict) else None
    written_per_face = isinstance(render_data, dict) and isinstance(render_data.get("skybox"), dict)
    for face in SKY_FACES:
        path = getattr(faces, face)
        error = _decode(path, scene, images)
        if error is not None:
            key = ("render", "skybox", face) if written_per_face else ("render", "skybox")
            raise single_error(f"{face} face {display_path(path)}: {error.reason}", key, scene.source)


def _decode(path: Path, scene, images: ImageStore, embedded: bool = False) -> ImageError | None:
    """Decode ``path`` into ``images``; the ImageError instead of raising it. The file
    counts as read either way (an ``embedded`` image is part of its mesh file, read already)."""
    if not embedded:
        scene.assets.record(Path(path))
    try:
        images.pixels(path)
    except ImageError as exc:
        return exc
    return None
