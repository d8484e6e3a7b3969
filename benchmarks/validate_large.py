"""How long `scenerender validate` takes on a large generated scene, phase by phase.

    python benchmarks/validate_large.py            # 50,000 primitive objects
    python benchmarks/validate_large.py 100000

The scene (written to a temporary folder) holds N objects with inline primitives, a named
material and one position each, about 100 bytes of YAML per object. Times are CPU seconds
of this process (the machine may be shared); each phase is run three times, the median shown.
"""
from __future__ import annotations

import statistics
import sys
import tempfile
import time
from pathlib import Path

PRIMITIVES = ["{primitive: box, size: 1}", "{primitive: sphere, radius: 0.5}", "{primitive: cone}",
              "{primitive: plane, size: [2, 3]}"]


def write_scene(folder: Path, count: int) -> Path:
    lines = ["render: {size: [64, 48]}", "materials:", "  red: {diffuse: [1, 0, 0]}", "objects:"]
    for i in range(count):
        lines.append(f"  - name: o{i}\n    mesh: {PRIMITIVES[i % 4]}\n"
                     f"    position: [{i % 100}, {i // 100 % 100}, {i // 10000}]\n    material: red")
    path = folder / "large.yaml"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def median_seconds(function, repeats: int = 3) -> tuple[float, object]:
    times, result = [], None
    for _ in range(repeats):
        started = time.process_time()
        result = function()
        times.append(time.process_time() - started)
    return statistics.median(times), result


def main(count: int) -> None:
    from scenerender.errors import Warnings
    from scenerender.limits import Limits
    from scenerender.scene import load_scene
    from scenerender.scene.yaml_source import load_yaml
    from scenerender.world.build import build_world

    limits = Limits(objects=max(count, Limits().objects))
    with tempfile.TemporaryDirectory() as folder:
        path = write_scene(Path(folder), count)
        size = path.stat().st_size
        yaml_s, _ = median_seconds(lambda: load_yaml(path, limits))
        load_s, loaded = median_seconds(lambda: load_scene(path, limits=limits))
        build_s, _ = median_seconds(lambda: build_world(loaded, Warnings()))
    print("| objects | YAML bytes | read YAML | + validate | build world | validate total |")
    print("|---|---|---|---|---|---|")
    print(f"| {count:,} | {size / 1e6:.1f} MB | {yaml_s:.2f} s | {load_s - yaml_s:.2f} s | {build_s:.2f} s "
          f"| {load_s + build_s:.2f} s |")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 50_000)
