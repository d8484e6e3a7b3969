"""The on-disk cache of parsed OBJ meshes (scenerender.mesh.cache)."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from scenerender.errors import UserError, Warnings
from scenerender.mesh import cache as cache_module
from scenerender.mesh import obj as obj_module
from scenerender.mesh import load_mesh
from scenerender.scene.assets import AssetPolicy


@pytest.fixture
def cache_dir(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("SCENERENDER_CACHE_DIR", str(folder))
    monkeypatch.delenv("SCENERENDER_CACHE", raising=False)
    monkeypatch.setattr(cache_module, "MIN_CACHED_BYTES", 0)  # the test models are small
    return folder / "meshes"


def write_model(folder: Path, lift: float = 0.0, library: str = "model.mtl") -> Path:
    """A textured grid with two materials and a degenerate face (one warning)."""
    folder.mkdir(parents=True, exist_ok=True)
    Image.new("RGB", (4, 4), (200, 30, 30)).save(folder / "red.png")
    (folder / "model.mtl").write_text("newmtl red\nKd 1 0 0\nmap_Kd red.png\nnewmtl blue\nKd 0 0 1\n")
    lines = [f"mtllib {library}"]
    n = 6
    for y in range(n):
        for x in range(n):
            lines.append(f"v {x} {y} {0.1 * x * y + lift}")
            lines.append(f"vt {x / n} {y / n}")
    for y in range(n - 1):
        lines.append("usemtl red" if y < 2 else "usemtl blue")
        for x in range(n - 1):
            a = y * n + x + 1
            lines.append(f"f {a}/{a} {a + 1}/{a + 1} {a + n + 1}/{a + n + 1} {a + n}/{a + n}")
    lines.append("f 1/1 1/1 2/2")  # zero area: skipped with a warning
    path = folder / "model.obj"
    path.write_text("\n".join(lines) + "\n")
    return path


def load(path: Path, warnings: Warnings | None = None, assets: AssetPolicy | None = None, **options):
    return load_mesh(path, warnings=warnings if warnings is not None else Warnings(),
                     assets=assets, **options)


def assert_same_mesh(a, b):
    for name in ("positions", "normals", "uvs", "indices"):
        left, right = getattr(a, name), getattr(b, name)
        assert left.dtype == right.dtype and np.array_equal(left, right), name
    assert a.groups == b.groups and a.materials == b.materials and a.source == b.source


def entries(folder: Path) -> list[Path]:
    return sorted(folder.glob("*.npz")) if folder.is_dir() else []


def forbid_parsing(monkeypatch):
    def parse_obj(*args, **kwargs):
        raise AssertionError("parsed although an entry is cached")

    monkeypatch.setattr(obj_module, "parse_obj", parse_obj)  # the loader imports it from there when it reads


def test_cached_load_equals_a_fresh_parse(tmp_path, cache_dir, monkeypatch):
    path = write_model(tmp_path / "m")
    fresh = load(path, normals="smooth", normalize=True)
    assert len(entries(cache_dir)) == 1
    forbid_parsing(monkeypatch)
    cached = load(path, normals="smooth", normalize=True)
    assert_same_mesh(cached, fresh)
    assert cached.materials["red"].diffuse_map.path.name == "red.png"


def test_an_entry_keeps_the_closed_surface_analysis(tmp_path, cache_dir, monkeypatch):
    """A cube: closed, wound outwards; the cached load does not work it out again."""
    folder = tmp_path / "cube"
    folder.mkdir()
    corners = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    quads = [(2, 4, 3, 1), (7, 8, 6, 5), (5, 6, 2, 1), (4, 8, 7, 3), (3, 7, 5, 1), (6, 8, 4, 2)]
    (folder / "cube.obj").write_text("".join(f"v {x} {y} {z}\n" for x, y, z in corners)
                                     + "".join(f"f {a} {b} {c} {d}\n" for a, b, c, d in quads))
    assert load(folder / "cube.obj").closed_winding() == 1
    forbid_parsing(monkeypatch)
    from scenerender.mesh import topology

    monkeypatch.setattr(topology, "closed_winding", lambda *a: pytest.fail("analysed again"))
    assert load(folder / "cube.obj").closed_winding() == 1


def test_other_options_or_a_changed_file_miss(tmp_path, cache_dir):
    path = write_model(tmp_path / "m")
    first = load(path)
    flat = load(path, normals="flat")
    write_model(tmp_path / "m", lift=1.0)
    changed = load(path)
    assert len(entries(cache_dir)) == 3
    assert not np.array_equal(flat.normals, first.normals) or len(flat.positions) != len(first.positions)
    assert changed.positions[:, 2].min() == pytest.approx(first.positions[:, 2].min() + 1.0)


def test_warnings_of_the_first_parse_are_given_again(tmp_path, cache_dir, monkeypatch):
    path = write_model(tmp_path / "m")
    first = Warnings()
    load(path, first)
    assert any("skipped" in text for text in first.items)
    forbid_parsing(monkeypatch)
    again = Warnings()
    load(path, again)
    assert again.items == first.items
    with pytest.raises(UserError, match="skipped"):
        load(path, Warnings(strict=True))


@pytest.mark.parametrize("damage", ["garbage", "truncated", "index_out_of_range", "float64_positions",
                                    "infinite_uvs", "other_key"])
def test_a_damaged_or_foreign_entry_is_ignored_and_rewritten(tmp_path, cache_dir, damage):
    path = write_model(tmp_path / "m")
    fresh = load(path)
    [entry] = entries(cache_dir)
    if damage == "garbage":
        entry.write_bytes(b"not a zip at all")
    elif damage == "truncated":
        entry.write_bytes(entry.read_bytes()[:200])
    else:
        with np.load(entry) as npz:
            arrays = {name: npz[name] for name in npz.files}
        if damage == "index_out_of_range":
            arrays["indices"] = arrays["indices"] + np.uint32(10_000)
        elif damage == "float64_positions":
            arrays["positions"] = arrays["positions"].astype(np.float64)
        elif damage == "infinite_uvs":
            arrays["uvs"][0, 0] = np.inf
        else:  # an entry of another file copied over this one
            arrays["meta"] = np.frombuffer(bytes(arrays["meta"]).replace(entry.stem.encode(), b"0" * 64),
                                           np.uint8)
        with open(entry, "wb") as handle:
            np.savez(handle, **arrays)
    assert cache_module.read_entry(entry, entry.stem) is None
    assert_same_mesh(load(path), fresh)
    assert cache_module.read_entry(entry, entry.stem) is not None  # written again


def test_a_number_beyond_32_bit_floats_is_the_same_error_on_every_load(tmp_path, cache_dir):
    path = write_model(tmp_path / "m")
    path.write_text(path.read_text() + "vt 1e39 0\n")
    messages = []
    for _ in range(2):
        with pytest.raises(UserError) as caught:
            load(path)
        messages.append(str(caught.value))
    assert messages[0] == messages[1] and "at most 3.4e38 in size (32-bit floats)" in messages[0]
    assert entries(cache_dir) == []


def test_an_entry_of_the_reader_that_took_numbers_beyond_32_bit_floats_is_not_used(tmp_path, cache_dir,
                                                                                  monkeypatch):
    """Reader version 2 read 'vt 1e39' and stored a mesh for it; that file is refused now,
    so such an entry must not stand in for the parse."""
    path = write_model(tmp_path / "m")
    mesh = load(path, normals="smooth")
    [current] = entries(cache_dir)
    current.unlink()
    path.write_text(path.read_text() + "vt 1e39 0\n")  # not used by any face: the same arrays
    with monkeypatch.context() as version_2:
        version_2.setattr(cache_module, "LOADER_VERSION", 2)
        old_key = cache_module.entry_key(path.read_bytes(), normals="smooth", normalize=False)
    cache_module.write_entry(cache_dir / f"{old_key}.npz", old_key, mesh, [], ["model.mtl"])
    with pytest.raises(UserError, match="32-bit floats"):
        load(path, normals="smooth")


def test_a_cached_mesh_whose_library_gained_a_number_beyond_32_bit_floats_is_refused(tmp_path, cache_dir):
    path = write_model(tmp_path / "m")
    load(path)
    (path.parent / "model.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nNs 1e39\n")
    with pytest.raises(UserError, match="32-bit floats") as caught:
        load(path)
    assert str(caught.value.location).endswith("model.mtl:4")


def test_a_cached_load_reads_the_libraries_through_the_asset_policy(tmp_path, cache_dir):
    path = write_model(tmp_path / "scene" / "models", library="../../shared/model.mtl")
    shared = tmp_path / "shared"
    shared.mkdir()
    os.replace(path.parent / "model.mtl", shared / "model.mtl")
    os.replace(path.parent / "red.png", shared / "red.png")
    wide = AssetPolicy(tmp_path / "scene", extra_roots=[shared])
    load(path, assets=wide)
    assert len(entries(cache_dir)) == 1
    again = AssetPolicy(tmp_path / "scene", extra_roots=[shared])
    load(path, assets=again)
    assert {p.name for p in again.files_read} >= {"model.mtl", "red.png"}
    with pytest.raises(UserError, match="model.obj:1"):  # refused, at the mtllib line
        load(path, assets=AssetPolicy(tmp_path / "scene"))


def test_an_edited_library_is_read_again(tmp_path, cache_dir):
    path = write_model(tmp_path / "m")
    load(path)
    (path.parent / "model.mtl").write_text("newmtl red\nKd 0 1 0\nnewmtl blue\nKd 0 0 1\n")
    assert load(path).materials["red"].diffuse == (0.0, 1.0, 0.0)


def test_cache_can_be_turned_off(tmp_path, cache_dir, monkeypatch):
    monkeypatch.setenv("SCENERENDER_CACHE", "0")
    load(write_model(tmp_path / "m"))
    assert entries(cache_dir) == []


def test_cache_folder_follows_the_environment(tmp_path):
    assert cache_module.cache_folder({"XDG_CACHE_HOME": "/x"}) == Path("/x/scenerender/meshes")
    assert cache_module.cache_folder({"SCENERENDER_CACHE_DIR": "/y", "XDG_CACHE_HOME": "/x"}) == Path("/y/meshes")
    assert cache_module.cache_folder({"SCENERENDER_CACHE": "0"}) is None


def test_eviction_removes_the_least_recently_used_first(tmp_path):
    for age, name in enumerate(["new", "middle", "old"]):
        entry = tmp_path / f"{name}.npz"
        entry.write_bytes(b"x" * 100)
        os.utime(entry, (1_000_000 - age * 10, 1_000_000 - age * 10))
    partial = tmp_path / ".k.npz.1-abcd.partial"
    partial.write_bytes(b"x")
    os.utime(partial, (0, 0))
    cache_module.evict(tmp_path, limit=250)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["middle.npz", "new.npz"]
