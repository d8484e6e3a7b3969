"""A glTF file rendered as it stands (``scenerender render model.glb``): the scene a viewer
would make of it, written as the scene format's keys so that everything after (``--set``,
validation, the world) treats it as any scene.

- the file is the one object, its materials its own;
- its lights light it (``lights: true``); a file without lights gets the default rig
  (a headlight that follows the camera, and a weak ambient), as a scene without ``lights``;
- its first camera in the default scene's node order is the view (``camera: {from, name}``),
  the image shaped as its aspectRatio (480 pixels high); without one the default camera
  frames its bounds;
- its first animation clip plays once over its length at the default frame rate; without
  clips, one frame.
"""
from __future__ import annotations

from pathlib import Path

from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.mesh.gltf import GltfProblem
from scenerender.mesh.gltf_scene import file_cameras, file_lights
from scenerender.mesh.loader import read_gltf_clips
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.loading import LoadedScene, load_scene, load_scene_mapping

MODEL_SUFFIXES = (".glb", ".gltf")
# the image height of a model's own camera with an aspectRatio (render.size's default height)
_IMAGE_HEIGHT = 480


def is_model_file(path) -> bool:
    """Whether ``path`` names a glTF file (rendered as the whole scene) rather than a scene."""
    return Path(path).suffix.lower() in MODEL_SUFFIXES


def load_scene_or_model(path, overrides=(), limits=None, asset_roots=()) -> LoadedScene:
    """``load_scene`` for a scene file; for a glTF file, the scene ``model_scene_data`` makes
    of it. Raises UserError (exit 2) naming the file where it is unusable."""
    if not is_model_file(path):
        return load_scene(path, overrides, limits=limits, asset_roots=asset_roots)
    path = Path(path).resolve()
    data = model_scene_data(path, AssetPolicy(path.parent, asset_roots))
    return load_scene_mapping(data, path, f"{display_path(path)} (as a scene)", overrides, limits, asset_roots)


def model_scene_data(path: Path, assets: AssetPolicy) -> dict:
    """The scene mapping of the glTF file ``path`` (see the module docstring)."""
    header, clips, _ = read_gltf_clips(path, assets)
    try:
        cameras, lights = file_cameras(header), file_lights(header)
    except GltfProblem as exc:
        raise UserError(f"cannot read its lights and cameras: {exc}", SourceLocation(display_path(path))) from None
    model = {"name": path.stem, "mesh": path.name}
    if lights:
        model["lights"] = True
    data: dict = {"render": {"shading": "pbr"}, "objects": [model]}
    if cameras:
        data["camera"] = {"from": path.stem, "name": cameras[0].name}
        aspect = cameras[0].aspect or (cameras[0].xmag / cameras[0].ymag if cameras[0].orthographic else None)
        if aspect is not None:
            width = max(16, 2 * round(_IMAGE_HEIGHT * aspect / 2))
            data["render"]["size"] = [min(width, 16384), _IMAGE_HEIGHT]
    if clips and clips[0].duration > 0.0:
        model["animation"] = {"clip": 0, "loop": False}
        data["output"] = {"duration": clips[0].duration}
    return data
