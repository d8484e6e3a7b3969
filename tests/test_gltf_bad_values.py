"""A glTF file whose JSON has a part of the wrong type, or whose animation keys are not
numbers a transform can use (NaN, infinite, a zero-length rotation), is bad input at
``validate`` and at ``render`` alike: exit 2, one line naming the file (and the key, or the
clip, channel and key index), no output folder left, no NumPy warning on the terminal."""
from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh
from click.testing import CliRunner

from gltf_files import GlbBuilder
from scenerender.cli import main
from scenerender.mesh.gltf import GltfStructureProblem, split_glb
from scenerender.errors import UserError
from scenerender.mesh.loader import read_gltf_clips
from scenerender.scene.assets import policy_for

TIMES = [0.0, 1.0, 2.0]
SPIN = [[0, 0, 0, 1], [0, 0, 1, 0], [0, 0, 0, -1]]
BOB = [[0, 1, 0], [0, 1.5, 0], [0, 1, 0]]
NAN = float("nan")


def _fan(path, channels=None, edit=None):
    """A hub and its child blades; ``channels`` (node name, path, times, values,
    interpolation) make the clip "clip" (by default the blades spin); ``edit(json)`` last."""
    builder = GlbBuilder()
    blades = builder.mesh(builder.primitive(trimesh.creation.box((1.6, 0.2, 0.1))))
    hub = builder.mesh(builder.primitive(trimesh.creation.box((0.3, 0.3, 0.3))))
    nodes = {"blades": builder.node(blades, root=False, name="blades", translation=[0, 0, 0.2])}
    nodes["hub"] = builder.node(hub, name="hub", translation=[0, 1, 0], children=[nodes["blades"]])
    channels = channels or [("blades", "rotation", TIMES, SPIN, "LINEAR")]
    first = len(builder.json["accessors"])
    builder.animation("clip", [(nodes[node], *rest) for node, *rest in channels])
    for accessor in builder.json["accessors"][first:]:  # the bad number is in the binary, the JSON stays JSON
        accessor.pop("min", None)
        accessor.pop("max", None)
    if edit is not None:
        edit(builder.json)
    return builder.write(path)


def _skinned(path, binds=None, joint_keys=None):
    """One triangle skinned to two joints; ``binds`` (2, 4, 4) its inverse bind matrices,
    ``joint_keys`` the rotation keys of joint 1 in the clip "clip"."""
    builder = GlbBuilder()
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)
    attributes = {"POSITION": builder.accessor(positions, "VEC3"),
                  "NORMAL": builder.accessor(np.tile([0.0, 0.0, 1.0], (3, 1)), "VEC3"),
                  "JOINTS_0": builder.accessor(np.tile([0, 1, 0, 0], (3, 1)), "VEC4", 5123),
                  "WEIGHTS_0": builder.accessor(np.tile([0.5, 0.5, 0, 0], (3, 1)), "VEC4")}
    mesh = builder.mesh({"attributes": attributes,
                         "indices": builder.accessor(np.arange(3), "SCALAR", 5125, target=34963)})
    upper = builder.node(root=False, name="upper", translation=[0, 1, 0])
    root = builder.node(name="root", children=[upper])
    binds = np.stack([np.eye(4), np.eye(4)]) if binds is None else binds
    ibm = builder.accessor(binds.transpose(0, 2, 1).reshape(-1, 16), "MAT4", target=None)
    builder.json["skins"] = [{"joints": [root, upper], "inverseBindMatrices": ibm}]
    builder.node(mesh, name="skinned", skin=0)
    keys = joint_keys if joint_keys is not None else [[0, 0, 0, 1], [0, 0, 0.7071, 0.7071]]
    builder.animation("clip", [(upper, "rotation", [0.0, 1.0], keys, "LINEAR")])
    return builder.write(path)


SCENE = """
render: {size: [32, 24], samples: 1}
output: {frames: 2, fps: 4}
camera: {position: [0, 1.2, 5], target: [0, 1, 0], fov: 50}
objects:
  - mesh: model.glb
    ANIMATION
"""


def _run(tmp_path, monkeypatch, command: str, animated: bool = True):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.yaml").write_text(SCENE.replace("ANIMATION", "animation: {clip: clip}" if animated else ""))
    args = [command, "scene.yaml"] + (["-o", "out", "-q"] if command == "render" else [])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = CliRunner().invoke(main, args)
    numpy_warnings = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    return result, numpy_warnings


def _assert_refused(result, numpy_warnings, tmp_path, *fragments):
    lines = result.stderr.splitlines()
    assert result.exit_code == 2, result.stderr
    assert len(lines) == 1 and lines[0].startswith("error: model.glb: "), result.stderr
    assert "internal error" not in result.stderr
    for fragment in fragments:
        assert fragment in lines[0], lines[0]
    assert not numpy_warnings
    assert not (tmp_path / "out").exists()  # a failed render leaves no folder behind


def _poke(keys, index, value):
    keys = [list(k) for k in keys]
    keys[index] = value
    return keys


