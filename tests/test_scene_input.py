"""The scene file as untrusted input: special files, names, limits, aliases and messages.

The corpus (tests/corpus/, run by test_corpus.py) holds the bad scene *contents*; the cases
here need files a folder of test data cannot hold (a FIFO, a device, symlinks, over-long
names) or look at the loaded data itself.
"""
from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest
from click.testing import CliRunner

from scenerender.cli import main
from scenerender.errors import SceneErrors, SourceLocation, UserError
from scenerender.limits import Limits, parse_limit, parse_limits
from scenerender.scene.loading import load_scene, load_scene_text
from scenerender.scene.yaml_source import load_yaml, parse_yaml_text

BOX = "objects:\n  - mesh: {primitive: box}\n"


def finishes(function, seconds: float = 30.0):
    """Run ``function`` in a thread -> (finished, exception). A bound against hangs, not a speed test."""
    outcome = {}

    def run():
        try:
            function()
        except BaseException as exc:  # noqa: BLE001 - handed back to the test
            outcome["error"] = exc

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    thread.join(seconds)
    return not thread.is_alive(), outcome.get("error")


def load_error(path) -> str:
    with pytest.raises(UserError) as info:
        load_scene(path)
    return str(info.value)


# ---------------------------------------------------------------------------------------
# special files


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes here")
def test_a_fifo_as_scene_is_an_error_not_a_hang(tmp_path):
    fifo = tmp_path / "scene.yaml"
    os.mkfifo(fifo)
    done, error = finishes(lambda: load_scene(fifo))
    assert done, "reading a FIFO blocked"
    assert isinstance(error, UserError) and "not a regular file (a named pipe" in str(error)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero here")
def test_dev_zero_as_scene_is_an_error_not_a_hang(tmp_path):
    done, error = finishes(lambda: load_scene("/dev/zero"))
    assert done
    assert isinstance(error, UserError) and "not a regular file (a device)" in str(error)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero here")
def test_symlink_to_a_device_is_refused(tmp_path):
    link = tmp_path / "scene.yaml"
    link.symlink_to("/dev/zero")
    assert "not a regular file (a device)" in load_error(link)


def test_a_folder_as_scene(tmp_path):
    (tmp_path / "scene.yaml").mkdir()
    assert "not a regular file (a folder)" in load_error(tmp_path / "scene.yaml")


def test_dangling_symlink_is_not_found(tmp_path):
    (tmp_path / "scene.yaml").symlink_to(tmp_path / "gone.yaml")
    assert "scene file not found" in load_error(tmp_path / "scene.yaml")


def test_symlinked_scene_file_loads(tmp_path):
    (tmp_path / "real.yaml").write_text(BOX, encoding="utf-8")
    (tmp_path / "scene.yaml").symlink_to(tmp_path / "real.yaml")
    assert len(load_scene(tmp_path / "scene.yaml").spec.objects) == 1


def test_over_long_file_name(tmp_path):
    message = load_error(tmp_path / ("s" * 300 + ".yaml"))
    assert "file name too long" in message and "s" * 300 in message


