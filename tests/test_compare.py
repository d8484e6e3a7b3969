"""scenerender.compare and `scenerender diff`: metrics, the rule on synthetic frames,
images, folders and videos, missing and extra frames, provenance, exit codes, JSON and the
HTML report. No GL: the frames are drawn here with numpy (anti-aliased by supersampling)."""
from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from scenerender.cli import main
from scenerender.compare import DEFAULT_RULE, DiffRule, compare_images, compare_paths, write_html_report
from scenerender.compare.metrics import flip_available, measure, unexplained_difference
from scenerender.compare.sources import decoder_reason, srgb_bytes
from scenerender.errors import display_path

SUPERSAMPLE = 4


def drawn(shift=(0.0, 0.0), disc_colour=(200, 60, 40), square_at=40, drop_disc=False, size=(64, 48)) -> np.ndarray:
    """A small (H, W, 3) uint8 frame: a gradient background, a disc and a square, drawn 4x
    larger and averaged down so edges are anti-aliased. ``shift`` moves the whole picture
    by (x, y) pixels, in steps of 1/4 pixel."""
    width, height = size[0] * SUPERSAMPLE, size[1] * SUPERSAMPLE
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    x -= shift[0] * SUPERSAMPLE
    y -= shift[1] * SUPERSAMPLE
    image = np.empty((height, width, 3))
    image[...] = np.stack([40 + 80 * y / height, 60 + 60 * y / height, 120 + 100 * y / height], axis=2)
    if not drop_disc:
        disc = (x - 20 * SUPERSAMPLE) ** 2 + (y - 22 * SUPERSAMPLE) ** 2 < (9 * SUPERSAMPLE) ** 2
        image[disc] = disc_colour
    square = (x >= square_at * SUPERSAMPLE) & (x < (square_at + 14) * SUPERSAMPLE) & \
             (y >= 12 * SUPERSAMPLE) & (y < 34 * SUPERSAMPLE)
    image[square] = (230, 220, 90)
    small = image.reshape(size[1], SUPERSAMPLE, size[0], SUPERSAMPLE, 3).mean(axis=(1, 3))
    return np.round(small).astype(np.uint8)


def save(path: Path, image: np.ndarray) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(path)
    return path


def verdict(reference, output, rule=DEFAULT_RULE) -> bool:
    return compare_images("frame", reference, output, rule).passed


# -- metrics and the rule -------------------------------------------------------------------

def test_identical_frames_score_zero():
    image = drawn()
    metrics, _ = measure(image, image, aa_tolerance=1)
    assert metrics.mean_abs == 0 and metrics.worst_tile_aa == 0 and metrics.unexplained_mean == 0
    assert math.isinf(metrics.psnr) and metrics.ssim == 1.0
    assert metrics.to_json()["psnr"] is None  # JSON has no infinity


def test_an_edge_shift_is_explained_and_a_new_colour_is_not():
    # one row: a dark-to-bright edge. Shifting it by a pixel puts colours where the other
    # image's neighbourhood already had them.
    reference = np.array([[[10] * 3, [10] * 3, [200] * 3, [200] * 3]], np.uint8)
    shifted = np.array([[[10] * 3, [10] * 3, [10] * 3, [200] * 3]], np.uint8)
    assert not unexplained_difference(reference, shifted, tolerance=0).any()
    # a 3x3 patch 20 levels darker: its centre's colour is in neither neighbourhood
    flat = np.full((5, 5, 3), 100, np.uint8)
    darker = flat.copy()
    darker[1:4, 1:4] = 80
    unexplained = unexplained_difference(flat, darker, tolerance=0)
    assert unexplained[2, 2] == 20 and unexplained.sum() == 20
    assert unexplained_difference(flat, darker, tolerance=5)[2, 2] == 15


def test_changes_thinner_than_three_pixels_are_excused():
    """The documented limit of the edge tolerance: a one- or two-pixel-wide change looks like
    an edge shift (either image's neighbourhood holds the other's colour)."""
    flat = np.full((6, 6, 3), 100, np.uint8)
    line = flat.copy()
    line[:, 2:4] = 20
    assert not unexplained_difference(flat, line, tolerance=0).any()


@pytest.mark.parametrize("shift", [(0.25, 0.0), (0.0, 0.25), (0.25, 0.25), (0.5, 0.0)])
def test_sub_pixel_shifts_pass(shift):
    assert verdict(drawn(), drawn(shift=shift))


def test_dither_and_a_one_level_offset_pass():
    image = drawn()
    noise = np.random.default_rng(1).integers(-1, 2, size=image.shape)
    assert verdict(image, np.clip(image.astype(int) + noise, 0, 255).astype(np.uint8))
    assert verdict(image, np.clip(image.astype(int) + 1, 0, 255).astype(np.uint8))


