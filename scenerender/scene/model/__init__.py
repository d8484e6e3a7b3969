"""The scene format as validated models, one module per section; docs/scene-format.md and
``scenerender schema`` are generated from them.

    render.py     render:     size, sampling, shading, sky, fog, ambient occlusion, shadows
    output.py     output:     frames, fps, format, file names
    camera.py     camera:
    lights.py     lights:     directional, point, spot and ambient lights
    materials.py  materials:  (and an object's inline material and overrides)
    meshes.py     an object's mesh: a file or a built-in primitive
    objects.py    objects:    placement, material, instances
    scene.py      the whole file: ``SceneSpec``
    unions.py, paths.py       shared shapes: unions chosen by a key, paths as written

Every mapping rejects unknown keys (``scene/strict.py``); every animatable value validates to
a ``scenerender.animation.Track`` (``scene/values.py``). Validation opens no file: a path is
kept as the scene wrote it, and ``scene/file_checks.py`` looks the files up afterwards.
"""
