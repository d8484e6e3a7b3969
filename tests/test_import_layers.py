"""The import graph of the package, read from the source: no module imports a higher layer,
and no modules import each other in a circle. Imports inside functions count too (they hide
circles as well as any). The layer order is the one docs/architecture.md draws."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "scenerender"

# Top first. A module belongs to the longest prefix that names it; a module may import its
# own layer and any layer below it.
LAYERS = [
    ["scenerender.cli", "scenerender.pytest_plugin", "scenerender.__main__"],  # entry points
    ["scenerender.preview"],                                                   # the live page (only the CLI imports it)
    ["scenerender.api"],                                                       # the public facade
    ["scenerender.tools"],                                                     # tools that render and measure
    ["scenerender.run"],                                                       # a run: scene -> sink
    ["scenerender.rendering", "scenerender.compare", "scenerender.raytrace"],  # passes; diffing; the CPU reference
    ["scenerender.gpu"],                                                       # GL objects
    ["scenerender.world"],                                                     # the world a renderer draws
    ["scenerender.mesh"],                                                      # mesh files and primitives
    ["scenerender.scene"],                                                     # the validated scene model
    ["scenerender.sinks", "scenerender.graph", "scenerender.animation"],       # independent of each other
    ["scenerender.errors", "scenerender.limits", "scenerender.json_input", "scenerender.colorspace", "scenerender.machine",
     "scenerender.version", "scenerender.option_rules"],
]
FACE = "scenerender"  # the package's __init__: __version__ and the lazy facade (see below)


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def package_modules(root: Path = PACKAGE) -> dict[str, Path]:
    return {module_name(path): path for path in root.rglob("*.py")}


def imported_modules(path: Path, known: set[str]) -> set[str]:
    """The package modules ``path`` imports anywhere in it (relative imports resolved)."""
    here = module_name(path).split(".")
    is_package = path.name == "__init__.py"
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = here if is_package else here[:-1]
                anchor = anchor[:len(anchor) - (node.level - 1)]
                base = ".".join(anchor + ([base] if base else []))
            names = [f"{base}.{alias.name}" for alias in node.names]
        else:
            continue
        for name in names:
            while name and name not in known:
                name = name.rpartition(".")[0]
            if name:
                found.add(name)
    return found


def import_graph(root: Path = PACKAGE) -> dict[str, set[str]]:
    modules = package_modules(root)
    known = set(modules)
    return {name: imported_modules(path, known) - {name} for name, path in modules.items()}


def layer_of(module: str) -> int | None:
    best = None
    for index, prefixes in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and (best is None or len(prefix) > best[1]):
                best = (index, len(prefix))
    return None if best is None else best[0]


def upward_imports(graph: dict[str, set[str]]) -> list[str]:
    return [f"{source} (layer {layer_of(source)}) imports {target} (layer {layer_of(target)})"
            for source, targets in sorted(graph.items()) if source != FACE
            for target in sorted(targets) if target != FACE and layer_of(target) < layer_of(source)]


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected groups of more than one module (Tarjan)."""
    order, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(node):
        order[node] = low[node] = len(order)
        stack.append(node)
        on_stack.add(node)
        for other in graph.get(node, ()):
            if other not in order:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], order[other])
        if low[node] == order[node]:
            group = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                found.append(sorted(group))

    for node in sorted(graph):
        if node not in order:
            visit(node)
    return found


def test_every_module_has_a_layer():
    assert [name for name in package_modules() if name != FACE and layer_of(name) is None] == []


def test_no_module_imports_a_higher_layer():
    assert upward_imports(import_graph()) == []


def test_no_import_circles():
    assert circles(import_graph()) == []


def test_the_package_face_imports_only_the_version_when_imported():
    """``import scenerender`` loads only ``version.py``: the API is imported on first use of
    one of its names, and no module inside the package imports the face."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text(encoding="utf-8"))
    imports = [node for node in tree.body if isinstance(node, (ast.Import, ast.ImportFrom))]
    assert [(node.module, [a.name for a in node.names]) for node in imports] == [
        ("scenerender.version", ["__version__"])]
    assert [name for name, targets in import_graph().items() if FACE in targets] == []


def test_only_the_command_line_imports_the_preview():
    """The preview is a leaf: its server, watcher and page stay out of every other path."""
    importers = {source for source, targets in import_graph().items() if not source.startswith("scenerender.preview")
                 and any(t == "scenerender.preview" or t.startswith("scenerender.preview.") for t in targets)}
    assert importers == {"scenerender.cli"}


# The checks must be able to fail: a small package with one upward import and one circle.

@pytest.fixture
def bad_package(tmp_path: Path) -> Path:
    root = tmp_path / "scenerender"
    for name, text in {
        "__init__.py": "",
        "errors.py": "from scenerender.scene import model\n",   # the bottom importing up
        "scene/__init__.py": "",
        "scene/model.py": "from scenerender.scene import checks\n",
        "scene/checks.py": "def f():\n    from scenerender.scene.model import X\n",  # a circle, hidden in a function
    }.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def test_the_checks_catch_an_upward_import_and_a_circle(bad_package, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "PACKAGE", bad_package)
    graph = import_graph(bad_package)
    assert upward_imports(graph) == ["scenerender.errors (layer 11) imports scenerender.scene.model (layer 9)"]
    assert circles(graph) == [["scenerender.scene.checks", "scenerender.scene.model"]]


@pytest.fixture
def tools_below_run(tmp_path: Path) -> Path:
    """The arrows this layer order was made to forbid: a tool in ``compare/`` and the
    reference renderer reaching up into the run layer, with one lawful arrow beside them."""
    root = tmp_path / "scenerender"
    for name, text in {
        "__init__.py": "",
        "run/__init__.py": "",
        "run/session.py": "from scenerender.compare import metrics\n",            # down: lawful
        "compare/__init__.py": "",
        "compare/metrics.py": "",
        "compare/perturbation.py": "from scenerender.run.session import Renderer\n",
        "raytrace/__init__.py": "",
        "raytrace/bench.py": "def sweep():\n    import scenerender.run\n",           # up, inside a function
        "tools/__init__.py": "",
        "tools/bench.py": "from scenerender.run import session\nfrom scenerender.raytrace import bench\n",
    }.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def test_the_layer_check_catches_a_tool_below_the_run_layer(tools_below_run, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "PACKAGE", tools_below_run)
    assert upward_imports(import_graph(tools_below_run)) == [
        "scenerender.compare.perturbation (layer 5) imports scenerender.run.session (layer 4)",
        "scenerender.raytrace.bench (layer 5) imports scenerender.run (layer 4)",
    ]
