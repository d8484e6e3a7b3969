"""Fuzzing the JSON files scenerender reads besides the scene: an output folder's run
manifest, a reference folder's ignore.json, and a GLB's animations (its JSON and the key
values its accessors hold).

Invariants:
- a run manifest of any bytes is used, or treated as absent with a one-line reason; never
  an exception, and a manifest used answers every question a run asks of it;
- an ignore.json is read, or refused with a one-line UserError naming it; what is read
  prints (no UnicodeEncodeError) and gives masks;
- a GLB's clips are read, or refused with a one-line UserError naming the file; the clips
  read give finite transforms at any time, a world built with one playing has finite
  32-bit matrices and bounds at any time, and no NumPy warning reaches the terminal.

Every input that once broke one of them is a case in tests/corpus/.
"""
from __future__ import annotations

import json
import struct
import tempfile
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import example, given
from hypothesis import strategies as st

from fuzz.test_fuzz_assets import apply_edits, edits
from gltf_files import GlbBuilder
from scenerender.compare.ignore import read_ignore
from scenerender.errors import UserError, Warnings
from scenerender.mesh.budget import TriangleBudget
from scenerender.mesh.gltf_geometry import placed_nodes
from scenerender.mesh.loader import load_gltf_nodes, read_gltf_clips
from scenerender.run.manifest import Fingerprint, Manifest, read_sidecar
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.loading import load_scene
from scenerender.world.build import build_world
from scenerender.world.transforms import normal_matrices

# a NumPy warning (overflow, an invalid value) would reach the user's terminal: a finding too
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")


# ---------------------------------------------------------------------------------------
# JSON values, and documents with one part replaced


def json_values():
    scalars = (st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.floats(allow_nan=False, allow_infinity=False)
               | st.text(max_size=8) | st.sampled_from(["\ud800", "\udcff", "", "*", "frame_0000.png", "x" * 500]))
    return st.recursive(scalars, lambda inner: st.lists(inner, max_size=4)
                        | st.dictionaries(st.text(max_size=6), inner, max_size=4), max_leaves=12)


def replaced(document, data) -> object:
    """``document`` (JSON values) with the part at a drawn path replaced by a drawn value."""
    if not isinstance(document, (dict, list)) or not document or data.draw(st.integers(0, 3)) == 0:
        return data.draw(json_values())
    keys = sorted(document) if isinstance(document, dict) else list(range(len(document)))
    key = data.draw(st.sampled_from(keys))
    copy = dict(document) if isinstance(document, dict) else list(document)
    copy[key] = replaced(document[key], data)
    return copy


def deeply_nested(depth: int) -> bytes:
    return b"[" * depth + b"]" * depth


# ---------------------------------------------------------------------------------------
# The run manifest


def _valid_manifest() -> dict:
    entry = {"index": 0, "scene": "scene.yaml", "run": "r1", "bytes": 5, "sha256": "ab",
             "object_ids": {"bytes": 3, "sha256": "cd"}, "cameras": [json.dumps({"frame": 0, "fov": 50})]}
    return {"format": 1, "scenerender": "0.8.0",
            "frames": {"frame_0000.png": entry, "frame_0001.png": {**entry, "index": 1, "cameras": None}},
            "runs": {"scene.yaml": {"run": "r1", "inputs": {"version": "0.8.0", "overrides": "o", "settings": "s"}}},
            "gl": {"renderer": "llvmpipe", "vendor": "Mesa", "version": "4.5", "software": True}}


VALID_MANIFEST = json.dumps(_valid_manifest()).encode()
RUN = Fingerprint({"version": "0.9.0", "overrides": "o", "settings": "t", "asset:a.obj": "d"})