@pytest.mark.parametrize("change", [
    dict(square_at=43),                      # an object moved 3 pixels
    dict(drop_disc=True),                    # an object dropped
    dict(disc_colour=(180, 54, 36)),         # its colour 10% darker
])
def test_real_changes_fail(change):
    result = compare_images("frame", drawn(), drawn(**change))
    assert not result.passed, result.metrics
    assert result.regions, "a changed frame outlines where it changed"
    assert result.images is not None and result.images.heatmap is not None


def test_a_looser_rule_passes_what_the_default_fails():
    moved = drawn(square_at=43)
    assert not verdict(drawn(), moved)
    assert verdict(drawn(), moved, DiffRule(max_tile=1000, max_unexplained_mean=1000, max_shift_tile=1000,
                                            max_still_region=1e9))


def test_the_tile_limit_catches_a_local_change_the_frame_mean_misses():
    """At 640x480 a 5x5-pixel patch 12 levels off (a lost highlight, say) adds too little to
    the frame's mean to cross its limit; the 8x8 tile holding it crosses the tile limit, which
    names it first, and so does the 12x12 window of what the best shift leaves (no shift
    explains it), and the still region (nothing else moved: 25 px, 11 levels past the
    rounding each). A rule with those three limits lifted passes it."""
    reference = drawn(size=(640, 480))
    patched = reference.copy()
    patched[296:301, 400:405] += 12
    result = compare_images("frame", reference, patched)
    assert result.metrics.unexplained_mean < DEFAULT_RULE.max_unexplained_mean
    assert result.metrics.worst_tile_aa > DEFAULT_RULE.max_tile
    assert not result.passed and result.reason.startswith("worst 8x8 tile")
    assert result.metrics.shift_tile > DEFAULT_RULE.max_shift_tile
    assert result.metrics.still_region == 25 * 11 and result.metrics.frame_shift < 1 / 128
    assert not verdict(reference, patched, DiffRule(max_tile=1000))
    assert not verdict(reference, patched, DiffRule(max_tile=1000, max_shift_tile=1000))
    assert verdict(reference, patched, DiffRule(max_tile=1000, max_shift_tile=1000, max_still_region=1e9))


