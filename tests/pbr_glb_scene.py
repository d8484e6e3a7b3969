"""The scene the pbr model's glTF tests share (the layers, their textures, anisotropy,
iridescence, specular-glossiness): the GLB the test writes as model.glb, at the origin,
seen from 4 m by a camera of 40 degrees, lit by a point light beside the camera and a dim
ambient light, on black."""
from __future__ import annotations

import scenerender

GLB_SCENE = """
render: {{size: [{width}, {height}], samples: 4, shading: pbr, background: [0, 0, 0]}}
camera: {{position: [0, 0, 4], target: [0, 0, 0], fov: 40}}
lights:
  - {{type: point, position: [0.6, 0.8, 4], intensity: 16, attenuation: [0, 0, 1]}}
  - {{type: ambient, color: [{ambient}, {ambient}, {ambient}]}}
objects:
  - mesh: model.glb
"""


def glb_scene(width: int = 96, height: int = 72, ambient: float = 0.15) -> str:
    """The scene's YAML text at ``width`` x ``height`` with grey ambient light ``ambient``."""
    return GLB_SCENE.format(width=width, height=height, ambient=ambient)


def render_glb(gl, folder, text: str | None = None):
    """(the loaded Scene, its frame 0 with linear values) of ``text`` (glb_scene() unset),
    its model.glb read from ``folder``."""
    loaded = scenerender.Scene.from_yaml(text if text is not None else glb_scene(), folder)
    with scenerender.Renderer(loaded, gl=gl, want_linear=True) as renderer:
        return loaded, renderer.render(0)
