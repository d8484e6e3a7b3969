"""The CI recipe as a user copies it: `render --check ref/ --update-references` once, then
`render --check ref/` after each edit, no other flag. Every change colours alone let
through (a sphere moved 5 cm, a shininess halved, a ~1-px pole moved 1 px on open floor, a
pole behind glass moved 1 px, a faceted model recoloured 15%, the sun turned 5 degrees)
fails; every noise case (a re-render, LP_NUM_THREADS 1 and 7, --workers 2, quarter-pixel
camera turns and moves, on two scenes) passes. Each test prints its margin: the largest
score / limit of the default rule (over 1 fails), so a change that fails by a hair shows."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from scenerender.cli import main
from scenerender.compare import DEFAULT_RULE, compare_paths
from scenerender.compare.sources import open_side
from scenerender.tools.perturbation import SceneCase

ROOT = Path(__file__).resolve().parent.parent
pytestmark = pytest.mark.gl

# name -> (scene, the view and size every render of it keeps)
# primitives at 6 frames a second: 24 frames over the point light's whole sweep (its own 24
# give 96 frames of the same sweep, four times the file's time for no other case)
PRIMITIVES = SceneCase("primitives", "scenes/primitives.yaml", 0, (0, 5.2, 8.5), (0, 0.4, 0), 50, size=(320, 240),
                       setup=("output.fps=6",))
VERDICT = SceneCase("verdict", "tests/diff_corpus/verdict.yaml", 0, (0, 1.6, 5), (0, 0.4, 0), 45, size=(320, 240))
SCENES = {case.name: case for case in (PRIMITIVES, VERDICT)}


def _pole_moved(case: SceneCase, index: int, position) -> list[str]:
    x, y, z = case.shifted(position, 1.0)
    return [f"objects[{index}].position=[{x:.5f}, {y:.5f}, {z:.5f}]"]


# case -> (scene, --set edits)
CHANGES = {
    "sphere moved 5 cm": ("primitives", ["objects[6].position=[3.05, 0.5, -2.2]"]),
    "steel shininess halved": ("primitives", ["materials.steel.shininess=80"]),
    "dark 1-px pole moved 1 px on open floor": ("verdict", _pole_moved(VERDICT, 1, (1.3, 0.7, 0.6))),
    "white pole behind glass moved 1 px": ("verdict", _pole_moved(VERDICT, 2, (-1.2, 0.45, -0.4))),
    "faceted model recoloured 15%": ("verdict", ["objects[4].material.diffuse=[0.4675, 0.425, 0.357]"]),
    "sun turned 5 degrees": ("verdict", ["lights[0].direction=[-0.53297, -1.0, -0.35491]"]),
}


def _camera_moved(case: SceneCase, fraction: float) -> list[str]:
    """The camera carried (not turned) so the image moves ``fraction`` of a pixel."""
    right, up = case.pixel_axes()
    step = (right + up) * fraction * case.pixel_size(case.target)
    return [f"camera.position=[{', '.join(f'{v:.6g}' for v in np.add(case.position, step))}]",
            f"camera.target=[{', '.join(f'{v:.6g}' for v in np.add(case.target, step))}]"]


def _sets(overrides) -> list[str]:
    return [arg for key in overrides for arg in ("--set", key)]


def render_check(case: SceneCase, out: Path, ref: Path, edits=(), *options, env=None):
    """`scenerender render SCENE -o OUT --check REF` with ``edits``, in a process of its own
    when ``env`` is given -> (exit code, stderr)."""
    args = ["render", str(case.path), "-o", str(out), "--check", str(ref), *_sets(case.base() + list(edits)),
            *options]
    if env is None:
        result = CliRunner().invoke(main, args)
        return result.exit_code, result.stderr
    done = subprocess.run([sys.executable, "-m", "scenerender", *args], cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, **env}, timeout=300)
    return done.returncode, done.stderr


def margin(ref: Path, out: Path) -> tuple[float, str]:
    """The largest score / limit of the default rule for the first frame of each folder,
    and which limit. Only that frame is compared: the --check before it has judged them all
    (primitives has 24), and comparing the rest again took a third of the file's time."""
    first = open_side(ref).names[0]
    frame = compare_paths(ref / first, out / first).frames[0]
    m, o, rule = frame.metrics, frame.objects, DEFAULT_RULE
    ratios = {"max_tile": m.worst_tile_aa / rule.max_tile,
              "max_unexplained_mean": m.unexplained_mean / rule.max_unexplained_mean,
              "max_shift_tile": m.shift_tile / rule.max_shift_tile,
              "max_still_region": m.still_region / rule.max_still_region}
    if o is not None:
        ratios.update({"min_object_pixels": o.one_side_pixels / rule.min_object_pixels,
                       "max_object_shift": o.shift / rule.max_object_shift,
                       "max_interior_change": o.interior / rule.max_interior_change})
    worst = max(ratios, key=ratios.get)
    return ratios[worst], worst