def _faceted(height=96, width=128, tint=1.0) -> np.ndarray:
    """A finely faceted surface: each pixel a random grey between 60 and 200 levels (every
    pixel's 3x3 neighbourhood spans a wide range), times ``tint``, beside a flat background."""
    rng = np.random.default_rng(3)
    image = rng.uniform(60, 200, size=(height, width)) * tint
    image[:, : width // 4] = 90.0
    return np.clip(np.stack([image] * 3, axis=2), 0, 255).round().astype(np.uint8)


def test_a_faint_recolour_of_a_faceted_surface_fails_in_a_still_frame():
    """A 5% darker faceted surface: every pixel lies inside its neighbours' colour range
    and under half their contrast, which the allowances for moved edges forgive; nothing
    moved (the frame's displacement reads 0), so the one-sign region fails the still limit,
    by far. Without that limit it passes: the limit, not another, catches it."""
    reference, darker = _faceted(), _faceted(tint=0.95)
    result = compare_images("frame", reference, darker)
    assert result.metrics.frame_shift < 1 / 128
    assert result.metrics.still_region > 20 * DEFAULT_RULE.max_still_region
    assert not result.passed and "nothing moved" in result.reason
    assert verdict(reference, darker, DiffRule(max_still_region=1e30))


def test_a_still_frame_with_rounding_noise_passes():
    """Dither of one level and an offset of one level leave nothing past the rounding."""
    reference = _faceted()
    rng = np.random.default_rng(0)
    dithered = np.clip(reference.astype(np.int16) + rng.integers(-1, 2, reference.shape), 0, 255).astype(np.uint8)
    result = compare_images("frame", reference, dithered)
    assert result.passed and result.metrics.still_region == 0


def _smooth_pattern(height=48, width=64, dx=0.0, dy=0.0) -> np.ndarray:
    """A smooth colour pattern sampled at pixel centres moved by (dx, dy): what a camera
    turned by a fraction of a pixel gives, without MSAA's steps."""
    y, x = np.mgrid[0:height, 0:width].astype(np.float64)
    x, y = x + dx, y + dy
    red = 128 + 90 * np.sin(x / 3.0) * np.cos(y / 4.0)
    green = 128 + 80 * np.cos((x + y) / 5.0)
    blue = 128 + 60 * np.sin(y / 2.5)
    return np.clip(np.stack([red, green, blue], axis=2), 0, 255).round().astype(np.uint8)


def test_a_quarter_pixel_shift_is_excused_and_its_shift_found():
    result = compare_images("frame", _smooth_pattern(), _smooth_pattern(dx=0.25))
    assert result.passed, result.reason
    m = result.metrics
    assert m.excused_pixels > 1000 and m.largest_shift <= 0.25 and m.shift_tile < 1.0
    assert result.images is not None and result.images.shifts is not None  # a pass that differs keeps its pictures


def test_changed_regions_box_the_change():
    result = compare_images("frame", drawn(), drawn(drop_disc=True))
    x, y, w, h = result.regions[0]
    # the disc is centred at (20, 22) with radius 9: the box holds it, on the 8-pixel tile grid
    assert x <= 11 and y <= 13 and x + w >= 29 and y + h >= 31
    assert w <= 32 and h <= 32


# -- files, folders and sidecars ------------------------------------------------------------

def make_folder(folder: Path, frames: dict[str, np.ndarray], provenance: dict | None = None) -> Path:
    for name, image in frames.items():
        save(folder / name, image)
    if provenance is not None:
        (folder / ".scenerender.json").write_text(json.dumps(provenance))
    return folder


PROVENANCE = {"scenerender": "9.9.9", "gl": {"renderer": "llvmpipe (LLVM 15.0.6, 256 bits)", "version": "4.5 (Core)"}}


def test_folders_match_by_name_and_list_missing_and_extra(tmp_path):
    ref = make_folder(tmp_path / "ref", {"frame_0000.png": drawn(), "frame_0001.png": drawn(),
                                         "frame_0002.png": drawn()}, PROVENANCE)
    out = make_folder(tmp_path / "out", {"frame_0000.png": drawn(), "frame_0001.png": drawn(drop_disc=True),
                                         "frame_0003.png": drawn()})
    (out / ".frame_0004.png.x1.partial.png").write_bytes(b"unfinished")  # never a frame
    result = compare_paths(ref, out)
    assert not result.passed
    assert [f.name for f in result.frames] == ["frame_0000.png", "frame_0001.png"]
    assert [f.name for f in result.changed] == ["frame_0001.png"]
    assert result.missing == ["frame_0002.png"] and result.extra == ["frame_0003.png"]
    lines = result.summary_lines()
    assert lines[0].startswith("CHANGED frame_0001.png: worst 8x8 tile")
    assert "MISSING frame_0002.png: in the reference, not in the output" in lines
    assert "EXTRA frame_0003.png: in the output, not in the reference" in lines
    assert lines[-1] == "FAIL: 1 of 2 frame(s) changed, 1 missing, 1 extra; judged by colour alone: neither side has object ids"
    assert result.reference.provenance.gl_renderer.startswith("llvmpipe")
    assert result.output.provenance.gl_renderer == "unknown"


def test_identical_folders_pass_and_the_sidecar_is_no_frame(tmp_path):
    frames = {"a.png": drawn(), "b.png": drawn(shift=(0.25, 0))}
    ref = make_folder(tmp_path / "ref", frames, PROVENANCE)
    out = make_folder(tmp_path / "out", {"a.png": drawn(), "b.png": drawn()}, PROVENANCE)
    result = compare_paths(ref, out)
    assert result.passed and not result.missing and not result.extra
    assert result.summary_lines() == [result.total_line()] and result.total_line().startswith("PASS: 2 frame(s)")


def test_single_file_provenance_comes_from_its_own_sidecar(tmp_path):
    ref = save(tmp_path / "ref.png", drawn())
    out = save(tmp_path / "out" / "frame_0000.png", drawn())
    (tmp_path / ".ref.png.scenerender.json").write_text(json.dumps(PROVENANCE))
    (tmp_path / "out" / ".scenerender.json").write_text(json.dumps({"scenerender": "1.2.3"}))
    result = compare_paths(ref, out)
    assert result.reference.provenance.scenerender == "9.9.9"
    assert result.output.provenance.scenerender == "1.2.3" and result.output.provenance.gl_renderer == "unknown"


def test_a_different_size_is_a_changed_frame(tmp_path):
    ref = save(tmp_path / "ref.png", drawn())
    out = save(tmp_path / "out.png", drawn(size=(32, 24)))
    result = compare_paths(ref, out)
    assert not result.passed and result.changed[0].reason == "size differs: 64x48 vs 32x24"
    assert result.changed[0].metrics is None


def test_exr_frames_are_compared_after_the_srgb_encode(tmp_path):
    import OpenEXR

    linear = np.random.default_rng(3).random((24, 32, 3)).astype(np.float32)
    with OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage},
                      {"RGB": linear}) as exr:
        exr.write(str(tmp_path / "frame.exr"))
    save(tmp_path / "frame.png", srgb_bytes(linear))
    assert srgb_bytes(np.array([[[0.5, 0.0, 1.0]]]))[0, 0].tolist() == [188, 0, 255]
    assert compare_paths(tmp_path / "frame.png", tmp_path / "frame.exr").passed


# -- videos -----------------------------------------------------------------------------------

