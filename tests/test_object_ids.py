"""Object ids: the render pass that names each pixel's object (rendering/passes/object_ids.py),
keeping them with the frames (sinks/object_ids.py, the manifest, references) and comparing
frames by object (compare/objects.py).

The comparing is tested without GL on synthetic frames: shaded discs on a textured
background, drawn 4x larger and averaged down (anti-aliased), their ids sampled at the
pixel centres as the render pass samples them. The rest renders small scenes."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from scenerender.cli import main
from scenerender.compare import DEFAULT_RULE, compare_images, compare_paths
from scenerender.compare.objects import CHANGED_LEVELS, IdMap, measure_objects
from scenerender.sinks.images import encode_grey16_png as encode_ids_png
from scenerender.sinks.object_ids import ids_path, names_path, read_ids, read_names

SUPERSAMPLE = 4
SIZE = (96, 72)
# name, centre x, centre y (pixels), radius (pixels), colour
DISCS = (("ball", 24.3, 30.2, 9.0, (200, 60, 40)), ("bead", 52.6, 20.4, 1.6, (20, 20, 30)),
         ("moon", 70.2, 44.7, 12.5, (90, 140, 210)), ("pebble", 40.4, 55.1, 5.2, (150, 150, 60)))


def frame(shift=(0.0, 0.0), discs=DISCS, moved=None, colours=None) -> tuple[np.ndarray, IdMap]:
    """A frame and its ids: ``discs`` shaded on a textured background, everything moved by
    ``shift`` (x, y pixels, any fraction), ``moved`` {name: (dx, dy)} moving some further,
    ``colours`` {name: colour} recolouring some."""
    width, height = SIZE
    moved, colours = moved or {}, colours or {}
    ys, xs = (np.mgrid[0:height * SUPERSAMPLE, 0:width * SUPERSAMPLE] + 0.5) / SUPERSAMPLE
    xs, ys = xs - shift[0], ys - shift[1]
    image = np.stack([60 + 40 * np.sin(xs / 3.1) * np.sin(ys / 2.3) + ys, 90 + 30 * np.cos(xs / 4.7), 120 + xs],
                     axis=2)
    pixel_ys, pixel_xs = np.mgrid[0:height, 0:width] + 0.5
    pixel_xs, pixel_ys = pixel_xs - shift[0], pixel_ys - shift[1]
    ids = np.zeros((height, width), np.uint16)
    names = {}
    for index, (name, cx, cy, radius, colour) in enumerate(discs, start=1):
        dx, dy = moved.get(name, (0.0, 0.0))
        cx, cy = cx + dx, cy + dy
        names[index] = name
        distance = np.hypot(xs - cx, ys - cy)
        inside = distance < radius
        shade = 0.55 + 0.45 * (1 - distance / radius) + 0.1 * (xs - cx) / radius  # lit from one side
        image[inside] = (np.asarray(colours.get(name, colour), np.float64) * shade[inside, None])
        ids[np.hypot(pixel_xs - cx, pixel_ys - cy) < radius] = index
    small = image.reshape(height, SUPERSAMPLE, width, SUPERSAMPLE, 3).mean(axis=(1, 3))
    return np.clip(np.round(small), 0, 255).astype(np.uint8), IdMap(ids, names)


def judge(reference, output, rule=DEFAULT_RULE):
    return compare_images("frame", reference[0], output[0], rule, object_ids=(reference[1], output[1]))


def by_name(objects, name):
    return next(score for score in objects.objects if score.name == name)


# -- comparing by object, no GL ------------------------------------------------------------

@pytest.mark.parametrize("shift", [(0.25, 0.25), (-0.125, 0.25), (0.25, -0.25)])
def test_a_sub_pixel_camera_move_passes_every_object_limit(shift):
    objects = measure_objects(*_pair(frame(), frame(shift)))
    assert objects.one_side_pixels == 0
    assert objects.shift < DEFAULT_RULE.max_object_shift / 2, objects
    assert objects.interior < DEFAULT_RULE.max_interior_change / 2, objects
    assert math.hypot(objects.common_shift[0] - shift[1], objects.common_shift[1] - shift[0]) < 0.1
    assert not DEFAULT_RULE.object_failures(objects)


def test_an_object_moved_a_pixel_against_the_frame_fails_by_name():
    reference, jittered = frame(), frame((0.25, 0.25), moved={"bead": (1.0, 0.0)})
    objects = measure_objects(*_pair(reference, jittered))
    bead = by_name(objects, "bead")
    assert bead.shift > 2 * DEFAULT_RULE.max_object_shift and objects.shift_object == "bead"
    assert all(score.shift < DEFAULT_RULE.max_object_shift for score in objects.objects if score.name != "bead")
    result = judge(reference, jittered)
    assert not result.passed and "bead moved" in result.reason


def test_an_object_only_one_side_shows_fails_as_new_or_gone():
    without_pebble = tuple(disc for disc in DISCS if disc[0] != "pebble")
    full, reduced = frame(), frame(discs=without_pebble)
    gone = judge(full, reduced)
    assert not gone.passed and gone.reason.startswith("gone: pebble on ")
    assert "gone: pebble" in gone.attribution() and gone.objects.one_side_object == "pebble"
    new = judge(reduced, full)
    assert not new.passed and "new: pebble" in new.reason
    assert by_name(new.objects, "pebble").status == "new"


def test_an_object_below_the_pixel_limit_may_vanish():
    reference, output = frame(), frame(discs=tuple(d for d in DISCS if d[0] != "bead"))
    coverage = by_name(measure_objects(*_pair(reference, output)), "bead").coverage
    rule = DEFAULT_RULE.__class__(min_object_pixels=coverage + 1)
    assert not any("bead" in failure for failure in rule.object_failures(measure_objects(*_pair(reference, output))))


def test_a_recoloured_interior_fails_and_a_one_level_offset_passes():
    reference = frame()
    brighter = frame(colours={"moon": (96, 146, 216)})  # +6 levels before shading
    objects = measure_objects(*_pair(reference, brighter))
    moon = by_name(objects, "moon")
    assert moon.interior > DEFAULT_RULE.max_interior_change and moon.interior_pixels >= 32
    reason = judge(reference, brighter).reason
    assert reason.startswith("moon interior") and "brighter" in reason
    offset = (np.clip(reference[0].astype(np.int16) + 1, 0, 255).astype(np.uint8), reference[1])
    assert measure_objects(*_pair(reference, offset)).interior < 0.1 * DEFAULT_RULE.max_interior_change
    assert judge(reference, offset).passed


def test_dither_passes():
    reference = frame()
    noise = np.random.default_rng(3).integers(-1, 2, size=reference[0].shape)
    dithered = (np.clip(reference[0].astype(np.int16) + noise, 0, 255).astype(np.uint8), reference[1])
    objects = measure_objects(*_pair(reference, dithered))
    assert objects.shift < 0.05 and objects.interior < 0.1 and judge(reference, dithered).passed


def test_the_changed_pixels_are_named_by_object():
    reference, output = frame(), frame(moved={"ball": (3.0, 0.0)}, discs=DISCS[:3])
    objects = measure_objects(*_pair(reference, output))
    text = objects.attribution()
    assert text.startswith("ball: ") and "gone: pebble" in text
    ball = by_name(objects, "ball")
    changed = np.abs(reference[0].astype(int) - output[0].astype(int)).max(axis=2) >= CHANGED_LEVELS
    on_ball = changed & ((reference[1].ids == 1) | (output[1].ids == 1))
    assert ball.changed_pixels == int(on_ball.sum())
    assert f"ball: {ball.changed_pixels} px" in judge(reference, output).summary_line()


def test_objects_are_matched_by_name_not_index():
    reference = frame()
    reordered = frame(discs=DISCS[::-1])  # the same picture, the ids numbered the other way
    assert not np.array_equal(reference[1].ids, reordered[1].ids)
    objects = measure_objects(*_pair(reference, reordered))
    assert objects.one_side_pixels == 0 and objects.shift == 0 and judge(reference, reordered).passed


def test_names_two_objects_share_are_told_apart_by_index():
    twins = (("rock", 24.3, 30.2, 9.0, (200, 60, 40)), ("rock", 70.2, 44.7, 12.5, (90, 140, 210)))
    objects = measure_objects(*_pair(frame(discs=twins), frame(discs=twins)))
    assert {score.name for score in objects.objects} == {"rock (objects[0])", "rock (objects[1])"}


def test_frames_without_ids_on_both_sides_are_judged_by_colour_alone():
    reference, output = frame(), frame(moved={"bead": (1.0, 0.0)})
    plain = compare_images("frame", reference[0], output[0])
    one_sided = compare_images("frame", reference[0], output[0], object_ids=(reference[1], None))
    assert plain.objects is None and one_sided.objects is None
    assert plain.passed == one_sided.passed and plain.reason == one_sided.reason
    assert plain.passed  # the 1-px move of a 3-px bead: no colour statistic tells it from a jitter


def _pair(reference, output):
    return reference[0], output[0], reference[1], output[1]


# -- keeping ids with the frames, no GL ---------------------------------------------------------

def test_ids_png_round_trip(tmp_path):
    ids = np.random.default_rng(1).integers(0, 65536, size=(7, 11)).astype(np.uint16)
    path = tmp_path / "ids.png"
    path.write_bytes(encode_ids_png(ids))
    assert np.array_equal(read_ids(path), ids)
    with Image.open(path) as image:
        # Pillow before 10.1 opens 16-bit grey PNGs as mode "I", later ones as "I;16"
        assert image.mode in ("I", "I;16", "I;16B") and image.size == (11, 7)
    assert read_ids(tmp_path / "missing.png") is None
    Image.new("RGB", (4, 4)).save(tmp_path / "rgb.png")
    assert read_ids(tmp_path / "rgb.png") is None  # not ids: the frame is judged by colour


def test_diff_of_folders_uses_ids_only_where_both_sides_have_them(tmp_path):
    reference, output = frame(), frame((0.25, 0.25), moved={"bead": (1.0, 0.0)})
    for side, (image, ids) in (("ref", reference), ("out", output)):
        folder = tmp_path / side
        folder.mkdir()
        for name in ("a.png", "b.png"):
            Image.fromarray(image).save(folder / name)
        ids_path(folder / "a.png").parent.mkdir()
        ids_path(folder / "a.png").write_bytes(encode_ids_png(ids.ids))
        names_path(folder).write_text(json.dumps({"format": 1, "objects": {str(k): v for k, v in ids.names.items()}}))
    assert read_names(tmp_path / "ref") == reference[1].names
    result = compare_paths(tmp_path / "ref", tmp_path / "out")
    a, b = result.frames
    assert a.objects is not None and not a.passed and "bead moved" in a.reason
    assert b.objects is None and b.passed  # no ids for b.png: judged by colour alone, as before
    assert "judged by object ids and colour: 1 of 2 frame(s); by colour alone: 1 (neither side" in result.total_line()
    assert result.to_json()["frames"][0]["objects"]["shift_object"] == "bead"


# -- the render pass ----------------------------------------------------------------------------

SCENE = """\
render: {size: [64, 48], samples: 4, background: [0.2, 0.3, 0.4]}
camera: {position: [0, 0, 6], target: [0, 0, 0], fov: 40}
output: {frames: 2}
lights:
  - {type: directional, direction: [-0.3, -1, -0.5]}