BAD_KEYS = {
    "rotation-nan": (("blades", "rotation", TIMES, _poke(SPIN, 1, [NAN, 0, 0, 1]), "LINEAR"),
                     "channels[0] (rotation of node 0", "key 1 holds [nan, 0, 0, 1]"),
    "rotation-zero": (("blades", "rotation", TIMES, _poke(SPIN, 2, [0, 0, 0, 0]), "LINEAR"),
                      "channels[0] (rotation of node 0", "key 2", "length 0"),
    "rotation-zero-step": (("blades", "rotation", TIMES, _poke(SPIN, 0, [0, 0, 0, 0]), "STEP"), "key 0", "length 0"),
    "rotation-cubic-value-zero": (("blades", "rotation", TIMES, [[0, 0, 0, 0]] * 9, "CUBICSPLINE"),
                                  "key 0", "length 0"),
    "translation-nan": (("hub", "translation", TIMES, _poke(BOB, 2, [0, NAN, 0]), "LINEAR"),
                        "channels[0] (translation of node 1", "key 2 holds [0, nan, 0]"),
    "translation-inf": (("hub", "translation", TIMES, _poke(BOB, 0, [float("inf"), 0, 0]), "LINEAR"), "key 0"),
    "scale-nan": (("hub", "scale", TIMES, _poke(BOB, 1, [NAN, NAN, NAN]), "LINEAR"), "(scale of node 1", "key 1"),
    "cubic-tangent-nan": (("hub", "translation", TIMES, [[0, 1, 0]] * 3 + [[0, NAN, 0]] + [[0, 1, 0]] * 5,
                           "CUBICSPLINE"), "the in-tangent of key 1"),
    "weights-nan": (("blades", "weights", TIMES, [0.0, NAN, 1.0], "LINEAR"), "(weights of node 0", "key 1"),
    "time-nan": (("hub", "translation", [0.0, NAN, 2.0], BOB, "LINEAR"), "key 1 has the time nan"),
}


@pytest.mark.parametrize("command", ["validate", "render"])
@pytest.mark.parametrize("case", BAD_KEYS.values(), ids=BAD_KEYS.keys())
def test_a_key_that_is_no_number_or_no_rotation_is_refused_naming_clip_channel_and_key(tmp_path, monkeypatch,
                                                                                     command, case):
    channel, *fragments = case
    _fan(tmp_path / "model.glb", [channel])
    result, numpy_warnings = _run(tmp_path, monkeypatch, command)
    _assert_refused(result, numpy_warnings, tmp_path, "animations[0] ('clip')", *fragments)


@pytest.mark.parametrize("command", ["validate", "render"])
def test_a_skin_joint_turned_by_a_zero_quaternion_is_refused(tmp_path, monkeypatch, command):
    _skinned(tmp_path / "model.glb", joint_keys=[[0, 0, 0, 1], [0, 0, 0, 0]])
    result, numpy_warnings = _run(tmp_path, monkeypatch, command)
    _assert_refused(result, numpy_warnings, tmp_path, "(rotation of node 0", "key 1", "length 0")


@pytest.mark.parametrize("command", ["validate", "render"])
def test_a_skin_whose_inverse_bind_matrix_is_nan_is_refused(tmp_path, monkeypatch, command):
    binds = np.stack([np.eye(4), np.full((4, 4), NAN)])
    _skinned(tmp_path / "model.glb", binds=binds)
    result, numpy_warnings = _run(tmp_path, monkeypatch, command)
    _assert_refused(result, numpy_warnings, tmp_path, "skins[0]", "joint 1")


def test_the_good_files_here_render(tmp_path, monkeypatch):
    """The files above, unbroken, render: what fails is the value, not the file."""
    _fan(tmp_path / "model.glb")
    result, numpy_warnings = _run(tmp_path, monkeypatch, "render")
    assert result.exit_code == 0 and not numpy_warnings, result.stderr
    _skinned(tmp_path / "model.glb")
    result, numpy_warnings = _run(tmp_path, monkeypatch, "render")
    assert result.exit_code == 0 and not numpy_warnings, result.stderr


def _set(key_path, value):
    def edit(document):
        node = document
        for step in key_path[:-1]:
            node = node[step]
        node[key_path[-1]] = value
    return edit