def write_video(path: Path, frames: list[np.ndarray]) -> Path:
    if path.suffix == ".gif":
        images = [Image.fromarray(f) for f in frames]
        images[0].save(path, save_all=True, append_images=images[1:], duration=40, loop=0)
        return path
    import imageio_ffmpeg

    writer = imageio_ffmpeg.write_frames(str(path), (frames[0].shape[1], frames[0].shape[0]), fps=10,
                                         codec="libx264", pix_fmt_out="yuv420p", macro_block_size=1,
                                         output_params=["-crf", "12"], quality=None)
    writer.send(None)
    for frame in frames:
        writer.send(np.ascontiguousarray(frame))
    writer.close()
    return path


def moving_frames(count: int) -> list[np.ndarray]:
    return [drawn(square_at=30 + 2 * i) for i in range(count)]


def test_gif_frames_are_matched_by_index(tmp_path):
    frames = moving_frames(4)
    ref = write_video(tmp_path / "ref.gif", frames)
    changed = frames[:2] + [drawn(square_at=34, drop_disc=True)] + frames[3:]
    assert compare_paths(ref, write_video(tmp_path / "same.gif", frames)).passed
    result = compare_paths(ref, write_video(tmp_path / "out.gif", changed))
    assert [f.name for f in result.changed] == ["frame_0002"]
    assert result.counts() == {"compared": 4, "passed": 3, "changed": 1, "missing": 0, "extra": 0}


def test_mp4_frame_counts_must_match(tmp_path):
    frames = moving_frames(5)
    ref = write_video(tmp_path / "ref.mp4", frames)
    assert compare_paths(ref, write_video(tmp_path / "same.mp4", frames)).passed
    short = compare_paths(ref, write_video(tmp_path / "short.mp4", frames[:3]))
    assert short.missing == ["frame_0003", "frame_0004"] and not short.passed
    long = compare_paths(ref, write_video(tmp_path / "long.mp4", frames + frames[:1]))
    assert long.extra == ["frame_0005"]


def test_mp4_with_a_dropped_object_fails_on_that_frame(tmp_path):
    frames = moving_frames(4)
    changed = frames[:1] + [drawn(square_at=32, drop_disc=True)] + frames[2:]
    result = compare_paths(write_video(tmp_path / "ref.mp4", frames), write_video(tmp_path / "out.mp4", changed))
    assert "frame_0001" in [f.name for f in result.changed]


# -- the command line -------------------------------------------------------------------------

def run(*args):
    return CliRunner().invoke(main, ["diff", *map(str, args)])


def test_exit_codes(tmp_path):
    ref = save(tmp_path / "ref.png", drawn())
    same = save(tmp_path / "same.png", drawn(shift=(0.25, 0.25)))
    changed = save(tmp_path / "changed.png", drawn(square_at=43))
    broken = tmp_path / "broken.png"
    broken.write_bytes(b"\x89PNG\r\n\x1a\nnot really")
    folder = make_folder(tmp_path / "folder", {"a.png": drawn()})
    video = write_video(tmp_path / "clip.gif", moving_frames(2))
    broken_video = tmp_path / "broken.mp4"
    broken_video.write_bytes(write_video(tmp_path / "whole.mp4", moving_frames(2)).read_bytes()[:300])

    assert run(ref, same).exit_code == 0
    result = run(ref, changed)
    assert result.exit_code == 1 and result.output.startswith("CHANGED changed.png: worst 8x8 tile")
    for args, message in [((ref, broken), "broken.png: cannot read image"),
                          ((ref, tmp_path / "nope.png"), "nope.png: no such file or folder"),
                          ((folder, video), "cannot compare a video with a folder"),
                          ((tmp_path / "whole.mp4", broken_video), "broken.mp4: cannot decode video"),
                          ((tmp_path / "empty1", tmp_path / "empty2"), "no frames to compare")]:
        for path in args:
            if path.name.startswith("empty"):
                path.mkdir()
        result = run(*args)
        assert result.exit_code == 2, (args, result.output)
        assert message in result.output and "Traceback" not in result.output


@pytest.mark.parametrize("damage", ["text", "truncated"])
def test_an_undecodable_video_is_one_short_line(tmp_path, damage):
    """ffmpeg's stderr (banner, build configuration, stream details) stays out of the message."""
    whole = write_video(tmp_path / "whole.mp4", moving_frames(3))
    broken = tmp_path / "broken.mp4"
    broken.write_bytes(b"junk\n" if damage == "text" else whole.read_bytes()[:300])
    result = run(whole, broken)
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line.startswith(f"error: {display_path(broken)}: cannot decode video: ")
    assert len(line) < 200 and "\\n" not in line and "ffmpeg version" not in line, line


