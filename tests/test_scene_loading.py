"""Reading, overriding and validating scene files (scenerender.scene), without GL."""
from __future__ import annotations

import re

import json
import math

import numpy as np
import pytest

from scenerender.errors import SceneErrors, UserError
from scenerender.scene.json_schema import scene_json_schema
from scenerender.scene.loading import load_scene, load_scene_text

MINIMAL = "objects: [{mesh: {primitive: box}}]\n"


def load(tmp_path, text, overrides=()):
    return load_scene_text(with_objects(text), base_dir=tmp_path, overrides=list(overrides), name="scene.yaml")


def with_objects(text: str) -> str:
    """Scenes about other sections say `objects: []` at the end (lines keep their numbers)."""
    if re.search(r"^objects:", text, re.M) or not re.search(r"^\w", text, re.M):
        return text
    return text.rstrip("\n") + "\nobjects: []\n"


def error_lines(tmp_path, text, overrides=()) -> list[str]:
    """The one-line messages a bad scene gives."""
    with pytest.raises(UserError) as info:
        load(tmp_path, text, overrides)
    err = info.value
    return err.lines() if isinstance(err, SceneErrors) else [str(err)]


def one_error(tmp_path, text, overrides=()) -> str:
    lines = error_lines(tmp_path, text, overrides)
    assert len(lines) == 1, lines
    return lines[0]


# ---------------------------------------------------------------------------------------
# defaults and the minimal scene


def test_minimal_scene_gets_contract_defaults(tmp_path):
    spec = load(tmp_path, MINIMAL).spec
    assert spec.render.size == (640, 480)
    assert spec.render.samples == 4
    assert spec.render.shading == "blinn_phong"
    assert spec.render.mode == "shaded"
    assert spec.render.output_transform == "srgb"
    assert spec.output.format == "png"
    assert spec.output.frame_count == 1
    assert spec.output.fps == 30.0
    assert spec.camera is None
    assert spec.lights is None
    assert len(spec.objects) == 1
    assert spec.objects[0].mesh.primitive == "box"


