"""The corpus of bad inputs (tests/corpus/, format in tests/corpus/README.md).

Every case runs through the command line in-process: a copy of the case folder is the
working directory, so messages name ``scene.yaml`` as a user would see it. Each case must
exit with its expected code, print its message fragment, print nothing but a few short
``error:``/``warning:`` lines (never a traceback or "internal error"), and leave no output
file behind, neither under ``-o`` nor next to the scene, but the files it ``writes``.
"""
from __future__ import annotations

import hashlib
import shutil
from pathlib import Path

import pytest
import yaml
from click.testing import CliRunner

from scenerender.cli import main

CORPUS = Path(__file__).resolve().parent / "corpus"
COMMANDS = ("validate", "render", "graph", "diff")
KEYS = {"exit", "message", "command", "args", "scene", "about", "stream", "writes"}
MAX_LINES = 12       # SceneErrors shows at most 10 problems, plus a summary line and a warning or two
MAX_LINE_CHARS = 600


def _cases() -> list[Path]:
    return sorted(p for p in CORPUS.iterdir() if (p / "expect.yaml").is_file())


def _expectation(case: Path) -> dict:
    expect = yaml.safe_load((case / "expect.yaml").read_text(encoding="utf-8"))
    unknown = set(expect) - KEYS
    assert not unknown, f"{case.name}/expect.yaml: unknown keys {sorted(unknown)}"
    assert isinstance(expect.get("exit"), int) and isinstance(expect.get("message"), str), (
        f"{case.name}/expect.yaml needs exit: (a number) and message: (text)")
    assert expect.get("command", "validate") in COMMANDS, f"{case.name}: command is one of {COMMANDS}"
    assert expect.get("stream", "stderr") in ("stderr", "stdout"), f"{case.name}: stream is stderr or stdout"
    return expect


def _files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")} if folder.exists() else set()


def _contents(folder: Path) -> dict[str, str]:
    """Every file under ``folder``, by its path there, with the digest of its bytes."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in folder.rglob("*") if p.is_file()}


def _arguments(expect: dict, out: Path) -> list[str]:
    command = expect.get("command", "validate")
    args = [str(a).replace("{out}", str(out)) for a in expect.get("args", [])]
    if command == "render" and "-o" not in args:
        args += ["-o", str(out), "-q"]
    return [command, expect.get("scene", "scene.yaml"), *args]


def test_corpus_is_large_enough():
    assert len(_cases()) >= 30


@pytest.mark.parametrize("case", _cases(), ids=lambda p: p.name)
def test_bad_input(case: Path, tmp_path, monkeypatch):
    expect = _expectation(case)
    work = tmp_path / "case"
    shutil.copytree(case, work, symlinks=True)
    (work / "expect.yaml").unlink()
    before, paths_before = _contents(work), _files(work)
    out = tmp_path / "out"
    monkeypatch.chdir(work)

    result = CliRunner().invoke(main, _arguments(expect, out))

    stderr = result.stderr
    shown = result.stdout if expect.get("stream") == "stdout" else stderr
    assert result.exit_code == expect["exit"], f"exit {result.exit_code}, stderr:\n{stderr}{result.output}"
    assert expect["message"] in shown, f"missing {expect['message']!r} in:\n{shown}"
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert "Traceback" not in result.output and "internal error" not in result.output, result.output
    lines = stderr.splitlines()
    assert (0 if expect.get("stream") == "stdout" else 1) <= len(lines) <= MAX_LINES, f"{len(lines)} lines:\n{stderr}"
    assert all(line.startswith(("error: ", "warning: ")) for line in lines), stderr
    assert all(len(line) <= MAX_LINE_CHARS for line in lines), stderr
    assert _files(out) == set(), f"left in -o: {sorted(_files(out))}"
    after = _contents(work)
    written = {path for path, digest in after.items() if before.get(path) != digest}
    assert written == set(expect.get("writes", [])), f"written next to the scene: {sorted(written)}"
    assert _files(work) == paths_before | written, f"left next to the scene: {sorted(_files(work) ^ paths_before)}"
