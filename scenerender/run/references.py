"""Reference frames for CI: pick the set made on this kind of GL renderer, compare the
output with it, and rewrite it only when asked.

Layout of a reference folder ``ref/``: frames (or the video) directly in it, and optionally
one sub-folder per renderer whose output differs enough to need its own references:
``ref/llvmpipe/``, ``ref/nvidia/``... A run uses ``ref/<its renderer>/`` when that folder
exists, else ``ref/`` itself.
"""
from __future__ import annotations

import filecmp
import re
import shutil
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.compare import DEFAULT_RULE, compare_paths, write_html_report
from scenerender.compare.sources import is_frame_file
from scenerender.errors import SourceLocation, UserError, display_path
from scenerender.gpu.gl_context import create_context
from scenerender.run.manifest import read_sidecar, sidecar_for
from scenerender.sinks.base import atomic_path, make_folders, output_errors
from scenerender.sinks.object_ids import behind_path, ids_path, names_path

# GL_RENDERER text -> key, first match wins. Mesa's software rasterisers name themselves;
# vendor drivers put the vendor first ("NVIDIA H100 80GB HBM3/PCIe/SSE2").
_RENDERER_KEYS = (("llvmpipe", "llvmpipe"), ("softpipe", "softpipe"), ("swiftshader", "swiftshader"),
                  ("nvidia", "nvidia"), ("geforce", "nvidia"), ("quadro", "nvidia"), ("radeon", "amd"),
                  ("amd", "amd"), ("intel", "intel"), ("apple", "apple"), ("mali", "mali"), ("adreno", "adreno"))
CHECK_OPTION = "--check"  # the option that names the references


def renderer_key(gl_renderer: str | None) -> str:
    """A short folder name for a GL renderer string: 'llvmpipe (LLVM 15.0.6, 256 bits)' ->
    'llvmpipe', 'NVIDIA H100 80GB HBM3/PCIe/SSE2' -> 'nvidia'; 'unknown' for None."""
    text = (gl_renderer or "").lower()
    for needle, key in _RENDERER_KEYS:
        if needle in text:
            return key
    words = re.findall(r"[a-z0-9]+", text)
    return words[0] if words else "unknown"


def reference_folder(root: Path, key: str) -> Path:
    """``root/key`` when it exists (references for this renderer), else ``root``."""
    keyed = Path(root) / key
    return keyed if keyed.is_dir() else Path(root)


def reference_path(target: Path, root: Path) -> Path:
    """The references ``target`` (a frame folder or one file) is compared with: the set
    under ``root`` for the GL renderer that made it (from its manifest), else ``root``."""
    target = Path(target)
    folder = reference_folder(root, renderer_key(recorded_renderer(target) or _this_renderer()))
    return folder if target.is_dir() else folder / target.name


def require_apart(target: Path, reference: Path) -> None:
    """Refuse to compare the render output ``target`` with itself: that always passes, and
    --update-references would find nothing to update, whatever the render drew."""
    if Path(target).resolve() == Path(reference).resolve():
        raise UserError(f"{display_path(reference)} is where this render writes (-o), so the output would be "
                        "compared with itself and always pass; keep the references in a folder of their own, "
                        "e.g. -o out/ --check ref/", SourceLocation(CHECK_OPTION))


def require_apart_before_rendering(target: Path, is_folder: bool, root: Path) -> None:
    """``require_apart`` before any frame is written, when the references are not yet known
    (the renderer's sub-folder, see ``reference_path``, is checked once they are): a render
    into the --check folder itself would also write over the references."""
    require_apart(target, Path(root) if is_folder else Path(root) / Path(target).name)


def report_path(target: Path) -> Path:
    """Where ``--check`` writes its report: inside a frame folder, beside a video or image."""
    target = Path(target)
    return target / "report.html" if target.is_dir() else target.with_name(f"{target.stem}.report.html")


@dataclass
class CheckResult:
    """The outcome of checking one output against its references.

    reference: the folder (or file) compared with; report: the HTML report written;
    comparison: the ``compare.CompareResult`` (None when references were created afresh);
    updated: reference files written or removed by ``update`` ("changed x", "added y"...).
    """

    reference: Path
    report: Path | None
    comparison: object | None
    updated: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return self.comparison is None or self.comparison.passed


