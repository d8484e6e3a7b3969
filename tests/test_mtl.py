"""MTL reading (scenerender.mesh.mtl)."""
from __future__ import annotations

from pathlib import Path

import pytest

from scenerender.errors import UserError, Warnings
from scenerender.mesh import MtlMaterial, TextureRef, parse_mtl
from scenerender.world.materials import resolve


def write(folder: Path, name: str, text: str = "") -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def touch_image(folder: Path, name: str) -> Path:
    path = folder / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"\x89PNG not really")
    return path


def parse(folder: Path, text: str, warnings: Warnings | None = None) -> dict[str, MtlMaterial]:
    return parse_mtl(write(folder, "materials.mtl", text), warnings if warnings is not None else Warnings())


def only_material(folder: Path, text: str, warnings: Warnings | None = None) -> MtlMaterial:
    materials = parse(folder, "newmtl m\n" + text, warnings)
    return materials["m"]


def test_colour_and_scalar_keys(tmp_path):
    material = only_material(
        tmp_path,
        "Ka 0.1 0.2 0.3\nKd 0.4 0.5 0.6\nKs 0.7 0.8 0.9\nKe 1 0.5 0\nNs 96.5\nd 0.25\nillum 2\n",
    )
    assert material.ambient == (0.1, 0.2, 0.3)
    assert material.diffuse == (0.4, 0.5, 0.6)
    assert material.specular == (0.7, 0.8, 0.9)
    assert material.emissive == (1.0, 0.5, 0.0)
    assert material.shininess == 96.5
    assert material.opacity == 0.25
    assert material.illum == 2
    assert material.location.line == 1
    assert material.location.file.endswith("materials.mtl")


def test_unset_values_are_none(tmp_path):
    material = only_material(tmp_path, "Kd 1 1 1\n")
    assert material.ambient is None and material.specular is None and material.emissive is None
    assert material.shininess is None and material.opacity is None and material.illum is None
    assert material.diffuse_map is None and material.normal_map is None


def test_single_value_colour_is_grey(tmp_path):
    assert only_material(tmp_path, "Kd 0.5\n").diffuse == (0.5, 0.5, 0.5)


def test_xyz_colour_is_converted_to_rgb(tmp_path):
    # D65 white in XYZ is linear sRGB white.
    diffuse = only_material(tmp_path, "Kd xyz 0.95047 1.0 1.08883\n").diffuse
    assert diffuse == pytest.approx((1.0, 1.0, 1.0), abs=1e-3)


def test_keys_are_case_insensitive_and_unknown_keys_ignored(tmp_path):
    warnings = Warnings()
    material = only_material(
        tmp_path,
        "ni 1.45\nTf 1 1 1\nmap_Ns spec.png\nPr 0.5\nkd 0.2 0.3 0.4\nNS 12\nILLUM 1\n",
        warnings,
    )
    assert material.diffuse == (0.2, 0.3, 0.4)
    assert material.shininess == 12.0
    assert material.illum == 1
    assert warnings.items == []


def test_tr_alone_gives_opacity_one_minus_tr(tmp_path):
    assert only_material(tmp_path, "Tr 0.25\n").opacity == pytest.approx(0.75)


@pytest.mark.parametrize("statements", ["d 0.4\nTr 0.9\n", "Tr 0.9\nd 0.4\n"])
def test_d_wins_over_tr_in_either_order(tmp_path, statements):
    assert only_material(tmp_path, statements).opacity == pytest.approx(0.4)


def test_d_with_halo_option(tmp_path):
    assert only_material(tmp_path, "d -halo 0.3\n").opacity == pytest.approx(0.3)


def test_several_materials_and_comments(tmp_path):
    materials = parse(
        tmp_path,
        "# exported\n\nnewmtl first\nKd 1 0 0\n\nnewmtl second material\nKd 0 1 0\n# end\n",
    )
    assert list(materials) == ["first", "second material"]
    assert materials["first"].diffuse == (1.0, 0.0, 0.0)
    assert materials["second material"].diffuse == (0.0, 1.0, 0.0)
    assert materials["second material"].location.line == 6


def test_all_map_keys(tmp_path):
    for name in ("a.png", "d.png", "s.png", "n.png", "o.png"):
        touch_image(tmp_path, name)
    material = only_material(tmp_path, "map_Ka a.png\nmap_Kd d.png\nmap_Ks s.png\nnorm n.png\nmap_d o.png\n")
    assert material.ambient_map.path == tmp_path / "a.png"
    assert material.diffuse_map.path == tmp_path / "d.png"
    assert material.specular_map.path == tmp_path / "s.png"
    assert material.normal_map.path == tmp_path / "n.png"
    assert material.opacity_map.path == tmp_path / "o.png"
    assert not material.diffuse_map.missing
    assert material.diffuse_map.scale == (1.0, 1.0)
    assert material.diffuse_map.offset == (0.0, 0.0)
    assert material.diffuse_map.bump_scale == 1.0
    assert material.diffuse_map.location.line == 3


