"""The package's import picture: modules, arrows between them, arrows that cross layers,
arrows that run up, circles and private reads, judged by the layer order of
tests/test_import_layers.py (this checkout's). Any source tree can be measured against it,
so the picture of an older commit is one command away:

    python benchmarks/import_picture.py                     # this checkout
    git worktree add /tmp/before 31fc68a
    python benchmarks/import_picture.py --root /tmp/before   # an older tree, today's layers

A private read is ``from scenerender.a import _name`` (not a dunder such as ``__version__``) from
a module outside the package that defines it. Imports inside functions count.
"""
from __future__ import annotations

import argparse
import ast
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

import test_import_layers as layers  # noqa: E402


def private_reads(package: Path) -> list[str]:
    found = []
    for name, path in sorted(layers.package_modules(package).items()):
        home = name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and not node.level and (node.module or "").startswith("scenerender"):
                source = node.module
                found += [f"{name} reads {source}.{alias.name}" for alias in node.names
                          if alias.name.startswith("_") and not alias.name.endswith("__")
                          and not source.startswith(home or name)]
    return found


def picture(package: Path) -> dict:
    layers.PACKAGE = package  # module_name() is relative to the package measured
    graph = layers.import_graph(package)
    arrows = [(source, target) for source, targets in graph.items() for target in targets
              if layers.FACE not in (source, target)]
    crossing = Counter((layers.layer_of(s), layers.layer_of(t)) for s, t in arrows
                       if layers.layer_of(s) != layers.layer_of(t))
    return {
        "modules": len(graph),
        "arrows": len(arrows),
        "cross-layer arrows": sum(crossing.values()),
        "upward arrows": layers.upward_imports(graph),
        "circles": layers.circles(graph),
        "private reads": private_reads(package),
        "unplaced modules": sorted(m for m in graph if m != layers.FACE and layers.layer_of(m) is None),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=ROOT, help="a source tree holding scenerender/")
    args = parser.parse_args(argv)
    for key, value in picture(args.root.resolve() / "scenerender").items():
        if isinstance(value, list):
            print(f"{key}: {len(value)}")
            for item in value:
                print(f"    {item}")
        else:
            print(f"{key}: {value}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
