"""Fuzzing the scene file: generated scenes from the format's keys, then mutated as text.

Invariant for every input: loading, validating and building the world (what ``validate``
runs) either succeeds or raises a ``UserError`` whose message is one line per problem and at
most a handful of lines; never another exception. Limits are lowered so that a valid but
large scene stays cheap. The number of examples comes from the hypothesis profile in
tests/fuzz/conftest.py; every input that once broke the invariant is a case in tests/corpus/.
"""
from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

import pytest
import yaml
from hypothesis import given
from hypothesis import strategies as st

from scenerender.errors import SceneErrors, UserError, Warnings
from scenerender.limits import Limits
from scenerender.scene.loading import load_scene_text
from scenerender.scene.yaml_source import parse_yaml_text
from scenerender.world.build import build_world

# a numpy warning (overflow, division by zero) would reach the user's terminal: a finding too
pytestmark = pytest.mark.filterwarnings("error::RuntimeWarning")

# small enough that a valid scene builds in well under a second
FUZZ_LIMITS = Limits(objects=40, triangles=400_000, texture_pixels=1 << 16, output_pixels=1 << 20, frames=100_000,
                     instances=5_000, yaml_bytes=1 << 20, yaml_alias_nodes=100_000)
# only under `make fuzz`: an input that takes this long is a finding (limits missing somewhere)
SLOW_SECONDS = 20.0 if os.environ.get("SCENERENDER_FUZZ") else None


def _asset_folder(folder: Path) -> Path:
    """A scene folder with a few real assets, so that file names in fuzzed scenes can resolve."""
    (folder / "model.obj").write_text("mtllib model.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                      "usemtl skin\nf 1/1 2/2 3/3\n", encoding="utf-8")
    (folder / "model.mtl").write_text("newmtl skin\nKd 1 0.5 0.2\nmap_Kd tex.png\n", encoding="utf-8")
    from PIL import Image

    Image.new("RGB", (4, 4), (200, 40, 40)).save(folder / "tex.png")
    (folder / "sky").mkdir()
    for face in ("posx", "negx", "posy", "negy", "posz", "negz"):
        Image.new("RGB", (4, 4), (90, 120, 200)).save(folder / "sky" / f"{face}.png")
    return folder


# removed when the test process ends (the object's finaliser), so runs leave nothing behind
_ASSETS_FOLDER = tempfile.TemporaryDirectory(prefix="scenerender-fuzz-")
ASSETS = _asset_folder(Path(_ASSETS_FOLDER.name))


# ---------------------------------------------------------------------------------------
# values

NUMBERS = st.one_of(
    st.integers(-3, 100),
    st.floats(-1e3, 1e3, allow_nan=False),
    st.sampled_from([0, -0.0, 0.5, 1, 2, 64, 4096, 16384, 10_000_001, 2**63, -(2**63), 1e308, -1e308, 5e-324,
                     float("inf"), float("nan")]),
)
WORDS = st.sampled_from(["", " ", "red", "box", "model.obj", "tex.png", "sky", "frame_{frame:04d}", "{frame}",
                         "../outside.obj", "/etc/passwd", "missing.obj", "model.mtl", "{frame.__class__}", "yes",
                         "null", "~", "é", "\t", "a\nb"])
ANY_SCALAR = st.one_of(NUMBERS, WORDS, st.booleans(), st.none())
ANY = st.recursive(ANY_SCALAR, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                        st.dictionaries(WORDS, inner, max_size=3)), max_leaves=8)


def maybe_wrong(good):
    """Mostly a plausible value, sometimes anything at all. Mostly: a model's own checks
    (frames against duration, near against far...) run only when all its keys are valid."""
    return st.one_of(*[good] * 7, ANY)


def vector(n: int):
    return st.lists(NUMBERS, min_size=n, max_size=n) | st.lists(NUMBERS, max_size=5)


COLOR = st.lists(st.floats(0, 1), min_size=3, max_size=4)


def track(value):
    key = st.one_of(st.tuples(NUMBERS, value).map(list),
                    st.fixed_dictionaries({"t": NUMBERS, "value": value},
                                          optional={"interpolation": st.sampled_from(["step", "linear", "cosine",
                                                                                      "catmull_rom", "cubic"])}))
    return st.fixed_dictionaries({"keys": st.lists(key, max_size=4)},
                                 optional={"interpolation": st.sampled_from(["step", "linear", "cosine", "catmull_rom"]),
                                           "loop": st.booleans()})