def test_object_defaults(tmp_path):
    obj = load(tmp_path, MINIMAL).spec.objects[0]
    np.testing.assert_array_equal(obj.position(0.0), [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(obj.rotation(0.0), [0.0, 0.0, 0.0])
    assert obj.visible(0.0) is True
    assert obj.cast_shadows is True
    assert obj.material is None


def test_light_defaults(tmp_path):
    spec = load(tmp_path, "lights: [{type: point}, {type: spot, position: [0, 5, 0]}]\n" + MINIMAL).spec
    point, spot = spec.lights
    np.testing.assert_array_equal(point.color(0.0), [1.0, 1.0, 1.0, 1.0])
    assert point.intensity(0.0) == 1.0
    assert point.attenuation == (1.0, 0.0, 0.0)
    assert point.shadows is False
    assert spot.attenuation == (1.0, 0.0, 0.0)
    assert spot.inner_angle(0.0) == 12.5
    assert spot.outer_angle(0.0) == 17.5


def test_empty_file_is_an_error_and_empty_objects_a_scene(tmp_path):
    for text in ("", "# only a comment\n", "---\n"):
        with pytest.raises(UserError, match="the scene is empty"):
            load(tmp_path, text)
    spec = load(tmp_path, "objects: []\n").spec
    assert spec.objects == []
    assert spec.render.size == (640, 480)


def test_a_scene_without_objects_must_say_so(tmp_path):
    with pytest.raises(UserError, match=r"missing required key 'objects' .*`objects: \[\]`"):
        load_scene_text("render: {size: [32, 24]}\n", base_dir=tmp_path)


def test_load_scene_from_file(tmp_path):
    path = tmp_path / "shot.yaml"
    path.write_text("render: {size: [32, 24]}\n" + MINIMAL, encoding="utf-8")
    loaded = load_scene(path)
    assert loaded.spec.render.size == (32, 24)
    assert loaded.name == "shot"
    assert loaded.base_dir == tmp_path.resolve()


def test_load_scene_missing_file(tmp_path):
    with pytest.raises(UserError) as info:
        load_scene(tmp_path / "nope.yaml")
    assert "scene file not found" in str(info.value)
    assert "nope.yaml" in str(info.value)


def test_top_level_must_be_a_mapping(tmp_path):
    line = one_error(tmp_path, "- a\n- b\n")
    assert line.startswith("scene.yaml:1:1:")
    assert "expected a mapping" in line


def test_yaml_syntax_error_has_a_line(tmp_path):
    line = one_error(tmp_path, "render:\n  size: [1, 2\n")
    assert line.startswith("scene.yaml:3:")
    assert "YAML syntax error" in line


# ---------------------------------------------------------------------------------------
# YAML 1.2 scalars and numbers


def test_exponent_numbers_are_floats(tmp_path):
    spec = load(tmp_path, "render:\n  fog: {density: 1e6}\noutput:\n  fps: 3e-05\n" + MINIMAL).spec
    assert spec.render.fog.density(0.0) == 1e6
    assert spec.output.fps == pytest.approx(3e-05)


def test_yes_is_text_not_a_bool(tmp_path):
    line = one_error(tmp_path, "objects:\n  - mesh: {primitive: box}\n    visible: yes\n")
    assert line.startswith("scene.yaml:3:")
    assert "objects[0].visible" in line
    assert "expected true or false, got 'yes'" in line


def test_true_and_false_are_bools(tmp_path):
    spec = load(tmp_path, "objects:\n  - mesh: {primitive: box}\n    visible: false\n    cast_shadows: False\n").spec
    assert spec.objects[0].visible(0.0) is False
    assert spec.objects[0].cast_shadows is False


def test_integers_accepted_where_floats_are(tmp_path):
    spec = load(tmp_path, "render: {background: [1, 1, 1], gamma: 2}\noutput: {fps: 24, duration: 1}\n"
                          "objects:\n  - mesh: {primitive: sphere, radius: 2}\n    scale: 3\n").spec
    np.testing.assert_array_equal(spec.render.background(0.0), [1.0, 1.0, 1.0, 1.0])
    assert spec.render.gamma == 2.0 and isinstance(spec.render.gamma, float)
    assert spec.objects[0].mesh.radius == 2.0
    np.testing.assert_array_equal(spec.objects[0].scale(0.0), [3.0])
    assert spec.output.frame_count == 24


def test_whole_float_accepted_for_integer_key(tmp_path):
    spec = load(tmp_path, "render: {samples: 8.0}\n" + MINIMAL).spec
    assert spec.render.samples == 8 and isinstance(spec.render.samples, int)


def test_fractional_number_rejected_for_integer_key(tmp_path):
    line = one_error(tmp_path, "render: {samples: 4.5}\n" + MINIMAL)
    assert "render.samples: expected a whole number, got 4.5" in line


@pytest.mark.parametrize("text, key, shown", [
    ("render:\n  fog: {density: .inf}\n", "render.fog.density", "inf"),
    ("output:\n  fps: .NaN\n", "output.fps", "nan"),
    ("render:\n  samples: -.inf\n", "render.samples", "-inf"),
    ("render:\n  background: [.nan, 0, 0]\n", "render.background", "nan"),
    ("objects:\n  - mesh: {primitive: box}\n    position: [0, .inf, 0]\n", "objects[0].position", "inf"),
])
def test_inf_and_nan_rejected(tmp_path, text, key, shown):
    line = one_error(tmp_path, text)
    assert f"{key}:" in line
    assert f"must be a finite number, got {shown}" in line


def test_quoted_number_is_text(tmp_path):
    line = one_error(tmp_path, "render: {samples: '8'}\n" + MINIMAL)
    assert "render.samples: expected a whole number, got '8'" in line


def test_explicit_str_tag_keeps_text(tmp_path):
    spec = load(tmp_path, "objects:\n  - name: !!str 123\n    mesh: {primitive: box}\n").spec
    assert spec.objects[0].name == "123"


# ---------------------------------------------------------------------------------------
# unknown keys, duplicate keys, typos


def test_unknown_key_suggests_and_locates(tmp_path):
    text = "render:\n  size: [10, 10]\n  shadng: phong\n" + MINIMAL
    with pytest.raises(SceneErrors) as info:
        load(tmp_path, text)
    err = info.value
    assert err.lines() == ["scene.yaml:3:3: render.shadng: unknown key 'shadng' (did you mean 'shading'?)"]
    assert str(err).startswith("scene.yaml:3:3: render.shadng:")
    assert err.location.line == 3 and err.location.column == 3
    assert err.key == "render.shadng"


def test_scene_errors_str_is_the_single_line(tmp_path):
    with pytest.raises(SceneErrors) as info:
        load(tmp_path, "render:\n  size: [10, 10]\n  shadng: phong\n" + MINIMAL)
    err = info.value
    assert str(err) == err.lines()[0]
    assert err.message == "unknown key 'shadng' (did you mean 'shading'?)"


def test_unknown_top_level_key(tmp_path):
    line = one_error(tmp_path, "objets: []\n")
    assert line == "scene.yaml:1:1: objets: unknown key 'objets' (did you mean 'objects'?)"


def test_unknown_key_without_close_match_lists_known_keys(tmp_path):
    line = one_error(tmp_path, "output: {zzzzzz: 1}\n")
    assert "unknown key 'zzzzzz'" in line
    assert "known keys:" in line and "fps" in line


def test_unknown_key_in_light_and_primitive(tmp_path):
    lines = error_lines(tmp_path, "lights:\n  - type: spot\n    position: [0, 1, 0]\n    inner_angel: 3\n"
                                  "objects:\n  - mesh: {primitive: box, sise: 2}\n")
    assert lines == [
        "scene.yaml:4:5: lights[0].inner_angel: unknown key 'inner_angel' (did you mean 'inner_angle'?)",
        "scene.yaml:6:28: objects[0].mesh.sise: unknown key 'sise' (did you mean 'size'?)",
    ]


def test_every_unknown_key_of_a_mapping_is_reported(tmp_path):
    lines = error_lines(tmp_path, "render: {size: [64, 48], sampels: 3, shadng: x, modd: y}\n")
    assert lines == [
        "scene.yaml:1:26: render.sampels: unknown key 'sampels' (did you mean 'samples'?)",
        "scene.yaml:1:38: render.shadng: unknown key 'shadng' (did you mean 'shading'?)",
        "scene.yaml:1:49: render.modd: unknown key 'modd' (did you mean 'mode'?)",
    ]


def test_every_unknown_key_of_a_track_and_of_a_track_key_is_reported(tmp_path):
    track = error_lines(tmp_path, "camera:\n  position: {keys: [[0, [0, 1, 3]]], loops: true, interpolatoin: step}\n")
    assert track == [
        "scene.yaml:2:38: camera.position.loops: unknown key 'loops' (did you mean 'loop'?)",
        "scene.yaml:2:51: camera.position.interpolatoin: unknown key 'interpolatoin' (did you mean 'interpolation'?)",
    ]
    key = error_lines(tmp_path, "camera:\n  position: {keys: [{t: 0, valeu: [0, 1, 3], interp: step}]}\n")
    assert key == [
        "scene.yaml:2:28: camera.position.keys[0].valeu: unknown key 'valeu' (did you mean 'value'?)",
        "scene.yaml:2:46: camera.position.keys[0].interp: unknown key 'interp' (did you mean 'interpolation'?)",
    ]


def test_the_same_unknown_keys_in_every_object_collapse(tmp_path):
    text = "objects:\n" + "  - {mesh: {primitive: box}, positon: [0, 0, 0], scal: 2}\n" * 3
    assert error_lines(tmp_path, text) == [
        "scene.yaml:2:30: objects[0].positon: unknown key 'positon' (did you mean 'position'?) (and 2 more like it)",
        "scene.yaml:2:50: objects[0].scal: unknown key 'scal' (did you mean 'scale'?) (and 2 more like it)",
    ]


def test_thousands_of_unknown_keys_stay_within_the_error_lines(tmp_path):
    text = "render:\n" + "".join(f"  key{i}: 1\n" for i in range(2000))
    lines = error_lines(tmp_path, text)
    assert len(lines) == SceneErrors.MAX_LINES
    assert lines[0].startswith("scene.yaml:2:3: render.key0: unknown key 'key0' (known keys: size, samples,")
    assert lines[-1] == "... and 1991 more problems"


def test_duplicate_key_names_both_lines(tmp_path):
    with pytest.raises(UserError) as info:
        load(tmp_path, "render:\n  samples: 4\n  samples: 8\n" + MINIMAL)
    text = str(info.value)
    assert text.startswith("scene.yaml:3:3:")
    assert "duplicate key 'samples'" in text
    assert "line 2" in text


def test_duplicate_key_inside_list_item(tmp_path):
    with pytest.raises(UserError) as info:
        load(tmp_path, "objects:\n  - mesh: {primitive: box}\n    mesh: {primitive: cone}\n")
    assert str(info.value) == "scene.yaml:3:5: duplicate key 'mesh' (first given on line 2)"


def test_same_key_in_different_mappings_is_fine(tmp_path):
    spec = load(tmp_path, "objects:\n  - {name: a, mesh: {primitive: box}}\n  - {name: b, mesh: {primitive: box}}\n").spec
    assert [o.name for o in spec.objects] == ["a", "b"]


def test_merge_key_fills_missing_keys(tmp_path):
    text = ("materials:\n  base: &b {diffuse: [1, 0, 0], shininess: 10}\n"
            "  red:\n    shininess: 50\n    <<: *b\n" + MINIMAL)
    red = load(tmp_path, text).spec.materials["red"]
    assert red.shininess(0.0) == 50.0
    np.testing.assert_array_equal(red.diffuse(0.0), [1.0, 0.0, 0.0, 1.0])


def test_key_after_merge_overrides_merged_value(tmp_path):
    text = ("materials:\n  base: &b {diffuse: [1, 0, 0], shininess: 10}\n"
            "  red:\n    <<: *b\n    shininess: 50\n" + MINIMAL)
    red = load(tmp_path, text).spec.materials["red"]
    assert red.shininess(0.0) == 50.0


@pytest.mark.parametrize("text, expected", [
    ("lights: [{type: pont}]\n", "lights[0].type: unknown type 'pont' (did you mean 'point'?)"),
    ("lights: [{type: spott, position: [0, 1, 0]}]\n", "(did you mean 'spot'?)"),
    ("objects: [{mesh: {primitive: bx}}]\n", "objects[0].mesh.primitive: unknown primitive 'bx' (did you mean 'box'?)"),
    ("objects: [{mesh: {primitive: spehre}}]\n", "(did you mean 'sphere'?)"),
    ("render: {shading: blin_phong}\n", "render.shading: expected one of phong, blinn_phong, pbr, unlit, "
                                        "got 'blin_phong' (did you mean 'blinn_phong'?)"),
    ("render: {mode: wirefame}\n", "(did you mean 'wireframe'?)"),
    ("objects:\n - mesh: {primitive: box}\n   position: {keys: [[0, [0, 0, 0]], [1, [1, 1, 1]]], "
     "interpolation: cosin}\n", "objects[0].position.interpolation: unknown interpolation 'cosin' "
                                "(did you mean 'cosine'?)"),
    ("objects:\n - mesh: {primitive: box}\n   position: {keys: [{t: 0, value: [0, 0, 0], "
     "interpolation: lienar}, [1, [1, 1, 1]]]}\n", "(did you mean 'linear'?)"),
])
def test_typos_give_suggestions(tmp_path, text, expected):
    assert expected in one_error(tmp_path, text)


def test_light_without_type(tmp_path):
    line = one_error(tmp_path, "lights:\n  - color: [1, 1, 1]\n")
    assert line.startswith("scene.yaml:2:")
    assert "lights[0]: a light needs 'type'" in line


def test_missing_mesh_names_the_object(tmp_path):
    line = one_error(tmp_path, "objects:\n  - mesh: {primitive: box}\n  - name: teapot\n    position: [0, 1, 0]\n")
    assert line == "scene.yaml:3:5: objects[1]: missing required key 'mesh'"


def test_several_errors_one_line_each(tmp_path):
    with pytest.raises(SceneErrors) as info:
        load(tmp_path, "objects:\n  - {mesh: {primitive: box}}\n  - {mesh: {primitive: sphere}, rotation: [1, 2]}\n"
                       "  - {mesh: {primitive: cone}, visible: 3}\n")
    lines = info.value.lines()
    assert lines == [
        "scene.yaml:3:33: objects[1].rotation: expected a list of 3 numbers, got [1, 2]",
        "scene.yaml:4:31: objects[2].visible: expected true or false, got 3",
    ]
    assert all("\n" not in line for line in lines)


def test_bad_values_are_shown_as_written(tmp_path):
    """Short lists show their items, booleans their YAML spelling."""
    with pytest.raises(SceneErrors) as info:
        load(tmp_path, "render: {size: [100000, 100000], wireframe_overlay: 2}\nobjects:\n"
                       "  - {mesh: {primitive: box}, visible: [true, 1]}\n")
    lines = info.value.lines()
    assert "render.size: width and height must be 1..16384, got [100000, 100000]" in lines[0]
    assert any(line.endswith("got [true, 1]") for line in lines), lines


def test_error_line_for_a_folded_value_has_no_newline(tmp_path):
    line = one_error(tmp_path, "objects:\n  - mesh: {primitive: box}\n    scale: 'two\n      words'\n")
    assert line == "scene.yaml:3:5: objects[0].scale: expected a number, got 'two words'"


def test_missing_file_error_with_newline_in_path_stays_one_line(tmp_path):
    with pytest.raises(SceneErrors) as info:
        load(tmp_path, "objects:\n  - mesh: |\n      not\n      a file\n")
    lines = info.value.lines()
    assert len(lines) == 1
    assert "\n" not in lines[0]


# ---------------------------------------------------------------------------------------
# files named in the scene


def test_missing_mesh_file_names_path_and_suggests(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "duck.obj").write_text("v 0 0 0\n", encoding="utf-8")
    line = one_error(tmp_path, "objects:\n  - mesh: models/duk.obj\n")
    assert line == "scene.yaml:2:5: objects[0].mesh: file not found: models/duk.obj (did you mean 'duck.obj'?)"


def test_missing_mesh_file_without_similar_file(tmp_path):
    line = one_error(tmp_path, "objects:\n  - mesh: models/zebra.obj\n")
    assert "file not found: models/zebra.obj" in line
    assert "did you mean" not in line


def test_existing_mesh_file_resolves_against_base_dir(tmp_path):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "duck.obj").write_text("v 0 0 0\n", encoding="utf-8")
    spec = load(tmp_path, "objects:\n  - mesh: models/duck.obj\n").spec
    assert spec.objects[0].mesh == (tmp_path / "models" / "duck.obj").resolve()


def test_mesh_file_of_unknown_type(tmp_path):
    (tmp_path / "notes.txt").write_text("hi", encoding="utf-8")
    line = one_error(tmp_path, "objects:\n  - mesh: notes.txt\n")
    assert "notes.txt: unsupported mesh format" in line


# ---------------------------------------------------------------------------------------
# materials and colours


def test_unknown_material_name_suggests(tmp_path):
    line = one_error(tmp_path, "materials:\n  grass: {diffuse: [0.1, 0.2, 0.3]}\n"
                               "objects:\n  - mesh: {primitive: box}\n    material: gras\n")
    assert line == ("scene.yaml:5:5: objects[0].material: no material named 'gras' "
                    "(did you mean 'grass'?) (known: grass)")


def test_material_name_with_no_materials_defined(tmp_path):
    line = one_error(tmp_path, "objects:\n  - mesh: {primitive: box}\n    material: nothing\n")
    assert "no material named 'nothing'" in line
    assert "none are defined" in line


def test_inline_material(tmp_path):
    spec = load(tmp_path, "objects:\n  - mesh: {primitive: box}\n    material: {diffuse: [1, 0, 0], shininess: 0}\n").spec
    material = spec.objects[0].material
    np.testing.assert_array_equal(material.diffuse(0.0), [1.0, 0.0, 0.0, 1.0])
    assert material.shininess(0.0) == 0.0


@pytest.mark.parametrize("colour, item, shown", [("[0.1, 0.2, 1.5]", 2, "1.5"), ("[-0.1, 0.2, 1]", 0, "-0.1"),
                                                 ("[0, 0, 0, 2]", 3, "2")])
def test_colour_out_of_range_rejected(tmp_path, colour, item, shown):
    line = one_error(tmp_path, f"materials:\n  m: {{diffuse: {colour}}}\n")
    assert line.startswith("scene.yaml:2:")
    assert f"materials.m.diffuse: item {item}: must be >= 0 and <= 1, got {shown}" in line


@pytest.mark.parametrize("colour", ["[1, 1]", "[1, 1, 1, 1, 1]", "red", "0.5"])
def test_colour_of_wrong_shape_rejected(tmp_path, colour):
    line = one_error(tmp_path, f"materials:\n  m: {{diffuse: {colour}}}\n")
    assert "expected a colour of 3 or 4 numbers in [0, 1]" in line


def test_three_and_four_number_colours(tmp_path):
    spec = load(tmp_path, "materials:\n  m: {diffuse: [1, 0.5, 0], ambient: [0.1, 0.2, 0.3, 0.5]}\n").spec
    np.testing.assert_allclose(spec.materials["m"].diffuse(0.0), [1.0, 0.5, 0.0, 1.0])
    np.testing.assert_allclose(spec.materials["m"].ambient(0.0), [0.1, 0.2, 0.3, 0.5])


# ---------------------------------------------------------------------------------------
# tracks

TRACK_SCENE = "objects:\n  - mesh: {primitive: box}\n    position:\n      keys:\n%s"


def track_scene(keys: str, extra: str = "") -> str:
    return TRACK_SCENE % keys + extra


def test_track_keys_sorted_on_load(tmp_path):
    text = track_scene("        - [2, [2, 0, 0]]\n        - [0, [0, 0, 0]]\n        - [1, [1, 4, 0]]\n")
    track = load(tmp_path, text).spec.objects[0].position
    np.testing.assert_array_equal(track.times, [0.0, 1.0, 2.0])
    np.testing.assert_array_equal(track.values, [[0, 0, 0], [1, 4, 0], [2, 0, 0]])
    np.testing.assert_allclose(track(0.5), [0.5, 2.0, 0.0])
    np.testing.assert_allclose(track(1.5), [1.5, 2.0, 0.0])
    np.testing.assert_allclose(track(-1.0), [0.0, 0.0, 0.0])
    np.testing.assert_allclose(track(9.0), [2.0, 0.0, 0.0])


def test_track_mapping_keys_and_per_key_interpolation(tmp_path):
    text = track_scene("        - {t: 2, value: [4, 0, 0]}\n"
                       "        - {t: 0, value: [0, 0, 0], interpolation: step}\n"
                       "        - {t: 1, value: [2, 0, 0]}\n")
    track = load(tmp_path, text).spec.objects[0].position
    assert track.modes == ("step", "linear", "linear")
    np.testing.assert_allclose(track(0.9), [0.0, 0.0, 0.0])  # step holds key 0
    np.testing.assert_allclose(track(1.5), [3.0, 0.0, 0.0])  # linear from key 1


def test_track_mixed_key_forms_and_default_interpolation(tmp_path):
    text = track_scene("        - [0, [0, 0, 0]]\n        - {t: 1, value: [1, 0, 0], interpolation: step}\n"
                       "        - [2, [2, 0, 0]]\n", "      interpolation: cosine\n")
    track = load(tmp_path, text).spec.objects[0].position
    assert track.modes == ("cosine", "step", "cosine")
    np.testing.assert_allclose(track(0.25), [(1 - math.cos(0.25 * math.pi)) / 2, 0.0, 0.0])


def test_track_same_time_error_points_at_later_key(tmp_path):
    text = track_scene("        - [0, [0, 0, 0]]\n        - [1, [1, 0, 0]]\n        - [0, [2, 0, 0]]\n")
    line = one_error(tmp_path, text)
    assert line.startswith("scene.yaml:7:")  # the third key, written last
    assert "objects[0].position.keys[2]" in line
    assert "keys 0 and 2 are both at t = 0" in line


def test_track_keys_of_different_shapes(tmp_path):
    text = ("objects:\n  - mesh: {primitive: box}\n    scale:\n      keys:\n"
            "        - [0, 1]\n        - [1, [1, 2, 3]]\n")
    line = one_error(tmp_path, text)
    assert line.startswith("scene.yaml:6:")
    assert "objects[0].scale.keys[1]" in line
    assert "key 1 has 3 numbers but key 0 has 1" in line


def test_track_key_value_out_of_range(tmp_path):
    text = "lights:\n  - type: point\n    color:\n      keys:\n        - [0, [1, 1, 1]]\n        - [1, [2, 0, 0]]\n"
    line = one_error(tmp_path, text)
    assert line.startswith("scene.yaml:6:")
    assert "lights[0].color.keys[1][1]: item 0: must be >= 0 and <= 1, got 2" in line


def test_track_key_unknown_field(tmp_path):
    text = track_scene("        - [0, [0, 0, 0]]\n        - {t: 1, valeu: [1, 0, 0]}\n")
    assert "unknown key 'valeu' (did you mean 'value'?)" in one_error(tmp_path, text)


def test_track_unknown_key_in_track_mapping(tmp_path):
    text = track_scene("        - [0, [0, 0, 0]]\n", "      loops: true\n")
    assert "unknown key 'loops' (did you mean 'loop'?)" in one_error(tmp_path, text)


def test_track_with_empty_keys(tmp_path):
    text = "objects:\n  - mesh: {primitive: box}\n    position: {keys: []}\n"
    assert "a track needs 'keys'" in one_error(tmp_path, text)


def test_bool_track_is_step(tmp_path):
    text = ("objects:\n  - mesh: {primitive: box}\n    visible:\n      keys: [[0, true], [1, false], [2, true]]\n"
            "      interpolation: linear\n")
    track = load(tmp_path, text).spec.objects[0].visible
    assert track.modes == ("step", "step", "step")
    assert [track(t) for t in (0.0, 0.5, 0.99, 1.0, 1.5, 2.0, 5.0)] == [True, True, True, False, False, True, True]


def test_scalar_track_with_loop(tmp_path):
    text = "lights:\n  - type: point\n    intensity: {keys: [[0, 1], [2, 3]], loop: true}\n"
    track = load(tmp_path, text).spec.lights[0].intensity
    assert track(1.0) == pytest.approx(2.0)
    assert track(3.0) == pytest.approx(2.0)
    assert isinstance(track(1.0), float)


def test_single_key_track_is_constant(tmp_path):
    track = load(tmp_path, "lights:\n  - type: point\n    intensity: {keys: [[5, 2]]}\n").spec.lights[0].intensity
    assert track.is_constant
    assert track(0.0) == 2.0 and track(100.0) == 2.0


# ---------------------------------------------------------------------------------------
# render and camera


@pytest.mark.parametrize("count", [1, 2, 4, 8, 16, 32, 64])
def test_msaa_sample_counts_are_powers_of_two(tmp_path, count):
    assert load(tmp_path, f"render: {{samples: {count}}}\n").spec.render.samples == count


@pytest.mark.parametrize("count", [0, 3, 6, 12, 65, 128])
def test_other_msaa_sample_counts_list_the_ones_offered(tmp_path, count):
    """A count GL devices never offer used to pass validation and fail in render."""
    assert one_error(tmp_path, f"render: {{samples: {count}}}\n") == (
        f"scene.yaml:1:10: render.samples: MSAA samples must be one of 1, 2, 4, 8, 16, 32, 64 (1 = off), got {count}")


def test_msaa_sample_count_from_set_is_checked(tmp_path):
    assert one_error(tmp_path, MINIMAL, ["render.samples=3"]) == (
        "--set render.samples=3: render.samples: MSAA samples must be one of 1, 2, 4, 8, 16, 32, 64 (1 = off), got 3")


@pytest.mark.parametrize("position", ["[0, 1, 3]", "{keys: [[0, [0, 1, 3]], [2, [0, 1, 3]]]}"])
def test_camera_at_its_own_target_is_an_error(tmp_path, position):
    """Like a zero light direction or camera up: there is no direction to look in."""
    line = one_error(tmp_path, f"camera:\n  position: {position}\n  target: [0, 1, 3]\n")
    assert line == ("scene.yaml:3:3: camera.target: camera position and target are the same point [0, 1, 3]: "
                    "there is no direction to look in; move the target or give yaw/pitch instead")


def test_animated_camera_may_pass_through_its_target(tmp_path):
    spec = load(tmp_path, "camera:\n  position: {keys: [[0, [0, 1, -3]], [2, [0, 1, 3]]]}\n  target: [0, 1, 0]\n").spec
    np.testing.assert_array_equal(spec.camera.position(1.0), spec.camera.target(1.0))


# ---------------------------------------------------------------------------------------
# output


def test_frames_and_duration_disagree(tmp_path):
    line = one_error(tmp_path, "output: {frames: 10, duration: 2, fps: 30}\n")
    assert line.startswith("scene.yaml:1:")
    assert "output.frames: frames (10) and duration x fps (60) disagree" in line


def test_frames_and_duration_agree(tmp_path):
    assert load(tmp_path, "output: {frames: 60, duration: 2, fps: 30}\n").spec.output.frame_count == 60


def test_duration_and_fps_give_frame_count(tmp_path):
    assert load(tmp_path, "output: {duration: 2, fps: 30}\n").spec.output.frame_count == 60
    assert load(tmp_path, "output: {duration: 0.5, fps: 24}\n").spec.output.frame_count == 12
    assert load(tmp_path, "output: {frames: 7}\n").spec.output.frame_count == 7


def test_output_name_pattern_needs_frame(tmp_path):
    line = one_error(tmp_path, "output: {name: shot, frames: 2}\n")
    assert line.startswith("scene.yaml:1:") and "output.name: name pattern must contain" in line


def test_output_name_without_frame_is_fine_for_a_single_frame(tmp_path):
    loaded = load(tmp_path, "output: {name: cover}\n")
    assert loaded.spec.output.name == "cover" and loaded.spec.output.frame_count == 1


@pytest.mark.parametrize("text", [
    "output: {name: shot, frames: 2}\n",
    "output: {name: 'shot_{fram}'}\n",
    "objects:\n  - mesh: {primitive: box}\n    position: {keys: [5]}\n",
])
def test_messages_show_single_braces(tmp_path, text):
    line = one_error(tmp_path, text)
    assert "{" in line
    assert "{{" not in line and "}}" not in line


# ---------------------------------------------------------------------------------------
# --set overrides

TWO_OBJECTS = "objects:\n  - mesh: {primitive: box}\n  - mesh: {primitive: sphere}\n"


def test_overrides_dotted_paths_and_indices(tmp_path):
    spec = load(tmp_path, TWO_OBJECTS, ["render.samples=8", "objects[1].position=[1,2,3]", "objects.0.scale=2",
                                        "render.size=[10, 20]", "output.fps=1e2"]).spec
    assert spec.render.samples == 8
    np.testing.assert_array_equal(spec.objects[1].position(0.0), [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(spec.objects[0].scale(0.0), [2.0])
    assert spec.render.size == (10, 20)
    assert spec.output.fps == 100.0


def test_override_replaces_file_value(tmp_path):
    spec = load(tmp_path, "render: {samples: 2}\n" + MINIMAL, ["render.samples=1"]).spec
    assert spec.render.samples == 1


def test_overrides_apply_in_order(tmp_path):
    spec = load(tmp_path, MINIMAL, ["render.samples=2", "render.samples=16"]).spec
    assert spec.render.samples == 16


def test_override_creates_missing_sections(tmp_path):
    spec = load(tmp_path, MINIMAL, ["camera.position=[0, 1, 2]", "render.shading=unlit"]).spec
    np.testing.assert_array_equal(spec.camera.position(0.0), [0.0, 1.0, 2.0])
    assert spec.render.shading == "unlit"


def test_override_appends_one_past_the_end(tmp_path):
    spec = load(tmp_path, TWO_OBJECTS, ["objects[2]={mesh: {primitive: cone}}"]).spec
    assert [o.mesh.primitive for o in spec.objects] == ["box", "sphere", "cone"]


def test_override_value_is_yaml_text(tmp_path):
    spec = load(tmp_path, MINIMAL, ["output.name=shot_{frame:03d}", "objects[0].visible=false"]).spec
    assert spec.output.name == "shot_{frame:03d}"
    assert spec.objects[0].visible(0.0) is False


def test_override_does_not_change_the_parsed_data(tmp_path):
    from scenerender.scene.overrides import apply_overrides
    from scenerender.scene.yaml_source import parse_yaml_text

    data, source = parse_yaml_text("render: {samples: 2}\n", "scene.yaml")
    changed = apply_overrides(data, ["render.samples=8"], source)
    assert data == {"render": {"samples": 2}}
    assert changed == {"render": {"samples": 8}}


def test_invalid_override_value_is_located_at_the_option(tmp_path):
    line = one_error(tmp_path, MINIMAL, ["render.shadng=phong"])
    assert line == "--set render.shadng=phong: render.shadng: unknown key 'shadng' (did you mean 'shading'?)"
    line = one_error(tmp_path, MINIMAL, ["render.samples=abc"])
    assert line == "--set render.samples=abc: render.samples: expected a whole number, got 'abc'"


@pytest.mark.parametrize("override, expected", [
    ("render.samples", "--set expects key=value"),
    ("=3", "--set expects key=value"),
    ("objects[5].position=[1,2,3]", "no item 5 at 'objects'"),
    ("lights[0].type=point", "no item 0 at 'lights'"),
    ("...=3", "cannot read key path '...'"),
    ("render.samples=[1", "YAML syntax error"),
])
def test_bad_override_is_a_user_error_mentioning_set(tmp_path, override, expected):
    with pytest.raises(UserError) as info:
        load(tmp_path, TWO_OBJECTS, [override])
    text = str(info.value)
    assert "--set" in text
    assert expected in text


def test_override_through_a_non_mapping(tmp_path):
    with pytest.raises(UserError) as info:
        load(tmp_path, "render: {samples: 4}\n" + MINIMAL, ["render.samples.x=3"])
    assert str(info.value) == "--set render.samples.x=3: 'render.samples' is not a mapping"


def test_override_through_a_default_scalar_mentions_set(tmp_path):
    with pytest.raises(UserError) as info:
        load(tmp_path, MINIMAL, ["render.samples.x=3"])
    err = info.value
    text = err.lines()[0] if isinstance(err, SceneErrors) else str(err)
    assert "--set" in text


def test_parse_key_path():
    from scenerender.scene.overrides import parse_key_path

    assert parse_key_path("objects[1].position") == ("objects", 1, "position")
    assert parse_key_path("objects.1.position") == ("objects", 1, "position")
    assert parse_key_path("render.samples") == ("render", "samples")
    with pytest.raises(ValueError):
        parse_key_path("...")


# ---------------------------------------------------------------------------------------
# JSON Schema


def test_json_schema_is_json_with_the_sections():
    schema = json.loads(scene_json_schema())
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["type"] == "object"
    assert {"render", "output", "camera", "lights", "materials", "objects"} <= set(schema["properties"])
    assert schema.get("additionalProperties") is False


def test_json_schema_validates_scenes():
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(scene_json_schema())
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    assert list(validator.iter_errors({"objects": [{"mesh": {"primitive": "box"}}]})) == []
    animated = {"objects": [{"mesh": {"primitive": "box"},
                             "position": {"keys": [[0, [0, 0, 0]], {"t": 1, "value": [1, 1, 1]}]}}],
                "lights": [{"type": "point", "position": [1, 2, 3]}]}
    assert list(validator.iter_errors(animated)) == []
    assert list(validator.iter_errors({"render": {"shadng": "phong"}})) != []
