"""Checks of a scene as a whole: that there is a scene at all, and that it stays within the
run's ``Limits`` (objects, instances, frames, image size, the environment's prefilter).

``check_document`` runs on the raw data before validation, so that a document with a
million objects is refused before a million objects are validated; ``check_scene`` runs on
the validated model, where frame counts and sizes are known (``--set`` applied).
"""
from __future__ import annotations

from scenerender.errors import UserError
from scenerender.limits import Limits
from scenerender.scene.describe import describe
from scenerender.scene.model.lights import prefilter_lookups
from scenerender.scene.messages import format_key
from scenerender.scene.yaml_source import SourceMap

_TOP_KEYS = "render, output, camera, lights, materials, objects"


def check_document(data, source: SourceMap, limits: Limits) -> dict:
    """The scene's top-level mapping; raises UserError for an empty document, a document that
    is not a mapping, or more objects than ``limits.objects``."""
    if data is None:
        raise UserError("the scene is empty (a scene that draws nothing says so with 'objects: []')",
                        source.locate(()))
    if not isinstance(data, dict):
        raise UserError(f"expected a mapping of scene keys ({_TOP_KEYS}), got {describe(data)}", source.locate(()))
    objects = data.get("objects")
    if isinstance(objects, list):
        _check(limits, "objects", len(objects), "the number of objects", ("objects",), source)
    return data


def check_scene(spec, source: SourceMap, limits: Limits) -> None:
    """Frames, image size, instances and the environment light's prefilter work of the
    validated ``SceneSpec`` against ``limits``."""
    output = spec.output
    frames_key = ("output", "frames") if output.frames is not None else ("output", "duration")
    _check(limits, "frames", output.frame_count, "the number of frames", frames_key, source)
    width, height = spec.render.size
    _check(limits, "output_pixels", width * height, f"the pixel count of {width}x{height}", ("render", "size"), source)
    total = 0
    for index, obj in enumerate(spec.objects):
        total += _instance_count(obj.instances)
        _check(limits, "instances", total, "the number of instances", ("objects", index, "instances"), source)
    for index, light in enumerate(spec.lights or ()):
        if light.type == "environment":
            lookups = prefilter_lookups(light.prefilter_size, light.samples)
            _check(limits, "prefilter_lookups", lookups,
                   f"the prefilter's count of texture lookups at {light.prefilter_size} px and {light.samples} samples",
                   ("lights", index, "samples"), source)


def _instance_count(instances) -> int:
    if instances is None:
        return 1
    if isinstance(instances, list):
        return len(instances)
    return instances.random.count


def _check(limits: Limits, name: str, value: int, what: str, path: tuple, source: SourceMap) -> None:
    try:
        limits.check(name, value, what)
    except UserError as exc:
        raise UserError(exc.message, source.locate(path), format_key(path)) from None
