"""Fuzzing the asset readers: generated and mutated OBJ, MTL and image files.

Invariant for every input: loading either succeeds with well-formed data or raises a
``UserError`` (one line, naming the file); never another exception, never a file read from
outside the allowed folders. The number of examples comes from the hypothesis profile in
force (a few dozen in the normal test run, many more under ``make fuzz``). Inputs that once
broke this are kept as ``@example``s.
"""
from __future__ import annotations

import io
import os
import struct
import tempfile
import zlib
from pathlib import Path

import numpy as np
import pytest
import trimesh
import yaml
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from PIL import Image

from scenerender.errors import UserError, Warnings
from scenerender.mesh import box, load_mesh, parse_mtl
from scenerender.scene.assets import AssetPolicy
from scenerender.scene.image_files import ImageError, image_size
from scenerender.scene.loading import load_scene
from scenerender.world.build import build_world
from scenerender.world.images import decode_image

# Each example writes a few small files; hypothesis' deadline is about speed, not this.
FUZZ = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


# ---------------------------------------------------------------------------------------
# Strategies


def numbers():
    return st.one_of(
        st.integers(-5, 5).map(str),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.sampled_from(["1e308", "-1e400", "nan", "inf", "0x1f", "1_0", "", "--1", "1e", ".", "٣"]),
    )


def indices():
    return st.one_of(
        st.integers(-6, 8).map(str),
        st.sampled_from(["9223372036854775807", "9223372036854775808", "-9223372036854775809",
                         "99999999999999999999999999", "4611686018427387904", "0", "-0", "+1", "1.5", "x", ""]),
    )


def corners():
    form = st.sampled_from(["{v}", "{v}/{t}", "{v}//{n}", "{v}/{t}/{n}", "{v}/", "{v}/{t}/", "/{v}", "{v}//", "{v}/{t}/{n}/1"])
    return st.builds(lambda f, v, t, n: f.format(v=v, t=t, n=n), form, indices(), indices(), indices())


def obj_lines():
    vec = lambda n: st.lists(numbers(), min_size=0, max_size=n + 1).map(" ".join)  # noqa: E731
    return st.one_of(
        vec(3).map("v {}".format),
        vec(2).map("vt {}".format),
        vec(3).map("vn {}".format),
        st.lists(corners(), min_size=0, max_size=7).map(lambda c: "f " + " ".join(c)),
        st.lists(indices(), min_size=0, max_size=4).map(lambda c: "l " + " ".join(c)),
        st.lists(indices(), min_size=0, max_size=3).map(lambda c: "p " + " ".join(c)),
        st.sampled_from(["usemtl a", "usemtl", "usemtl missing", "mtllib lib.mtl", "mtllib ../escape.mtl",
                         "mtllib /etc/hostname", "mtllib " + "n" * 300 + ".mtl", "mtllib lib.mtl other.mtl",
                         "mtllib pipe.mtl", "mtllib .", "o thing", "g", "s off", "# comment", "f 1 2 \\", "\\",
                         "vp 0.5", "curv 0 1 1 2"]),
        st.text(max_size=20),
    )


def valid_obj() -> str:
    return ("mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
            "usemtl a\nf 1/1/1 2/2/1 3/1/1 4/2/1\nf -1 -2 -3\n")


def apply_edits(base: bytes, edits) -> bytes:
    """``base`` with each (kind, position, value) edit applied: kind 0 replaces the byte at
    position, 1 inserts one there, 2 deletes it (positions wrap around the length)."""
    data = bytearray(base)
    for kind, position, value in edits:
        position = position % (len(data) + 1)
        if kind == 0 and position < len(data):
            data[position] = value
        elif kind == 1:
            data[position:position] = bytes([value])
        elif position < len(data):
            del data[position]
    return bytes(data)


def edits():
    return st.lists(st.tuples(st.integers(0, 2), st.integers(0, 10_000), st.integers(0, 255)), min_size=1, max_size=8)


def mutated(base: bytes):
    """``base`` with a few bytes replaced, inserted or removed."""
    return edits().map(lambda changes: apply_edits(base, changes))


MTL_KEYS = ["Kd", "Ka", "Ks", "Ke", "Ns", "d", "Tr", "illum", "map_Kd", "map_Ks", "map_Bump", "bump", "norm",
            "map_d", "map_Ka", "newmtl", "Ni", "KD", "MAP_KD"]
