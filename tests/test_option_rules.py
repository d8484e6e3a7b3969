"""One rule per option, and every door uses it (scenerender/option_rules.py): the command line,
the scene file (and ``--set``) and the Python API accept and refuse the same values and say
why in the same words. Before, ``--samples`` took 1..64 (3 passed it, then the scene model
refused it), ``Renderer(samples=3)`` skipped the model's check, and ``diff``'s options were
copied by hand from ``DiffRule``."""
from __future__ import annotations

import math
from dataclasses import fields

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

import scenerender
from conftest import scene as api_scene
from scenerender import option_rules
from scenerender.cli import main
from scenerender.compare.rule import DEFAULT_RULE, DiffRule
from scenerender.errors import UserError
from scenerender.raytrace import render_reference

SCENE = "render: {size: [16, 12], samples: %s}\nobjects:\n  - mesh: {primitive: box}\n"


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


# --- MSAA samples: --samples, render.samples (file and --set), Renderer(samples=) and render()

BAD_SAMPLES = [0, 3, 6, 65, 128]
GOOD_SAMPLES = [1, 2, 4, 8, 16, 32, 64]


def samples_message(count) -> str:
    return f"MSAA samples must be one of 1, 2, 4, 8, 16, 32, 64 (1 = off), got {count}"


@pytest.mark.parametrize("count", BAD_SAMPLES)
def test_msaa_samples_are_refused_alike_by_every_door(tmp_path, monkeypatch, count):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.yaml").write_text(SCENE % 1, encoding="utf-8")
    (tmp_path / "file.yaml").write_text(SCENE % count, encoding="utf-8")
    message = samples_message(count)

    option = cli("validate", "scene.yaml", "--samples", count)
    assert option.exit_code == 2 and option.stderr.splitlines()[-1] == f"Error: Invalid value for '--samples': {message}"
    in_file = cli("validate", "file.yaml")
    assert in_file.exit_code == 2 and in_file.stderr == f"error: file.yaml:1:26: render.samples: {message}\n"
    override = cli("validate", "scene.yaml", "--set", f"render.samples={count}")
    assert override.exit_code == 2 and override.stderr.endswith(f"render.samples: {message}\n")

    scene = api_scene(SCENE % 1)
    with pytest.raises(ValueError, match=f"^{message.replace('(', '[(]').replace(')', '[)]')}$"):
        scenerender.Renderer(scene, samples=count)  # refused before a GL context is made
    with pytest.raises(ValueError, match="MSAA samples must be one of"):
        next(scenerender.render(scene, [0], samples=count))


@pytest.mark.parametrize("count", GOOD_SAMPLES)
def test_msaa_samples_are_accepted_alike_by_every_door(tmp_path, monkeypatch, count):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "scene.yaml").write_text(SCENE % count, encoding="utf-8")
    assert cli("validate", "scene.yaml").exit_code == 0
    assert cli("validate", "scene.yaml", "--samples", count).exit_code == 0
    assert cli("validate", "scene.yaml", "--set", f"render.samples={count}").exit_code == 0
    assert option_rules.MSAA_SAMPLES.check(count) == count  # what Renderer(samples=) calls


def test_a_renderer_takes_a_good_sample_count(gl):
    with scenerender.Renderer(api_scene(SCENE % 1), gl=gl, samples=2) as renderer:
        assert renderer.samples == 2
        assert renderer.render(0).pixels.shape == (12, 16, 3)


def test_the_schema_lists_the_rules_counts():
    from scenerender.scene.model.render import RenderSpec

    schema = RenderSpec.model_json_schema()
    assert schema["properties"]["samples"]["enum"] == list(option_rules.MSAA_SAMPLES.choices)


# --- the diff rule: each DiffRule field is one option of `scenerender diff`, with one rule

def test_every_diff_rule_field_is_a_diff_option_with_its_default():
    help_text = " ".join(cli("diff", "--help").output.split())
    for item in fields(DiffRule):
        option = "--" + item.name.replace("_", "-")
        assert f"{option} {item.metadata['metavar']}" in help_text
        assert f"[default: {getattr(DEFAULT_RULE, item.name)}]" in help_text.split(option, 1)[1]