objects:
  - name: wall
    mesh: {primitive: box, size: [3, 2, 0.2]}
    position: [0, 0, -1]
    material: {diffuse: [0.8, 0.8, 0.8]}
  - name: ball
    mesh: {primitive: sphere, radius: 0.5}
    position: [-0.6, 0, 0]
    material: {diffuse: [0.8, 0.2, 0.2]}
  - mesh: {primitive: box, size: [0.6, 0.6, 0.6]}
    position: [0.8, 0, 0]
    material: {diffuse: [0.2, 0.8, 0.2], opacity: 0.4}
"""


def _pixel(x: float, y: float, z: float, size=(64, 48), fov=40.0, distance=6.0) -> tuple[int, int]:
    """(column, row) of the pixel showing world point (x, y, z) from the camera of SCENE."""
    scale = size[1] / 2 / math.tan(math.radians(fov) / 2)
    depth = distance - z
    return int(size[0] / 2 + x / depth * scale), int(size[1] / 2 - y / depth * scale)


@pytest.mark.gl
def test_the_pass_names_the_nearest_surface_at_each_pixel(gl):
    import scenerender

    scene = scenerender.Scene.from_yaml(SCENE)
    with scenerender.Renderer(scene, gl=gl, object_ids=True) as renderer:
        result = renderer.render(0)
        assert "object_ids" in renderer._renderer.compiled.pass_names
    with scenerender.Renderer(scene, gl=gl) as renderer:
        plain = renderer.render(0)
        assert "object_ids" not in renderer._renderer.compiled.pass_names + renderer._renderer.compiled.culled_names
    assert plain.object_ids is None
    assert np.array_equal(plain.pixels, result.pixels)  # the colours do not change
    ids = result.object_ids
    assert ids.dtype == np.uint16 and ids.shape == (48, 64)
    assert ids[0, 0] == 0 and ids[-1, -1] == 0  # the background
    column, row = _pixel(-0.6, 0, 0.5)
    assert ids[row, column] == 2  # the ball, in front of the wall
    column, row = _pixel(0.8, 0, 0.3)
    assert ids[row, column] == 3  # the transparent box is the nearest surface
    column, row = _pixel(0, 0.7, -0.9)
    assert ids[row, column] == 1  # the wall
    assert set(np.unique(ids)) == {0, 1, 2, 3}


def test_default_graphs_have_no_object_id_pass():
    """No GL: the graph a run compiles without ids has no trace of the pass."""
    import scenerender
    from scenerender.rendering.renderer import plan

    world = scenerender.Scene.from_yaml(SCENE).world
    for samples in (1, 4):
        compiled = plan(world, (64, 48), samples).compiled
        assert "object_ids" not in compiled.pass_names + compiled.culled_names
        assert all(name != "object_ids" for _, name, _ in compiled.resources())
        with_ids = plan(world, (64, 48), samples, object_ids=True).compiled
        assert "object_ids" in with_ids.pass_names and [r.name for r in with_ids.node("readback").reads[-2:]] == [
            "object_ids", "object_ids_behind"]


# -- render --object-ids, diff, resume, references ------------------------------------------------

@pytest.fixture
def project(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.yaml").write_text(SCENE)
    return tmp_path


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.mark.gl
def test_render_with_ids_then_diff_names_the_object(project):
    assert cli("render", "scene.yaml", "-o", "ref", "--object-ids", "-q").exit_code == 0
    ids_folder = project / "ref" / ".object_ids"
    assert sorted(p.name for p in ids_folder.iterdir()) == ["behind", "frame_0000.png", "frame_0001.png",
                                                             "objects.json"]
    assert sorted(p.name for p in (ids_folder / "behind").iterdir()) == ["frame_0000.png", "frame_0001.png"]
    names = json.loads((ids_folder / "objects.json").read_text())
    assert names["objects"] == {"1": "wall", "2": "ball", "3": "box inline at (0.8, 0, 0)"}
    assert names["scene"] == "scene.yaml"
    assert read_ids(ids_folder / "frame_0000.png").max() == 3
    moved = SCENE.replace("position: [-0.6, 0, 0]", "position: [-0.51, 0, 0]")  # about a pixel
    (project / "moved.yaml").write_text(moved)
    assert cli("render", "moved.yaml", "-o", "out", "--object-ids", "-q").exit_code == 0
    result = cli("diff", "ref", "out", "--json")
    assert result.exit_code == 1
    data = json.loads(result.output)
    frame_0 = data["frames"][0]
    assert "ball moved" in frame_0["reason"] and frame_0["objects"]["shift_object"] == "ball"
    assert frame_0["objects"]["attribution"].startswith("ball: ")
    lines = cli("diff", "ref", "out").output
    assert "by object: ball: " in lines
    # the colours alone pass the move: --max-object-shift lifts the object limit
    assert cli("diff", "ref", "out", "--max-object-shift", "5").exit_code == 0


INSERTED = """\
objects:
  - mesh: {primitive: sphere, radius: 0.25}
    position: [0.1, 0.75, 0.5]
    material: {diffuse: [0.9, 0.9, 0.2]}