MTL_ARGS = ["tex.png", "TEX.PNG", "missing.png", "../escape.png", "/etc/hostname", "C:\\art\\tex.png",
            "sub/../tex.png", "-s 2 2 tex.png", "-o 1 tex.png", "-bm 0.5 tex.png", "-clamp on tex.png",
            "-mm 0 1 tex.png", "-zz 3 tex.png", "-s", "\"tex.png\"", "pipe.png", "n" * 300 + ".png", "xyz 1 2 3",
            "spectral x.spd", "-halo 0.5", "1 2", "a", ""]


def mtl_lines():
    return st.one_of(
        st.builds(lambda k, a: f"{k} {a}", st.sampled_from(MTL_KEYS), st.sampled_from(MTL_ARGS)),
        st.builds(lambda k, ns: f"{k} " + " ".join(ns), st.sampled_from(MTL_KEYS), st.lists(numbers(), max_size=4)),
        st.text(max_size=20),
    )


# ---------------------------------------------------------------------------------------
# The folder every example reads from


class Folder:
    """A scene folder with a texture, a FIFO and a file outside it to try to reach."""

    def __init__(self):
        self._temp = tempfile.TemporaryDirectory()
        top = Path(self._temp.name)
        self.root = top / "scene"
        self.root.mkdir()
        (top / "escape.mtl").write_text("newmtl a\nKd 1 0 0\n")
        (top / "escape.png").write_bytes(_png(2, 2))
        (self.root / "tex.png").write_bytes(_png(2, 2))
        (self.root / "lib.mtl").write_text("newmtl a\nKd 1 1 1\nmap_Kd tex.png\n")
        if hasattr(os, "mkfifo"):
            os.mkfifo(self.root / "pipe.mtl")
            os.mkfifo(self.root / "pipe.png")

    def policy(self) -> AssetPolicy:
        return AssetPolicy(self.root, environ={})

    def close(self):
        self._temp.cleanup()


@pytest.fixture(scope="module")
def folder():
    made = Folder()
    yield made
    made.close()


def check_confined(policy: AssetPolicy) -> None:
    for path in policy.files_read:
        assert policy.allows(path), path
        assert path.is_file()


# ---------------------------------------------------------------------------------------
# OBJ


def load_obj(folder: Folder, data: bytes, warnings: Warnings | None = None):
    path = folder.root / "model.obj"
    path.write_bytes(data)
    policy = folder.policy()
    try:
        mesh = load_mesh(path, warnings=warnings or Warnings(), assets=policy)
    except UserError as exc:
        assert "\n" not in str(exc)
        assert exc.location is not None and exc.location.file.endswith(".obj") or "mtl" in str(exc)
        return None
    finally:
        check_confined(policy)
    assert mesh.positions.dtype == np.float32 and np.isfinite(mesh.positions).all()
    assert np.isfinite(mesh.normals).all()
    assert mesh.indices.size == 0 or int(mesh.indices.max()) < mesh.vertex_count
    assert sum(group.count for group in mesh.groups) == mesh.triangle_count
    return mesh


@FUZZ
@given(lines=st.lists(obj_lines(), max_size=40))
@example(lines=["v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 9223372036854775808"])
@example(lines=["v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 -9223372036854775809"])
@example(lines=["mtllib " + "n" * 300 + ".mtl"])
@example(lines=["mtllib pipe.mtl", "v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 3"])
def test_generated_obj(folder, lines):
    load_obj(folder, "\n".join(lines).encode("utf-8", "surrogatepass"))


@FUZZ
@given(data=mutated(valid_obj().encode()))
def test_mutated_obj(folder, data):
    load_obj(folder, data)


@FUZZ
@given(strict=st.booleans(), short=st.integers(0, 5), lines=st.integers(0, 3))
def test_degenerate_elements_warn_once_or_fail_when_strict(folder, strict, short, lines):
    path = folder.root / "degenerate.obj"
    path.write_text(valid_obj() + "f 1 2\n" * short + "l 1 2\n" * lines)
    warnings = Warnings(strict=strict)
    try:
        load_mesh(path, warnings=warnings, assets=folder.policy())
    except UserError as exc:
        assert strict and (short or lines) and "skipped" in str(exc)
        return
    assert not (strict and (short or lines))
    assert len([w for w in warnings.items if "skipped" in w]) == (1 if short or lines else 0)


# ---------------------------------------------------------------------------------------
# MTL