def animated(value):
    return maybe_wrong(st.one_of(value, track(value)))


def mapping(required=None, **optional):
    return st.fixed_dictionaries(required or {}, optional={k: maybe_wrong(v) for k, v in optional.items()})


PRIMITIVE = st.one_of(
    mapping({"primitive": st.just("plane")}, size=NUMBERS | vector(2), uv_repeat=NUMBERS),
    mapping({"primitive": st.just("box")}, size=NUMBERS | vector(3)),
    mapping({"primitive": st.just("sphere")}, radius=NUMBERS, segments=st.integers(0, 70), rings=st.integers(0, 70)),
    mapping({"primitive": st.sampled_from(["cylinder", "cone"])}, radius=NUMBERS, height=NUMBERS,
            segments=st.integers(0, 70)),
    mapping({"primitive": st.sampled_from(["prism", "sphre"])}, sides=st.integers(0, 20)),
)
MATERIAL = mapping(diffuse=animated(COLOR), specular=COLOR, shininess=NUMBERS, opacity=animated(NUMBERS),
                   emissive=COLOR, diffuse_map=WORDS, normal_map=WORDS, wrap=st.sampled_from(["repeat", "clamp"]),
                   unlit=st.booleans())
INSTANCES = st.one_of(
    st.lists(mapping(position=animated(vector(3)), rotation=vector(3), scale=NUMBERS), max_size=3),
    st.fixed_dictionaries({"random": mapping({"count": st.integers(0, 50)}, seed=NUMBERS,
                                             position=st.fixed_dictionaries({"min": vector(3), "max": vector(3)}),
                                             scale=st.fixed_dictionaries({"min": NUMBERS, "max": NUMBERS}))}),
)
OBJECT = mapping(
    {"mesh": maybe_wrong(PRIMITIVE | WORDS)},
    name=WORDS, position=animated(vector(3)), rotation=animated(vector(3)), scale=animated(NUMBERS | vector(3)),
    material=st.sampled_from(["red", "blue"]) | MATERIAL, visible=animated(st.booleans()), normalize=st.booleans(),
    normals=st.sampled_from(["auto", "smooth", "flat"]), cast_shadows=st.booleans(), instances=INSTANCES,
    outline=mapping(color=COLOR, width=NUMBERS), material_overrides=st.dictionaries(WORDS, MATERIAL, max_size=2))
LIGHT = mapping(
    {"type": st.sampled_from(["directional", "point", "spot", "ambient", "area"])},
    position=animated(vector(3)), direction=animated(vector(3)), color=animated(COLOR), intensity=animated(NUMBERS),
    shadows=st.booleans() | mapping(size=NUMBERS, pcf=NUMBERS, bias=NUMBERS), attenuation=vector(3),
    inner_angle=animated(NUMBERS), outer_angle=animated(NUMBERS), attach=st.just("camera"), enabled=animated(st.booleans()))
SCENE = mapping(
    render=mapping(size=st.lists(st.integers(0, 2000), min_size=2, max_size=2), samples=NUMBERS,
                   shading=st.sampled_from(["phong", "blinn_phong", "unlit"]),
                   mode=st.sampled_from(["shaded", "depth", "shadow", "light_depth", "wireframe"]),
                   background=animated(COLOR), skybox=WORDS, exposure=animated(NUMBERS),
                   tone_map=st.sampled_from(["none", "aces", "agx"]),
                   output_transform=st.sampled_from(["srgb", "gamma"]),
                   fog=mapping(density=animated(NUMBERS), mode=st.sampled_from(["exp", "linear"]), start=NUMBERS,
                               end=NUMBERS),
                   ambient_occlusion=mapping(radius=NUMBERS, samples=NUMBERS), shadows=mapping(size=NUMBERS)),
    output=mapping(fps=NUMBERS, duration=NUMBERS, frames=NUMBERS, format=st.sampled_from(["png", "mp4", "gif", "bmp"]),
                   name=st.sampled_from(["f_{frame:03d}", "{frame}", "still"]) | WORDS, quality=NUMBERS),
    camera=mapping(position=animated(vector(3)), target=animated(vector(3)), yaw=animated(NUMBERS),
                   pitch=animated(NUMBERS), fov=animated(NUMBERS), near=NUMBERS | st.just("auto"), far=NUMBERS,
                   up=vector(3), projection=st.sampled_from(["perspective", "orthographic"]), height=NUMBERS),
    lights=st.lists(LIGHT, max_size=3),
    materials=st.dictionaries(st.sampled_from(["red", "blue", "x"]), MATERIAL, max_size=2),
    objects=st.lists(OBJECT, max_size=4),
)