BAD_LIMITS = [
    ("max_tile", math.nan), ("max_tile", math.inf), ("max_tile", -1.0), ("max_unexplained_mean", -0.5),
    ("max_shift_tile", math.inf), ("aa_tolerance", -1), ("aa_tolerance", 256), ("aa_tolerance", 1.5),
    ("min_object_pixels", 0), ("max_object_shift", -0.1), ("max_object_shift", math.nan), ("max_interior_change", -2.0),
]


@pytest.fixture
def two_images(tmp_path):
    pixels = np.zeros((12, 16, 3), np.uint8)
    for name in ("a.png", "b.png"):
        Image.fromarray(pixels).save(tmp_path / name)
    return tmp_path / "a.png", tmp_path / "b.png"


@pytest.mark.parametrize("name, value", BAD_LIMITS)
def test_a_diff_limit_is_refused_alike_by_the_option_and_the_rule(two_images, name, value):
    rule = next(item.metadata["rule"] for item in fields(DiffRule) if item.name == name)
    message = rule.problem(value)
    assert message is not None
    option = cli("diff", *two_images, f"--{name.replace('_', '-')}", value)
    assert option.exit_code == 2
    assert option.stderr.splitlines()[-1].endswith(message)
    with pytest.raises(ValueError) as refused:  # the Python door, also scene_regression's rule=
        DiffRule(**{name: value})
    assert str(refused.value) == f"DiffRule.{name}: {message}"


def test_the_diff_limits_at_their_bounds_pass_everywhere(two_images):
    edge = {"max_tile": 0, "max_unexplained_mean": 0, "max_shift_tile": 0, "aa_tolerance": 255,
            "min_object_pixels": 1, "max_object_shift": 0, "max_interior_change": 0}
    DiffRule(**edge)
    args = [a for name, value in edge.items() for a in (f"--{name.replace('_', '-')}", value)]
    assert cli("diff", *two_images, *args).exit_code == 0


# --- the CPU reference: --spp, --ambient-samples, --environment-samples, --shutter-samples, --bounces and
# render_reference

REFERENCE_LIMITS = [("spp", option_rules.SPP, 0), ("spp", option_rules.SPP, 33),
                    ("ambient_samples", option_rules.AMBIENT_SAMPLES, -1),
                    ("environment_samples", option_rules.ENVIRONMENT_SAMPLES, 0),
                    ("environment_samples", option_rules.ENVIRONMENT_SAMPLES, 65537),
                    ("shutter_samples", option_rules.SHUTTER_SAMPLES, 0),
                    ("shutter_samples", option_rules.SHUTTER_SAMPLES, 4097),
                    ("bounces", option_rules.BOUNCES, -1), ("bounces", option_rules.BOUNCES, 1025),
                    ("bounces", option_rules.BOUNCES, 2.5)]


@pytest.mark.parametrize("name, rule, value", REFERENCE_LIMITS)
def test_a_reference_count_is_refused_alike_by_the_option_and_the_function(tmp_path, name, rule, value):
    (tmp_path / "scene.yaml").write_text(SCENE % 1, encoding="utf-8")
    option = cli("reference", tmp_path / "scene.yaml", "-o", tmp_path / "ref", f"--{name.replace('_', '-')}", value)
    assert option.exit_code == 2
    assert option.stderr.splitlines()[-1].endswith(rule.problem(value))
    with pytest.raises(UserError, match=rule.what.replace("(", "[(]").replace(")", "[)]")):
        render_reference(api_scene(SCENE % 1), 0, **{name: value})
    assert not (tmp_path / "ref").exists()


def test_the_bench_command_shares_the_reference_rules():
    for option, rule in (("--spp", option_rules.SPP), ("--environment-samples", option_rules.ENVIRONMENT_SAMPLES),
                         ("--bounces", option_rules.BOUNCES)):
        for command in ("reference", "bench"):
            param = next(p for p in main.commands[command].params if option in p.opts)
            assert param.type.rule is rule
    env = next(p for p in main.commands["reference"].params if "--environment-samples" in p.opts)
    assert env.default == option_rules.DEFAULT_ENVIRONMENT_SAMPLES
    shutter = next(p for p in main.commands["reference"].params if "--shutter-samples" in p.opts)
    assert shutter.type.rule is option_rules.SHUTTER_SAMPLES
    assert shutter.default == option_rules.DEFAULT_SHUTTER_SAMPLES