@FUZZ
@given(lines=st.lists(mtl_lines(), max_size=25))
@example(lines=["newmtl a", "map_Kd " + "n" * 300 + ".png"])
@example(lines=["newmtl a", "map_Kd pipe.png"])
@example(lines=["newmtl a", "map_Kd ../escape.png"])
def test_generated_mtl(folder, lines):
    path = folder.root / "fuzz.mtl"
    path.write_bytes("\n".join(lines).encode("utf-8", "surrogatepass"))
    policy = folder.policy()
    try:
        materials = parse_mtl(path, Warnings(), assets=policy)
    except UserError as exc:
        assert "\n" not in str(exc) and "fuzz.mtl" in str(exc)
        return
    finally:
        check_confined(policy)
    for material in materials.values():
        for key in ("ambient_map", "diffuse_map", "specular_map", "normal_map", "opacity_map"):
            ref = getattr(material, key)
            if ref is not None and not ref.missing:
                assert policy.allows(ref.path) and ref.path.is_file()


# ---------------------------------------------------------------------------------------
# Images


def _png(width: int, height: int) -> bytes:
    out = io.BytesIO()
    Image.fromarray(np.full((height, width, 4), 90, np.uint8)).save(out, format="PNG")
    return out.getvalue()


def _encoded(fmt: str) -> bytes:
    pixels = np.random.default_rng(3).integers(0, 255, (6, 5, 3), dtype=np.uint8)
    out = io.BytesIO()
    Image.fromarray(pixels).save(out, format=fmt)
    return out.getvalue()


SEEDS = {fmt: _encoded(fmt) for fmt in ("PNG", "BMP", "TGA", "GIF", "JPEG", "TIFF")}


def _png_with_size(width: int, height: int, bit_depth: int, color_type: int) -> bytes:
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"\x00" * 64))
            + chunk(b"IEND", b""))


def decode_checked(data: bytes, suffix: str = ".png", max_pixels: int = 4096 * 4096):
    with tempfile.TemporaryDirectory() as temp:
        path = Path(temp) / f"image{suffix}"
        path.write_bytes(data)
        try:
            width, height = image_size(path, max_pixels)
        except ImageError as exc:
            assert "\n" not in str(exc)
            return None
        assert width * height <= max_pixels
        try:
            pixels = decode_image(path, max_pixels)
        except ImageError as exc:
            assert "\n" not in str(exc)
            return None
    assert pixels.dtype == np.uint8 and pixels.ndim == 3 and pixels.shape[2] == 4
    assert pixels.shape[0] * pixels.shape[1] <= max_pixels
    return pixels


@FUZZ
@given(fmt=st.sampled_from(sorted(SEEDS)), changes=edits())
def test_mutated_images(fmt, changes):
    decode_checked(apply_edits(SEEDS[fmt], changes), "." + fmt.lower())


@FUZZ
@given(width=st.integers(0, 2**32 - 1), height=st.integers(0, 2**32 - 1),
       bit_depth=st.sampled_from([0, 1, 2, 4, 8, 16, 3, 255]), color_type=st.sampled_from([0, 2, 3, 4, 6, 1, 7]))
@example(width=100_000, height=100_000, bit_depth=8, color_type=6)
def test_image_headers_claiming_any_size(width, height, bit_depth, color_type):
    decode_checked(_png_with_size(width, height, bit_depth, color_type))


@FUZZ
@given(data=st.binary(max_size=300))
def test_random_bytes_as_an_image(data):
    decode_checked(data)


# ---------------------------------------------------------------------------------------
# Formats read through trimesh, and the whole path from a scene file to a world


def _trimesh_seeds() -> dict:
    """A box in every trimesh-read format (written by trimesh itself)."""
    cube = box(1.0)
    mesh = trimesh.Trimesh(cube.positions, cube.indices.astype(np.int64), process=False)
    seeds = {}
    for suffix, options in ((".ply", {"encoding": "ascii"}), (".ply", {"encoding": "binary"}),
                            (".stl", {"file_type": "stl_ascii"}), (".stl", {}), (".off", {}), (".glb", {})):
        data = mesh.export(file_type=options.pop("file_type", suffix[1:]), **options)
        seeds[f"{suffix}:{len(seeds)}"] = data if isinstance(data, bytes) else data.encode()
    return seeds


TRIMESH_SEEDS = _trimesh_seeds()