@pytest.fixture(scope="module")
def references(tmp_path_factory):
    """Each scene's references, made as the README says: --update-references, no other flag."""
    root = tmp_path_factory.mktemp("verdict")
    for case in SCENES.values():
        code, err = render_check(case, root / f"first-{case.name}", root / f"ref-{case.name}",
                                 (), "--update-references")
        assert code == 0, err
        assert (root / f"ref-{case.name}" / ".object_ids" / "frame_0000.png").is_file()  # kept by default
    return root


@pytest.mark.parametrize("name", sorted(CHANGES))
def test_each_change_fails_by_default(references, name, tmp_path):
    scene, edits = CHANGES[name]
    case = SCENES[scene]
    ref = references / f"ref-{scene}"
    code, err = render_check(case, tmp_path / "out", ref, edits)
    ratio, limit = margin(ref, tmp_path / "out")
    print(f"{name}: fails by {limit}, score / limit {ratio:.2f}")
    assert code == 1, f"{name} passed the default --check: {err}"
    assert "judged by object ids and colour" in err
    assert ratio > 1
    if "behind glass" in name:  # judged on the layer behind the glass, which the first layer hides
        assert "white_pole (behind glass) moved" in err, err


NOISE = {
    "re-render": ((), {}),
    "LP_NUM_THREADS=1": ((), {"LP_NUM_THREADS": "1"}),
    "LP_NUM_THREADS=7": ((), {"LP_NUM_THREADS": "7"}),
    "--workers 2": (("--workers", "2"), {}),
}


@pytest.mark.slow
@pytest.mark.parametrize("noise", sorted(NOISE))
def test_each_noise_case_passes(references, noise, tmp_path):
    """On the scene with glass, thin poles and a faceted model; a re-render of primitives below."""
    noise_case_passes("verdict", noise, references, tmp_path)


def test_a_re_render_of_primitives_passes(references, tmp_path):
    noise_case_passes("primitives", "re-render", references, tmp_path)


def noise_case_passes(scene, noise, references, tmp_path):
    case = SCENES[scene]
    options, env = NOISE[noise]
    ref = references / f"ref-{scene}"
    code, err = render_check(case, tmp_path / "out", ref, (), *options, env=env or None)
    ratio, limit = margin(ref, tmp_path / "out")
    print(f"{scene}, {noise}: passes, worst {limit} at {ratio:.2f} of its limit")
    assert code == 0, err


@pytest.mark.parametrize("scene", sorted(SCENES))
@pytest.mark.parametrize("how", ["turned", "moved"])
def test_a_quarter_pixel_camera_change_passes(references, scene, how, tmp_path):
    case = SCENES[scene]
    edits = case.jittered(1 / 4) if how == "turned" else _camera_moved(case, 1 / 4)
    ref = references / f"ref-{scene}"
    code, err = render_check(case, tmp_path / "out", ref, edits)
    ratio, limit = margin(ref, tmp_path / "out")
    print(f"{scene}, camera {how} 1/4 px: passes, worst {limit} at {ratio:.2f} of its limit")
    assert code == 0, err
    assert ratio < 1


def test_references_without_ids_still_work_and_say_by_colour(references, tmp_path):
    """A reference folder as 0.5.0 made it (no .object_ids/): the check still runs, judges
    by colour alone and says so; an edit colours catch still fails."""
    import shutil

    old = tmp_path / "old-ref"
    shutil.copytree(references / "ref-verdict", old)
    shutil.rmtree(old / ".object_ids")
    code, err = render_check(VERDICT, tmp_path / "same", old)
    assert code == 0, err
    assert "judged by colour alone: the reference has no object ids" in err
    code, err = render_check(VERDICT, tmp_path / "changed", old, ["objects[4].visible=false"])
    assert code == 1 and "judged by colour alone" in err


def test_no_object_ids_opts_out_and_the_colours_alone_still_fail_a_still_frame(references, tmp_path):
    """--no-object-ids: the colour verdict alone, said so. The shininess halved (130 px, up
    to 27 levels, every one under half its local contrast) passed the colours before the
    still region limit; the frame did not move, so it fails them now."""
    code, err = render_check(PRIMITIVES, tmp_path / "out", references / "ref-primitives",
                             CHANGES["steel shininess halved"][1], "--no-object-ids")
    assert "judged by colour alone" in err
    assert not (tmp_path / "out" / ".object_ids").exists()
    assert code == 1 and "nothing moved, yet a region changed one way" in err, err