"""


@pytest.mark.gl
def test_an_object_inserted_first_is_the_only_new_one(project):
    """An unnamed object inserted before the others renames none of them (the box keeps
    its name made from its mesh, material and position), so the diff blames the new one
    alone; by index the box would have been called gone and new."""
    (project / "inserted.yaml").write_text(SCENE.replace("objects:\n", INSERTED, 1))
    assert cli("render", "scene.yaml", "-o", "ref", "--object-ids", "-q").exit_code == 0
    assert cli("render", "inserted.yaml", "-o", "out", "--object-ids", "-q").exit_code == 0
    assert read_names(project / "out")[1] == "sphere inline at (0.1, 0.75, 0.5)"
    result = cli("diff", "ref", "out", "--json")
    assert result.exit_code == 1
    objects = json.loads(result.output)["frames"][0]["objects"]["objects"]
    assert {o["name"]: o["status"] for o in objects if o["status"] != "both"} == \
        {"sphere inline at (0.1, 0.75, 0.5)": "new"}
    # the wall shows through the glass box: judged on the layer behind too
    assert {o["name"] for o in objects if o["status"] == "both"} == {"wall", "ball", "box inline at (0.8, 0, 0)",
                                                                     "wall (behind glass)"}


@pytest.mark.gl
def test_a_video_with_ids_is_refused_naming_the_fix(project):
    result = cli("render", "scene.yaml", "-o", "clip.mp4", "--object-ids")
    assert result.exit_code == 2
    assert "--object-ids" in result.stderr and "image sequence" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1
    assert not (project / "clip.mp4").exists()


@pytest.mark.gl
def test_a_frame_whose_ids_are_missing_is_rendered_again(project):
    assert cli("render", "scene.yaml", "-o", "out", "--object-ids", "-q").exit_code == 0
    again = cli("render", "scene.yaml", "-o", "out", "--object-ids")
    assert "nothing to do" in again.stderr
    (project / "out" / ".object_ids" / "frame_0001.png").unlink()
    resumed = cli("render", "scene.yaml", "-o", "out", "--object-ids")
    assert "rendered 1 frame" in resumed.stderr and "1 already there" in resumed.stderr
    assert (project / "out" / ".object_ids" / "frame_0001.png").is_file()
    # asked without ids the frames are not the same run's: rendered again, the ids removed
    plain = cli("render", "scene.yaml", "-o", "out")
    assert "the --object-ids option" in plain.stderr and "rendered 2 frames" in plain.stderr
    assert not any(p.suffix == ".png" for p in (project / "out" / ".object_ids").iterdir())


@pytest.mark.gl
def test_update_references_keeps_the_ids_and_check_names_the_object(project):
    created = cli("render", "scene.yaml", "-o", "out", "--object-ids", "--check", "ref", "--update-references")
    assert created.exit_code == 0, created.stderr
    assert sorted(p.name for p in (project / "ref" / ".object_ids").iterdir()) == \
        ["behind", "frame_0000.png", "frame_0001.png", "objects.json"]
    assert sorted(p.name for p in (project / "ref" / ".object_ids" / "behind").iterdir()) == \
        ["frame_0000.png", "frame_0001.png"]
    (project / "scene.yaml").write_text(SCENE + "  - name: speck\n    mesh: {primitive: sphere, radius: 0.1}\n"
                                               "    position: [0, 0.8, 0]\n    material: {diffuse: [0.3, 0.3, 0.3]}\n")
    checked = cli("render", "scene.yaml", "-o", "out", "--object-ids", "--check", "ref")
    assert checked.exit_code == 1
    assert "new: speck" in checked.stderr


@pytest.mark.gl
def test_a_single_image_keeps_its_ids_beside_it(project):
    assert cli("render", "scene.yaml", "-o", "still.png", "--frames", "1", "--object-ids", "-q").exit_code == 0
    assert read_ids(project / ".object_ids" / "still.png").shape == (48, 64)
    assert read_names(project) == {1: "wall", 2: "ball", 3: "box inline at (0.8, 0, 0)"}
    (project / "moved.yaml").write_text(SCENE.replace("position: [-0.6, 0, 0]", "position: [-0.51, 0, 0]"))
    assert cli("render", "moved.yaml", "-o", "other/still.png", "--frames", "1", "--object-ids", "-q").exit_code == 0
    result = cli("diff", "still.png", "other/still.png")
    assert result.exit_code == 1 and "ball moved" in result.output
    again = cli("render", "scene.yaml", "-o", "still.png", "--frames", "1", "--object-ids")
    assert "nothing to do" in again.stderr


@pytest.mark.gl
def test_the_api_renders_ids_on_request():
    import scenerender

    scene = scenerender.Scene.from_yaml(SCENE)
    first, = scenerender.render(scene, frames=[0], object_ids=True)
    plain, = scenerender.render(scene, frames=[0])
    assert first.object_ids.shape == (48, 64) and plain.object_ids is None


def test_the_numpy_filters_of_the_object_diff_equal_scipy_ndimage():
    # compare/objects.py does without SciPy, so that a render does not import it (0.15 s)
    from scipy import ndimage

    from scenerender.compare.objects import bounding_boxes, square_filter

    rng = np.random.default_rng(0)
    for _ in range(10):
        for most in (6, 64, 300):  # under 64 labels by bits, past that by counts
            many = rng.integers(0, most, (37, 53)).astype(np.uint8 if most < 256 else np.int32)
            many[rng.random(many.shape) < 0.6] = 0
            boxes = bounding_boxes(many)
            found = ndimage.find_objects(many)
            assert len(boxes) == sum(box is not None for box in found)
            for index, box in enumerate(found):
                assert boxes.get(index + 1) == box
        labels = rng.integers(0, 6, (37, 53))
        labels[rng.random(labels.shape) < 0.6] = 0
        mask = labels > 3
        assert np.array_equal(square_filter(mask, 3, np.max, "constant"),
                              ndimage.binary_dilation(mask, structure=np.ones((3, 3), bool)))
        for side in (3, 7, 11):
            assert np.array_equal(square_filter(labels, side, np.min, "edge"),
                                  ndimage.minimum_filter(labels, side, mode="nearest"))
            assert np.array_equal(square_filter(labels, side, np.max, "edge"),
                                  ndimage.maximum_filter(labels, side, mode="nearest"))


@pytest.mark.parametrize("whole_frame", [False, True])
def test_the_registrations_samples_equal_those_of_whole_frame_gradients(whole_frame):
    # compare/objects.py works the gradients out at the pixels it samples above
    # WHOLE_FRAME_PIXELS (75 MB at 1080p), and over the frame in one table up to it: either
    # way the samples must be the numbers the whole-frame arrays give
    from scenerender.compare.objects import _bilinear, _Images

    rng = np.random.default_rng(3)
    for shape in ((1, 1, 3), (1, 6, 3), (5, 1, 3), (2, 2, 3), (37, 53, 3)):
        reference = rng.integers(0, 256, shape).astype(np.uint8)
        images = _Images(reference, reference, whole_frame=whole_frame)
        assert (images._table is not None) == whole_frame
        padded = np.pad(reference.astype(np.float32), ((1, 1), (1, 1), (0, 0)), mode="edge")
        down = (padded[2:, 1:-1] - padded[:-2, 1:-1]) * 0.5
        across = (padded[1:-1, 2:] - padded[1:-1, :-2]) * 0.5
        whole = np.concatenate([reference.astype(np.float32), down, across], axis=2)
        ys, xs = rng.uniform(-2, shape[0] + 1, 400), rng.uniform(-2, shape[1] + 1, 400)
        assert np.array_equal(images.sampled(ys, xs), _bilinear(whole, ys, xs))
        assert np.array_equal(images.reference_at(ys, xs), _bilinear(whole[..., :3], ys, xs))
        assert np.array_equal(images.strength, np.maximum(np.abs(down), np.abs(across)).max(axis=2))