@pytest.mark.parametrize("log, reason", [
    ("[in#0 @ 0x55d1c] moov atom not found\n[in#0 @ 0x55d1a] Error opening input: Invalid data found when "
     "processing input\nError opening input file x.mp4.\n", "Invalid data found when processing input"),
    ("[vist#0:0/h264 @ 0x5a] [dec:h264 @ 0x5b] Decoding error: Invalid data found when processing input\n"
     "Conversion failed!\n", "Invalid data found when processing input"),
    ("ffmpeg version 4.2\n  configuration: --enable-gpl\nx.mp4: Invalid data found when processing input\n",
     "Invalid data found when processing input"),
    ("ffmpeg version 9\nsomething else entirely\n", "Could not load meta information"),
])
def test_decoder_reason_is_the_line_that_names_the_cause(log, reason):
    error = OSError(f"Could not load meta information\n=== stderr ===\n{log}")
    assert decoder_reason(error, Path("x.mp4")) == reason


def test_decoder_reason_without_ffmpeg_log():
    assert decoder_reason(OSError("cannot identify image file 'a.gif'"), Path("a.gif")) == \
        "cannot identify image file 'a.gif'"
    assert decoder_reason(RuntimeError("Could not read frame 3:\nEnd of file reached"), Path("a.mp4")) == \
        "Could not read frame 3: End of file reached"


@pytest.mark.parametrize("report", ["afile/report.html", "afile/sub/report.html", "/proc/report.html"])
def test_an_unwritable_report_is_exit_2_naming_report(tmp_path, monkeypatch, report):
    """Exit 1 means "frames changed": a report that cannot be written must not read as that."""
    if report.startswith("/proc") and not Path("/proc/self").is_dir():
        pytest.skip("no /proc here")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile").write_text("mine")
    ref, out = save(tmp_path / "ref.png", drawn()), save(tmp_path / "out.png", drawn(square_at=43))
    result = run(ref, out, "--report", report)
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line.startswith("error: ") and ": cannot write: " in line, line
    assert line.endswith("write elsewhere with --report)"), line
    assert (tmp_path / "afile").read_text() == "mine"
    assert result.stdout == ""  # no verdict printed for a run that failed


def test_a_different_size_exits_1(tmp_path):
    result = run(save(tmp_path / "ref.png", drawn()), save(tmp_path / "out.png", drawn(size=(32, 24))))
    assert result.exit_code == 1 and "size differs: 64x48 vs 32x24" in result.output


def test_json_output(tmp_path):
    ref = make_folder(tmp_path / "ref", {"a.png": drawn(), "b.png": drawn(), "c.png": drawn()}, PROVENANCE)
    out = make_folder(tmp_path / "out", {"a.png": drawn(), "b.png": drawn(drop_disc=True)})
    result = run(ref, out, "--json", "--report", tmp_path / "report.html")
    assert result.exit_code == 1
    data = json.loads(result.output)  # nothing but JSON on stdout
    assert data["verdict"] == "changed" and data["passed"] is False
    assert data["counts"] == {"compared": 2, "passed": 1, "changed": 1, "missing": 1, "extra": 0}
    assert data["missing"] == ["c.png"] and data["extra"] == []
    assert data["rule"] == {"max_tile": DEFAULT_RULE.max_tile, "aa_tolerance": DEFAULT_RULE.aa_tolerance,
                            "max_unexplained_mean": DEFAULT_RULE.max_unexplained_mean,
                            "max_shift_tile": DEFAULT_RULE.max_shift_tile,
                            "max_still_region": DEFAULT_RULE.max_still_region,
                            "min_object_pixels": DEFAULT_RULE.min_object_pixels,
                            "max_object_shift": DEFAULT_RULE.max_object_shift,
                            "max_interior_change": DEFAULT_RULE.max_interior_change}
    assert data["reference"]["provenance"]["gl"]["renderer"].startswith("llvmpipe")
    assert data["output"]["provenance"] == {"scenerender": "unknown", "gl": {"renderer": "unknown",
                                                                               "version": "unknown"}, "sidecar": None}
    a, b = data["frames"]
    assert a["passed"] and a["metrics"]["psnr"] is None and a["reason"] == ""
    assert not b["passed"] and b["regions"] and b["size"] == [64, 48]
    assert a["objects"] is None and b["objects"] is None  # no object ids on either side
    assert set(b["metrics"]) == {"mean_abs", "max_abs", "worst_tile", "bad_percent", "psnr", "unexplained_mean",
                                 "worst_tile_aa", "shift_tile", "shift_pixel", "still_region", "frame_shift", "changed_percent",
                                 "excused_pixels", "largest_shift", "ssim", "flip"}
    assert data["report"] == str(tmp_path / "report.html")
    if flip_available():  # FLIP is computed for the changed frames, where a person looks
        assert b["metrics"]["flip"] > 0 and a["metrics"]["flip"] is None


def test_thresholds_are_options(tmp_path):
    ref, out = save(tmp_path / "ref.png", drawn()), save(tmp_path / "out.png", drawn(square_at=43))
    assert run(ref, out).exit_code == 1
    assert run(ref, out, "--max-tile", "1000", "--max-unexplained-mean", "1000", "--max-shift-tile", "1000").exit_code == 0


