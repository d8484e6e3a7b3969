"""The format reference shipped in the repository cannot drift from the schema.

docs/scene-format.md and scene.schema.json are generated; these tests regenerate both and
compare them with the committed files, check that every key of the schema is described
(and no description names a key that is gone), and validate every example the reference
shows, per key and per YAML block.
"""
from __future__ import annotations

import copy
import json
import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from scenerender.cli import main
from scenerender.scene.json_schema import scene_json_schema
from scenerender.scene.loading import load_scene_data, load_scene_text
from scenerender.scene.reference import (
    REGENERATE, SchemaWalker, Table, editor_schema, entry_for, reference_markdown, scene_tables, stale_entries, undocumented_keys,
)
from scenerender.scene.reference_keys import KEYS
from scenerender.scene.yaml_source import parse_yaml_text
from scenerender.world.environment_files import write_hdr

ROOT = Path(__file__).resolve().parent.parent
REFERENCE = ROOT / "docs" / "scene-format.md"
SCHEMA_FILE = ROOT / "scene.schema.json"
SKY_FACES = ("posx", "negx", "posy", "negy", "posz", "negz")

# Keys that the schema does not require but a validator does, for an example to stand alone.
CONTEXT = {"lights[spot]": {"position": [0, 4, 0]}, "camera": {"position": [0, 2, 8]}}


@pytest.fixture(scope="module")
def tables() -> list[Table]:
    return scene_tables()


@pytest.fixture(scope="module")
def scene_dir(tmp_path_factory) -> Path:
    """A folder holding the files the reference's examples name."""
    root = tmp_path_factory.mktemp("scene")
    (root / "models").mkdir()
    (root / "models" / "duck.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (root / "models" / "walker.glb").write_bytes(b"")  # named, not read: the examples only validate
    (root / "textures" / "sky").mkdir(parents=True)
    Image.new("RGB", (2, 2), (90, 140, 60)).save(root / "textures" / "ground.png")
    for face in SKY_FACES:
        Image.new("RGB", (2, 2), (120, 160, 220)).save(root / "textures" / "sky" / f"{face}.png")
    (root / "assets" / "environments").mkdir(parents=True)
    write_hdr(root / "assets" / "environments" / "studio.hdr", np.ones((4, 8, 3)))
    return root


# -- the committed files ------------------------------------------------------------------

def _committed(path: Path) -> str:
    return path.read_text(encoding="utf-8") if path.is_file() else ""


def test_committed_reference_is_current():
    assert _committed(REFERENCE) == reference_markdown(), (
        f"docs/scene-format.md is stale; regenerate it with `{REGENERATE}`")


def test_committed_json_schema_is_current():
    assert _committed(SCHEMA_FILE) == editor_schema() + "\n", (
        "scene.schema.json is stale; regenerate it with `scenerender schema -o scene.schema.json`")


def test_cli_prints_the_reference_and_the_schema():
    runner = CliRunner()
    markdown = runner.invoke(main, ["schema", "--markdown"])
    assert markdown.exit_code == 0, markdown.output
    assert markdown.output == reference_markdown()
    schema = runner.invoke(main, ["schema"])
    assert json.loads(schema.output)["title"] == "scenerender scene"


def test_every_key_of_the_editor_schema_has_a_description():
    """Editors show these on hover and in completion lists."""
    schema = json.loads(editor_schema())
    models = [schema, *schema["$defs"].values()]
    assert [key for model in models for key, value in model.get("properties", {}).items()
            if not value.get("description")] == []
    assert schema["$defs"]["ShadowOverride"]["properties"]["pcf"]["description"].startswith("Filter width")

# -- descriptions cover exactly the schema's keys -----------------------------------------

def test_every_key_of_the_schema_is_described(tables):
    assert undocumented_keys(tables) == [], "describe these keys in scenerender/scene/reference_keys.py"


def test_no_description_names_a_key_that_does_not_exist(tables):
    assert stale_entries(tables) == [], "these entries of scenerender/scene/reference_keys.py describe no key"


def test_a_new_schema_key_is_reported_undescribed():
    """The guard itself: a key added to the models shows up as undescribed."""
    schema = json.loads(scene_json_schema())
    schema["$defs"]["Fog"]["properties"]["height_falloff"] = {"type": "number", "minimum": 0, "default": 0}
    assert undocumented_keys(SchemaWalker(schema).walk()) == ["render.fog.height_falloff"]


def test_a_removed_schema_key_leaves_its_description_stale():
    schema = json.loads(scene_json_schema())
    del schema["$defs"]["Fog"]["properties"]["start"]
    assert stale_entries(SchemaWalker(schema).walk()) == ["render.fog.start"]


def test_a_changed_range_changes_the_reference():
    schema = json.loads(scene_json_schema())
    before = _row(SchemaWalker(copy.deepcopy(schema)).walk(), "render.ambient_occlusion.samples")
    schema["$defs"]["AmbientOcclusion"]["properties"]["samples"]["maximum"] = 32
    after = _row(SchemaWalker(schema).walk(), "render.ambient_occlusion.samples")
    assert (before.type_text, after.type_text) == ("whole number in [1, 64]", "whole number in [1, 32]")


def test_what_the_tables_say_about_some_keys(tables):
    fog_density = _row(tables, "render.fog.density")
    assert (fog_density.type_text, fog_density.default, fog_density.animatable) == ("number ≥ 0", "`0.03`", "yes")
    assert _row(tables, "objects[].visible").animatable == "yes (step)"
    assert _row(tables, "render.background").default == "`[0.1, 0.1, 0.12]`"
    assert _row(tables, "lights[spot].type").fixed == "spot"
    assert _row(tables, "objects[].mesh").default == "required"
    assert "render.shadows" in _row(tables, "lights[point].shadows").type_text


# -- every example validates --------------------------------------------------------------

def _row(tables, path):
    return next(row for table in tables for row in table.rows if row.path == path)


def _yaml_value(text: str):
    data, _ = parse_yaml_text(f"value: {text}\n", "example")
    return data["value"]


def _example_rows():
    return [row for table in scene_tables() for row in table.rows if row.fixed is None]


def _own_mapping(table: Table, key: str, value) -> dict:
    """A mapping of ``table`` holding ``key: value``, plus what it cannot do without."""
    mapping = copy.deepcopy(CONTEXT.get(table.path, {}))
    for row in table.rows:
        if row.fixed is not None:
            mapping[row.name] = row.fixed
        elif row.default == "required":
            mapping[row.name] = _yaml_value(KEYS[entry_for(row.path, KEYS)].example)
    mapping[key] = value
    if table.path == "camera" and key == "pose":  # a pose places the camera instead of a position
        mapping.pop("position", None)
    if table.path == "camera" and key in ("from", "name"):  # a file's camera places the camera itself
        mapping.pop("position", None)
        mapping["from"] = "walker"
    if table.path == "objects[]" and key in ("animation", "lights", "variant"):  # clips, lights, variants: a glTF file's
        mapping["mesh"] = "models/walker.glb"
    if table.path == "camera.pose" and key == "convention":  # a pose needs its matrix
        mapping["camera_to_world"] = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 5], [0, 0, 0, 1]]
    return mapping