@FUZZ
@given(seed=st.sampled_from(sorted(TRIMESH_SEEDS)), changes=edits())
@example(seed=".glb:5", changes=[(0, 653, 1)])  # a face index past the vertices: IndexError in normals
def test_mutated_trimesh_formats(folder, seed, changes):
    suffix = seed.split(":")[0]
    path = folder.root / f"mesh{suffix}"
    path.write_bytes(apply_edits(TRIMESH_SEEDS[seed], changes))
    policy = folder.policy()
    try:
        mesh = load_mesh(path, warnings=Warnings(), assets=policy)
    except UserError as exc:
        assert "\n" not in str(exc) and exc.location.file.endswith(path.name)
        return
    finally:
        check_confined(policy)
    assert np.isfinite(mesh.positions).all() and np.isfinite(mesh.normals).all()
    assert int(mesh.indices.max()) < mesh.vertex_count


@FUZZ
@given(obj=st.lists(obj_lines(), max_size=15), mtl=st.lists(mtl_lines(), max_size=8),
       image=mutated(SEEDS["PNG"]), scene_map=st.booleans(), strict=st.booleans())
def test_scene_to_world(obj, mtl, image, scene_map, strict):
    """A scene naming a fuzzed OBJ (with a fuzzed MTL and texture): ``build_world`` gives a
    world whose every texture decodes, or a UserError."""
    with tempfile.TemporaryDirectory() as temp:
        root = Path(temp)
        (root / "model.obj").write_bytes(("mtllib lib.mtl\nusemtl a\n" + "\n".join(obj)).encode("utf-8", "surrogatepass"))
        (root / "lib.mtl").write_bytes(("newmtl a\nmap_Kd tex.png\n" + "\n".join(mtl)).encode("utf-8", "surrogatepass"))
        (root / "tex.png").write_bytes(image)
        material = "\n    material: {diffuse_map: tex.png}" if scene_map else ""
        (root / "scene.yaml").write_text(f"objects:\n  - mesh: model.obj{material}\n")
        try:
            loaded = load_scene(root / "scene.yaml")
            world = build_world(loaded, Warnings(strict=strict))
        except UserError as exc:
            lines = exc.lines() if hasattr(exc, "lines") else [str(exc)]
            assert all("\n" not in line for line in lines)
            return
        for obj_ in world.objects:
            for material_ in obj_.materials:
                for source in material_.maps.values():
                    if source.path is not None:
                        assert world.images.pixels(source.path).dtype == np.uint8
        assert all(loaded.assets.allows(path) for path in loaded.assets.files_read)


def path_texts():
    """Paths as a scene might write them, hostile ones included."""
    parts = st.sampled_from(["tex.png", "lib.mtl", "model.obj", "..", ".", "", "sub", "/", "//", "\\", "~",
                             "pipe.png", "escape.png", "n" * 300, "\x00", "TEX.PNG", "tex.png/", "*", "%s", "$HOME"])
    joined = st.lists(parts, min_size=1, max_size=5).map("/".join)
    return st.one_of(joined, joined.map(lambda p: "/" + p), st.text(max_size=40))


@FUZZ
@given(mesh=path_texts(), texture=st.none() | path_texts(), sky=st.none() | path_texts())
@example(mesh="model.obj", texture="\x00", sky="..")
def test_paths_written_in_the_scene(folder, mesh, texture, sky):
    """Any string where the scene names a file: a UserError or a file inside the folder."""
    (folder.root / "model.obj").write_text(valid_obj())
    scene = {"render": {"skybox": sky} if sky is not None else {},
             "materials": {"m": {"diffuse_map": texture} if texture is not None else {}},
             "objects": [{"mesh": mesh, "material": "m"}]}
    (folder.root / "scene.yaml").write_text(yaml.safe_dump(scene))
    try:
        loaded = load_scene(folder.root / "scene.yaml")
    except UserError as exc:
        assert all("\n" not in line for line in (exc.lines() if hasattr(exc, "lines") else [str(exc)]))
        return
    assert all(loaded.assets.allows(path) and path.is_file() for path in loaded.assets.files_read)


def test_the_fuzz_strategies_reach_both_outcomes(folder):
    """The generators are worth running only if they produce loadable and broken files."""
    assert load_obj(folder, valid_obj().encode()) is not None
    assert load_obj(folder, b"f 1 2 3\n") is None
    assert decode_checked(SEEDS["PNG"]) is not None
    assert decode_checked(SEEDS["PNG"][:40]) is None