# ---------------------------------------------------------------------------------------
# text mutations

TOKENS = ["&a ", "*a", "<<: *a\n", "<<: ", "!!float ", "!!int ", "!!bool ", "!!python/object ", "!!set ", "? ",
          "[", "]", "{", "}", ":", ": ", "- ", ",", "#", "'", '"', "\\", "|\n", ">\n", "---\n", "...\n",
          "%YAML 1.2\n---\n", "%TAG ! tag:x,2000:\n", "\t", "\x00", "\x07", "\ufeff", "\u2028", "\U0001F600",
          ".inf", ".nan", "1e308", "1e999", "0x1f", "0o17", "9" * 400, "-0", "~", "null", "" , "  ", "\n",
          "objects: []\n", "objects:\n", "x: &a [*a]\n", "{" * 80, "[" * 80]
MUTATIONS = ["insert", "replace_char", "delete_line", "duplicate_line", "swap_lines", "indent", "dedent",
             "truncate", "anchor_alias", "nest"]


def mutate(text: str, steps) -> str:
    for kind, where, token in steps:
        lines = text.split("\n")
        line = where % max(1, len(lines))
        position = where % (len(text) + 1)
        if kind == "insert":
            text = text[:position] + token + text[position:]
        elif kind == "replace_char" and text:
            text = text[:position] + token[:1] + text[position + 1:]
        elif kind == "delete_line":
            del lines[line]
            text = "\n".join(lines)
        elif kind == "duplicate_line":
            lines.insert(line, lines[line])
            text = "\n".join(lines)
        elif kind == "swap_lines":
            other = (where // 7) % len(lines)
            lines[line], lines[other] = lines[other], lines[line]
            text = "\n".join(lines)
        elif kind == "indent":
            lines[line] = "  " + lines[line]
            text = "\n".join(lines)
        elif kind == "dedent":
            lines[line] = lines[line][2:]
            text = "\n".join(lines)
        elif kind == "truncate":
            text = text[:position]
        elif kind == "anchor_alias":  # name a value and use it somewhere else (maybe inside itself)
            colon = text.find(": ", position)
            if colon >= 0:
                text = text[:colon + 2] + "&a " + text[colon + 2:]
                later = text.find(": ", (where // 3) % (len(text) + 1))
                if later >= 0:
                    text = text[:later + 2] + "*a" + text[text.find("\n", later) if "\n" in text[later:] else len(text):]
        elif kind == "nest":
            depth = 1 + where % 100
            text = text[:position] + "[" * depth + "1" + "]" * depth + text[position:]
    return text


STEPS = st.lists(st.tuples(st.sampled_from(MUTATIONS), st.integers(0, 10**6), st.sampled_from(TOKENS)), max_size=4)


def dump(scene: dict) -> str:
    return yaml.safe_dump(scene, sort_keys=False, allow_unicode=True, width=80)


# ---------------------------------------------------------------------------------------
# the invariant


def check_scene_text(text: str, overrides=()) -> None:
    """Load, validate and build: success, or a short UserError; anything else fails the test."""
    started = time.monotonic()
    try:
        loaded = load_scene_text(text, ASSETS, list(overrides), limits=FUZZ_LIMITS)
        build_world(loaded, Warnings())
    except SceneErrors as exc:
        lines = exc.lines()
        assert 1 <= len(lines) <= SceneErrors.MAX_LINES and all("\n" not in line for line in lines), lines
    except UserError as exc:
        assert str(exc) and "\n" not in str(exc), repr(str(exc))
    if SLOW_SECONDS is not None:
        assert time.monotonic() - started < SLOW_SECONDS, f"took {time.monotonic() - started:.1f} s"


@given(scene=SCENE, steps=STEPS)
def test_generated_and_mutated_scenes(scene, steps):
    check_scene_text(mutate(dump(scene), steps))


@given(scene=SCENE)
def test_generated_scenes(scene):
    check_scene_text(dump(scene))


@given(text=st.text(st.sampled_from(list("ab:-[]{}&*!<>?|'\"#%@`,.~ \n\t0123456789eE+x\\")), max_size=200))
def test_yaml_punctuation_soup(text):
    try:
        parse_yaml_text(text, "soup.yaml", FUZZ_LIMITS)
    except UserError as exc:
        assert "\n" not in str(exc)


KEYS = st.sampled_from(["render.size", "render.samples", "output.duration", "output.frames", "output.fps", "objects",
                        "objects[0]", "objects[0].position", "objects[3].mesh", "camera.fov", "lights[0].type",
                        "materials.red", "render..x", "[0]", "objects.0.scale", "render.fog.density", ""])


@given(key=KEYS, value=st.one_of(st.sampled_from(TOKENS), ANY.map(lambda v: yaml.safe_dump(v).strip())),
       scene=SCENE)
def test_set_overrides(key, value, scene):
    check_scene_text(dump(scene), [f"{key}={value}"])


# ---------------------------------------------------------------------------------------
# the YAML builder against PyYAML's own loader, on documents full of anchors, aliases and
# merge keys whose scalars mean the same in YAML 1.1 and 1.2

SCALARS = ["1", "-2", "3.5", "word", "'quoted'", "null", "true", "''", '"two words"']


def _document(data) -> str:
    """A random flow-style document; aliases only name finished anchors (no self-reference)."""
    anchors: list[str] = []
    mapping_anchors: list[str] = []
    names = iter(range(10**6))

    def node(depth: int) -> str:
        kinds = ["scalar", "alias", "sequence", "mapping"] if depth < 4 else ["scalar", "alias"]
        kind = data.draw(st.sampled_from(kinds))
        if kind == "alias" and anchors:
            return "*" + data.draw(st.sampled_from(anchors))
        anchor = f"a{next(names)}" if data.draw(st.booleans()) else None
        if kind == "sequence":
            text = "[" + ", ".join(node(depth + 1) for _ in range(data.draw(st.integers(0, 3)))) + "]"
        elif kind == "mapping":
            keys = data.draw(st.lists(st.sampled_from(["k", "m", "n", "<<"]), unique=True, max_size=4))
            parts = []
            for key in keys:
                if key == "<<":
                    if not mapping_anchors:
                        continue
                    merged = data.draw(st.lists(st.sampled_from(mapping_anchors), min_size=1, max_size=3))
                    parts.append("<<: " + ("*" + merged[0] if len(merged) == 1 else
                                           "[" + ", ".join("*" + m for m in merged) + "]"))
                else:
                    parts.append(f"{key}: {node(depth + 1)}")
            text = "{" + ", ".join(parts) + "}"
        else:
            text = data.draw(st.sampled_from(SCALARS))
        if anchor is None:
            return text
        anchors.append(anchor)
        if kind == "mapping":
            mapping_anchors.append(anchor)
        return f"&{anchor} {text}"

    return node(0)


@given(st.data())
def test_builder_agrees_with_pyyaml(data):
    text = _document(data)
    expected = yaml.safe_load(text)
    got, source = parse_yaml_text(text, "doc.yaml", Limits())
    assert got == expected, text
    assert () in source.values


# ---------------------------------------------------------------------------------------
# one bad value in an otherwise valid scene: every model's own checks (which run only when
# all its keys are valid) meet every kind of value

BASE_SCENE = {
    "render": {"size": [32, 24], "samples": 1, "background": {"keys": [[0, [0, 0, 0]], [1, [1, 1, 1]]]},
               "exposure": {"keys": [[0, 0], [1, 0.5]]}, "tone_map": "agx",
               "fog": {"mode": "linear", "start": 1, "end": 20, "density": 0.1},
               "ambient_occlusion": {"radius": 0.5, "samples": 4}, "shadows": {"size": 64, "pcf": 1}},
    "output": {"fps": 24, "duration": 2, "format": "png", "name": "f_{frame:03d}", "quality": 90},
    "camera": {"position": {"keys": [[0, [0, 2, 8]], [2, [4, 2, 4]]], "interpolation": "catmull_rom"},
               "target": [0, 0, 0], "fov": 50, "near": 0.1, "far": 100, "up": [0, 1, 0]},
    "lights": [{"type": "directional", "direction": [-1, -1, -1], "shadows": True},
               {"type": "point", "position": [0, 3, 0], "attenuation": [1, 0.1, 0.01], "shadows": {"size": 32}},
               {"type": "spot", "position": [0, 4, 0], "direction": [0, -1, 0], "inner_angle": 10,
                "outer_angle": 20, "intensity": {"keys": [[0, 0], [1, 2]], "loop": True}},
               {"type": "ambient", "color": [0.2, 0.2, 0.2]}],
    "materials": {"red": {"diffuse": [1, 0, 0], "shininess": 32, "opacity": 0.5, "diffuse_map": "tex.png"}},
    "objects": [
        {"name": "model", "mesh": "model.obj", "normalize": True, "scale": [1, 2, 1],
         "material_overrides": {"skin": {"diffuse": [0, 1, 0]}}},
        {"mesh": {"primitive": "sphere", "radius": 1, "segments": 8, "rings": 4}, "material": "red",
         "position": {"keys": [{"t": 0, "value": [0, 0, 0]}, {"t": 1, "value": [1, 0, 0], "interpolation": "step"}]},
         "outline": {"color": [1, 1, 0], "width": 0.05}, "visible": {"keys": [[0, True], [1, False]]}},
        {"mesh": {"primitive": "plane", "size": [4, 4], "uv_repeat": 2}, "rotation": [0, 45, 0],
         "instances": [{"position": [1, 0, 0]}, {"position": [-1, 0, 0], "scale": 2}]},
        {"mesh": {"primitive": "cone", "radius": 0.5, "height": 1, "segments": 6}, "cast_shadows": False,
         "instances": {"random": {"count": 5, "seed": 3, "position": {"min": [-1, 0, -1], "max": [1, 0, 1]},
                                  "scale": {"min": 0.5, "max": 1.5}}}},
        {"mesh": {"primitive": "box", "size": 1}, "material": {"diffuse": [0, 0, 1], "unlit": True}},
    ],
}


def _leaf_paths(value, path=()) -> list[tuple]:
    paths = [path] if path else []
    if isinstance(value, dict):
        for key, item in value.items():
            paths += _leaf_paths(item, path + (key,))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            paths += _leaf_paths(item, path + (index,))
    return paths


BASE_PATHS = _leaf_paths(BASE_SCENE)
HOSTILE = st.sampled_from([0, -1, -0.0, 1e-320, 1e308, -1e308, 1e300, 2**63, 2**64 + 1, float("inf"), float("nan"),
                           10_000_001, 16385, [], {}, [0], [0, 0], [0, 0, 0], [1, 1, 1, 1, 1], None, True, "",
                           "x", {"keys": []}, {"keys": [[0, 1]]}, {"keys": [[0, 1], [0, 2]]}, {"keys": [[1e308, 1]]},
                           {"keys": [[0, [1, 2, 3]], [1, 5]]}, {"keys": [[0, 0], [1e-300, 1]], "loop": True}])


def _replace(scene, path: tuple, value):
    node = scene
    for step in path[:-1]:
        node = node[step]
    node[path[-1]] = value


@given(path=st.sampled_from(BASE_PATHS), value=st.one_of(HOSTILE, HOSTILE, NUMBERS, ANY), delete=st.booleans())
def test_one_bad_value_in_a_valid_scene(path, value, delete):
    import copy

    scene = copy.deepcopy(BASE_SCENE)
    if delete and isinstance(path[-1], str):
        node = scene
        for step in path[:-1]:
            node = node[step]
        del node[path[-1]]
    else:
        _replace(scene, path, value)
    check_scene_text(dump(scene))


@pytest.mark.skipif(not os.environ.get("SCENERENDER_FUZZ"), reason="a sweep of minutes: make fuzz runs it")
def test_every_hostile_value_at_every_key():
    """Not random: each value of HOSTILE at each key of BASE_SCENE, and each key left out."""
    import copy

    failures = []
    for path in BASE_PATHS:
        for value in [*HOSTILE.elements, _DELETE]:
            scene = copy.deepcopy(BASE_SCENE)
            if value is _DELETE:
                parent = scene
                for step in path[:-1]:
                    parent = parent[step]
                if not isinstance(path[-1], str):
                    continue
                del parent[path[-1]]
            else:
                _replace(scene, path, value)
            try:
                check_scene_text(dump(scene))
            except Exception as exc:  # noqa: BLE001 - collected, so one run lists them all
                failures.append(f"{path} = {value!r}: {type(exc).__name__}: {exc}")
    assert not failures, "\n".join(failures[:20])


_DELETE = object()


def test_the_base_scene_is_valid():
    loaded = load_scene_text(dump(BASE_SCENE), ASSETS, limits=FUZZ_LIMITS)
    build_world(loaded, Warnings())