def check_manifest(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as temp:
        folder = Path(temp)
        (folder / ".scenerender.json").write_bytes(data)
        (folder / "frame_0000.png").write_bytes(b"12345")
        found, why = read_sidecar(folder / ".scenerender.json")
        assert (found == {}) if why is not None else isinstance(found, dict)
        if why is not None:
            assert "\n" not in why and ".scenerender.json" in why
        manifest = Manifest.open(folder, True, RUN, "scene.yaml", cameras=True)
        assert manifest.unusable == why
        # what a run asks of it (run/plan.py), and what it writes back
        RUN.changes_since(manifest.previous_inputs)
        assert manifest.previous_run is None or isinstance(manifest.previous_run, str)
        manifest.is_current("frame_0000.png", folder / "frame_0000.png", folder / "missing.png")
        for name in manifest.stale_frames():
            manifest.forget(name)
        manifest.write_cameras()
        manifest.start({"GL_RENDERER": "llvmpipe"})
        manifest.record("frame_0000.png", 0, folder / "frame_0000.png", None, [{"frame": 0}])
        manifest.finish()
        assert read_sidecar(folder / ".scenerender.json")[1] is None  # what it writes, it reads back


@given(data=st.data())
@example(data=None)
def test_manifest_with_a_part_replaced(data):
    document = _valid_manifest() if data is None else replaced(_valid_manifest(), data)
    check_manifest(json.dumps(document).encode("utf-8", "surrogatepass"))


@given(changes=edits())
@example(changes=[(0, 0, ord("["))])
def test_manifest_bytes_mutated(changes):
    check_manifest(apply_edits(VALID_MANIFEST, changes))


@given(value=json_values())
@example(value={"format": 1, "frames": 5})
@example(value={"format": 1, "runs": {"scene.yaml": "abc"}})
@example(value={"format": 1, "frames": {"f.png": {"cameras": ["[" * 10_000 + "]" * 10_000, "\ud800", "{"]}}})
def test_manifest_of_any_json_value(value):
    check_manifest(json.dumps(value).encode("utf-8", "surrogatepass"))


def test_manifest_nested_100000_deep():
    check_manifest(deeply_nested(100_000))


# ---------------------------------------------------------------------------------------
# ignore.json


VALID_IGNORE = {"rectangles": [{"x": 1, "y": 2, "w": 3, "h": 4, "frames": "frame_*", "why": "clock"},
                               {"x": -5, "y": 0, "w": 100, "h": 1}]}


def check_ignore(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as temp:
        folder = Path(temp)
        (folder / "ignore.json").write_bytes(data)
        try:
            regions = read_ignore(folder)
        except UserError as exc:
            assert "\n" not in str(exc) and "ignore.json" in str(exc)
            str(exc).encode("utf-8")  # printable
            return
        regions.describe().encode("utf-8")  # the verdict prints it
        for name in ("frame_0000.png", "other.png", "\udcff.png"):
            mask = regions.mask_for(name, (6, 8))
            assert mask is None or (mask.shape == (6, 8) and mask.dtype == bool)


@given(data=st.data())
def test_ignore_with_a_part_replaced(data):
    check_ignore(json.dumps(replaced(VALID_IGNORE, data)).encode("utf-8", "surrogatepass"))


@given(changes=edits())
def test_ignore_bytes_mutated(changes):
    check_ignore(apply_edits(json.dumps(VALID_IGNORE).encode(), changes))


@given(value=json_values())
@example(value={"rectangles": [{"x": 0, "y": 0, "w": 1, "h": 1, "why": "\ud800"}]})
def test_ignore_of_any_json_value(value):
    check_ignore(json.dumps(value).encode("utf-8", "surrogatepass"))


def test_ignore_nested_100000_deep():
    check_ignore(b'{"rectangles": ' + deeply_nested(100_000) + b"}")


# ---------------------------------------------------------------------------------------
# A GLB's animations: the key values in its accessors, and its JSON


TIMES = [0.0, 1.0, 2.0]
SPIN = [[0, 0, 0, 1], [0, 0, 1, 0], [0, 0, 0, -1]]
BOB = [[0, 1, 0], [0, 1.5, 0], [0, 1, 0]]


def _animated_glb() -> tuple[dict, bytes, list]:
    """(JSON, BIN chunk, [(offset, count) of each animation accessor's float32 values in
    the BIN chunk]) of a hub and its blades with one clip of every kind of channel."""
    builder = GlbBuilder()
    blades = builder.mesh(builder.primitive(trimesh.creation.box((1.6, 0.2, 0.1))))
    hub = builder.mesh(builder.primitive(trimesh.creation.box((0.3, 0.3, 0.3))))
    blade = builder.node(blades, root=False, name="blades", translation=[0, 0, 0.2])
    top = builder.node(hub, name="hub", translation=[0, 1, 0], children=[blade])
    first = len(builder.json["accessors"])
    builder.animation("clip", [(blade, "rotation", TIMES, SPIN, "LINEAR"), (top, "translation", TIMES, BOB, "STEP"),
                               (top, "scale", TIMES, [[1, 1, 1]] * 9, "CUBICSPLINE"),
                               (blade, "rotation", [0.0, 2.0], [[0, 0, 0, 1]] * 6, "CUBICSPLINE")])
    regions = []
    for accessor in builder.json["accessors"][first:]:
        accessor.pop("min", None)
        accessor.pop("max", None)
        view = builder.json["bufferViews"][accessor["bufferView"]]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[accessor["type"]]
        regions.append((view["byteOffset"], accessor["count"] * width))
    while len(builder.binary) % 4:
        builder.binary += b"\0"
    builder.json["buffers"][0]["byteLength"] = len(builder.binary)
    return builder.json, bytes(builder.binary), regions


GLB_JSON, GLB_BIN, KEY_REGIONS = _animated_glb()


def glb(document: dict, binary: bytes) -> bytes:
    text = json.dumps(document).encode("utf-8", "surrogatepass")
    text += b" " * (-len(text) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body


def key_numbers():
    return st.floats(width=32) | st.sampled_from([0.0, -0.0, np.nan, np.inf, -np.inf, 3.4e38, -3.4e38, 1e-45])


TIMES_ASKED = (-1.0, 0.0, 0.3, 1.0, 1.7, 2.0, 3.0)


def check_clips(data: bytes) -> None:
    with tempfile.TemporaryDirectory() as temp:
        folder = Path(temp)
        path = folder / "model.glb"
        path.write_bytes(data)
        assets = AssetPolicy(folder, environ={})
        try:
            header, clips, _skins = read_gltf_clips(path, assets)
            load_gltf_nodes(path, warnings=Warnings(), assets=assets, budget=TriangleBudget.unlimited())
        except UserError as exc:
            assert "\n" not in str(exc) and "model.glb" in str(exc)
            return
        for clip in clips:
            for t in TIMES_ASKED:
                values = clip.node_values(t)
                assert all(np.isfinite(v).all() for node in values.values() for v in node.values())
                for _index, _node, world in placed_nodes(header, values):
                    assert np.isfinite(world).all()
        if clips:
            check_world_playing(folder)


def check_world_playing(folder: Path) -> None:
    """A scene playing the file's first clip: refused at build (what ``validate`` runs), or
    every part's matrices, normal matrices and bounds are finite 32-bit values at any time."""
    (folder / "scene.yaml").write_text("objects:\n  - mesh: model.glb\n    animation: {clip: 0}\n")
    try:
        world = build_world(load_scene(folder / "scene.yaml"), Warnings())
    except UserError as exc:
        lines = exc.lines() if hasattr(exc, "lines") else [str(exc)]
        assert all("\n" not in line for line in lines)
        return
    for obj in world.objects:
        for t in TIMES_ASKED:
            matrices = obj.matrices(t)
            assert np.isfinite(matrices.astype(np.float32)).all()
            assert np.isfinite(normal_matrices(matrices).astype(np.float32)).all()
            assert np.isfinite(obj.world_bounds(matrices, t).astype(np.float32)).all()


@given(values=st.lists(st.tuples(st.integers(0, len(KEY_REGIONS) - 1), st.integers(0, 63), key_numbers()),
                       min_size=1, max_size=6))
@example(values=[(1, 4, np.nan)])       # the x of a rotation key (regions: each channel's times, then values)
@example(values=[(1, 4, 0.0), (1, 5, 0.0), (1, 6, 0.0), (1, 7, 0.0)])  # a rotation key of length 0
@example(values=[(3, 1, np.inf)])       # a translation key
@example(values=[(0, 1, np.nan)])       # a key time
@example(values=[(3, 0, 3.4e38), (5, 3, 3.4e38)])  # finite keys whose product is not: a translation and a scale
def test_animation_key_values(values):
    binary = bytearray(GLB_BIN)
    for region, position, value in values:
        offset, count = KEY_REGIONS[region]
        struct.pack_into("<f", binary, offset + 4 * (position % count), value)
    check_clips(glb(GLB_JSON, bytes(binary)))


@given(data=st.data())
def test_animation_json_with_a_part_replaced(data):
    check_clips(glb(replaced(GLB_JSON, data), GLB_BIN))


@given(changes=edits())
def test_animated_glb_bytes_mutated(changes):
    check_clips(apply_edits(glb(GLB_JSON, GLB_BIN), changes))