WRONG_TYPES = {
    "material-a-number": (_set(("materials",), [5]), "materials[0]", "expected a mapping"),
    "material-a-string": (_set(("materials",), ["red"]), "materials[0]", "expected a mapping"),
    "materials-an-object": (_set(("materials",), {"a": 1}), "materials", "expected a list"),
    "texture-info-a-list": (_set(("materials",), [{"normalTexture": [0]}]), "materials[0].normalTexture"),
    "node-a-string": (_set(("nodes", 1, "children"), "blades"), "nodes[1].children"),
    "translation-short": (_set(("nodes", 1, "translation"), [0, 1]), "nodes[1].translation"),
    "translation-text": (_set(("nodes", 1, "translation"), [0, "1", 0]), "nodes[1].translation[1]"),
    "rotation-zero": (_set(("nodes", 0, "rotation"), [0, 0, 0, 0]), "nodes[0].rotation", "non-zero length"),
    "rotation-infinite": (_set(("nodes", 0, "rotation"), ["INFINITE", 0, 0, 1]), "nodes[0].rotation[0]", "finite"),
    "accessor-count-a-float": (_set(("accessors", 0, "count"), 8.0), "accessors[0].count", "whole number"),
    "channel-a-number": (_set(("animations", 0, "channels"), [3]), "animations[0].channels[0]"),
    "sampler-input-a-bool": (_set(("animations", 0, "samplers", 0, "input"), True), "animations[0].samplers[0].input"),
    "skin-joints-text": (_set(("skins",), [{"joints": "all"}]), "skins[0].joints"),
    "attributes-a-list": (_set(("meshes", 0, "primitives", 0, "attributes"), [0]),
                          "meshes[0].primitives[0].attributes"),
}


@pytest.mark.parametrize("command, animated", [("validate", False), ("validate", True), ("render", False),
                                               ("render", True)])
@pytest.mark.parametrize("case", WRONG_TYPES.values(), ids=WRONG_TYPES.keys())
def test_a_part_of_the_wrong_type_is_bad_input_naming_file_and_key(tmp_path, monkeypatch, command, animated, case):
    edit, *fragments = case
    path = _fan(tmp_path / "model.glb", edit=edit)
    # a number JSON reads as infinite (json.dumps would write the non-standard Infinity); same length
    path.write_bytes(path.read_bytes().replace(b'"INFINITE"', b"1e99999999"))
    result, numpy_warnings = _run(tmp_path, monkeypatch, command, animated)
    _assert_refused(result, numpy_warnings, tmp_path, "not a usable glTF file", *fragments)


def test_deep_json_is_a_structure_problem_not_a_recursion_error(tmp_path):
    deep = _fan(tmp_path / "model.glb", edit=_set(("extras",), [[[[[]]]]])).read_bytes()
    split_glb(deep)  # extras of depth 6: fine
    with pytest.raises(GltfStructureProblem, match="nested more than 64 deep"):
        _fan(tmp_path / "model.glb", edit=_set(("extras",), _nested(200)))
        split_glb((tmp_path / "model.glb").read_bytes())


def _nested(depth: int):
    value: list = []
    for _ in range(depth):
        value = [value]
    return value


def test_the_readers_meet_the_guard_too(tmp_path):
    """The loader's way to the clips passes the guard first: a wrong part of the animations
    is refused naming its key, before read_clips walks it."""
    path = _fan(tmp_path / "model.glb", edit=_set(("animations", 0, "channels"), [3]))
    with pytest.raises(UserError, match="not a usable glTF file") as caught:
        read_gltf_clips(path, policy_for(path))
    assert caught.value.key == "animations[0].channels[0]"


# Keys each finite, whose products are not: a part placed beyond 32-bit floats at some time
# of the clip. The world's build bounds every part's transform over the whole clip
# (world/reach.py), as it does an object's own tracks, so the frames never round one to
# infinity (and NumPy never warns of the overflow).
HUGE = 3.0e38
OVERFLOWING = {
    "translation-times-scale": lambda path: _fan(path, [("hub", "scale", TIMES, [[1, 1, 1], [HUGE] * 3, [1, 1, 1]],
                                                         "LINEAR"),
                                                        ("blades", "translation", TIMES, [[0, 0, 0], [HUGE, 0, 0],
                                                                                          [0, 0, 0]], "STEP")]),
    # 10 s between keys: the out-tangent's term reaches 10 * 4/27 * 3e38 = 4.4e38 (values stay at 1)
    "cubic-tangents": lambda path: _fan(path, [("hub", "translation", [0.0, 10.0, 20.0],
                                                [[0, 0, 0], [0, 1, 0], [HUGE, HUGE, HUGE]] * 3, "CUBICSPLINE")]),
    "skin-inverse-binds": lambda path: _skinned(path, binds=np.stack([np.eye(4), np.diag([HUGE, HUGE, 1.0, 1.0])])),
}


@pytest.mark.parametrize("command", ["validate", "render"])
@pytest.mark.parametrize("build", OVERFLOWING.values(), ids=OVERFLOWING.keys())
def test_finite_keys_that_multiply_beyond_float32_are_refused_at_the_animation_key(tmp_path, monkeypatch, command,
                                                                                  build):
    build(tmp_path / "model.glb")
    result, numpy_warnings = _run(tmp_path, monkeypatch, command)
    lines = result.stderr.splitlines()
    assert result.exit_code == 2 and len(lines) == 1, result.stderr
    assert lines[0].startswith("error: scene.yaml:7:5: objects[0].animation: object 'model0/"), lines[0]
    assert "with its glTF clip" in lines[0] and "beyond 32-bit floats" in lines[0], lines[0]
    assert not numpy_warnings and not (tmp_path / "out").exists()