def _scene_holding(tables: list[Table], path: str, value) -> dict:
    """The smallest scene in which key ``path`` has ``value``."""
    table = next(t for t in tables if any(row.path == path for row in t.rows))
    mapping = _own_mapping(table, _row([table], path).name, value)
    while table.path:
        parent_row, rest = max(((row, table.path[len(row.path):]) for t in tables for row in t.rows
                                if table.path.startswith(row.path) and re.fullmatch(r"|\[\w*\]|\.<name>", table.path[len(row.path):])),
                               key=lambda found: len(found[0].path))
        if rest == ".<name>":
            value = {"example": mapping}
        elif rest.startswith("[") and parent_row.type_text.startswith("list of"):
            value = [mapping]
        else:
            value = mapping
        table = next(t for t in tables if parent_row in t.rows)
        mapping = _own_mapping(table, parent_row.name, value)
    return mapping


@pytest.mark.parametrize("row", _example_rows(), ids=lambda row: row.path)
def test_example_of_each_key_validates(row, tables, scene_dir):
    example = _yaml_value(KEYS[entry_for(row.path, KEYS)].example)
    data = _scene_holding(tables, row.path, example)
    if row.path.startswith("lights[environment]"):  # image: sky, the default, needs a skybox
        data["lights"][0].setdefault("image", "assets/environments/studio.hdr")
    load_scene_data(data, scene_dir, name="example.yaml")


def _yaml_blocks(text: str) -> list[str]:
    return re.findall(r"```yaml\n(.*?)```", text, re.S)


def test_every_yaml_block_of_the_reference_is_a_valid_scene(scene_dir):
    blocks = _yaml_blocks(reference_markdown())
    assert len(blocks) >= 8
    for block in blocks:  # a block showing one section is completed with the background alone
        load_scene_text(block if re.search(r"^objects:", block, re.M) else block + "objects: []\n", scene_dir)


def test_every_link_inside_the_reference_has_a_heading():
    text = reference_markdown()
    targets, seen = set(), {}
    for heading in re.findall(r"^#+ (.+)$", text, re.M):
        slug = re.sub(r"[^\w\- ]", "", heading.replace("`", "").lower()).replace(" ", "-")
        targets.add(f"{slug}-{seen[slug]}" if slug in seen else slug)
        seen[slug] = seen.get(slug, 0) + 1
    links = re.findall(r"\]\(#([^)]+)\)", text)
    assert len(links) > 20
    assert sorted(set(links) - targets) == []
    assert "scene-notes.md" in text


# -- the reference ships --------------------------------------------------------------------

def test_source_distribution_carries_the_reference_and_the_schema(tmp_path):
    pytest.importorskip("hatchling")
    import subprocess
    import sys
    import tarfile

    subprocess.run([sys.executable, "-m", "hatchling", "build", "-t", "sdist", "-d", str(tmp_path)],
                   cwd=ROOT, check=True, capture_output=True, timeout=120)
    archive = next(tmp_path.glob("scenerender-*.tar.gz"))
    names = {name.split("/", 1)[1] for name in tarfile.open(archive).getnames() if "/" in name}
    assert {"docs/scene-format.md", "docs/scene-notes.md", "scene.schema.json"} <= names


# -- the editor schema accepts what scenerender accepts --------------------------------------

@pytest.mark.parametrize("scene", sorted((ROOT / "scenes").glob("*.yaml")), ids=lambda p: p.name)
def test_committed_json_schema_accepts_every_example_scene(scene):
    """What an editor checks scenes against (scene.schema.json) must not flag a valid scene."""
    jsonschema = pytest.importorskip("jsonschema")
    from scenerender.scene.yaml_source import load_yaml

    data, _ = load_yaml(scene)
    validator = jsonschema.Draft202012Validator(json.loads(SCHEMA_FILE.read_text(encoding="utf-8")))
    assert [error.message for error in validator.iter_errors(data)] == []
    assert list(validator.iter_errors({**data, "render": {"samplez": 4}})), "a misspelt key must be flagged"