def test_over_long_file_name_on_the_command_line(tmp_path):
    result = CliRunner().invoke(main, ["validate", str(tmp_path / ("s" * 300 + ".yaml"))])
    assert result.exit_code == 2, result.output
    assert "file name too long" in result.stderr and "internal error" not in result.stderr


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root reads any file")
def test_unreadable_scene(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(BOX, encoding="utf-8")
    scene.chmod(0)
    assert "cannot read the scene file: permission denied" in load_error(scene)


def test_reading_stops_at_the_size_limit(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(BOX + "#" * 5000 + "\n", encoding="utf-8")
    with pytest.raises(UserError, match=r"over the limit of 1,000 \(raise with --limit yaml_bytes=N\)"):
        load_yaml(scene, Limits(yaml_bytes=1000))
    assert load_yaml(scene, Limits(yaml_bytes=len(scene.read_bytes())))[0]["objects"]


def test_byte_order_mark_is_accepted(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_bytes(b"\xef\xbb\xbf" + BOX.encode())
    assert len(load_scene(scene).spec.objects) == 1


# ---------------------------------------------------------------------------------------
# YAML: values, tags, aliases


def test_yaml_1_2_integers_in_explicit_tags():
    data, _ = parse_yaml_text("a: !!int 0x1f\nb: !!int 0o17\nc: !!float 2\nd: !!str 12\n", "s.yaml")
    assert data == {"a": 31, "b": 15, "c": 2.0, "d": "12"}
    assert isinstance(data["c"], float)


def test_aliased_values_are_copies(tmp_path):
    """--set on one use of an alias must not change the other uses."""
    text = "x: &p [1, 2, 3]\nobjects:\n  - {mesh: {primitive: box}, position: *p}\n  - {mesh: {primitive: box}, position: *p}\n"
    data, _ = parse_yaml_text(text, "s.yaml")
    assert data["objects"][0]["position"] is not data["objects"][1]["position"]


def test_merge_keys_take_explicit_keys_first_and_keep_positions():
    text = ("base: &b {size: [8, 8], samples: 2}\n"
            "render:\n  <<: *b\n  samples: 4\n")
    data, source = parse_yaml_text(text, "s.yaml")
    assert data["render"] == {"samples": 4, "size": [8, 8]}
    assert source.locate(("render", "size")) == SourceLocation("s.yaml", 1, 11)  # where it is written
    assert source.locate(("render", "samples")) == SourceLocation("s.yaml", 4, 3)


def test_plain_keys_stay_as_written():
    data, _ = parse_yaml_text("1e3: a\ntrue: b\n0x10: c\n", "s.yaml")
    assert set(data) == {"1e3", "true", "0x10"}


def test_anchors_may_be_used_many_times_within_the_limits(tmp_path):
    objects = "".join("  - {mesh: *m, position: *p}\n" for _ in range(199))
    text = f"objects:\n  - {{mesh: &m {{primitive: box}}, position: &p [0, 1, 0]}}\n{objects}"
    assert len(load_scene_text(text, tmp_path).spec.objects) == 200


def test_alias_expansion_limit_counts_values(tmp_path):
    text = "x: &x [1, 2, 3, 4]\ny: [*x, *x, *x]\n"  # 3 uses x 5 values
    with pytest.raises(UserError, match="aliases expand to more than 14 values"):
        parse_yaml_text(text, "s.yaml", Limits(yaml_alias_nodes=14))
    parse_yaml_text(text, "s.yaml", Limits(yaml_alias_nodes=15))


def test_raised_depth_limit_cannot_exhaust_recursion(tmp_path):
    """Even with the depth limit raised far, nothing recurses per level: a clear error
    (a list where a mapping belongs) and no RecursionError."""
    deep = "[" * 3000 + "]" * 3000  # Python recursion stops at 1000
    with pytest.raises(UserError) as info:
        load_scene_text(f"render: {deep}\n" + BOX, tmp_path, limits=Limits(yaml_depth=5000))
    assert "render" in str(info.value)


@pytest.mark.parametrize("opening, closing", [("[", "]"), ("{a: ", "}")])
def test_our_depth_limit_acts_before_the_yaml_librarys(opening, closing):
    """libyaml (PyYAML 6.0.4 on) refuses 1000 flow levels while it scans ahead, before the
    builder sees the level past ours: the message, its place and the hint are still ours,
    for the default limit and for one raised past the library's own."""
    for limit, levels in [(64, 3000), (1200, 3000)]:
        text = "render: " + opening * levels + "1" + closing * levels + "\n"
        with pytest.raises(UserError) as info:
            parse_yaml_text(text, "s.yaml", Limits(yaml_depth=limit))
        column = len("render: ") + len(opening) * (limit - 1) + 1
        assert str(info.value) == (f"s.yaml:1:{column}: nested more than {limit} levels deep "
                                   "(raise with --limit yaml_depth=N)")


def test_a_library_depth_limit_that_no_parser_passes_is_named_plainly(monkeypatch):
    """Should every parser PyYAML has stop short of a raised limit, the message says whose
    limit it was and that --limit cannot raise it."""
    import yaml

    from scenerender.scene import yaml_source

    def refusing_parse(text, Loader):
        mark = yaml.Mark("s", 0, 0, 1000, None, None)
        raise yaml.MarkedYAMLError("while increasing flow level", mark, "exceeded maximum nesting depth", mark)
        yield  # a generator, like yaml.parse

    monkeypatch.setattr(yaml_source.yaml, "parse", refusing_parse)
    with pytest.raises(UserError) as info:
        parse_yaml_text("a: 1\n", "s.yaml", Limits(yaml_depth=5000))
    assert str(info.value).startswith("s.yaml:1:1001: nested deeper than the YAML reader allows (PyYAML ")
    assert str(info.value).endswith("exceeded maximum nesting depth), whatever --limit yaml_depth says")


def test_deep_block_nesting_is_ours_to_refuse():
    text = "".join(" " * level + "k:\n" for level in range(1500)) + " " * 1500 + "v\n"
    with pytest.raises(UserError, match=r"^s.yaml:65:65: nested more than 64 levels deep"):
        parse_yaml_text(text, "s.yaml")


# ---------------------------------------------------------------------------------------
# limits


def test_limit_parsing():
    assert parse_limit("objects=200_000") == ("objects", 200000)
    assert parse_limits(["frames=5", "texture_pixels=64"]) == Limits(frames=5, texture_pixels=64)
    for bad, message in [("frames", "expected NAME=N"), ("frame=1", "unknown limit 'frame'"),
                         ("frames=0", "positive whole number"), ("frames=1.5", "positive whole number"),
                         ("frames=000", "positive whole number"), ("frames=²", "positive whole number"),
                         ("frames=" + "9" * 5000, "at most 30 digits")]:  # more than int() converts
        with pytest.raises(UserError, match=message):
            parse_limit(bad)
    assert parse_limit("frames=" + "0" * 40 + "7") == ("frames", 7)


def test_limits_reach_the_loaded_scene(tmp_path):
    loaded = load_scene_text(BOX, tmp_path, limits=Limits(triangles=123))
    assert loaded.limits.triangles == 123
    assert load_scene_text(BOX, tmp_path).limits == Limits()


def test_limits_apply_after_set(tmp_path):
    with pytest.raises(UserError, match=r"output\.frames: the number of frames is 20"):
        load_scene_text(BOX, tmp_path, ["output.frames=20"], limits=Limits(frames=10))
    with pytest.raises(UserError, match="the number of objects is 2"):
        load_scene_text(BOX, tmp_path, ["objects[1]={mesh: {primitive: box}}"], limits=Limits(objects=1))


def test_raising_a_limit_lets_the_scene_through(tmp_path):
    (tmp_path / "scene.yaml").write_text("output: {frames: 20}\n" + BOX, encoding="utf-8")
    refused = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml"), "--limit", "frames=10"])
    assert refused.exit_code == 2 and "--limit frames=N" in refused.stderr
    allowed = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml"), "--limit", "frames=20"])
    assert allowed.exit_code == 0, allowed.output


def test_objects_over_the_limit_are_refused_before_validation(tmp_path):
    """50 broken objects over a limit of 10: the limit is the one message (nothing validated)."""
    text = "objects:\n" + "  - {mesh: 7}\n" * 50
    with pytest.raises(UserError) as info:
        load_scene_text(text, tmp_path, limits=Limits(objects=10))
    assert not isinstance(info.value, SceneErrors)
    assert "the number of objects is 50" in str(info.value)


# ---------------------------------------------------------------------------------------
# messages stay short


def test_repeated_mistakes_collapse(tmp_path):
    text = "objects:\n" + "  - {mesh: {primitive: box}, scale: -1}\n" * 500
    with pytest.raises(SceneErrors) as info:
        load_scene_text(text, tmp_path)
    assert info.value.lines() == ["scene.yaml:2:30: objects[0].scale: must be > 0, got -1 (and 499 more like it)"]


def test_many_different_mistakes_are_capped():
    errors = [UserError(f"problem {i}", SourceLocation("s.yaml", i)) for i in range(25)]
    lines = SceneErrors(errors).lines()
    assert len(lines) == SceneErrors.MAX_LINES
    assert lines[-1] == "... and 16 more problems"


def test_empty_objects_is_a_scene(tmp_path):
    assert load_scene_text("objects: []\n", tmp_path).spec.objects == []


def test_undecodable_bytes_in_set_are_a_user_error(tmp_path):
    """Found by hand: bytes that are not UTF-8 in a --set argument reached PyYAML and pydantic
    as surrogates and failed there with UnicodeEncodeError."""
    (tmp_path / "scene.yaml").write_text(BOX, encoding="utf-8")
    for text in ("objects\udcff=1", "render.samples=\udcff"):
        result = CliRunner().invoke(main, ["validate", str(tmp_path / "scene.yaml"), "--set", text])
        assert result.exit_code == 2, result.output
        assert "not valid UTF-8 text" in result.stderr and "\\xff" in result.stderr


def test_nul_in_a_scene_file_name():
    with pytest.raises(UserError, match="cannot contain a NUL character"):
        load_scene("scene\0.yaml")


def test_negative_zero_is_zero(tmp_path):
    """Found by the fuzzer: max [0, -0.0, 0] over min [0, 0, 0] passed validation, then numpy's
    uniform() refused the range (ValueError: high - low < 0). Numbers are validated to +0.0."""
    from scenerender.errors import Warnings
    from scenerender.world.build import build_world

    text = ("objects:\n  - mesh: {primitive: box}\n    position: [-0.0, 0, 0]\n"
            "    instances: {random: {count: 3, position: {min: [0, 0, 0], max: [0, -0.0, 0]}}}\n")
    loaded = load_scene_text(text, tmp_path)
    assert str(loaded.spec.objects[0].position(0.0)[0]) == "0.0"
    build_world(loaded, Warnings())
