"""The white furnace the pbr layers' tests share: a sphere of one material, lit by uniform
white ambient light in a white surround, drawn by the reference both ways. What arrives is
1, so what the sphere gives back is its albedo under uniform light."""
from __future__ import annotations

import numpy as np

import scenerender
from scenerender.raytrace import render_reference

FURNACE = """
render: {{size: [64, 64], samples: 1, shading: pbr, background: [1, 1, 1]}}
camera: {{position: [0, 0, 3], target: [0, 0, 0], fov: 45}}
lights: [{{type: ambient, color: [1, 1, 1]}}]
objects:
  - mesh: {{primitive: sphere, radius: 1, segments: 64, rings: 32}}
    material: {{{material}}}
"""


def white_furnace(material: str) -> tuple[np.ndarray, np.ndarray]:
    """(integral, formula): (P, 3) float linear values of the sphere's whole pixels (P of
    them), lit through the reference's Monte Carlo integral of the per-direction BRDF (256
    directions a sample, seeded) and through the uniform-light formula the GPU uses.
    ``material``: the YAML mapping's body, ``base_color: [1, 1, 1], roughness: 0.3``."""
    loaded = scenerender.Scene.from_yaml(FURNACE.format(material=material), ".")
    integral = render_reference(loaded, 0, spp=2, ambient_samples=256)
    inside = (integral.object == 0) & ~integral.mixed
    formula = render_reference(loaded, 0, spp=2)
    return integral.linear[inside], formula.linear[inside]
