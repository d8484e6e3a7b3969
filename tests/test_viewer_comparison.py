"""The pure parts of benchmarks/viewer/ (scenerender beside the Khronos glTF Sample Viewer):
the decoding of the viewer's 1/2.2 canvas, the differences and per-sphere ratios, the
side-by-side picture, the table, and the models' files as scenerender reads them. The
browser and the npm package are not needed (the comparison itself is not run here)."""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

import scenerender

VIEWER = Path(__file__).resolve().parent.parent / "benchmarks" / "viewer"


def viewer_module(name: str):
    """benchmarks/viewer/<name>.py as a module (the folder is not a package)."""
    sys.path.insert(0, str(VIEWER))
    spec = importlib.util.spec_from_file_location(f"viewer_{name}", VIEWER / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


image_diff = viewer_module("image_diff")
models = viewer_module("models")


def two_spheres(width: int = 40, height: int = 20, level: float = 0.5) -> np.ndarray:
    """(H, W, 3) linear: two grey discs on black, one in each half."""
    y, x = np.mgrid[0:height, 0:width]
    image = np.zeros((height, width, 3))
    for centre in (width // 4, 3 * width // 4):
        image[(x - centre) ** 2 + (y - height // 2) ** 2 < (height // 3) ** 2] = level
    return image


def test_the_viewers_canvas_decodes_to_the_linear_light_it_encoded():
    levels = np.arange(256, dtype=np.uint8).reshape(16, 16, 1).repeat(3, axis=2)
    assert np.array_equal(image_diff.linear_to_gamma8(image_diff.gamma_to_linear(levels)), levels)
    # pow(x, 1 / 2.2), not the piecewise sRGB curve: 0.5 linear is 186, where sRGB gives 188
    assert image_diff.linear_to_gamma8(np.full((1, 1, 3), 0.5))[0, 0, 0] == 186


def test_identical_renders_differ_by_nothing():
    image = two_spheres()
    d = image_diff.difference(image, image.copy(), [(0, 20), (20, 40)])
    assert (d.linear, d.surface, d.levels) == (0.0, 0.0, 0.0)
    assert d.light_ratio == pytest.approx(1.0) and d.sphere_ratios == pytest.approx((1.0, 1.0))


def test_a_sphere_brighter_by_ten_percent_shows_in_its_column_alone():
    viewer = two_spheres()
    ours = viewer.copy()
    ours[:, 20:] *= 1.1
    d = image_diff.difference(viewer, ours, [(0, 20), (20, 40)])
    assert d.sphere_ratios == pytest.approx((1.0, 1.1))
    lit = viewer[..., 0] > 0
    # mean |0.05| over the right disc's pixels and channels, over the whole image
    assert d.linear == pytest.approx(100.0 * 0.05 * lit[:, 20:].sum() / lit.size)
    assert d.surface == pytest.approx(100.0 * 0.05 * lit[:, 20:].sum() / lit.sum())
    assert d.light_ratio == pytest.approx(1.05)


def test_clipped_and_dark_pixels_do_not_count_in_a_spheres_ratio():
    viewer = two_spheres(level=0.99)  # above RATIO_RANGE's top: clipped white in the 8-bit output
    d = image_diff.difference(viewer, viewer * 0.5, [(0, 20), (20, 40)])
    assert np.isnan(d.sphere_ratios).all()
    dark = two_spheres(level=0.01)
    assert np.isnan(image_diff.column_ratios(dark, dark, [(0, 40)])).all()


def test_images_of_different_shapes_are_refused():
    with pytest.raises(ValueError, match="differ in shape"):
        image_diff.difference(np.zeros((4, 4, 3)), np.zeros((4, 5, 3)))


def test_the_side_by_side_picture_shows_both_and_four_times_their_difference():
    viewer = two_spheres()
    ours = viewer.copy()
    ours[:, 20:] = np.where(ours[:, 20:] > 0, 0.6, 0.0)
    v8, o8 = image_diff.linear_to_gamma8(viewer), image_diff.linear_to_gamma8(ours)
    picture = image_diff.side_by_side(v8, o8, viewer, ours, gap=2)
    assert picture.shape == (20, 3 * 40 + 4, 3)
    assert np.array_equal(picture[:, :40], v8) and np.array_equal(picture[:, 42:82], o8)
    assert (picture[:, 40:42] == 255).all()
    difference = picture[:, 84:]
    assert difference[:, :20].max() == 0
    assert difference[10, 30, 0] == min(255, 4 * (int(o8[10, 30, 0]) - int(v8[10, 30, 0])))


def test_the_table_has_a_row_per_model_with_its_numbers():
    d = image_diff.Difference(linear=0.0612, surface=0.28, levels=0.171, light_ratio=1.0144, sphere_ratios=(1.0, 0.94))
    table = image_diff.markdown_table([("sheen", "no sheen, white", d)])
    assert table.splitlines()[2] == "| sheen | no sheen, white | 0.06 | 0.28 | 0.17 | 1.014 | 1.000 0.940 |"
    assert '"sphere_ratios": [\n        1.0,\n        0.94\n      ]' in image_diff.json_table(
        [("sheen", "no sheen, white", d)], {"size": [400, 200]})


def test_each_sphere_lies_inside_its_own_column():
    columns = models.sphere_columns(400)
    assert columns[0][0] == 0 and columns[-1][1] == 400
    half_width = models.CAMERA_Z * np.tan(models.YFOV / 2.0) * models.ASPECT
    pixels_per_metre = 400 / (2.0 * half_width)
    for (x0, x1), x in zip(columns, models.SPHERE_X):
        left = (x - models.RADIUS + half_width) * pixels_per_metre
        right = (x + models.RADIUS + half_width) * pixels_per_metre
        assert x0 <= left and right <= x1


@pytest.mark.parametrize("model", [m for m in models.MODELS if m.name in ("clearcoat", "sheen")], ids=lambda m: m.name)
def test_a_models_file_is_a_scene_with_its_camera_and_three_lights(tmp_path, model):
    path = models.write_model(model, tmp_path / f"{model.name}.glb")
    scene = scenerender.load(path)
    assert scene.size == (960, 480)  # the camera's aspectRatio 2, rendered as it stands
    assert not scene.warnings  # every extension of the file read
    assert len(scene.world.lights) == 3