def check_output(target: Path, root: Path, update: bool = False, echo=print, rule=None,
                 notice=None) -> CheckResult:
    """Compare the render output ``target`` (a frame folder or one file) with its
    references under ``root`` (the set for the GL renderer its manifest names); with
    ``update``, make the references equal to the output. ``rule``: a ``compare.DiffRule``.
    A passing verdict goes to ``echo``; a failing one, the report's path and the
    references updated go to ``notice`` (default ``echo``), which ``-q`` keeps.

    Without references and without ``update`` this is a UserError: a first run must never
    pass by silently creating what it compares with.
    """
    notice = echo if notice is None else notice
    target = Path(target)
    reference = reference_path(target, root)
    require_apart(target, reference)
    if not has_references(reference):
        if not update:
            raise UserError(f"no references to check against in {display_path(reference)} "
                            "(render once with --update-references to create them, then commit them)",
                            SourceLocation(CHECK_OPTION))
        return CheckResult(reference, None, None, _update(target, reference, None, notice))
    comparison = compare_paths(reference, target, rule or DEFAULT_RULE)
    report = report_path(target)
    write_html_report(comparison, report)
    for line in comparison.summary_lines():
        (echo if comparison.passed else notice)(line)
    notice(f"report: {display_path(report)}")
    updated = _update(target, reference, comparison, notice) if update else []
    return CheckResult(reference, report, comparison, updated)


def recorded_renderer(target: Path) -> str | None:
    """The GL renderer that made ``target``, from its run manifest."""
    gl = read_sidecar(sidecar_for(target, target.is_dir()))[0].get("gl") or {}
    return gl.get("renderer")


def _this_renderer() -> str | None:
    """The GL renderer of this machine, for outputs whose manifest does not say."""
    gl = create_context()
    try:
        return gl.info.get("GL_RENDERER")
    finally:
        gl.release()


def has_references(reference: Path) -> bool:
    """True when ``reference`` is a file, or a folder holding at least one frame."""
    if reference.is_dir():
        return any(is_frame_file(p) for p in reference.iterdir())
    return reference.is_file()


def _update(target: Path, reference: Path, comparison, echo) -> list[str]:
    """Make ``reference`` hold exactly the output's frames (and its provenance sidecar).
    The references are a destination given with --check: failures to write name it."""
    with output_errors(reference, CHECK_OPTION):
        if target.is_dir():
            changes = _sync_folder(target, reference, comparison)
            _copy(sidecar_for(target, True), sidecar_for(reference, True))
        else:
            changes = [] if comparison is not None and comparison.passed else [f"wrote {reference.name}"]
            _copy(target, reference)
            _copy(sidecar_for(target, False), sidecar_for(reference, False))
            changes += _sync_ids(target.parent, reference.parent, {target.name}, set(), set())
    echo(f"updated references in {display_path(reference)}: " + (", ".join(changes) if changes else "no change"))
    return changes


def _sync_folder(output: Path, reference: Path, comparison) -> list[str]:
    make_folders(reference)
    produced = {p.name for p in output.iterdir() if is_frame_file(p)}
    existing = {p.name for p in reference.iterdir() if is_frame_file(p)}
    changed = {f.name for f in comparison.changed} if comparison is not None else set()
    copied = {name for name in produced if name in changed or name not in existing}
    for name in sorted(copied):
        _copy(output / name, reference / name)
    for name in sorted(existing - produced):
        (reference / name).unlink()
    return ([f"{len(changed)} changed"] if changed else []) + \
        ([f"{len(produced - existing)} added"] if produced - existing else []) + \
        ([f"{len(existing - produced)} removed"] if existing - produced else []) + \
        _sync_ids(output, reference, copied, produced - copied, existing - produced)


def _sync_ids(output: Path, reference: Path, copied: set, kept: set, removed: set) -> list[str]:
    """The object ids of the reference frames: those of the output for the frames ``copied``
    (a frame the output has no ids for loses its own, which would name another render);
    for the frames ``kept`` (they passed), the output's only where the reference has none;
    none for the frames ``removed``. objects.json comes along."""
    written = 0
    for name in sorted(copied | kept):
        if name in kept and ids_path(reference / name).is_file():
            continue
        written += _sync_file(ids_path(output / name), ids_path(reference / name))
        _sync_file(behind_path(output / name), behind_path(reference / name))
    for name in sorted(removed):
        ids_path(reference / name).unlink(missing_ok=True)
        behind_path(reference / name).unlink(missing_ok=True)
    names, kept_names = names_path(output), names_path(reference)
    if names.is_file() and not (kept_names.is_file() and filecmp.cmp(names, kept_names, shallow=False)):
        _copy(names, kept_names)
    return [f"object ids of {written} frame(s)"] if written else []


def _sync_file(source: Path, destination: Path) -> int:
    """Make ``destination`` a copy of ``source``, or absent where ``source`` is -> 1 when
    it was written."""
    if source.is_file():
        if not destination.is_file() or not filecmp.cmp(source, destination, shallow=False):
            _copy(source, destination)
            return 1
    elif destination.is_file():
        destination.unlink()
    return 0


def _copy(source: Path, destination: Path) -> None:
    """Copy whole or not at all (temporary name, then rename); a missing source is skipped."""
    if not source.is_file():
        return
    with atomic_path(destination, CHECK_OPTION) as temp:
        shutil.copyfile(source, temp)
