"""The HTML report of a comparison: one self-contained file (images embedded as
``data:image/png;base64``, styles and a few lines of script inline), readable offline and
as a CI artifact.

Top: the verdict, counts, the rule, and what made each side (scenerender version, GL
renderer). Then per changed frame: reference, output, heatmap with the changed regions
outlined and the map of each tile's best shift, a slider and a blink toggle between
reference and output, and the metrics against the rule's limits. Above those, a close-up:
reference, output and heatmap cropped around the window that decided (the worst window of
the limit that failed; for a pass, the window holding the most excused pixels), magnified
and outlined, that window also outlined on the whole frames. Every passing frame that
differs at all gets the same pictures and what it excused, so a pass can be audited; passing
frames are also one table row each.
"""
from __future__ import annotations

import base64
import io
import math
from html import escape
from pathlib import Path

import numpy as np

from scenerender.compare.diff import FORGIVEN_LEVELS
from scenerender.compare.metrics import PIXEL_THRESHOLD, FrameMetrics
from scenerender.compare.objects import PICTURE_COLOURS
from scenerender.compare.result import CompareResult, FrameComparison
from scenerender.compare.rule import SHIFT_WINDOW, TILE, DiffRule
from scenerender.compare.sources import Side
from scenerender.sinks.base import OUTPUT_OPTION, atomic_path

# Small frames are scaled up (pixelated) to at least this width on the page.
MIN_SHOWN_WIDTH = 320
# The close-up: this many pixels around the window that decided, each shown ZOOM times larger.
CLOSE_UP = 40
ZOOM = 8
# zlib level of the report's images: the fastest, see png_data_uri
REPORT_PNG_LEVEL = 1

STYLE = """
body { font: 14px/1.4 system-ui, sans-serif; margin: 0; background: #f4f4f6; color: #1d1d22; }
header { padding: 16px 24px; color: #fff; }
header.fail { background: #b3261e; } header.pass { background: #1e7b34; }
header h1 { margin: 0 0 4px; font-size: 22px; }
main { padding: 8px 24px 32px; }
section { background: #fff; border-radius: 6px; padding: 12px 16px; margin: 12px 0;
          box-shadow: 0 1px 2px rgba(0,0,0,.15); }
h2 { font-size: 17px; margin: 0 0 6px; } .reason { color: #b3261e; margin: 0 0 10px; }
table { border-collapse: collapse; } td, th { padding: 2px 10px 2px 0; text-align: left; }
th { font-weight: 600; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.bad { color: #b3261e; font-weight: 600; } .ok { color: #1e7b34; }
.row { display: flex; flex-wrap: wrap; gap: 14px; align-items: flex-start; margin-bottom: 10px; }
figure { margin: 0; } figcaption { font-size: 12px; color: #555; }
.frame { position: relative; display: inline-block; line-height: 0; }
.frame img { image-rendering: pixelated; display: block; }
.box { position: absolute; border: 2px solid #ffd400; box-shadow: 0 0 0 1px #000; box-sizing: border-box; }
.forgiven { position: absolute; border: 2px solid #ff2bd6; box-shadow: 0 0 0 1px #000; box-sizing: border-box; }
.warn { color: #8a4b00; background: #fff4d6; padding: 4px 8px; border-left: 4px solid #ff2bd6; }
.focus { position: absolute; border: 2px dashed #00e5ff; box-shadow: 0 0 0 1px #000; box-sizing: border-box; }
.closeup { border-left: 4px solid #00b8d4; padding-left: 10px; }
.stack { position: relative; display: inline-block; line-height: 0; }
.stack img { image-rendering: pixelated; display: block; }
.stack img.top { position: absolute; left: 0; top: 0; }
.controls { font-size: 12px; margin-top: 4px; } .controls input { vertical-align: middle; }
.side { display: inline-block; vertical-align: top; margin-right: 32px; }
pre { white-space: pre-wrap; overflow-wrap: anywhere; }
.swatch { display: inline-block; width: 10px; height: 10px; margin-right: 5px; border: 1px solid #333; }
"""

