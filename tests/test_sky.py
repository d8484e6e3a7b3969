"""The sky behind the image: drawn by a pass into a single-sampled target, added behind
the samples by the resolve with MSAA (rendering/passes/sky.py). Both ways must show the
same picture: an opaque surface hides the sky whatever alpha its texture holds, a
transparent one shows it through, and the sky fills the rest."""
from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import scenerender
from scenerender.rendering import features

# one colour per face, so a wrong direction shows as a wrong colour
FACES = {"posx": (200, 60, 40), "negx": (40, 200, 60), "posy": (60, 90, 220),
         "negy": (220, 200, 40), "posz": (150, 150, 230), "negz": (230, 120, 200)}


def _scene(tmp_path) -> scenerender.Scene:
    sky = tmp_path / "sky"
    sky.mkdir()
    for face, color in FACES.items():
        Image.new("RGB", (8, 8), color).save(sky / f"{face}.png")
    # a diffuse map whose alpha is a quarter: the material stays opaque (no opacity below 1)
    Image.new("RGBA", (4, 4), (230, 230, 230, 64)).save(tmp_path / "see_through.png")
    return scenerender.Scene.from_dict({
        "render": {"size": [96, 72], "skybox": "sky", "background": [1, 0, 0]},
        "output": {"frames": 1},
        "camera": {"position": [-1, 0.5, 3], "target": [1, 0.8, -1], "fov": 90},
        "lights": [{"type": "directional", "direction": [-0.3, -1, -0.5]}, {"type": "ambient", "color": [0.3, 0.3, 0.3]}],
        "materials": {"textured": {"diffuse_map": "see_through.png"},
                      "glass": {"diffuse": [0.2, 0.4, 1.0], "opacity": 0.4}},
        "objects": [
            {"mesh": {"primitive": "box", "size": 1.5}, "material": "textured", "position": [-0.6, 0.2, 0]},
            {"mesh": {"primitive": "plane", "size": 2.0}, "material": "glass", "position": [1.4, 1.4, -1.2],
             "rotation": [90, 0, 45]},
        ],
    }, base_dir=tmp_path)


def _render(gl, scene, samples: int) -> np.ndarray:
    with scenerender.Renderer(scene, samples=samples, gl=gl) as renderer:
        assert renderer.samples == samples
        return renderer.render(0).pixels.astype(int)


def _disagreement(gl, scene) -> tuple[float, float]:
    """Mean level difference between the MSAA and single-sampled pictures, and the share
    of pixels more than 3 levels apart (anti-aliased edges differ, nothing else should)."""
    difference = np.abs(_render(gl, scene, 4) - _render(gl, scene, 1)).max(axis=2)
    return float(difference.mean()), float((difference > 3).mean())


@pytest.mark.gl
def test_msaa_resolve_shows_the_same_sky_as_the_single_sampled_pass(gl, tmp_path):
    scene = _scene(tmp_path)
    multisampled, single = _render(gl, scene, 4), _render(gl, scene, 1)
    # the sky is there in both, never the background
    corner = multisampled[2, 2]
    assert tuple(corner) != (255, 0, 0) and np.abs(corner - single[2, 2]).max() <= 1
    mean, share = _disagreement(gl, scene)
    assert mean < 1.0 and share < 0.04, (mean, share)


@pytest.mark.gl
def test_an_opaque_surface_whose_texture_alpha_is_low_still_hides_the_sky(gl, tmp_path, monkeypatch):
    """The regression the comparison catches: opaque surfaces writing their texture's
    alpha (a quarter here) let the resolve add the sky through them."""
    scene = _scene(tmp_path)
    assert _disagreement(gl, scene)[1] < 0.04
    real = features.material_defines
    monkeypatch.setattr(features, "material_defines",
                        lambda material, *model: {**real(material, *model), "TRANSPARENT": True})
    (tmp_path / "again").mkdir()
    scene = _scene(tmp_path / "again")
    mean, share = _disagreement(gl, scene)
    assert share > 0.08, (mean, share)
