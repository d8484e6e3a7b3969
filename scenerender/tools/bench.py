"""Speed against error: the GPU path over a sweep of quality knobs, each variant timed
in-process and measured against the CPU reference.

One knob changes at a time from the scene's own settings (the "default" row): MSAA
samples, shadow map size, PCF size, shadow bias, ambient occlusion on/off, image size;
then a few shadow map size and PCF pairs together ("combined"); with an environment light,
its prefilter size, spherical-harmonic order, prefilter samples and footprint filter, its
specular term (split sum, or sampled with a few sample counts), and its visibility (off,
and its directions, map size and pixel blocks); with a shutter or an aperture, the
sub-frames a frame (render.film_samples); with a shutter, the other way of
filming it (render.motion_blur: sub_frames or velocity). What is made once a run
(the prefiltered environment) is timed apart, in ``once_ms``.
Timing: every variant keeps its renderer open and the variants take turns frame by frame
(so a slow spell of a shared machine spreads over all of them), frames 1..F of the scene
after frame 0 which warms up (when the shadowed lights move, shadow maps are rendered again
on each of those frames), ``rounds`` times; the number reported is the median. Error: frame 0 against the
reference at that variant's image size.
"""
from __future__ import annotations

import json
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path

from scenerender.gpu.gl_context import create_context
from scenerender.tools.penumbra import penumbra_columns
from scenerender.tools.quality import frame_errors
from scenerender.raytrace.render import ENVIRONMENT_SAMPLES, render_reference
from scenerender.run.session import Renderer, load
from scenerender.sinks.base import atomic_path

SAMPLES = (1, 2, 4, 8)
SHADOW_SIZES = (512, 1024, 2048, 4096)
PCF_SIZES = (1, 3, 5, 7)
BIASES = (0.0005, 0.001, 0.002, 0.005)
DEFAULT_AO = "{radius: 0.5, samples: 16, strength: 1.0}"
# shadow map size and PCF together: the pairs the one-knob sweep suggests are worth a look
COMBINATIONS = ((512, 5), (1024, 5), (1024, 7))
PREFILTER_SIZES = (64, 128, 256, 512)
SH_ORDERS = (1, 2, 3, 4)
PREFILTER_SAMPLES = (32, 128, 256, 512, 1024)
# sub-frames a frame where the camera has a shutter or an aperture (world/lens.py)
FILM_SAMPLES = (1, 2, 4, 8, 16, 32, 64)
VISIBILITY_DIRECTIONS = (8, 16, 32, 64)
VISIBILITY_MAP_SIZES = (256, 512, 1024)
# the soft shadows of lights with a size: the blocker search's and the filter's reads
BLOCKER_SAMPLES = (8, 16, 32)
FILTER_SAMPLES = (16, 32, 64)
VISIBILITY_INTERLEAVES = (1, 2, 3, 4)  # 1: the exact per-pixel sum
SPECULAR_SAMPLES = (8, 16, 32, 64)  # a pixel's GGX samples of the sampled specular term
KNOBS = ("samples", "shadow_size", "pcf", "bias", "ao", "size", "combined", "prefilter_size", "sh_order",
         "env_samples", "env_footprint", "env_specular", "env_visibility", "env_directions", "env_map_size",
         "env_interleave", "film_samples", "blocker_samples", "filter_samples", "motion_blur")
ONCE_PASSES = ("environment_prefilter",)  # passes a run makes once, whose cost is not per frame


@dataclass(frozen=True)
class Variant:
    """One point of the sweep: ``overrides`` applied over the scene (``--set`` strings)."""

    name: str
    knob: str
    overrides: tuple = ()