@pytest.mark.parametrize("key", ["map_Bump", "bump", "map_bump", "norm"])
def test_bump_spellings_fill_the_normal_map(tmp_path, key):
    touch_image(tmp_path, "normal.png")
    assert only_material(tmp_path, f"{key} normal.png\n").normal_map.path == tmp_path / "normal.png"


def test_texture_options_scale_offset_and_bump_multiplier(tmp_path):
    touch_image(tmp_path, "bricks.png")
    material = only_material(
        tmp_path,
        "map_Kd -s 2 3 1 -o 0.5 0.25 bricks.png\nmap_Bump -bm 0.4 bricks.png\n",
    )
    texture = material.diffuse_map
    assert texture.path == tmp_path / "bricks.png"
    assert texture.scale == (2.0, 3.0)
    assert texture.offset == (0.5, 0.25)
    assert material.normal_map.bump_scale == pytest.approx(0.4)


def test_options_with_fewer_values_use_the_defaults_for_the_rest(tmp_path):
    touch_image(tmp_path, "bricks.png")
    texture = only_material(tmp_path, "map_Kd -s 4 -o 0.5 bricks.png\n").diffuse_map
    assert texture.scale == (4.0, 1.0)
    assert texture.offset == (0.5, 0.0)


def test_unused_options_are_skipped_to_find_the_file_name(tmp_path):
    touch_image(tmp_path, "wood.png")
    line = "map_Kd -clamp on -blendu off -blendv on -mm 0.1 0.9 -t 0.1 0.1 0 -texres 512 -imfchan r -cc off -boost 2 wood.png\n"
    warnings = Warnings()
    texture = only_material(tmp_path, line, warnings).diffuse_map
    assert texture.path == tmp_path / "wood.png"
    assert not texture.missing
    assert warnings.items == []


def test_file_name_with_spaces_after_options(tmp_path):
    touch_image(tmp_path, "old wood  planks.png")
    texture = only_material(tmp_path, "map_Kd -s 2 2 old wood  planks.png   \n").diffuse_map
    assert texture.path == tmp_path / "old wood  planks.png"
    assert texture.scale == (2.0, 2.0)
    assert not texture.missing


def test_numeric_looking_file_name_is_not_taken_as_an_option_value(tmp_path):
    touch_image(tmp_path, "2")
    texture = only_material(tmp_path, "map_Kd -s 3 2\n").diffuse_map
    assert texture.path == tmp_path / "2"
    assert texture.scale == (3.0, 1.0)


def test_backslashes_separate_folders(tmp_path):
    touch_image(tmp_path, "textures/stone.png")
    texture = only_material(tmp_path, "map_Kd textures\\stone.png\n").diffuse_map
    assert texture.path == tmp_path / "textures" / "stone.png"
    assert not texture.missing


def test_absolute_path_from_another_machine_falls_back_to_the_mtl_folder(tmp_path):
    touch_image(tmp_path, "stone.png")
    texture = only_material(tmp_path, "map_Kd C:\\Users\\artist\\maps\\stone.png\n").diffuse_map
    assert texture.path == tmp_path / "stone.png"
    assert not texture.missing


def test_letter_case_of_the_file_name_may_differ(tmp_path):
    touch_image(tmp_path, "Stone.PNG")
    texture = only_material(tmp_path, "map_Kd stone.png\n").diffuse_map
    assert texture.path == tmp_path / "Stone.PNG"
    assert not texture.missing


def test_missing_texture_warns_with_mtl_file_and_line(tmp_path):
    warnings = Warnings()
    material = only_material(tmp_path, "Kd 1 1 1\nmap_Kd -s 2 2 missing.png\n", warnings)
    texture = material.diffuse_map
    assert isinstance(texture, TextureRef)
    assert texture.missing
    assert texture.path == tmp_path / "missing.png"
    assert texture.scale == (2.0, 2.0)
    assert texture.location.line == 3
    assert len(warnings.items) == 1
    assert "materials.mtl:3:" in warnings.items[0]
    assert "texture 'missing.png' not found" in warnings.items[0]


