"""Assemble GLSL programs from the .glsl files in ``shaders/`` for one feature set.

A program is a vertex and a fragment file plus a set of defines (``N_POINT_LIGHTS 3``,
``HAS_FOG``, ``FOG_EXP2``...). ``#include "path.glsl"`` splices another file in once.
Features a scene lacks are simply not compiled: there is no uber-shader branching on
runtime flags.
"""
from __future__ import annotations

import re
from pathlib import Path

from scenerender.errors import EnvironmentProblem

GLSL_VERSION = "#version 430 core"
_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$', re.MULTILINE)


def shader_dir() -> Path:
    """The folder holding the .glsl files: inside the installed package (wheels), or
    the repository's top-level shaders/ (source checkouts and editable installs)."""
    package = Path(__file__).resolve().parent.parent
    for candidate in (package / "shaders", package.parent / "shaders"):
        if (candidate / "mesh" / "forward.frag").is_file():
            return candidate
    raise EnvironmentProblem(f"scenerender's shaders are missing (looked in {package / 'shaders'}); reinstall the package")


def assemble(name: str, defines: dict, root: Path | None = None) -> str:
    """Full GLSL source of ``name`` with ``defines`` and includes expanded."""
    root = root or shader_dir()
    header = [GLSL_VERSION]
    for key in sorted(defines):
        value = defines[key]
        header.append(f"#define {key}" if value is True else f"#define {key} {value}")
    body = _expand(root, name, set(), [])
    return "\n".join(header) + "\n#line 1\n" + body


def _expand(root: Path, name: str, seen: set, stack: list) -> str:
    if name in stack:
        raise ValueError(f"circular #include: {' -> '.join(stack + [name])}")
    path = root / name
    text = path.read_text(encoding="utf-8")

    def include(match):
        target = match.group(1)
        if target in seen:
            return ""
        seen.add(target)
        return _expand(root, target, seen, stack + [name])

    return _INCLUDE.sub(include, text)


class ProgramCache:
    """Compiles each (vertex, fragment, defines) combination once per context."""

    def __init__(self, ctx, root: Path | None = None):
        self.ctx = ctx
        self.root = root or shader_dir()
        self._programs: dict = {}
        self._by_key: dict = {}

    def get(self, vertex: str, fragment: str, defines: dict | None = None):
        defines = dict(defines or {})
        key = (vertex, fragment, tuple(sorted(defines.items())))
        program = self._programs.get(key)
        if program is None:
            program = self._compile(vertex, fragment, defines)
            self._programs[key] = program
        return program

    def memo(self, key, make):
        """The program ``make()`` returns for ``key``, asked once: for callers whose
        defines are costly to work out on every draw (a material's shader variant)."""
        program = self._by_key.get(key)
        if program is None:
            program = self._by_key[key] = make()
        return program

    def _compile(self, vertex: str, fragment: str, defines: dict):
        vs = assemble(vertex, defines, self.root)
        fs = assemble(fragment, defines, self.root)
        try:
            return self.ctx.program(vertex_shader=vs, fragment_shader=fs)
        except Exception as exc:  # a shader bug is scenerender's, report it with the sources named
            raise RuntimeError(f"GLSL compile error in {vertex} + {fragment} with {defines}:\n{exc}") from exc

    @property
    def count(self) -> int:
        return len(self._programs)

    def release(self) -> None:
        for program in self._programs.values():
            program.release()
        self._programs.clear()
        self._by_key.clear()