@dataclass
class BenchRow:
    variant: Variant
    ms_per_frame: float | None = None
    ms_samples: list = field(default_factory=list)
    errors: dict = field(default_factory=dict)
    pareto: bool = False
    once_ms: float | None = None  # the passes of ONCE_PASSES, on the first frame
    samples_used: int | None = None  # MSAA samples the device gave (it may round a request up)

    @property
    def ms_iqr(self) -> float | None:
        """Interquartile range of the timed frames: how far to trust ms_per_frame."""
        if len(self.ms_samples) < 2:
            return None
        quartiles = statistics.quantiles(self.ms_samples, n=4)
        return quartiles[2] - quartiles[0]

    @property
    def label(self) -> str:
        name = self.variant.name
        requested = self.variant.name.removeprefix("msaa ")
        if self.variant.knob == "samples" and self.samples_used is not None and requested != str(self.samples_used):
            name += f" (device: {self.samples_used})"
        return name

    def to_json(self) -> dict:
        return {"name": self.variant.name, "knob": self.variant.knob, "overrides": list(self.variant.overrides),
                "samples_used": self.samples_used,
                "ms_per_frame": _round(self.ms_per_frame, 3), "ms_iqr": _round(self.ms_iqr, 3),
                "ms_samples": [round(v, 3) for v in self.ms_samples],
                "once_ms": _round(self.once_ms, 3), "pareto": self.pareto, **{k: _round(v, 4) for k, v in self.errors.items()}}


def _round(value, digits):
    return round(value, digits) if isinstance(value, float) else value


def _specular_variants(key: str, environment) -> list[Variant]:
    """The environment's specular term other than its own: the split sum, and sampled with
    each of SPECULAR_SAMPLES (two overrides each: the mode and the count)."""
    found = []
    if environment.specular != "split_sum":
        found.append(Variant("specular split_sum", "env_specular", (f"{key}.specular=split_sum",)))
    for count in SPECULAR_SAMPLES:
        if environment.specular != "sampled" or count != environment.specular_samples:
            found.append(Variant(f"specular sampled {count}", "env_specular",
                                 (f"{key}.specular=sampled", f"{key}.specular_samples={count}")))
    return found


def sweep_variants(scene, knobs=KNOBS) -> list[Variant]:
    """The default row, then one row per other value of each knob in ``knobs``."""
    spec = scene.world.render
    shadows = spec.shadows
    width, height = (int(v) for v in spec.size)
    variants = [Variant("default", "default")]

    def add(knob, name, override, current, value):
        if knob in knobs and value != current:
            variants.append(Variant(name, knob, (override,)))

    def each(knob, label, key, values, current):
        """One variant per value of ``values`` other than ``current``, labelled ``label``."""
        for value in values:
            add(knob, label.format(value), f"{key}={value}", current, value)

    each("samples", "msaa {}", "render.samples", SAMPLES, spec.samples)
    if scene.world.shadowed_lights:
        each("shadow_size", "map {}", "render.shadows.size", SHADOW_SIZES, shadows.size)
        each("pcf", "pcf {}", "render.shadows.pcf", PCF_SIZES, shadows.pcf)
        each("bias", "bias {:g}", "render.shadows.bias", BIASES, shadows.bias)
        for size, pcf in COMBINATIONS:
            if "combined" in knobs and (size, pcf) != (shadows.size, shadows.pcf):
                variants.append(Variant(f"map {size} pcf {pcf}", "combined",
                                        (f"render.shadows.size={size}", f"render.shadows.pcf={pcf}")))
        if any(light.sized and light.shadow is not None for light in scene.world.lights):
            each("blocker_samples", "blocker search {}", "render.shadows.blocker_samples", BLOCKER_SAMPLES,
                 shadows.blocker_samples)
            each("filter_samples", "soft filter {}", "render.shadows.filter_samples", FILTER_SAMPLES,
                 shadows.filter_samples)
    if spec.ambient_occlusion is None:
        add("ao", "ao on", f"render.ambient_occlusion={DEFAULT_AO}", False, True)
    else:
        add("ao", "ao off", "render.ambient_occlusion=null", True, False)
    add("size", f"size {width // 2}x{height // 2}", f"render.size=[{width // 2}, {height // 2}]", 0, 1)
    environment = scene.world.environment
    if environment is not None:
        key = f"lights[{environment.path[1]}]"
        each("prefilter_size", "prefilter {}", f"{key}.prefilter_size", PREFILTER_SIZES, environment.prefilter_size)
        each("sh_order", "SH order {}", f"{key}.sh_order", SH_ORDERS, environment.sh_order)
        each("env_samples", "prefilter samples {}", f"{key}.samples", PREFILTER_SAMPLES, environment.samples)
        add("env_footprint", "footprint " + ("off" if environment.footprint else "on"),
            f"{key}.footprint={'false' if environment.footprint else 'true'}", False, True)
        if "env_specular" in knobs:
            variants += _specular_variants(key, environment)
        seen = bool(environment.visibility)
        add("env_visibility", "visibility " + ("off" if seen else "on"),
            f"{key}.visibility={'false' if seen else 'true'}", False, True)
        if seen:
            each("env_directions", "{} directions", f"{key}.visibility_directions", VISIBILITY_DIRECTIONS,
                 environment.visibility)
            each("env_map_size", "visibility maps {}", f"{key}.visibility_map_size", VISIBILITY_MAP_SIZES,
                 environment.visibility_map_size)
            each("env_interleave", "visibility blocks {0}x{0}", f"{key}.visibility_interleave", VISIBILITY_INTERLEAVES,
                 environment.visibility_interleave)
    camera = scene.world.spec.camera
    if camera is not None and (camera.shutter > 0 or camera.aperture is not None):
        each("film_samples", "{} sub-frames", "render.film_samples", FILM_SAMPLES, spec.film_samples)
    if camera is not None and camera.shutter > 0:
        other = "velocity" if spec.motion_blur == "sub_frames" else "sub_frames"
        add("motion_blur", f"motion blur by {other.replace('_', '-')}", f"render.motion_blur={other}",
            spec.motion_blur, other)
    return variants