def test_missing_texture_is_an_error_when_strict(tmp_path):
    with pytest.raises(UserError, match="missing.png") as caught:
        only_material(tmp_path, "map_Kd missing.png\n", Warnings(strict=True))
    assert caught.value.location.line == 2


def test_bad_number_names_file_and_line(tmp_path):
    with pytest.raises(UserError) as caught:
        parse(tmp_path, "newmtl m\nKd 1 1 1\nNs lots\n")
    assert caught.value.location.line == 3
    assert caught.value.location.file.endswith("materials.mtl")
    assert "'lots'" in caught.value.message


@pytest.mark.parametrize("line, key", [("Kd 1e39 0 0", "Kd"), ("Ns -1e39", "Ns"), ("map_Kd -s 1e39 1 a.png", "-s"),
                                       ("map_Kd -o 0 3.5e38 a.png", "-o"), ("map_Bump -bm 1e39 a.png", "-bm")])
def test_a_number_beyond_32_bit_floats_is_an_error_at_its_line(tmp_path, line, key):
    """Colours, shininess and texture options reach the shaders as 32-bit floats, where
    such a number would be infinite."""
    touch_image(tmp_path, "a.png")
    with pytest.raises(UserError) as caught:
        only_material(tmp_path, "Kd 1 1 1\n" + line + "\n")
    assert caught.value.location.line == 3
    assert caught.value.message.startswith(f"expected a number at most 3.4e38 in size (32-bit floats) after '{key}'")


def test_an_xyz_colour_converting_beyond_32_bit_floats_is_an_error(tmp_path):
    only_material(tmp_path, "Kd xyz 1e37 1e37 1e37\n")  # converts to about 3e37 at most
    with pytest.raises(UserError, match="beyond 32-bit floats") as caught:
        only_material(tmp_path, "Kd xyz 3e38 0 0\n")  # 3.24 times that in red
    assert caught.value.location.line == 2


def test_bad_texture_option_value_is_an_error(tmp_path):
    touch_image(tmp_path, "a.png")
    with pytest.raises(UserError, match="'big'") as caught:
        only_material(tmp_path, "map_Kd -s big 1 a.png\n")
    assert caught.value.location.line == 2


def test_colour_with_two_numbers_is_an_error(tmp_path):
    with pytest.raises(UserError, match="1 or 3 numbers") as caught:
        only_material(tmp_path, "Kd 1 0\n")
    assert caught.value.location.line == 2


def test_map_without_file_name_is_an_error(tmp_path):
    with pytest.raises(UserError, match="file name"):
        only_material(tmp_path, "map_Kd   \n")


def test_statement_before_newmtl_warns(tmp_path):
    warnings = Warnings()
    materials = parse(tmp_path, "Kd 1 0 0\nnewmtl m\nKd 0 1 0\n", warnings)
    assert materials["m"].diffuse == (0.0, 1.0, 0.0)
    assert len(warnings.items) == 1 and "materials.mtl:1:" in warnings.items[0]


def test_pbr_extension_keys(tmp_path):
    for name in ("rough.png", "metal.png", "glow.png", "n.png"):
        touch_image(tmp_path, name)
    material = only_material(tmp_path, "Kd 0.8 0.2 0.1\nPr 0.35\nPm 1.5\nKe 0.1 0.2 0.3\nmap_Pr rough.png\n"
                                       "map_Pm metal.png\nmap_Ke glow.png\nnorm n.png\n")
    assert material.roughness == 0.35
    assert material.metallic == 1.0  # clamped to [0, 1]
    assert material.emissive == (0.1, 0.2, 0.3)
    assert material.roughness_map.path.name == "rough.png"
    assert material.metallic_map.path.name == "metal.png"
    assert material.emissive_map.path.name == "glow.png"
    assert material.normal_map.path.name == "n.png"


def test_pbr_extension_keys_make_a_pbr_material(tmp_path):
    touch_image(tmp_path, "rough.png")
    pbr = resolve("m", only_material(tmp_path, "Kd 0.8 0.2 0.1\nPr 0.35\nPm 0.5\nmap_Pr rough.png\n"))
    assert pbr.model("blinn_phong") == "pbr"
    assert pbr.roughness(0.0) == 0.35 and pbr.metallic(0.0) == 0.5
    assert pbr.diffuse(0.0)[:3] == pytest.approx((0.8, 0.2, 0.1))
    assert not pbr.maps["roughness_map"].srgb
    plain = resolve("m", only_material(tmp_path, "Kd 0.8 0.2 0.1\nNs 20\n"))
    assert plain.model("phong") == "phong"