@pytest.mark.parametrize("option, value", [
    ("--max-tile", "nan"), ("--max-tile", "inf"), ("--max-tile", "-1"), ("--max-tile", "-inf"),
    ("--max-unexplained-mean", "nan"), ("--max-unexplained-mean", "inf"), ("--max-unexplained-mean", "-0.5"),
    ("--max-shift-tile", "nan"), ("--max-shift-tile", "-1"), ("--max-shift-tile", "inf"),
    ("--aa-tolerance", "-1"), ("--aa-tolerance", "256"), ("--aa-tolerance", "1000000"),
])
@pytest.mark.parametrize("output", ["same.png", "changed.png"])
def test_limits_out_of_range_are_usage_errors(tmp_path, option, value, output):
    """NaN compares false with every score, so a NaN or infinite limit would pass any change;
    a negative one fails identical frames; an --aa-tolerance past the 8-bit levels overflowed.
    Each is a usage error (exit 2), never a verdict (0 or 1)."""
    ref = save(tmp_path / "ref.png", drawn())
    save(tmp_path / "same.png", drawn())
    save(tmp_path / "changed.png", drawn(square_at=43))
    result = run(ref, tmp_path / output, option, value)
    assert result.exit_code == 2, result.output
    assert f"Invalid value for '{option}'" in result.output
    assert "internal error" not in result.output and "Traceback" not in result.output


def test_limits_at_the_ends_of_their_ranges(tmp_path):
    ref, out = save(tmp_path / "ref.png", drawn()), save(tmp_path / "out.png", drawn(square_at=43))
    assert run(ref, ref, "--max-tile", "0", "--max-unexplained-mean", "0", "--max-shift-tile", "0",
               "--aa-tolerance", "0").exit_code == 0
    assert run(ref, out, "--aa-tolerance", "255").exit_code == 0  # every level forgiven


def test_the_cli_defaults_are_the_default_rule():
    params = {p.name: p.default for p in main.commands["diff"].params}
    assert params["max_tile"] == DEFAULT_RULE.max_tile
    assert params["max_unexplained_mean"] == DEFAULT_RULE.max_unexplained_mean
    assert params["max_shift_tile"] == DEFAULT_RULE.max_shift_tile
    assert params["aa_tolerance"] == DEFAULT_RULE.aa_tolerance


def test_the_rule_loads_without_numpy():
    """The command line reads the rule's defaults at start-up; that must stay cheap."""
    code = "import sys, scenerender.compare.rule; print('numpy' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip() == "False"


# -- the report -------------------------------------------------------------------------------

def test_report_is_self_contained(tmp_path):
    ref = make_folder(tmp_path / "ref", {"a.png": drawn(), "b<1>.png": drawn(), "c.png": drawn()}, PROVENANCE)
    out = make_folder(tmp_path / "out", {"a.png": drawn(), "b<1>.png": drawn(drop_disc=True), "d.png": drawn()})
    report = tmp_path / "report.html"
    write_html_report(compare_paths(ref, out), report)
    html = report.read_text()
    # the close-up's three crops; reference, output, heatmap, shift map; the slider's pair
    assert html.count("data:image/png;base64,") == 9
    assert "src=\"http" not in html and "<link" not in html  # nothing fetched from elsewhere
    assert "b&lt;1&gt;.png" in html and "b<1>.png" not in html
    assert 'class="box"' in html and "llvmpipe" in html and "unknown" in html
    assert "missing in the output (1)" in html and "extra in the output (1)" in html
    assert "1 frame(s) pass" in html


def test_the_report_shows_close_up_where_a_thin_line_was_added(tmp_path):
    """A 1-px line fails by the window after the shift; the frame's close-up is centred on
    that window, which holds the line, and the report shows it magnified and says why."""
    reference = drawn()
    output = reference.copy()
    output[6:42, 60] = (250, 250, 250)
    frame = compare_images("frame", reference, output)
    assert not frame.passed and frame.reason.startswith("a 12x12 window")
    x, y, w, h = frame.images.focus
    assert x <= 60 < x + w and y < 42 and y + h > 6, frame.images.focus
    assert frame.images.focus_note.startswith("the worst 12x12 window after the best shift")
    ref = make_folder(tmp_path / "ref", {"f.png": reference})
    out = make_folder(tmp_path / "out", {"f.png": output})
    write_html_report(compare_paths(ref, out), tmp_path / "r.html")
    html = (tmp_path / "r.html").read_text()
    assert "Close up, 8x:" in html and html.count('class="focus"') == 3 + 4  # 3 crops, 4 whole pictures
    assert 'alt="output, close up"' in html


def test_a_passing_frame_shows_close_up_what_it_excused():
    frame = compare_images("frame", drawn(), drawn(shift=(0.25, 0.25)))
    assert frame.passed
    x, y, w, h = frame.images.focus
    assert frame.images.focus_note.startswith("the most excused pixels")
    assert frame.metrics.excused_pixels > 0 and (w, h) == (12, 12)