def run_bench(path, overrides=(), *, knobs=KNOBS, frames: int = 3, rounds: int = 2, spp: int = 16,
              echo=lambda text: None, asset_roots=(),
              environment_samples: int = ENVIRONMENT_SAMPLES, bounces: int = 0) -> list[BenchRow]:
    """Sweep ``path`` (a scene file) and return one BenchRow per variant, Pareto flags set
    on (ms_per_frame, rmse_linear); the reference gathers an environment light from
    ``environment_samples`` directions a sample, and path-traces ``bounces`` bounces (0:
    direct light only)."""

    base = load(path, list(overrides), asset_roots=asset_roots)
    rows = [BenchRow(v) for v in sweep_variants(base, knobs)]
    references: dict = {}
    gl = create_context()
    try:
        for row in rows:
            scene = load(path, list(overrides) + list(row.variant.overrides), asset_roots=asset_roots)
            if scene.size not in references:
                started = time.perf_counter()
                references[scene.size] = render_reference(scene, 0, spp=spp, warn=echo,
                                                          environment_samples=environment_samples,
                                                          bounces=bounces)
                echo(f"reference {scene.size[0]}x{scene.size[1]}, {spp}x{spp} samples a pixel, {bounces} bounces: "
                     f"{time.perf_counter() - started:.1f} s")
            with Renderer(scene, gl=gl, want_linear=True, profile=True) as renderer:
                frame = renderer.render(0)
                row.samples_used = renderer.samples
                once = [sum(renderer.timings[name]) for name in ONCE_PASSES if name in renderer.timings]
                row.once_ms = 1000.0 * sum(once) if once else None
            row.errors = frame_errors(references[scene.size], frame.pixels, frame.linear)
            if any(light.sized and light.shadow is not None for light in scene.world.lights):
                row.errors.update(penumbra_columns(references[scene.size], frame.linear))
        _time_interleaved(path, overrides, rows, frames, rounds, gl, asset_roots, echo)
    finally:
        gl.release()
    for row in rows:
        row.ms_per_frame = statistics.median(row.ms_samples) if row.ms_samples else None
    mark_pareto(rows)
    return rows


def _time_interleaved(path, overrides, rows: list[BenchRow], frames: int, rounds: int, gl, asset_roots,
                      echo) -> None:
    """Append to each row's ms_samples the milliseconds of frames 1..frames, ``rounds``
    times. Every variant's renderer stays open and the variants take turns frame by frame
    (in a rotated order each round), so a slow spell of a shared machine hits them alike."""
    import contextlib


    with contextlib.ExitStack() as stack:
        renderers = []
        for row in rows:
            scene = load(path, list(overrides) + list(row.variant.overrides), asset_roots=asset_roots)
            renderer = stack.enter_context(Renderer(scene, gl=gl, want_linear=False))
            renderer.render(0)  # warm-up: programs, uploads, static passes
            renderers.append(renderer)
        order = list(range(len(rows)))
        for round_index in range(rounds):
            turn = order[round_index % len(order):] + order[:round_index % len(order)]
            for index in range(1, frames + 1):
                for k in turn:
                    started = time.perf_counter()
                    renderers[k].render(index)
                    rows[k].ms_samples.append(1000.0 * (time.perf_counter() - started))
            echo(f"round {round_index + 1}/{rounds} timed")


