"""The reference's ray engine fallback, the error regions, the Pareto front, and the
`reference` and `bench` commands."""
from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from click.testing import CliRunner

import scenerender
from scenerender.cli import main
from scenerender.raytrace import rays
from scenerender.raytrace.render import ReferenceFrame
from scenerender.tools import bench
from scenerender.tools.quality import frame_errors, region_masks
from scenerender.world.environment_files import write_hdr

SCENE = """
render: {size: [40, 30], samples: 4}
camera: {position: [0, 3, 4], target: [0, 0, 0]}
lights:
  - {type: point, position: [1, 3, 1], shadows: {size: 256}}
objects:
  - mesh: {primitive: plane, size: 6}
  - mesh: {primitive: box}
    position: [0, 0.5, 0]
"""


def test_numpy_fallback_finds_the_hits_embree_finds(monkeypatch):
    rng = np.random.default_rng(3)
    triangles = rng.uniform(-1, 1, (40, 3, 3))
    origins = np.tile([0.0, 0.0, 5.0], (200, 1))
    directions = np.column_stack([rng.uniform(-0.2, 0.2, (200, 2)), -np.ones(200)])
    fast = rays.TriangleCaster(triangles).first_hit(origins, directions)
    monkeypatch.setattr(rays, "embree_available", lambda: False)
    monkeypatch.setattr(rays, "_SLOW_WARNED", False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        slow = rays.TriangleCaster(triangles).first_hit(origins, directions)
    assert any("slow" in str(w.message) for w in caught)
    assert (fast >= 0).sum() > 50
    assert np.array_equal(fast, slow)


def test_hit_parameters_are_float64_exact():
    caster = rays.TriangleCaster(np.array([[[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]]) + 1e7)
    origin = np.array([[1e7 + 0.25, 1e7 + 0.5, 3.0]])
    t, u, v = caster.hit_parameters(np.array([0]), origin, np.array([[0.0, 0.0, -1.0]]))
    assert t[0] == pytest.approx(3.0 - 1e7, abs=1e-6) and (u[0], v[0]) == pytest.approx((0.25, 0.5), abs=1e-9)


def _frame(shadow: np.ndarray, cone: np.ndarray | None = None, mixed=None) -> ReferenceFrame:
    h, w = shadow.shape
    return ReferenceFrame(0, 0.0, np.zeros((h, w, 3), np.float32), np.zeros((h, w, 3), np.uint8),
                          shadow[:, :, None], np.zeros((h, w, 0)) if cone is None else cone[:, :, None],
                          np.zeros((h, w), np.int32), np.zeros((h, w), bool) if mixed is None else mixed, 1)


def test_shadow_edge_region_follows_the_shadow_boundary():
    shadow = np.zeros((20, 20))
    shadow[:, 10:] = 1.0          # a boundary between columns 9 and 10, at a pixel edge
    masks = region_masks(_frame(shadow), radius=2)
    columns = np.flatnonzero(masks["shadow_edge"].any(axis=0))
    assert columns.tolist() == list(range(7, 13))
    assert not (masks["interior"] & masks["shadow_edge"]).any()
    assert masks["interior"][:, :7].all() and masks["interior"][:, 13:].all()


def test_silhouette_pixels_count_as_geometry_edge_not_shadow_or_cone_edge():
    shadow = np.zeros((20, 20))
    shadow[:, 10:] = 1.0
    hard = np.zeros((20, 20))
    hard[10:, :] = 1.0
    mixed = np.zeros((20, 20), bool)
    mixed[:, 9] = True            # an object's silhouette along the shadow's edge
    masks = region_masks(_frame(shadow, hard, mixed), radius=2)
    assert masks["shadow_edge"].any() and masks["cone_edge"].any()
    assert not (masks["shadow_edge"] & mixed).any() and not (masks["cone_edge"] & mixed).any()
    assert masks["geometry_edge"][:, 8:11].all()


def test_umbra_leak_is_the_share_of_the_blocked_light_let_through():
    shadow = np.zeros((10, 10))
    shadow[:, 5:] = 1.0
    shadow[:, 5] = 0.5            # partly in shadow: left out
    frame = _frame(shadow)
    frame.linear[:] = 0.1
    frame.blocked = np.where(shadow == 1.0, 0.4, 0.0)[:, :, None].astype(np.float32)
    gpu = frame.linear.copy()
    gpu[:, 6:] += 0.1             # a quarter of the 0.4 the shadow takes away
    errors = frame_errors(frame, frame.pixels, gpu, with_flip=False)
    assert errors["umbra_leak"] == pytest.approx(25.0)
    assert errors["shadow_edge_rel"] == pytest.approx(100.0 * errors["shadow_edge_rmse"] / 100.0 / 0.1, rel=1e-6)
    frame.blocked = None
    assert frame_errors(frame, frame.pixels, gpu, with_flip=False)["umbra_leak"] is None


def test_a_smooth_cone_falloff_is_not_an_edge_but_a_hard_one_is():
    ramp = np.tile(np.linspace(0, 1, 20), (20, 1))  # 0.05 a pixel
    hard = (ramp > 0.5).astype(float)
    assert not region_masks(_frame(np.zeros((20, 20)), ramp))["cone_edge"].any()
    assert region_masks(_frame(np.zeros((20, 20)), hard))["cone_edge"].any()


def test_pareto_front_keeps_only_unbeaten_rows():
    rows = [bench.BenchRow(bench.Variant(name, "size" if name == "smaller" else "k"), ms, errors={"rmse_linear": err})
            for name, ms, err in [("fast", 10, 3.0), ("good", 30, 1.0), ("worse", 40, 2.0), ("tie", 30, 1.0),
                                  ("mid", 20, 2.0), ("smaller", 1, 0.1)]]
    bench.mark_pareto(rows)
    # another image size is measured against another reference: it neither joins nor beats
    assert [r.variant.name for r in rows if r.pareto] == ["fast", "good", "tie", "mid"]


def test_reference_command_writes_exr_and_png(tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text(SCENE)
    result = CliRunner().invoke(main, ["reference", str(scene), "-o", str(tmp_path / "ref"), "--spp", "2"])
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in (tmp_path / "ref").iterdir()) == ["frame_0000.exr", "frame_0000.png"]


def test_reference_command_refuses_other_modes_in_one_line(tmp_path):
    scene = tmp_path / "s.yaml"
    scene.write_text(SCENE)
    result = CliRunner().invoke(main, ["reference", str(scene), "-o", str(tmp_path / "ref"),
                                       "--set", "render.mode=depth"])
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and "render.mode" in lines[0] and "'shaded' only" in lines[0]
    assert not (tmp_path / "ref").exists()


def test_bench_command_writes_table_json_and_plot(gl, tmp_path):
    scene = tmp_path / "tiny.yaml"
    scene.write_text(SCENE)
    result = CliRunner().invoke(main, ["bench", str(scene), "-o", str(tmp_path / "q"), "--knob", "ao",
                                       "--frames", "1", "--rounds", "1", "--spp", "2", "--json"])
    assert result.exit_code == 0, result.output
    rows = json.loads(result.output[result.output.index("["):result.output.rindex("]") + 1])
    assert [r["name"] for r in rows] == ["default", "ao on"]
    assert all(r["ms_per_frame"] > 0 and r["rmse_linear"] is not None for r in rows)
    assert any(r["pareto"] for r in rows)
    written = sorted(p.name for p in (tmp_path / "q").iterdir())
    assert written == ["tiny.json", "tiny.md", "tiny.png"]
    assert (tmp_path / "q" / "tiny.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_bench_measures_against_the_path_traced_reference_where_asked(gl, tmp_path):
    scene = tmp_path / "tiny.yaml"
    scene.write_text(SCENE)
    runs = {}
    for bounces in ("0", "3"):
        folder = tmp_path / f"q{bounces}"
        result = CliRunner().invoke(main, ["bench", str(scene), "-o", str(folder), "--knob", "ao", "--frames", "1",
                                           "--rounds", "1", "--spp", "2", "--bounces", bounces])
        assert result.exit_code == 0, result.output
        runs[bounces] = (json.loads((folder / "tiny.json").read_text()), (folder / "tiny.md").read_text())
    assert runs["0"][0]["bounces"] == 0 and "path-traced" not in runs["0"][1]
    assert runs["3"][0]["bounces"] == 3 and "Against the reference path-traced to 3 bounces." in runs["3"][1]
    # the floor lights the box's sides: the GPU, with no bounce light, is further off
    default = [r for r in runs["3"][0]["rows"] if r["name"] == "default"][0]
    direct = [r for r in runs["0"][0]["rows"] if r["name"] == "default"][0]
    assert default["rmse_linear"] > direct["rmse_linear"]


def test_bench_offers_every_knob_of_the_sweep_and_the_environment_ones_where_it_has_one(tmp_path):
    command = next(c for name, c in main.commands.items() if name == "bench")
    knob_option = next(p for p in command.params if p.name == "knobs")
    assert tuple(knob_option.type.choices) == bench.KNOBS
    write_hdr(tmp_path / "e.hdr", np.ones((8, 16, 3)))
    text = "lights: [{type: point}, {type: environment, image: e.hdr}]\nobjects: [{mesh: {primitive: box}}]\n"
    variants = bench.sweep_variants(scenerender.Scene.from_yaml(text, tmp_path))
    overrides = [o for v in variants if v.knob in ("prefilter_size", "sh_order", "env_samples", "env_footprint")
                 for o in v.overrides]
    assert "lights[1].prefilter_size=64" in overrides and "lights[1].sh_order=1" in overrides
    assert "lights[1].prefilter_size=128" not in overrides  # the default
    assert "lights[1].samples=32" in overrides and "lights[1].samples=512" not in overrides  # 512: the default
    assert "lights[1].footprint=true" in overrides
    specular = [v.overrides for v in variants if v.knob == "env_specular"]
    assert ("lights[1].specular=sampled", "lights[1].specular_samples=32") in specular
    assert all(o != ("lights[1].specular=split_sum",) for o in specular)  # split_sum: the default
    seen = [o for v in variants if v.knob in ("env_visibility", "env_directions", "env_map_size", "env_interleave")
            for o in v.overrides]
    assert "lights[1].visibility=false" in seen and "lights[1].visibility_directions=16" in seen
    assert "lights[1].visibility_directions=32" not in seen and "lights[1].visibility_map_size=1024" in seen  # 32: the default
    # 3: what the default, auto, takes at the default image size
    assert "lights[1].visibility_interleave=1" in seen and "lights[1].visibility_interleave=2" in seen
    assert "lights[1].visibility_interleave=3" not in seen
    without = bench.sweep_variants(scenerender.Scene.from_yaml("objects: [{mesh: {primitive: box}}]\n", tmp_path))
    assert not [v for v in without if v.knob in ("prefilter_size", "sh_order", "env_samples")]


def test_bench_sweeps_the_sub_frames_only_where_the_camera_films(tmp_path):
    box = "objects: [{mesh: {primitive: box}}]\n"
    filmed = bench.sweep_variants(scenerender.Scene.from_yaml("camera: {shutter: 0.5}\n" + box, tmp_path))
    overrides = [o for v in filmed if v.knob == "film_samples" for o in v.overrides]
    assert "render.film_samples=4" in overrides and "render.film_samples=16" not in overrides  # 16: the default
    plain = bench.sweep_variants(scenerender.Scene.from_yaml(box, tmp_path))
    assert not [v for v in plain if v.knob == "film_samples"]


def test_bench_sweeps_the_other_motion_blur_only_where_the_shutter_opens(tmp_path):
    box = "objects: [{mesh: {primitive: box}}]\n"
    filmed = bench.sweep_variants(scenerender.Scene.from_yaml("camera: {shutter: 0.5}\n" + box, tmp_path))
    assert [v.overrides for v in filmed if v.knob == "motion_blur"] == [("render.motion_blur=velocity",)]
    fast = "render: {motion_blur: velocity}\ncamera: {shutter: 0.5}\n" + box
    assert [v.overrides for v in bench.sweep_variants(scenerender.Scene.from_yaml(fast, tmp_path))
            if v.knob == "motion_blur"] == [("render.motion_blur=sub_frames",)]
    lens_only = bench.sweep_variants(scenerender.Scene.from_yaml("camera: {aperture: 2}\n" + box, tmp_path))
    assert not [v for v in lens_only if v.knob == "motion_blur"]
