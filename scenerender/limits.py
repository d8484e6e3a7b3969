"""Upper bounds on what one scene may ask for, each raisable with ``--limit NAME=N``.

A scene file or an asset can claim sizes that would take hours or all memory to honour (a
billion frames, a 100000x100000 texture, a YAML alias bomb). Every such size is checked
against ``Limits`` before work starts, and the message of a limit hit names the flag that
raises it, so a user who really means it can say so.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from scenerender.errors import SourceLocation, UserError


@dataclass(frozen=True)
class Limits:
    """The largest accepted value of each size; defaults suit a workstation.

    objects:        entries in the scene's ``objects`` list (instances not counted).
    triangles:      triangles of all meshes the scene loads, together.
    texture_pixels: width * height of any one texture or skybox face (16k x 16k).
    output_pixels:  width * height of the rendered image (8K UHD).
    frames:         frames in the scene's animation (``output.frames`` or duration * fps).
    yaml_bytes:     size of the scene file.
    yaml_depth:     nesting depth of the scene file's mappings and lists.
    yaml_aliases:   uses of YAML aliases (``*name``) in the scene file.
    yaml_alias_nodes: values copied by all alias uses together (what a "billion laughs"
                    document inflates).
    instances:      instances of all objects together (``instances`` lists and ``random.count``).
    prefilter_lookups: texture lookups of the environment light's prefilter, prefilter_size x
                    prefilter_size / 2 x (1 + 5 x samples); the default lets the largest
                    through (10 to 20 minutes on a 2-core CPU with Mesa llvmpipe): lower it
                    for scenes you do not trust.
    """

    objects: int = 100_000
    triangles: int = 50_000_000
    texture_pixels: int = 16384 * 16384
    output_pixels: int = 7680 * 4320
    frames: int = 10_000_000
    yaml_bytes: int = 16 * 1024 * 1024
    yaml_depth: int = 64
    yaml_aliases: int = 1_000_000
    yaml_alias_nodes: int = 1_000_000
    instances: int = 1_000_000
    prefilter_lookups: int = 2048 * 1024 * (1 + 5 * 4096)

    def check(self, name: str, value: int, what: str, location: SourceLocation | None = None,
              key: str | None = None) -> None:
        """Raise a UserError when ``value`` exceeds limit ``name``; ``what`` says what was counted."""
        allowed = getattr(self, name)
        if value > allowed:
            raise UserError(exceeded_message(name, value, allowed, what), location, key)

    def with_overrides(self, texts) -> "Limits":
        """A copy with ``NAME=N`` texts (the ``--limit`` option's values) applied."""
        changes = dict(parse_limit(text) for text in texts)
        return dataclasses.replace(self, **changes) if changes else self


def limit_names() -> list[str]:
    return [f.name for f in dataclasses.fields(Limits)]


def exceeded_message(name: str, value: int, allowed: int, what: str) -> str:
    """The one-line text for a limit hit: what, how much, the limit and how to raise it."""
    shown = f"{value:,}" if value < 10**15 else f"{float(value):.3g}"  # a 300-digit count stays short
    return f"{what} is {shown}, over the limit of {allowed:,} (raise with --limit {name}=N)"


_MAX_DIGITS = 30  # in a --limit value: no count comes near, and int() refuses past 4300


def parse_limit(text: str) -> tuple[str, int]:
    """``"objects=200000"`` -> ``("objects", 200000)``; underscores in N are allowed (``1_000``).

    Raises UserError (located at the option) for an unknown name or a value that is not a
    positive whole number.
    """
    where = SourceLocation(f"--limit {text}")
    name, sep, value = text.partition("=")
    name = name.strip().replace("-", "_")
    names = limit_names()
    if not sep:
        raise UserError(f"expected NAME=N, one of {', '.join(names)}", where)
    if name not in names:
        raise UserError(f"unknown limit '{name}' (one of {', '.join(names)})", where)
    digits = value.strip().replace("_", "")
    significant = digits.lstrip("0")
    if not digits.isascii() or not digits.isdigit() or not significant:
        raise UserError(f"expected a positive whole number, got '{value.strip()}'", where)
    if len(significant) > _MAX_DIGITS:  # int() would refuse beyond 4300 digits
        raise UserError(f"expected at most {_MAX_DIGITS} digits (no count comes near such a limit), "
                        f"got {len(significant)}", where)
    return name, int(significant)



def parse_limits(texts) -> Limits:
    """``Limits`` from the repeated ``--limit NAME=N`` option values (defaults elsewhere)."""
    return Limits().with_overrides(texts)