def test_report_keeps_pictures_of_a_limited_number_of_frames(tmp_path, monkeypatch):
    from scenerender.compare import diff

    monkeypatch.setattr(diff, "MAX_KEPT_IMAGES", 1)
    ref = make_folder(tmp_path / "ref", {f"{i}.png": drawn() for i in range(3)})
    out = make_folder(tmp_path / "out", {f"{i}.png": drawn(drop_disc=True) for i in range(3)})
    result = compare_paths(ref, out)
    assert result.images_dropped == 2 and [f.images is not None for f in result.changed] == [True, False, False]
    write_html_report(result, tmp_path / "r.html")
    assert "2 more changed frame(s) are listed without pictures" in (tmp_path / "r.html").read_text()


def test_videos_inside_folders_are_compared_frame_by_frame(tmp_path):
    frames = moving_frames(3)
    (tmp_path / "ref").mkdir()
    (tmp_path / "out").mkdir()
    write_video(tmp_path / "ref" / "clip.gif", frames)
    write_video(tmp_path / "out" / "clip.gif", frames[:1] + [drawn(drop_disc=True)] + frames[2:])
    write_video(tmp_path / "ref" / "gone.gif", frames)
    (tmp_path / "out" / ".clip.gif.scenerender.json").write_text(json.dumps(PROVENANCE))
    result = compare_paths(tmp_path / "ref", tmp_path / "out")
    assert [f.name for f in result.frames] == ["clip.gif/frame_0000", "clip.gif/frame_0001", "clip.gif/frame_0002"]
    assert [f.name for f in result.changed] == ["clip.gif/frame_0001"]
    assert result.missing == ["gone.gif"]
    assert result.output.provenance.scenerender == "9.9.9"


# -- ignore regions -------------------------------------------------------------------------

def _clock_pair(tmp_path: Path) -> tuple[Path, Path]:
    """Two folders whose frame differs only in a 'clock' at the top right."""
    reference = drawn()
    output = reference.copy()
    output[2:10, 50:62] = 255 - output[2:10, 50:62]
    for folder, image in (("ref", reference), ("out", output)):
        (tmp_path / folder).mkdir()
        Image.fromarray(image).save(tmp_path / folder / "frame_0000.png")
    return tmp_path / "ref", tmp_path / "out"


def test_an_ignore_rectangle_leaves_the_clock_out_and_says_so(tmp_path):
    ref, out = _clock_pair(tmp_path)
    assert not compare_paths(ref, out).passed  # without it, the clock fails
    (ref / "ignore.json").write_text(json.dumps({"rectangles": [{"x": 48, "y": 0, "w": 16, "h": 12, "why": "clock"}]}))
    result = compare_paths(ref, out)
    assert result.passed and result.frames[0].ignored == 16 * 12
    assert "ignored: 192 px in 1 frame(s) (ignore.json: clock)" in result.total_line()
    (ref / "ignore.json").write_text(json.dumps({"rectangles": [{"x": 48, "y": 0, "w": 16, "h": 12,
                                                                 "frames": "other_*"}]}))
    assert not compare_paths(ref, out).passed  # the pattern names other frames


def test_an_ignore_mask_is_not_a_frame_and_leaves_its_pixels_out(tmp_path):
    ref, out = _clock_pair(tmp_path)
    mask = np.zeros((48, 64), np.uint8)
    mask[0:12, 48:64] = 255
    Image.fromarray(mask).save(ref / "ignore.png")
    result = compare_paths(ref, out)
    assert result.passed and [f.name for f in result.frames] == ["frame_0000.png"] and not result.missing
    assert "ignore.png" in result.total_line()


def test_a_malformed_ignore_file_is_bad_input_naming_it(tmp_path):
    ref, out = _clock_pair(tmp_path)
    (ref / "ignore.json").write_text(json.dumps({"rectangles": [{"x": 1, "y": 2, "w": "wide", "h": 3}]}))
    result = CliRunner().invoke(main, ["diff", str(ref), str(out)])
    assert result.exit_code == 2
    assert "ignore.json" in result.stderr and "rectangles[0]" in result.stderr and "Traceback" not in result.output


# -- what a pass excused ------------------------------------------------------------------------

def _square(dx: float = 0.0, h: int = 48, w: int = 64) -> np.ndarray:
    """A light square on a dark ground, anti-aliased (8x8 supersampling), moved ``dx`` px."""
    ss = 8
    y, x = np.mgrid[0:h * ss, 0:w * ss] / ss
    inside = ((x >= 20.3 + dx) & (x < 44.3 + dx) & (y >= 12.2) & (y < 36.2)).astype(float)
    image = inside.reshape(h, ss, w, ss).mean(axis=(1, 3)) * 230 + 10
    return np.stack([image] * 3, axis=2).round().astype(np.uint8)