def mark_pareto(rows: list[BenchRow], error_key: str = "rmse_linear") -> None:
    """Flag the rows no other row beats on both ms/frame and error (ties kept). Rows of
    another image size take no part: their error is against another reference, and a
    smaller image is a different product, not a cheaper way to the same one."""
    candidates = [r for r in rows if r.variant.knob != "size"
                  and r.ms_per_frame is not None and r.errors.get(error_key) is not None]
    points = [(r.ms_per_frame, r.errors[error_key]) for r in candidates]
    for row, (ms, err) in zip(candidates, points):
        row.pareto = not any(o_ms <= ms and o_err <= err and (o_ms < ms or o_err < err) for o_ms, o_err in points)


# -- outputs ----------------------------------------------------------------------------------

COLUMNS = (("ms/frame", "ms_per_frame", "{:.1f}"), ("ms IQR", "ms_iqr", "{:.1f}"), ("once ms", "once_ms", "{:.0f}"),
           ("RMSE lin %", "rmse_linear", "{:.2f}"),
           ("RMSE sRGB %", "rmse_srgb", "{:.2f}"), ("PSNR dB", "psnr", "{:.1f}"), ("FLIP", "flip", "{:.4f}"),
           ("shadow-edge RMSE %", "shadow_edge_rmse", "{:.2f}"), ("cone-edge RMSE %", "cone_edge_rmse", "{:.2f}"),
           ("interior RMSE %", "interior_rmse", "{:.3f}"), ("geometry-edge RMSE %", "geometry_edge_rmse", "{:.2f}"),
           ("shadow-edge % of mean", "shadow_edge_rel", "{:.2f}"), ("cone-edge % of mean", "cone_edge_rel", "{:.2f}"),
           ("umbra leak %", "umbra_leak", "{:.1f}"),
           ("penumbra band RMS %", "penumbra_rms", "{:.1f}"), ("penumbra band mean %", "penumbra_bias", "{:+.1f}"))


def markdown_table(title: str, rows: list[BenchRow]) -> str:
    """A Markdown section: one line per variant, Pareto rows marked with *."""
    head = "| variant | " + " | ".join(label for label, _, _ in COLUMNS) + " | Pareto |"
    lines = [f"### {title}", "", head, "|" + "---|" * (len(COLUMNS) + 2)]
    for row in rows:
        values = {"ms_per_frame": row.ms_per_frame, "ms_iqr": row.ms_iqr, "once_ms": row.once_ms, **row.errors}
        cells = [_cell(values.get(key), fmt) for _, key, fmt in COLUMNS]
        lines.append(f"| {row.label} | " + " | ".join(cells) + f" | {'*' if row.pareto else ''} |")
    return "\n".join(lines) + "\n"


def _cell(value, fmt: str) -> str:
    return "-" if value is None else fmt.format(value)


def write_outputs(name: str, rows: list[BenchRow], folder: Path, meta: dict) -> list[Path]:
    """folder/NAME.md, NAME.json and NAME.png (each written whole, then renamed)."""
    folder = Path(folder)
    payload = {"scene": name, **meta, "rows": [r.to_json() for r in rows]}
    outputs = {folder / f"{name}.md": markdown_table(name, rows).encode(),
               folder / f"{name}.json": (json.dumps(payload, indent=2) + "\n").encode()}
    for path, data in outputs.items():
        with atomic_path(path) as temp:
            temp.write_bytes(data)
    plot = folder / f"{name}.png"
    with atomic_path(plot) as temp:
        plot_rows(name, rows, temp)
    return list(outputs) + [plot]


PANELS = (("rmse_linear", "whole-image RMSE vs reference, linear %"),
          ("shadow_edge_rmse", "shadow-edge RMSE, linear %"),
          ("cone_edge_rmse", "spot-cone-edge RMSE, linear %"))