SCRIPT = """
document.querySelectorAll('.compare').forEach(function (c) {
  var top = c.querySelector('img.top'), range = c.querySelector('input[type=range]'),
      blink = c.querySelector('button'), label = c.querySelector('.showing'), timer = null;
  function clip(v) { top.style.clipPath = 'inset(0 ' + (100 - v) + '% 0 0)'; }
  range.addEventListener('input', function () { clip(range.value); });
  blink.addEventListener('click', function () {
    if (timer) { clearInterval(timer); timer = null; blink.textContent = 'blink'; clip(range.value); return; }
    var on = true; blink.textContent = 'stop';
    timer = setInterval(function () { on = !on; clip(on ? 100 : 0);
      label.textContent = on ? 'reference' : 'output'; }, 600);
  });
  clip(range.value);
});
"""


def png_data_uri(image: np.ndarray) -> str:
    """(H, W, 3) uint8 -> 'data:image/png;base64,...'."""
    from PIL import Image

    buffer = io.BytesIO()
    # level 1: a 320x240 frame in 4.9 ms and 73 KB, where zlib's default level 6 took
    # 17.7 ms for 66 KB (a report holds ten images a changed frame); optimize=True,
    # searching every level and filter, took 7x level 6's time for 4 % fewer bytes
    Image.fromarray(np.ascontiguousarray(image)).save(buffer, format="PNG", compress_level=REPORT_PNG_LEVEL)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def shown_width(width: int) -> int:
    """Page width of a frame: small frames scaled up by a whole factor, so pixels stay square."""
    return width * max(1, -(-MIN_SHOWN_WIDTH // max(width, 1)))


def _boxes(frame: FrameComparison) -> str:
    """The changed regions (yellow) and the close-up's window (dashed cyan) over a full frame."""
    if not frame.size:
        return ""
    focus = [frame.images.focus] if frame.images is not None and frame.images.focus else []
    return (_outlines(frame.regions, frame.size, "box") + _outlines([f.box for f in frame.forgiven], frame.size,
                                                                    "forgiven")
            + _outlines(focus, frame.size, "focus"))


def _outlines(boxes, size: tuple[int, int], css: str) -> str:
    """Divs outlining ``boxes`` (x, y, w, h in pixels) over a picture of ``size`` (w, h)."""
    width, height = size
    return "".join(
        f'<div class="{css}" style="left:{100 * x / width:.3f}%;top:{100 * y / height:.3f}%;'
        f'width:{100 * w / width:.3f}%;height:{100 * h / height:.3f}%"></div>'
        for x, y, w, h in boxes)


def close_up_box(focus: tuple[int, int, int, int], size: tuple[int, int]) -> tuple[int, int, int, int]:
    """(x, y, w, h): CLOSE_UP pixels a side (less in a smaller frame) centred on ``focus``
    (x, y, w, h), moved inside the frame of ``size`` (w, h)."""
    fx, fy, fw, fh = focus
    w, h = min(CLOSE_UP, size[0]), min(CLOSE_UP, size[1])
    x = min(max(fx + fw // 2 - w // 2, 0), size[0] - w)
    y = min(max(fy + fh // 2 - h // 2, 0), size[1] - h)
    return x, y, w, h


def _close_up(images) -> str:
    """The row that points at the decisive window: reference, output and heatmap cropped
    around it, magnified, the window outlined, and what it holds in words."""
    height, width = images.reference.shape[:2]
    x, y, w, h = close_up_box(images.focus, (width, height))
    fx, fy, fw, fh = images.focus
    inner = _outlines([(fx - x, fy - y, fw, fh)], (w, h), "focus")
    crops = [("reference", images.reference), ("output", images.output), ("heatmap", images.heatmap)]
    figures = "".join(
        f'<figure><div class="frame"><img src="{png_data_uri(image[y:y + h, x:x + w])}" width="{w * ZOOM}" '
        f'alt="{name}, close up">{inner}</div><figcaption>{name}</figcaption></figure>' for name, image in crops)
    return (f'<div class="closeup"><p>Close up, {ZOOM}x: x {x}..{x + w - 1}, y {y}..{y + h - 1} around '
            f'{escape(images.focus_note)} (dashed, also on the whole frames below)</p>'
            f'<div class="row">{figures}</div></div>')


def _figure(caption: str, image: np.ndarray, boxes: str = "") -> str:
    width = shown_width(image.shape[1])
    return (f'<figure><div class="frame"><img src="{png_data_uri(image)}" width="{width}" alt="{escape(caption)}">'
            f'{boxes}</div><figcaption>{escape(caption)} ({image.shape[1]}x{image.shape[0]})</figcaption></figure>')


def _compare_widget(reference: np.ndarray, output: np.ndarray) -> str:
    width = shown_width(reference.shape[1])
    return (f'<figure class="compare"><div class="stack">'
            f'<img src="{png_data_uri(output)}" width="{width}" alt="output">'
            f'<img class="top" src="{png_data_uri(reference)}" width="{width}" alt="reference"></div>'
            '<div class="controls">reference | output <input type="range" min="0" max="100" value="50"> '
            '<button type="button">blink</button> <span class="showing"></span></div>'
            '<figcaption>left of the handle: reference, right: output</figcaption></figure>')


def _fmt(value, digits=3) -> str:
    if value is None:
        return "n/a"
    if isinstance(value, float) and math.isinf(value):
        return "inf"
    return f"{value:.{digits}f}" if isinstance(value, float) else str(value)


def metrics_rows(metrics: FrameMetrics, rule: DiffRule, objects=None) -> list[tuple[str, str, str, bool | None]]:
    """(name, value, limit, within limit or None for information only) per metric; with
    ``objects`` (compare.objects.ObjectMetrics) the object limits first."""
    flip = _fmt(metrics.flip, 5) if metrics.flip is not None else "n/a (pip install 'scenerender[flip]')"
    return _object_rows(objects, rule) + [
        (f"worst {TILE}x{TILE} tile outside the 3x3 ranges (levels, largest channel)", _fmt(metrics.worst_tile_aa),
         f"<= {rule.max_tile:g}", metrics.worst_tile_aa <= rule.max_tile),
        ("mean outside the 3x3 ranges (levels)", _fmt(metrics.unexplained_mean, 5), f"<= {rule.max_unexplained_mean:g}",
         metrics.unexplained_mean <= rule.max_unexplained_mean),
        (f"worst {SHIFT_WINDOW}x{SHIFT_WINDOW} window after the best shift (levels, signed mean)", _fmt(metrics.shift_tile),
         f"<= {rule.max_shift_tile:g}", metrics.shift_tile <= rule.max_shift_tile),
        ("still frame: largest region changed one way (levels x px)", _fmt(metrics.still_region, 1),
         f"<= {rule.max_still_region:g}", metrics.still_region <= rule.max_still_region),
        ("how far the whole frame moved (px; under 1/128: still)", _fmt(metrics.frame_shift, 3), "", None),
        ("worst pixel after the best shift (levels)", _fmt(metrics.shift_pixel, 1), "", None),
        ("pixels excused (edge shifts and rounding)", str(metrics.excused_pixels), "", None),
        ("largest shift a tile took (px)", _fmt(metrics.largest_shift, 2), "", None),
        ("% pixels changed (unexplained)", _fmt(metrics.changed_percent), "", None),
        ("mean |diff| (levels)", _fmt(metrics.mean_abs), "", None),
        (f"worst {TILE}x{TILE} tile, plain (levels, channel mean)", _fmt(metrics.worst_tile), "", None),
        (f"% pixels off by >{PIXEL_THRESHOLD}", _fmt(metrics.bad_percent), "", None),
        ("largest difference (levels)", _fmt(metrics.max_abs), "", None),
        ("PSNR (dB)", _fmt(metrics.psnr, 2), "", None),
        ("SSIM", _fmt(metrics.ssim, 5), "", None),
        ("FLIP", flip, "", None),
    ]


def _object_rows(objects, rule: DiffRule) -> list[tuple[str, str, str, bool | None]]:
    if objects is None:
        return []
    def named(value: str, name: str) -> str:
        return f"{value} ({name})" if name else value
    return [
        ("object on one side only (px it covers)", named(str(objects.one_side_pixels), objects.one_side_object),
         f"< {rule.min_object_pixels}", objects.one_side_pixels < rule.min_object_pixels),
        ("object moved against the frame (px)", named(_fmt(objects.shift), objects.shift_object),
         f"<= {rule.max_object_shift:g}", objects.shift <= rule.max_object_shift),
        ("object interior change (levels)", named(_fmt(objects.interior), objects.interior_object),
         f"<= {rule.max_interior_change:g}", objects.interior <= rule.max_interior_change),
    ]


MAX_OBJECT_ROWS = 40


def _objects_table(objects, rule: DiffRule) -> str:
    """The objects either side shows, the most changed first: pixels, changed pixels, shift
    and interior change, the values past a limit marked."""
    rows = []
    offenders = list(dict.fromkeys(s.name for kind in rule.offenders(objects) for s in kind))
    for score in objects.objects[:MAX_OBJECT_ROWS]:
        swatch = ""
        if score.name in offenders:
            colour = PICTURE_COLOURS[offenders.index(score.name) % len(PICTURE_COLOURS)]
            swatch = f'<span class="swatch" style="background:rgb{colour}"></span>'
        one_side = score.status != "both" and score.coverage >= rule.min_object_pixels
        moved = score.shift is not None and score.shift > rule.max_object_shift
        inside = score.interior is not None and abs(score.interior) > rule.max_interior_change
        shift = "" if score.shift is None else _fmt(score.shift, 2)
        interior = "" if score.interior is None else f"{score.interior:+.2f}"
        rows.append(f'<tr><td>{swatch}{escape(score.name)}</td>'
                    f'<td class="{"bad" if one_side else ""}">{score.status}</td>'
                    f'<td class="num">{score.reference_pixels}</td><td class="num">{score.output_pixels}</td>'
                    f'<td class="num">{score.changed_pixels}</td><td class="num {"bad" if moved else ""}">{shift}</td>'
                    f'<td class="num {"bad" if inside else ""}">{interior}</td></tr>')
    more = len(objects.objects) - MAX_OBJECT_ROWS
    dy, dx = objects.common_shift
    return (f"<p>by object: {escape(objects.attribution() or 'no pixel off by 5 levels or more')}; the frame as a "
            f"whole moved {dx:+.2f} px across, {dy:+.2f} px down</p>"
            "<table><tr><th>object</th><th>shown</th><th>px reference</th><th>px output</th><th>px changed</th>"
            "<th>moved against the frame (px)</th><th>interior change (levels)</th></tr>" + "".join(rows) + "</table>"
            + (f"<p>{more} more object(s) not listed</p>" if more > 0 else ""))


def _metrics_table(metrics: FrameMetrics, rule: DiffRule, objects=None) -> str:
    rows = []
    for name, value, limit, ok in metrics_rows(metrics, rule, objects):
        css = "" if ok is None else ("ok" if ok else "bad")
        rows.append(f'<tr><td>{escape(name)}</td><td class="num {css}">{escape(value)}</td>'
                    f'<td>{escape(limit)}</td></tr>')
    return "<table><tr><th>metric</th><th>value</th><th>limit</th></tr>" + "".join(rows) + "</table>"


def _frame_section(frame: FrameComparison, rule: DiffRule) -> str:
    """A changed frame, or a passing one that differs: pictures, what was excused, metrics."""
    kind = "changed" if not frame.passed else "excused"
    headline = (f'<p class="reason">{escape(frame.reason)}</p>' if not frame.passed
                else f'<p class="ok">passes: {escape(frame.excused_line().split(": ", 1)[-1])}</p>')
    if frame.forgiven:
        headline += (f'<p class="warn">This pass excused a large, connected difference (boxed in magenta): '
                     f'{escape("; ".join(f.text() for f in frame.forgiven))}. The rule took it for a sub-pixel '
                     'edge shift; if nothing should have moved, look closely.</p>')
    parts = [f'<section class="{kind}" id="{escape(frame.name)}"><h2>{escape(frame.name)}</h2>{headline}']
    images = frame.images
    if images is None:
        parts.append("<p>(pictures not kept: too many frames differ)</p>")
    else:
        if images.focus is not None and images.heatmap is not None:
            parts.append(_close_up(images))
        boxes = _boxes(frame)
        figures = [_figure("reference", images.reference, boxes), _figure("output", images.output, boxes)]
        if images.heatmap is not None:
            figures.append(_figure("heatmap: red changed, blue edge shifts (excused)", images.heatmap, boxes))
        if images.shifts is not None:
            figures.append(_figure("best shift per tile: red right, green down (1/4 px full), grey none",
                                   images.shifts, boxes))
        if images.objects is not None:
            figures.append(_figure("objects past an object limit, at both sides' places (table below)",
                                   images.objects))
        if images.heatmap is not None:
            figures.append(_compare_widget(images.reference, images.output))
        parts.append('<div class="row">' + "".join(figures) + "</div>")
    if frame.ignored:
        parts.append(f"<p>ignored: {frame.ignored} px, taken from the reference (the reference folder's "
                     "ignore.json / ignore.png)</p>")
    if frame.metrics is not None:
        regions = ", ".join(f"x {x}..{x + w - 1} y {y}..{y + h - 1}" for x, y, w, h in frame.regions)
        parts.append(_metrics_table(frame.metrics, rule, frame.objects))
        if regions:
            parts.append(f"<p>changed regions (outlined): {escape(regions)}</p>")
        if frame.objects is not None:
            parts.append(_objects_table(frame.objects, rule))
    return "".join(parts) + "</section>"


def _passing_row(frame: FrameComparison) -> str:
    m = frame.metrics
    name = escape(frame.name)
    cell = f'<a href="#{name}">{name}</a>' if frame.images is not None else name
    return (f'<tr><td>{cell}</td><td class="num">{_fmt(m.mean_abs)}</td><td class="num">{m.excused_pixels}</td>'
            f'<td class="num">{_fmt(m.largest_shift, 2)}</td><td class="num">{_fmt(m.shift_tile)}</td>'
            f'<td class="num">{_fmt(m.psnr, 1)}</td></tr>')


def _passing_table(frames: list[FrameComparison]) -> str:
    if not frames:
        return ""
    rows = "".join(_passing_row(f) for f in frames if f.metrics is not None)
    return (f'<section class="passing"><h2>{len(frames)} frame(s) pass</h2><table><tr><th>frame</th>'
            '<th>mean</th><th>px excused</th><th>largest shift (px)</th><th>worst window after shift</th>'
            f'<th>PSNR</th></tr>{rows}</table></section>')


def _side_block(title: str, side: Side) -> str:
    p = side.provenance
    return (f'<div class="side"><b>{escape(title)}</b>: {escape(str(side.path))} ({escape(side.kind)})<br>'
            f'scenerender {escape(p.scenerender)}<br>GL renderer {escape(p.gl_renderer)}<br>'
            f'GL version {escape(p.gl_version)}</div>')


def _names_section(title: str, names: list[str]) -> str:
    if not names:
        return ""
    items = "".join(f"<li>{escape(n)}</li>" for n in names)
    return f'<section class="listing"><h2 class="bad">{escape(title)} ({len(names)})</h2><ul>{items}</ul></section>'


def _forgiven_note(result: CompareResult) -> str:
    """For the header: how many passing frames excused a large, connected difference."""
    count = sum(1 for frame in result.frames if frame.passed and frame.forgiven)
    if not count:
        return ""
    return (f'<br><b>but {count} passing frame(s) excused a large, connected difference (over '
            f'{FORGIVEN_LEVELS} levels): boxed in magenta below</b>')


def render_html(result: CompareResult) -> str:
    """The whole report page as text."""
    c = result.counts()
    verdict = "SAME" if result.passed else "CHANGED"
    css = "pass" if result.passed else "fail"
    dropped = (f"<p>{result.images_dropped} more changed frame(s) are listed without pictures.</p>"
               if result.images_dropped else "")
    body = [
        f'<header class="{css}"><h1>{verdict}: {escape(str(result.output.path))}</h1>'
        f'{c["compared"]} frame(s) compared: {c["passed"]} pass, {c["changed"]} changed, '
        f'{c["missing"]} missing, {c["extra"]} extra<br>{escape(result.judged_by())}{_forgiven_note(result)}'
        '</header><main>',
        '<section class="summary"><h2>Summary</h2>'
        f'<p>rule: {escape(result.rule.describe())}</p>'
        f'{_side_block("reference", result.reference)}{_side_block("output", result.output)}'
        f'<pre>{escape(chr(10).join(result.summary_lines(excused=True)))}</pre>{dropped}</section>',
        _names_section("missing in the output", result.missing),
        _names_section("extra in the output", result.extra),
        *(_frame_section(frame, result.rule) for frame in result.changed),
        *(_frame_section(frame, result.rule) for frame in result.frames if frame.passed and frame.images is not None),
        _passing_table([f for f in result.frames if f.passed]),
        "</main>",
    ]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>scenerender diff: {verdict}</title><style>{STYLE}</style></head><body>"
            + "".join(body) + f"<script>{SCRIPT}</script></body></html>\n")


def write_html_report(result: CompareResult, path: Path, option: str = OUTPUT_OPTION) -> None:
    """Write the report to ``path`` whole (temporary file + rename) or not at all; a
    failure to write is a UserError naming ``path`` and ``option``, the option that gave it."""
    text = render_html(result)
    with atomic_path(Path(path), option) as temp:
        temp.write_text(text, encoding="utf-8")