def test_a_pass_that_excused_a_large_outline_says_so_and_boxes_it(tmp_path):
    """The square moved 0.3 px passes (a sub-pixel shift), but its two vertical edges are
    off by 58 levels over 23 px each: the summary says so in a line of its own, the JSON
    lists both, the report boxes them; a shift of 0.1 px (23 levels) says nothing."""
    (tmp_path / "ref").mkdir()
    (tmp_path / "out").mkdir()
    Image.fromarray(_square()).save(tmp_path / "ref" / "f.png")
    Image.fromarray(_square(0.3)).save(tmp_path / "out" / "f.png")
    result = compare_paths(tmp_path / "ref", tmp_path / "out")
    assert result.passed
    frame = result.frames[0]
    assert [(f.box, f.large, f.levels) for f in frame.forgiven] == [((20, 13, 1, 23), 23, 58), ((44, 13, 1, 23), 23, 58)]
    line = next(line for line in result.summary_lines() if "excused a large, connected difference" in line)
    assert line.startswith("PASS f.png, but") and "up to 58" in line
    write_html_report(result, tmp_path / "report.html")
    page = (tmp_path / "report.html").read_text()
    assert page.count('class="forgiven"') >= 2 and "excused a large, connected difference" in page
    Image.fromarray(_square(0.1)).save(tmp_path / "out" / "f.png")
    quiet = compare_paths(tmp_path / "ref", tmp_path / "out")
    assert quiet.passed and not quiet.frames[0].forgiven
    assert not any("excused a large" in line for line in quiet.summary_lines())


def test_the_fast_channel_and_window_passes_equal_the_plain_numpy_ones():
    # compare/metrics.py replaces reductions over the channels and the 3x3 range's nine
    # shifted views with faster passes for speed (docs/performance.md); the numbers must not move
    from scenerender.compare.metrics import (channel_max, channel_mean, neighbourhood_range, second_difference,
                                             strongest_channel, tile_means)

    rng = np.random.default_rng(5)
    for shape in ((1, 1, 3), (1, 7, 3), (6, 1, 3), (2, 2, 3), (37, 53, 3), (16, 24, 3)):
        image = rng.integers(0, 256, shape).astype(np.uint8)
        signed = image.astype(np.int16) - rng.integers(0, 256, shape).astype(np.int16)
        signed[..., 2][signed[..., 2] > 0] = np.abs(signed[..., 0][signed[..., 2] > 0])  # ties: the first wins
        assert np.array_equal(channel_max(signed), signed.max(axis=2))
        assert np.array_equal(channel_mean(signed), signed.mean(axis=2, dtype=np.float32))
        strongest = np.abs(signed).argmax(axis=2)[..., None]
        assert np.array_equal(strongest_channel(signed), np.take_along_axis(signed, strongest, axis=2)[..., 0])
        padded = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
        views = [padded[dy:dy + shape[0], dx:dx + shape[1]] for dy in range(3) for dx in range(3)]
        low, high = neighbourhood_range(image)
        assert np.array_equal(low, np.min(views, axis=0)) and np.array_equal(high, np.max(views, axis=0))
        as_float = padded.astype(np.float32)
        centre = as_float[1:-1, 1:-1]
        plain = np.maximum(np.abs(2 * centre - as_float[1:-1, :-2] - as_float[1:-1, 2:]),
                           np.abs(2 * centre - as_float[:-2, 1:-1] - as_float[2:, 1:-1]))
        assert np.array_equal(second_difference(image), plain)
        per_pixel = rng.random(shape[:2]).astype(np.float32)
        rows, cols = -(-shape[0] // 8), -(-shape[1] // 8)
        expected = [[per_pixel[r * 8:r * 8 + 8, c * 8:c * 8 + 8].astype(np.float64).mean() for c in range(cols)]
                    for r in range(rows)]
        assert np.allclose(tile_means(per_pixel), expected, rtol=1e-12, atol=0)


def test_an_identical_pair_found_by_a_byte_compare_has_the_numbers_of_the_full_measure(monkeypatch):
    # measure() answers an identical pair without looking at its differences; its numbers and
    # maps must be those the full path gives
    from scenerender.compare import metrics

    image = np.random.default_rng(9).integers(0, 256, (37, 53, 3)).astype(np.uint8)
    shortcut, shortcut_maps = metrics.measure(image, image.copy(), 1)
    with monkeypatch.context() as patched:
        patched.setattr(metrics.np, "array_equal", lambda a, b: False)  # the full path
        full, full_maps = metrics.measure(image, image.copy(), 1)
    assert shortcut == full and shortcut.to_json() == full.to_json()
    for name in ("magnitude", "unexplained", "residual", "shifts"):
        ours, theirs = getattr(shortcut_maps, name), getattr(full_maps, name)
        assert ours.dtype == theirs.dtype and np.array_equal(ours, theirs)
    assert shortcut_maps.still is None and full_maps.still is None