def plot_rows(title: str, rows: list[BenchRow], path: Path) -> None:
    """A PNG of ms/frame (x, log scale) against whole-image error, shadow-edge error and
    (with spot lights) cone-edge error, a panel each; one marker per variant coloured by
    knob, the Pareto front on whole-image error drawn as a staircase, the default circled."""
    try:
        import matplotlib
    except ImportError:
        points = [(r, r.ms_per_frame, r.errors.get("rmse_linear")) for r in rows
                  if r.ms_per_frame is not None and r.errors.get("rmse_linear") is not None]
        return _plot_with_pillow(title, points, path)
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import ticker

    panels = [(key, label) for key, label in PANELS if any(r.errors.get(key) is not None for r in rows)]
    figure, axes_list = plt.subplots(1, len(panels), figsize=(6.5 * len(panels), 5.2), dpi=100, squeeze=False)
    knobs = sorted({r.variant.knob for r in rows})
    colours = plt.get_cmap("tab10")
    for axes, (key, label) in zip(axes_list[0], panels):
        axes.set_xscale("log")
        points = [(r, r.ms_per_frame, r.errors.get(key)) for r in rows
                  if r.ms_per_frame is not None and r.errors.get(key) is not None]
        for k, knob in enumerate(knobs):
            chosen = [(x, y) for r, x, y in points if r.variant.knob == knob]
            if chosen:
                axes.scatter(*zip(*chosen), color=colours(k), label=knob, s=30, zorder=3)
        _label_points(axes, points)
        if key == "rmse_linear":
            front = sorted((x, y) for r, x, y in points if r.pareto)
            if front:
                xs, ys = zip(*front)
                axes.step(xs, ys, where="post", color="black", linewidth=1, linestyle="--", zorder=2)
                axes.scatter(xs, ys, marker="D", s=70, facecolors="none", edgecolors="black",
                             label="Pareto front", zorder=4)
        for r, x, y in points:
            if r.variant.knob == "default":
                axes.scatter([x], [y], s=160, facecolors="none", edgecolors="black", zorder=4)
        axes.xaxis.set_major_formatter(ticker.ScalarFormatter())
        axes.xaxis.set_minor_formatter(ticker.ScalarFormatter())
        axes.tick_params(axis="x", which="minor", labelsize=7)
        axes.set_xlabel("ms / frame (median, log scale)")
        axes.set_ylabel(label)
        axes.grid(alpha=0.3, which="both")
    axes_list[0][0].legend(fontsize=7)
    figure.suptitle(f"{title}: speed against error (default circled)")
    figure.tight_layout()
    figure.savefig(path, format="png")
    plt.close(figure)


def _label_points(axes, points: list) -> None:
    """Name each point, skipping a name that would sit on one already written (the
    variants a knob leaves unchanged crowd round the default)."""
    axes.autoscale_view()  # data limits into view limits, so transData maps to the final place
    placed = []
    for r, x, y in sorted(points, key=lambda p: (not p[0].pareto, p[0].variant.knob != "default")):
        px, py = axes.transData.transform((x, y))
        if any(abs(px - qx) < 45 and abs(py - qy) < 10 for qx, qy in placed):
            continue
        placed.append((px, py))
        axes.annotate(r.label, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=7)


def _plot_with_pillow(title: str, points: list, path: Path) -> None:
    """The same plot drawn with Pillow (no matplotlib): axes, points, labels, front."""
    from PIL import Image, ImageDraw

    width, height, margin = 880, 600, 70
    image = Image.new("RGB", (width, height), "white")
    draw = ImageDraw.Draw(image)
    if points:
        xs = [x for _, x, _ in points]
        ys = [y for _, _, y in points]
        x0, x1 = 0.0, max(xs) * 1.1
        y0, y1 = 0.0, max(ys) * 1.1 or 1.0

        def at(x, y):
            return (margin + (x - x0) / (x1 - x0) * (width - 2 * margin),
                    height - margin - (y - y0) / (y1 - y0) * (height - 2 * margin))

        front = sorted((x, y) for r, x, y in points if r.pareto)
        if len(front) > 1:
            draw.line([at(x, y) for x, y in front], fill="black", width=1)
        for r, x, y in points:
            px, py = at(x, y)
            draw.ellipse([px - 4, py - 4, px + 4, py + 4], fill="red" if r.pareto else "steelblue")
            draw.text((px + 6, py - 6), r.label, fill="black")
        draw.text((margin, height - margin + 20), f"ms / frame (0 .. {x1:.0f})", fill="black")
        draw.text((10, 10), f"{title}: RMSE linear % (0 .. {y1:.2f}) against ms/frame", fill="black")
    draw.line([(margin, margin), (margin, height - margin), (width - margin, height - margin)], fill="black")
    image.save(path, format="PNG")
