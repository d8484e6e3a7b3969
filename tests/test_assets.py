"""Assets a scene reads: confinement to the allowed folders (scenerender.scene.assets),
regular files only, hostile and broken images (scenerender.scene.image_files and
scenerender.world.images), texture fallbacks, skybox checks, and what ``validate``
reports. No GL needed.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from asset_files import (
    TRIANGLE_OBJ, png_bytes, png_header_only, truncated_png, write,
)
from scenerender.cli import main
from scenerender.errors import SceneErrors, UserError, Warnings
from scenerender.limits import Limits
from scenerender.mesh import load_mesh
from scenerender.scene.assets import ENV_ROOTS, AssetPolicy
from scenerender.scene.files import read_regular_file
from scenerender.scene.image_files import ImageError, image_size
from scenerender.scene.loading import load_scene
from scenerender.world.build import build_world
from scenerender.world.images import decode_image

SKY_FACES = ("posx", "negx", "posy", "negy", "posz", "negz")


@pytest.fixture
def layout(tmp_path, monkeypatch):
    """tmp/scene/ holds the scene and a triangle; tmp/outside/ holds files it must not read."""
    monkeypatch.delenv(ENV_ROOTS, raising=False)
    scene, outside = tmp_path / "scene", tmp_path / "outside"
    write(scene / "tri.obj", TRIANGLE_OBJ)
    write(outside / "x.obj", TRIANGLE_OBJ)
    write(outside / "x.mtl", "newmtl a\nKd 1 0 0\n")
    write(outside / "t.png", png_bytes())
    return scene, outside


def build(scene_dir: Path, text: str, warnings: Warnings | None = None, **load_options):
    """Write scene.yaml, load it and build its world; returns (loaded, world)."""
    path = write(scene_dir / "scene.yaml", text)
    loaded = load_scene(path, **load_options)
    return loaded, build_world(loaded, warnings if warnings is not None else Warnings())


def mesh_scene(mesh: str) -> str:
    return f"objects:\n  - mesh: {json.dumps(mesh)}\n"


def obj_with_mtl(scene_dir: Path, mtl_text: str, name: str = "m") -> str:
    """An OBJ using material 'a' from ``name``.mtl; returns a scene text loading it."""
    write(scene_dir / f"{name}.mtl", mtl_text)
    write(scene_dir / f"{name}.obj", f"mtllib {name}.mtl\nusemtl a\n" + TRIANGLE_OBJ)
    return mesh_scene(f"{name}.obj")


def error_of(scene_dir: Path, text: str, **options) -> str:
    with pytest.raises(UserError) as caught:
        build(scene_dir, text, **options)
    error = caught.value
    return "\n".join(error.lines()) if isinstance(error, SceneErrors) else str(error)


# ---------------------------------------------------------------------------------------
# Confinement


ESCAPES = {
    "absolute path": lambda scene, out: mesh_scene(str(out / "x.obj")),
    "dot-dot": lambda scene, out: mesh_scene("../outside/x.obj"),
    "symlinked file": lambda scene, out: (os.symlink(out / "x.obj", scene / "link.obj"), mesh_scene("link.obj"))[1],
    "symlinked folder": lambda scene, out: (os.symlink(out, scene / "linked"), mesh_scene("linked/x.obj"))[1],
    "mtllib ../x.mtl": lambda scene, out: (write(scene / "m.obj", "mtllib ../outside/x.mtl\n" + TRIANGLE_OBJ),
                                           mesh_scene("m.obj"))[1],
    "map_Kd /abs/file.png": lambda scene, out: obj_with_mtl(scene, f"newmtl a\nmap_Kd {out / 't.png'}\n"),
    "map_Kd ../file.png": lambda scene, out: obj_with_mtl(scene, "newmtl a\nmap_Kd ../outside/t.png\n"),
    "scene material map": lambda scene, out: (
        "materials:\n  m: {diffuse_map: ../outside/t.png}\nobjects:\n  - mesh: tri.obj\n    material: m\n"),
    "skybox folder": lambda scene, out: "render: {skybox: ../outside}\nobjects: []\n",
    # a folder whose name merely starts with the scene folder's: containment is by path
    # components, not by string prefix
    "sibling with the same prefix": lambda scene, out: (
        write(scene.parent / f"{scene.name}-evil" / "x.obj", TRIANGLE_OBJ), mesh_scene(f"../{scene.name}-evil/x.obj"))[1],
}


@pytest.mark.parametrize("case", ESCAPES)
def test_assets_outside_the_scene_folder_are_refused(layout, case):
    scene, outside = layout
    text = ESCAPES[case](scene, outside)
    message = error_of(scene, text)
    assert "outside the folders this scene may read" in message
    assert "--asset-root DIR" in message and ENV_ROOTS in message
    assert message.count("\n") == 0  # one line


@pytest.mark.parametrize("case", ["absolute path", "dot-dot", "symlinked file", "symlinked folder",
                                  "mtllib ../x.mtl", "map_Kd /abs/file.png", "scene material map"])
def test_an_asset_root_allows_them(layout, case):
    scene, outside = layout
    text = ESCAPES[case](scene, outside)
    loaded, _ = build(scene, text, asset_roots=[outside])
    assert any(path.parent == outside.resolve() for path in loaded.assets.files_read)


# Each kind of reference, to a file or folder named NAME in the outside folder.
REACHES = {
    "mesh": lambda scene, out, name: mesh_scene(str(out / f"{name}.obj")),
    "mtllib": lambda scene, out, name: (write(scene / "m.obj", f"mtllib ../outside/{name}.mtl\n" + TRIANGLE_OBJ),
                                        mesh_scene("m.obj"))[1],
    "map_Kd absolute": lambda scene, out, name: obj_with_mtl(scene, f"newmtl a\nmap_Kd {out / name}.png\n"),
    "map_Kd dot-dot": lambda scene, out, name: obj_with_mtl(scene, f"newmtl a\nmap_Kd ../outside/{name}.png\n"),
    "scene material map": lambda scene, out, name: (
        f"materials:\n  m: {{diffuse_map: ../outside/{name}.png}}\nobjects:\n  - mesh: tri.obj\n    material: m\n"),
    "skybox folder": lambda scene, out, name: f"render: {{skybox: ../outside/{name}}}\nobjects: []\n",
}


@pytest.mark.parametrize("case", REACHES)
def test_an_outside_path_is_refused_the_same_whether_or_not_something_is_there(layout, case):
    """Where a path leads is decided before anything is looked up there: otherwise the
    outcome (an error, or a warning and exit code 0) would tell whether a file exists
    outside the folders the scene may read."""
    scene, outside = layout
    write(outside / "existing.obj", TRIANGLE_OBJ)
    write(outside / "existing.mtl", "newmtl a\nKd 1 0 0\n")
    write(outside / "existing.png", png_bytes())
    for face in SKY_FACES:
        write(outside / "existing" / f"{face}.png", png_bytes(8, 8))
    present = error_of(scene, REACHES[case](scene, outside, "existing"))
    absent = error_of(scene, REACHES[case](scene, outside, "missing"))
    assert "outside the folders this scene may read" in present
    assert absent == present.replace("existing", "missing")


def test_an_outside_texture_path_still_finds_the_file_beside_the_mtl(layout):
    """Exporters write absolute paths from the artist's machine; the file named so beside
    the MTL is used instead, whatever is (or is not) at the path written."""
    scene, outside = layout
    write(scene / "t.png", png_bytes())
    for written in (outside / "t.png", "/nowhere/scenerender/t.png"):
        warnings = Warnings()
        loaded, world = build(scene, obj_with_mtl(scene, f"newmtl a\nmap_Kd {written}\n"), warnings)
        assert world.objects[0].materials[0].maps["diffuse_map"].path == scene.resolve() / "t.png"
        assert warnings.items == []


@pytest.mark.parametrize("name", ["x.obj", "gone.obj"])
def test_load_mesh_refuses_a_path_outside_its_policy_before_looking_for_it(layout, name):
    scene, outside = layout
    with pytest.raises(UserError, match="outside the folders this scene may read"):
        load_mesh(outside / name, warnings=Warnings(), assets=AssetPolicy(scene, environ={}))


def test_the_environment_variable_allows_them(layout, monkeypatch):
    scene, outside = layout
    monkeypatch.setenv(ENV_ROOTS, os.pathsep.join(["", str(outside)]))
    loaded, _ = build(scene, mesh_scene("../outside/x.obj"))
    assert loaded.assets.files_read == [outside.resolve() / "x.obj"]


def test_a_symlink_staying_inside_the_scene_folder_is_fine(layout):
    scene, _ = layout
    os.symlink(scene / "tri.obj", scene / "alias.obj")
    loaded, _ = build(scene, mesh_scene("alias.obj"))
    assert loaded.assets.files_read == [scene.resolve() / "tri.obj"]


def test_an_asset_root_that_is_not_a_folder_is_an_error(layout):
    scene, outside = layout
    with pytest.raises(UserError, match="not a folder") as caught:
        AssetPolicy(scene, [outside / "t.png"])
    assert str(caught.value.location) == "--asset-root"


def test_files_read_lists_every_file_once_in_order(layout):
    scene, _ = layout
    write(scene / "tex/wood.png", png_bytes())
    write(scene / "tex/stone.png", png_bytes())
    for face in SKY_FACES:
        write(scene / f"sky/{face}.png", png_bytes(8, 8))
    text = obj_with_mtl(scene, "newmtl a\nmap_Kd tex/wood.png\nmap_Ks tex/wood.png\n")
    text = ("render: {skybox: sky}\nmaterials:\n  s: {diffuse_map: tex/stone.png}\n" + text
            + "  - mesh: m.obj\n  - mesh: tri.obj\n    material: s\n")
    loaded, _ = build(scene, text)
    root = scene.resolve()
    # validation names the scene's own files; building the world adds what they name
    expected = [root / f"sky/{face}.png" for face in SKY_FACES] + [
        root / "tex/stone.png", root / "m.obj", root / "tri.obj", root / "m.mtl", root / "tex/wood.png"]
    assert loaded.assets.files_read == expected


# ---------------------------------------------------------------------------------------
# Regular files and valid names


def test_a_fifo_as_mesh_or_texture_is_refused_without_blocking(layout):
    scene, _ = layout
    os.mkfifo(scene / "pipe.obj")
    os.mkfifo(scene / "pipe.png")
    assert "FIFO" in error_of(scene, mesh_scene("pipe.obj"))
    assert "FIFO" in error_of(scene, obj_with_mtl(scene, "newmtl a\nmap_Kd pipe.png\n"))
    assert "FIFO" in error_of(scene, "materials:\n  m: {diffuse_map: pipe.png}\nobjects: []\n")
    with pytest.raises(UserError, match="FIFO"):  # swapped in after validation: still no hang
        read_regular_file(scene / "pipe.obj")
    with pytest.raises(UserError, match="FIFO"):
        load_mesh(scene / "pipe.obj", warnings=Warnings())


def test_a_folder_is_not_a_mesh(layout):
    scene, _ = layout
    (scene / "dir.obj").mkdir()
    assert "is a folder, not a regular file" in error_of(scene, mesh_scene("dir.obj"))


def test_an_over_long_mesh_name_is_a_user_error(layout):
    scene, _ = layout
    message = error_of(scene, mesh_scene("n" * 300 + ".obj"))
    assert "file name too long" in message
    assert len(message) < 300  # the name is shortened in the message


@pytest.mark.parametrize("where", ["mtllib", "map_Kd", "map_Kd absolute"])
def test_an_over_long_name_in_an_obj_or_mtl_is_missing_with_a_warning(layout, where):
    scene, _ = layout
    long_name = "n" * 300
    text = {
        "mtllib": lambda: (write(scene / "m.obj", f"mtllib {long_name}.mtl\n" + TRIANGLE_OBJ), mesh_scene("m.obj"))[1],
        "map_Kd": lambda: obj_with_mtl(scene, f"newmtl a\nmap_Kd {long_name}.png\n"),
        # absolute, and inside the scene folder (outside it, the path is refused as written)
        "map_Kd absolute": lambda: obj_with_mtl(
            scene, f"newmtl a\nmap_Kd {scene.resolve()}/{long_name}/{long_name}.png\n"),
    }[where]()
    warnings = Warnings()
    build(scene, text, warnings)
    assert len(warnings.items) == 1 and len(warnings.items[0]) < 400
    assert "file name too long" in warnings.items[0] or "not found" in warnings.items[0]
    with pytest.raises(UserError):
        build(scene, text, Warnings(strict=True))


# ---------------------------------------------------------------------------------------
# Images


def test_a_corrupt_texture_named_by_an_mtl_is_a_warning_and_the_placeholder(layout):
    scene, _ = layout
    write(scene / "broken.png", truncated_png())
    warnings = Warnings()
    _, world = build(scene, obj_with_mtl(scene, "newmtl a\nmap_Kd broken.png\nmap_Ks broken.png\n"), warnings)
    maps = world.objects[0].materials[0].maps
    assert maps["diffuse_map"].is_placeholder and maps["specular_map"].is_placeholder
    assert len(warnings.items) == 1  # once per file, however many maps use it
    assert "m.mtl:2:" in warnings.items[0] and "broken.png" in warnings.items[0]
    assert "placeholder" in warnings.items[0]


def test_a_corrupt_texture_named_by_an_mtl_is_an_error_when_strict(layout):
    scene, _ = layout
    write(scene / "broken.png", truncated_png())
    with pytest.raises(UserError, match="truncated"):
        build(scene, obj_with_mtl(scene, "newmtl a\nmap_Kd broken.png\n"), Warnings(strict=True))


def test_a_corrupt_texture_named_by_the_scene_is_an_error_at_its_key(layout):
    scene, _ = layout
    write(scene / "broken.png", truncated_png())
    text = "objects:\n  - mesh: tri.obj\n    material: {diffuse_map: broken.png}\n"
    message = error_of(scene, text)
    assert "scene.yaml:3:" in message and "objects[0].material.diffuse_map" in message
    assert "truncated" in message


def test_a_file_that_is_no_image_named_by_the_scene(layout):
    scene, _ = layout
    write(scene / "notes.png", "just text\n")
    message = error_of(scene, "materials:\n  m: {diffuse_map: notes.png}\nobjects: []\n")
    assert "materials.m.diffuse_map: not an image this renderer reads" in message


def test_formats_outside_the_list_are_not_opened(tmp_path):
    # Pillow would recognise this as EPS (whose decoder runs Ghostscript)
    path = write(tmp_path / "cover.png", "%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 10 10\nshowpage\n")
    with pytest.raises(ImageError, match="not an image this renderer reads"):
        image_size(path)


def test_a_decompression_bomb_header_is_refused_before_decoding(tmp_path, capfd):
    path = write(tmp_path / "bomb.png", png_header_only(100_000, 100_000))
    for read in (image_size, decode_image):
        with pytest.raises(ImageError) as caught:
            read(path)
        assert "100000x100000" in caught.value.reason
        assert "--limit texture_pixels=N" in caught.value.reason
    assert capfd.readouterr().err == ""  # Pillow's multi-line warning does not leak
    assert Image.MAX_IMAGE_PIXELS is not None  # Pillow's own check is back for other callers


def test_the_texture_pixel_limit_comes_from_the_scene_limits(layout):
    scene, _ = layout
    write(scene / "t.png", png_bytes(8, 8))
    text = "materials:\n  m: {diffuse_map: t.png}\nobjects: []\n"
    build(scene, text)
    message = error_of(scene, text, limits=Limits(texture_pixels=63))
    assert "64, over the limit of 63" in message


def test_a_texture_side_longer_than_any_device_takes_is_refused(tmp_path):
    path = write(tmp_path / "strip.png", png_header_only(20_000, 2))  # 40,000 pixels: under the limit
    with pytest.raises(ImageError, match="at most 16384 pixels on a side"):
        image_size(path)


def test_a_bomb_named_by_an_mtl_is_a_placeholder(layout):
    scene, _ = layout
    write(scene / "bomb.png", png_header_only(100_000, 100_000))
    warnings = Warnings()
    _, world = build(scene, obj_with_mtl(scene, "newmtl a\nmap_Kd bomb.png\n"), warnings)
    assert world.objects[0].materials[0].maps["diffuse_map"].is_placeholder
    assert "over the limit" in warnings.items[0]


def test_decoded_images_are_kept_for_the_upload(layout):
    scene, _ = layout
    write(scene / "t.png", png_bytes(8, 4, (1, 2, 3, 255)))
    _, world = build(scene, obj_with_mtl(scene, "newmtl a\nmap_Kd t.png\n"))
    pixels = world.images.pixels(world.objects[0].materials[0].maps["diffuse_map"].path)
    assert pixels.shape == (4, 8, 4) and pixels.dtype == np.uint8
    assert tuple(pixels[0, 0]) == (1, 2, 3, 255)


# ---------------------------------------------------------------------------------------
# Skyboxes


def write_sky(folder: Path, odd_face: str | None = None, odd_size=(8, 4)):
    for face in SKY_FACES:
        width, height = odd_size if face == odd_face else (8, 8)
        write(folder / f"{face}.png", png_bytes(width, height))


@pytest.mark.parametrize("odd_size", [(8, 4), (16, 16)])
def test_skybox_faces_must_be_square_and_equal_and_validate_says_so(layout, monkeypatch, odd_size):
    scene, _ = layout
    write_sky(scene / "sky", odd_face="negy", odd_size=odd_size)
    write(scene / "scene.yaml", "render: {skybox: sky}\nobjects: []\n")
    monkeypatch.chdir(scene)
    result = CliRunner().invoke(main, ["validate", "scene.yaml"])
    assert result.exit_code == 2
    assert result.stderr.startswith("error: scene.yaml:1:10: render.skybox.negy: skybox faces must be square")
    assert f"negy is {odd_size[0]}x{odd_size[1]}" in result.stderr


def test_a_corrupt_skybox_face_is_an_error_naming_the_face(layout):
    scene, _ = layout
    write_sky(scene / "sky")
    write(scene / "sky/posz.png", truncated_png(8, 8))  # the header reads, the data does not
    faces = ", ".join(f"{face}: sky/{face}.png" for face in SKY_FACES)
    message = error_of(scene, f"render:\n  skybox: {{{faces}}}\nobjects: []\n")
    assert "render.skybox.posz" in message and "posz face" in message


# ---------------------------------------------------------------------------------------
# validate runs what render runs


def test_validate_lists_asset_warnings_and_counts_files(layout, monkeypatch):
    scene, _ = layout
    write(scene / "broken.png", truncated_png())
    obj_with_mtl(scene, "newmtl a\nmap_Kd broken.png\nmap_Ka gone.png\n")
    write(scene / "scene.yaml", mesh_scene("m.obj"))
    monkeypatch.chdir(scene)
    result = CliRunner().invoke(main, ["validate", "scene.yaml"])
    assert result.exit_code == 0, result.output
    warnings = [line for line in result.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 2
    assert "gone.png' not found" in warnings[0] and "broken.png" in warnings[1]
    assert "3 asset file(s), 2 warning(s)" in result.stdout
    strict = CliRunner().invoke(main, ["validate", "scene.yaml", "--strict"])
    assert strict.exit_code == 2


def test_validate_and_graph_take_asset_roots(layout, monkeypatch):
    scene, outside = layout
    write(scene / "scene.yaml", mesh_scene("../outside/x.obj"))
    monkeypatch.chdir(scene)
    refused = CliRunner().invoke(main, ["validate", "scene.yaml"])
    assert refused.exit_code == 2 and "--asset-root" in refused.stderr
    for command in ("validate", "graph"):
        allowed = CliRunner().invoke(main, [command, "scene.yaml", "--asset-root", str(outside)])
        assert allowed.exit_code == 0, allowed.output


def test_the_triangle_limit_is_checked_while_the_obj_is_read(layout):
    scene, _ = layout
    rows = ["v 0 0 0", "v 1 0 0", "v 0 1 0"] + ["f 1 2 3"] * 50
    write(scene / "many.obj", "\n".join(rows) + "\n")
    message = error_of(scene, mesh_scene("many.obj"), limits=Limits(triangles=20))
    assert "many.obj:24:" in message  # the face that went over, found while reading
    assert "--limit triangles=N" in message


def test_the_triangle_limit_counts_all_meshes_together(layout):
    scene, _ = layout
    text = "objects:\n" + "".join(f"  - mesh: {{primitive: box}}\n    position: [{i}, 0, 0]\n" for i in range(3))
    build(scene, text, limits=Limits(triangles=12))  # one box, loaded once
    text = "objects:\n  - mesh: {primitive: box}\n  - mesh: tri.obj\n"
    message = error_of(scene, text, limits=Limits(triangles=12))
    assert "triangles in the scene's meshes is 13, over the limit of 12" in message


def test_repeated_warnings_of_one_file_are_counted_not_listed(layout):
    scene, _ = layout
    mtl = "".join(f"newmtl m{i}\nmap_Kd gone{i}.png\n" for i in range(10))
    warnings = Warnings()
    build(scene, obj_with_mtl(scene, "newmtl a\n" + mtl), warnings)
    assert len(warnings.items) == 4
    assert all("not found" in item for item in warnings.items[:3])
    assert warnings.items[3].endswith("m.mtl: and 7 more warnings like these")
