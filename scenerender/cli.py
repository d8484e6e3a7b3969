"""The ``scenerender`` command line. ``scenerender --help`` and ``scenerender COMMAND --help``
are the manual.

Exit codes: 0 success, 2 bad input (scene file, asset, option), 3 the machine lacks
something (no EGL driver), 1 a bug in scenerender.
"""
from __future__ import annotations

import atexit
import functools
import gc
import os
import sys
import threading
from dataclasses import fields
from pathlib import Path

import click

from scenerender import option_rules
from scenerender.compare.rule import DiffRule  # the diff options are its fields (loads no numpy)
from scenerender.errors import EnvironmentProblem, SceneErrors, UserError
from scenerender.option_rules import MSAA_SAMPLES
from scenerender.run import collection
from scenerender.version import __version__

SET_HELP = "Override any scene key, e.g. --set render.samples=8 or --set objects[0].position=[0,1,0] (repeatable)."
# every output option: -o out/new/dir makes out/new/dir (and out/new) without asking
MAKES_PARENTS = "Folders on the way that do not exist are created."
ASSET_ROOT_HELP = ("Also let the scene read assets (meshes, MTL files, textures, skyboxes) from DIR; by default "
                   "only the scene file's folder is allowed (repeatable; SCENERENDER_ASSET_ROOTS adds more, "
                   "separated by the path separator).")


def _limit_option(command):
    from scenerender.limits import limit_names

    return click.option("--limit", "limit_texts", multiple=True, metavar="NAME=N",
                        help=f"Raise (or lower) a size limit, e.g. --limit objects=200000 (repeatable; names: "
                             f"{', '.join(limit_names())}).")(command)


def _limits(texts):
    from scenerender.limits import parse_limits

    return parse_limits(texts)


def _asset_root_option(command):
    return click.option("--asset-root", "asset_roots", multiple=True, metavar="DIR",
                        type=GivenPath(path_type=Path), help=ASSET_ROOT_HELP)(command)


def _echo_error(text: str) -> None:
    from scenerender.errors import one_line

    click.echo(f"error: {one_line(text)}", err=True)


def _is_user_os_error(exc: BaseException) -> bool:
    """An OSError the user can act on that no sink turned into a UserError first."""
    from scenerender.sinks.base import WRITE_ERRNOS

    return isinstance(exc, OSError) and exc.errno in WRITE_ERRNOS and bool(exc.strerror)


# A command's start-up makes many objects that live as long as the process (modules, the
# scene model's validator, the render graph) and few that die in cycles; with Python's
# default first threshold (700) the collector walks them some 150 times in a one-frame
# render, about a tenth of its CPU time. Collections stay on, only rarer; `render` pauses
# them until its first frame is out (run/collection.py).
COMMAND_GC_THRESHOLD = (10_000, 10, 10)


class _Command(click.Group):
    """Turns scenerender's own exceptions into one-line messages and exit codes."""

    def invoke(self, ctx):
        default_threshold = gc.get_threshold()
        gc.set_threshold(*COMMAND_GC_THRESHOLD)
        try:
            return self._invoke_with_exit_codes(ctx)
        finally:  # a caller in the same process (a test's CliRunner) keeps its own
            collection.end_pause()
            gc.set_threshold(*default_threshold)

    def _invoke_with_exit_codes(self, ctx):
        try:
            return super().invoke(ctx)
        except SceneErrors as exc:
            for line in exc.lines():
                _echo_error(line)
            sys.exit(exc.exit_code)
        except UserError as exc:
            _echo_error(str(exc))
            sys.exit(exc.exit_code)
        except EnvironmentProblem as exc:
            _echo_error(str(exc))
            sys.exit(exc.exit_code)
        except BrokenPipeError:  # output piped into `head` and friends: stop quietly
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            sys.exit(0)
        except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM/SIGHUP as interrupts.Interrupted
            by = f" by {exc.signal_name}" if hasattr(exc, "signal_name") else ""
            _echo_error(f"interrupted{by}; frames already finished are complete, nothing partial was left")
            sys.exit(getattr(exc, "exit_code", 130))
        except (click.ClickException, click.exceptions.Exit, click.exceptions.Abort, SystemExit):
            raise
        except MemoryError:  # where nothing closer named what was being loaded
            if os.environ.get("SCENERENDER_DEBUG"):
                raise
            _echo_error("not enough memory to finish; render smaller (--size), use smaller textures, or allow "
                        "the process more memory")
            sys.exit(UserError.exit_code)
        except Exception as exc:  # a bug: say so plainly, keep the traceback for --debug
            if os.environ.get("SCENERENDER_DEBUG"):
                raise
            if _is_user_os_error(exc):  # disk full, read-only, no permission: never a bug
                _echo_error(f"{exc.filename or 'output'}: {exc.strerror.lower()}")
                sys.exit(UserError.exit_code)
            _echo_error(f"internal error: {type(exc).__name__}: {exc} "
                        "(this is a bug in scenerender; set SCENERENDER_DEBUG=1 for the traceback)")
            sys.exit(1)


@click.group(cls=_Command, context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(__version__, prog_name="scenerender")
def main():
    """Render YAML scene files offscreen: image sequences, MP4 and GIF.

    \b
    Examples:
      scenerender render scenes/showcase.yaml -o out/
      scenerender render scene.yaml -o out/ --size 320x240 --frames 0:10
      scenerender validate scene.yaml
      scenerender preview scene.yaml          # a page that renders again on every save
      scenerender graph scene.yaml --dot | dot -Tpng > graph.png
      scenerender diff ref/ out/ --report report.html

    The scene format, every key with its type, range, default and an example, is
    docs/scene-format.md (`scenerender schema --markdown` prints it); `scenerender schema`
    prints it as JSON Schema for editors (scene.schema.json).
    """


# -- option types: values are checked as the command line is read, before any work starts


class GivenPath(click.Path):
    """A click.Path that refuses the empty string: `-o ""` would otherwise mean the current
    folder (a render writing frames there), and an empty scene or report path nothing."""

    def convert(self, value, param, ctx):
        if isinstance(value, str) and not value.strip():
            self.fail("an empty path names no file or folder; give one (e.g. out/)", param, ctx)
        return super().convert(value, param, ctx)


class RuleType(click.ParamType):
    """A number checked by its one rule (``scenerender.option_rules``), the rule the scene
    file and the Python API check too, in the same words."""

    def __init__(self, rule):
        self.rule = rule
        self.name = rule.bounds()

    def convert(self, value, param, ctx):
        if isinstance(value, str):
            value = _number(value)
        problem = self.rule.problem(value)
        if problem is not None:
            self.fail(problem, param, ctx)
        return self.rule.check(value)


def _number(text: str):
    """``text`` as an int, else a float, else itself (which the rule then calls no number)."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


class ImageSize(click.ParamType):
    """``WxH`` -> (width, height) in whole pixels; the scene's own rules (1..16384) then
    apply to the ``render.size`` it overrides."""

    name = "WxH"

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        width, sep, height = value.lower().partition("x")
        if sep and _is_whole_number(width) and _is_whole_number(height):
            return int(width), int(height)
        self.fail(f"expected WIDTHxHEIGHT such as 640x480, got '{value}'", param, ctx)


def _is_whole_number(text: str) -> bool:
    """ASCII digits only ('²' is a digit to str.isdigit but not to int), and few enough
    for int() (Python refuses to convert more than 4300)."""
    return text.isascii() and text.isdigit() and len(text) <= 100


def _overrides(sets, size, samples) -> list[str]:
    out = list(sets) + ([f"render.size=[{size[0]}, {size[1]}]"] if size is not None else [])
    if samples is not None:
        out.append(f"render.samples={samples}")
    return out


def _scene_overrides(with_samples: bool = True):
    """``--set`` and ``--size`` (and, ``with_samples``, ``--samples``), declared once for every
    command that loads a scene; the command receives them as one ``overrides`` list of
    ``key=value`` strings, applied like the scene file's own keys."""
    options = [
        click.option("--set", "sets", multiple=True, metavar="KEY=VALUE", help=SET_HELP),
        click.option("--size", type=ImageSize(), metavar="WxH",
                     help="Image size, e.g. 1280x720 (overrides render.size)."),
    ]
    if with_samples:
        options.append(click.option("--samples", type=RuleType(MSAA_SAMPLES), metavar="N",
                                    help=f"MSAA samples: {MSAA_SAMPLES.bounds()} {MSAA_SAMPLES.note}; overrides "
                                         "render.samples."))

    def decorate(command):
        @functools.wraps(command)
        def with_overrides(*args, sets, size, samples=None, **kwargs):
            return command(*args, overrides=_overrides(sets, size, samples), **kwargs)

        for option in reversed(options):
            with_overrides = option(with_overrides)
        return with_overrides

    return decorate


@main.command()
@click.argument("scene", type=GivenPath(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=GivenPath(path_type=Path), default=Path("out"), show_default=True,
              help="Folder for image sequences, or the video file / folder for MP4 and GIF. " + MAKES_PARENTS)
@_scene_overrides()
@click.option("--format", "fmt", type=click.Choice(["png", "jpg", "tga", "exr", "mp4", "gif"]),
              help="Output format (overrides output.format).")
@click.option("--frames", metavar="A:B", help="Render frames A to B-1 only, like a Python slice: also A:B:STEP, "
                                               "-10: (the last ten) or N (frame N alone).")
@click.option("--overwrite", is_flag=True, help="Render frames again even if complete files exist.")
@click.option("--strict", is_flag=True, help="Treat warnings (missing MTL textures...) as errors.")
@click.option("-q", "--quiet", is_flag=True, help="No progress and no summary line.")
@click.option("--profile", is_flag=True,
              help="Afterwards print ms per pass and per frame (GPU-synchronised, so slower).")
@click.option("--check", "check", type=GivenPath(file_okay=False, path_type=Path), metavar="REF_DIR",
              help="Then compare the output with the references in REF_DIR (or REF_DIR/<renderer>/, e.g. "
                   "ref/llvmpipe/, when that exists); exit 1 on a change; report.html written with the output. "
                   "REF_DIR is a folder of its own, never -o itself.")
@click.option("--update-references", is_flag=True,
              help="With --check: make the references equal to this output on purpose, and say what changed.")
@click.option("--object-ids/--no-object-ids", default=None,
              help="Keep which object each pixel shows (OUT/.object_ids/, 16-bit PNGs and objects.json), "
                   "so `diff` and --check name changes by object and catch small moves and material changes "
                   "colour alone cannot. On by default with --check (and so with --update-references) "
                   "wherever the output can hold them (image sequences and single images, not MP4/GIF); "
                   "--no-object-ids judges by colour alone.")
@click.option("--workers", type=click.IntRange(1, 256), default=1, show_default=True,
              help="Render on N local processes, each with its own GL context (same files as one).")
@click.option("--scheduler", metavar="ADDRESS",
              help="Render on a Dask cluster, e.g. tcp://10.0.0.5:8786; the scene, its assets and -o must "
                   "be on storage every worker sees (needs the 'distributed' extra).")
@click.option("--require-gpu", is_flag=True, default=None,
              help="Exit 3 when the GL renderer draws on the CPU (llvmpipe, softpipe, swrast), as a driver that "
                   "finds no GPU does without a word; SCENERENDER_REQUIRE_GPU=1 does the same for every render. "
                   "The renderer used is the first line of progress and is recorded in the run manifest.")
@_asset_root_option
@_limit_option
def render(scene, output, overrides, fmt, frames, overwrite, strict, quiet, profile, check,
           update_references, object_ids, workers, scheduler, require_gpu, asset_roots, limit_texts):
    """Render SCENE into -o OUTPUT: a folder of frames, or the video or image file it names.
    SCENE is a scene file, or a glTF file (.glb, .gltf) rendered as it stands: its first
    camera (else framing its bounds), its lights (else the default rig), its first clip.

    A frame already in OUTPUT is kept only when the run manifest (OUTPUT/.scenerender.json)
    shows it was made from the same scene, assets, options and scenerender version;
    anything else is rendered again. Each file is written whole (temporary file + rename)
    or not at all.

    \b
    Examples:
      scenerender render scene.yaml -o out/                 # frames or a video, as the scene says
      scenerender render scene.yaml -o out/clip.mp4 --format mp4
      scenerender render scene.yaml -o out/ --size 320x240 --samples 1 --frames 0:10
      scenerender render scene.yaml -o still.png --format png --frames 12   # one frame, one file
      scenerender render model.glb -o out/     # a glTF file as it stands: its camera, lights, first clip
    In CI:
      scenerender render scene.yaml -o out/ --check ref/             # exit 1 when frames changed
      scenerender render scene.yaml -o out/ --check ref/ --update-references
      scenerender render scene.yaml -o out/ --no-object-ids --check ref/   # judged by colour alone

    Exit codes: 0 done, 1 frames changed (--check), 2 bad input or an output that cannot be
    written, 3 the machine lacks something (no OpenGL driver; no GPU with --require-gpu),
    130 / 143 interrupted.
    """
    collection.pause_until_started()  # before the imports: the first frame ends the pause
    from scenerender.run.interrupts import signals_as_exceptions
    from scenerender.run.job import RenderOptions, run_render

    if update_references and check is None:
        raise click.UsageError("--update-references needs --check REF_DIR (the references to rewrite)")

    def notice(text):  # warnings and a failing check: shown even with -q
        click.echo(text, err=True)

    def echo(text):
        if not quiet:
            notice(text)

    options = RenderOptions(output=output, overrides=overrides, frames=frames,
                            overwrite=overwrite, strict=strict, quiet=quiet, format=fmt, profile=profile,
                            check=check, update_references=update_references, object_ids=object_ids,
                            asset_roots=tuple(asset_roots),
                            workers=workers, scheduler=scheduler, limits=_limits(limit_texts),
                            require_gpu=require_gpu)
    with signals_as_exceptions():  # also while the scene loads: exit 143/129 with a message
        summary = run_render(scene, options, echo=echo, notice=notice)
    if summary.profile:
        click.echo(summary.profile)
    if summary.check is not None and not summary.check.passed and not update_references:
        sys.exit(1)


@main.command()
@click.argument("scene", type=GivenPath(dir_okay=False, path_type=Path))
@_scene_overrides()
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
@click.option("--assets/--no-assets", default=True, show_default=True,
              help="Also load meshes, MTL files, textures and skybox faces to check them.")
@_asset_root_option
@_limit_option
def validate(scene, overrides, strict, assets, asset_roots, limit_texts):
    """Check SCENE without rendering: everything `render` checks short of drawing. Keys and
    values; every file the scene names (inside the allowed folders, regular files); meshes
    and MTL files parsed; textures and skybox faces decoded; limits. Lists every warning,
    then prints 'ok' and exits 0 when the scene is valid; a scene that validates does not
    fail in `render` because of its input. SCENE may be a glTF file (.glb, .gltf): the
    scene `render` makes of it."""
    from scenerender.errors import Warnings
    from scenerender.run.model_scene import load_scene_or_model

    warnings = Warnings(strict=strict, echo=lambda t: click.echo(t, err=True))
    loaded = load_scene_or_model(scene, overrides, asset_roots=tuple(asset_roots), limits=_limits(limit_texts))
    clips, brought = [], 0
    if assets:
        from scenerender.world.build import build_world, variant_lines
        from scenerender.world.node_animation import clip_lines

        world = build_world(loaded, warnings)
        clips = clip_lines(loaded) + variant_lines(loaded)
        brought = sum(1 for light in world.lights if light.path[:1] == ("objects",))  # objects' `lights: true`
    spec = loaded.spec
    noted = f", {len(warnings.items)} warning(s)" if warnings.items else ""
    click.echo(f"ok: {scene} ({len(spec.objects)} objects, {len(spec.lights or []) + brought} lights, "
               f"{spec.output.frame_count} frame(s), {spec.render.size[0]}x{spec.render.size[1]}, "
               f"{len(loaded.assets.files_read)} asset file(s){noted})")
    for line in clips:  # what `animation: {clip: ...}` and `variant:` can name
        click.echo(line)


@main.command()
@click.option("-o", "--output", type=GivenPath(dir_okay=False, path_type=Path),
              help="Write to a file. " + MAKES_PARENTS)
@click.option("--markdown", is_flag=True,
              help="The format reference (every key, its type, range, default and an example) as Markdown.")
def schema(output, markdown):
    """Print the scene format as JSON Schema (for editor completion and validation), or
    with --markdown as the reference that docs/scene-format.md holds."""
    if markdown:
        from scenerender.scene.reference import reference_markdown

        text = reference_markdown()
    else:
        from scenerender.scene.reference import editor_schema

        text = editor_schema() + "\n"
    if output:
        from scenerender.sinks.base import atomic_path, write_file

        with atomic_path(output) as temp:  # never a half-written schema or reference
            write_file(temp, text.encode("utf-8"))
    else:
        click.echo(text, nl=False)


@main.command()
@click.argument("scene", type=GivenPath(dir_okay=False, path_type=Path))
@click.option("--dot", is_flag=True, help="Graphviz dot instead of text.")
@_scene_overrides()
@_asset_root_option
@_limit_option
def graph(scene, dot, overrides, asset_roots, limit_texts):
    """Print the render graph SCENE compiles to: the world's inputs (static or animated),
    the passes kept (static ones render once per run, derived from what they read), passes
    culled, and the images between them. Works without a GL device; where one is at hand,
    the MSAA samples are what it offers."""
    from scenerender.api import load
    from scenerender.run.graph_report import graph_report

    loaded_scene = load(scene, overrides, asset_roots=asset_roots, limits=_limits(limit_texts),
                        on_warning=lambda t: click.echo(t, err=True))
    report = graph_report(loaded_scene)
    if dot:
        click.echo(report.compiled.dot())
        return
    click.echo(report.header(str(scene)))
    click.echo(report.compiled.dump())


PREVIEW_INSTALL_HINT = "preview needs its extra libraries: pip install 'scenerender[preview]'"


@main.command()
@click.argument("scene", type=GivenPath(exists=True, dir_okay=False, path_type=Path))
@click.option("--host", default="127.0.0.1", show_default=True,
              help="Address to serve the page on; the default is reachable from this machine only.")
@click.option("--port", type=click.IntRange(0, 65535), default=8765, show_default=True,
              help="Port to serve the page on; 0 picks a free one (the address is printed).")
@_scene_overrides()
@click.option("--check", "check", type=GivenPath(file_okay=False, path_type=Path), metavar="REF_DIR",
              help="Show each frame's reference from REF_DIR (or REF_DIR/<renderer>/) beside the live one, with "
                   "the diff verdict of the frame rendered at the scene's own size and samples.")
@click.option("--open/--no-open", "open_browser", default=True, show_default=True,
              help="Open the page in the browser, where there is a graphical session to open it in.")
@_asset_root_option
@_limit_option
def preview(scene, host, port, overrides, check, open_browser, asset_roots, limit_texts):
    """Serve a page that shows SCENE rendered and renders it again whenever the scene file
    or an asset it uses is saved: a timeline over its frames (play at the scene's fps),
    a camera to drag (orbit), wheel (dolly) and fly (W A S D, Q E) with its YAML to
    copy, the camera path seen from above, a render.mode switch, and the CLI's messages
    (file and line) over the last good image while the scene does not validate.

    Preview frames are lowered: the scene's shape shrunk to fit 320x240 (a 16:9 scene at
    320x180) and 1 MSAA sample, unless --size, --samples or --set say otherwise; everything
    else renders as the scene says. --check renders at the scene's own size and samples.

    \b
    Examples:
      scenerender preview scene.yaml                  # then open http://127.0.0.1:8765/
      scenerender preview scene.yaml --port 0 --size 640x480
      scenerender preview scene.yaml --check ref/     # the reference and the verdict beside each frame
    """
    try:
        from scenerender.preview import serve as preview_serve
        from scenerender.preview.server import Preview
    except ImportError as exc:  # the optional extra is not installed: the machine lacks it (exit 3)
        raise EnvironmentProblem(f"{PREVIEW_INSTALL_HINT} ({exc})") from None
    from scenerender.preview.views import PreviewQuality

    size_given = any(text.startswith("render.size=") for text in overrides)
    samples_given = any(text.startswith("render.samples=") for text in overrides)
    references = preview_serve.check_folder(check)
    session = Preview(scene, overrides, PreviewQuality.for_options(size_given, samples_given), references=references, asset_roots=asset_roots, limits=_limits(limit_texts))
    sock = preview_serve.bind(host, port)
    preview_serve.serve(session, sock, echo=click.echo, open_browser=open_browser)


@main.command()
def info():
    """Print the OpenGL renderer, version and limits scenerender will use."""
    from scenerender.gpu.gl_context import create_context, gl_info
    from scenerender.gpu.shaders import shader_dir

    ctx = create_context()
    for key, value in gl_info(ctx).items():
        click.echo(f"{key:<36} {value}")
    click.echo(f"{'shaders':<36} {shader_dir()}")


def _diff_rule_options(command):
    """One option per field of ``DiffRule`` (``--max-tile`` for ``max_tile``), with the
    field's default, rule and help: a limit added to the rule is an option here."""
    for item in reversed(fields(DiffRule)):
        command = click.option(f"--{item.name.replace('_', '-')}", item.name, type=RuleType(item.metadata["rule"]),
                               metavar=item.metadata["metavar"], default=item.default, show_default=True,
                               help=item.metadata["help"])(command)
    return command


@main.command()
@click.argument("reference", type=GivenPath(path_type=Path))
@click.argument("output", type=GivenPath(path_type=Path))
@click.option("--report", type=GivenPath(dir_okay=False, path_type=Path),
              help="Write a self-contained HTML report (images, heatmaps, changed regions). " + MAKES_PARENTS)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON on stdout instead of lines.")
@_diff_rule_options
def diff(reference, output, report, as_json, **limits):
    """Compare OUTPUT with REFERENCE: two images, two folders of frames (PNG, JPG, TGA, EXR;
    matched by file name) or two videos (MP4, GIF; matched frame by frame).

    Frames both sides kept object ids for (render --check keeps them by default) are also
    judged by object: the changed pixels are named by the objects they belong to, and an
    object that appeared or went, moved against the frame or changed inside (also behind
    glass) fails the frame. The total line says when frames were judged by colour alone, and
    why. A reference folder's ignore.json (rectangles) and ignore.png (a mask) name pixels
    left out of the verdict. Without --report only the verdict is computed (no SSIM or FLIP).

    Prints one line per changed, missing or extra frame and a total line. Exits 0 when every
    frame matches, 1 when a frame changed (a different size counts as changed) or is missing
    or extra, 2 when the input cannot be compared (no such path, an unreadable file, a
    folder against a video), an option is out of range or the report cannot be written.
    EXR frames are compared after the sRGB encode.
    """
    import json

    from scenerender.compare import compare_paths, write_html_report

    result = compare_paths(reference, output, DiffRule(**limits), pictures=report is not None)
    if report is not None:
        write_html_report(result, report, option="--report")
    if as_json:
        payload = result.to_json()
        payload["report"] = str(report) if report is not None else None
        click.echo(json.dumps(payload, indent=2))
    else:
        for line in result.summary_lines():
            click.echo(line)
        if report is not None:
            click.echo(f"report: {report}")
    sys.exit(0 if result.passed else 1)


@main.command()
@click.argument("scene", type=GivenPath(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=GivenPath(file_okay=False, path_type=Path), default=Path("ref"),
              show_default=True, help="Folder for frame_NNNN.exr (linear float) and frame_NNNN.png. " + MAKES_PARENTS)
@click.option("--frames", metavar="A:B", default="0:1", show_default=True,
              help="Frames to render (like a Python slice).")
@click.option("--spp", type=RuleType(option_rules.SPP), default=4, show_default=True,
              help="Stratified samples a pixel along each axis (4 gives 4x4 = 16).")
@click.option("--ambient-samples", type=RuleType(option_rules.AMBIENT_SAMPLES), default=0, show_default=True,
              help="0: ambient light by the GPU's formula. N: integrated over N directions a sample "
                   "(Monte Carlo, seeded), each weighted by the BRDF and blocked by surfaces in its way.")
@click.option("--environment-samples", type=RuleType(option_rules.ENVIRONMENT_SAMPLES),
              default=option_rules.DEFAULT_ENVIRONMENT_SAMPLES, show_default=True,
              help="Directions a sample an environment light is gathered from (Monte Carlo, seeded, "
                   "importance-sampled between the cosine and the GGX lobe), each blocked by surfaces in its way.")
@click.option("--shutter-samples", type=RuleType(option_rules.SHUTTER_SAMPLES),
              default=option_rules.DEFAULT_SHUTTER_SAMPLES, show_default=True,
              help="With camera.shutter: instants over the open shutter averaged (one drawn at random in each "
                   "slice, seeded). With camera.aperture every ray starts at its own random point of the lens.")
@click.option("--bounces", type=RuleType(option_rules.BOUNCES), default=0, show_default=True,
              help="0: direct light only. N: path tracing, light that bounced off up to N surfaces too "
                   "(each light, the environment and ambient sampled at every bounce, emissive surfaces "
                   "light what they face; Russian roulette after 3 bounces; seeded).")
@_scene_overrides(with_samples=False)
@_asset_root_option
def reference(scene, output, frames, spp, ambient_samples, environment_samples, shutter_samples, bounces,
              overrides, asset_roots):
    """Render SCENE (render.mode: shaded) with the CPU reference: ray-cast visibility, exact
    hard shadows, the GPU's shading equations, spp x spp samples a pixel. It is the truth
    error is measured against (`scenerender bench`), not a second renderer: normal and
    opacity maps, ambient occlusion, transparency, alpha masks, outlines and the skybox are
    left out (one warning names what the scene has of them); rays that miss the scene show
    the background colour, also where an environment light lights it. With --bounces N it
    path-traces: light that bounced off up to N surfaces too (docs/scene-notes.md, "Light
    that bounces, in the reference"); 0 is direct light only. Transmissive materials
    (`transmission`) are traced through: one path a sample through the rough glass and its
    volume (docs/scene-notes.md, "Transmission and volume")."""
    import time

    from scenerender.api import load
    from scenerender.raytrace import embree_available, render_reference, write_reference
    from scenerender.run.plan import parse_frame_range

    loaded = load(scene, overrides, asset_roots=asset_roots, on_warning=lambda line: click.echo(line, err=True))
    warn = lambda text: click.echo(f"warning: {text}", err=True)  # noqa: E731
    if not embree_available():
        warn("embreex is not installed (pip install 'scenerender[reference]'): ray casting is slow")
    for index in parse_frame_range(frames, loaded.frame_count):
        started = time.perf_counter()
        frame = render_reference(loaded, index, spp=spp, warn=warn, ambient_samples=ambient_samples,
                                 environment_samples=environment_samples, shutter_samples=shutter_samples,
                                 bounces=bounces)
        paths = write_reference(frame, output)
        warn = None  # the left-out features are the same on every frame
        click.echo(f"frame {index}: {', '.join(str(p) for p in paths)} ({time.perf_counter() - started:.1f} s)")


@main.command()
@click.argument("scene", type=GivenPath(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=GivenPath(file_okay=False, path_type=Path), default=Path("bench"),
              show_default=True, help="Folder for NAME.md (table), NAME.json and NAME.png (plot). " + MAKES_PARENTS)
@click.option("--knob", "knobs", multiple=True,
              type=click.Choice(["samples", "shadow_size", "pcf", "bias", "ao", "size", "combined", "prefilter_size",
                                 "sh_order", "env_samples", "env_footprint", "env_specular", "env_visibility",
                                 "env_directions", "env_map_size", "env_interleave", "film_samples", "blocker_samples",
                                 "filter_samples", "motion_blur"]),
              help="Sweep only these knobs (repeatable; default all).")
@click.option("--frames", type=click.IntRange(1, 1000), default=3, show_default=True,
              help="Timed frames per variant and round (after one warm-up frame).")
@click.option("--rounds", type=click.IntRange(1, 100), default=2, show_default=True,
              help="Rounds over all variants; ms/frame is the median over all of them.")
@click.option("--spp", type=RuleType(option_rules.SPP), default=16, show_default=True,
              help="Reference samples a pixel along each axis (at 4, the reference's own noise at "
                   "shadow and cone edges is larger than a good GPU frame's error there).")
@click.option("--environment-samples", type=RuleType(option_rules.ENVIRONMENT_SAMPLES),
              default=option_rules.DEFAULT_ENVIRONMENT_SAMPLES, show_default=True,
              help="Directions a sample an environment light is gathered from (Monte Carlo, seeded, "
                   "importance-sampled between the cosine and the GGX lobe), each blocked by surfaces in its way.")
@click.option("--bounces", type=RuleType(option_rules.BOUNCES), default=0, show_default=True,
              help="The reference's bounces (see `scenerender reference --help`): 0 measures against direct "
                   "light only, 16 against the path-traced whole.")
@_scene_overrides(with_samples=False)
@click.option("--json", "as_json", is_flag=True, help="Print the rows as JSON on stdout.")
@_asset_root_option
def bench(scene, output, knobs, frames, rounds, spp, environment_samples, bounces, overrides, as_json, asset_roots):
    """Sweep SCENE's quality knobs (MSAA, shadow map size, PCF, bias, AO, image size, an
    environment light's prefilter size, SH order and prefilter samples, and the soft
    shadows' blocker and filter reads where a shadowed light has a size) on
    the GPU path and measure each variant's ms/frame and its error against the CPU
    reference (RMSE linear and sRGB, PSNR, FLIP, shadow-edge, cone-edge and interior RMSE).
    Writes a Markdown table, JSON and a plot of ms/frame against error with the Pareto
    front marked."""
    import json

    from scenerender.tools import bench as sweep

    echo = (lambda text: click.echo(text, err=True))
    rows = sweep.run_bench(scene, overrides, knobs=knobs or sweep.KNOBS, frames=frames,
                           rounds=rounds, spp=spp, echo=echo, asset_roots=asset_roots,
                           environment_samples=environment_samples, bounces=bounces)
    meta = {"frames": frames, "rounds": rounds, "spp": spp, "environment_samples": environment_samples,
            "bounces": bounces, "overrides": overrides}
    paths = sweep.write_outputs(scene.stem, rows, output, meta)
    if as_json:
        click.echo(json.dumps([row.to_json() for row in rows], indent=2))
    else:
        click.echo(sweep.markdown_table(scene.stem, rows, bounces))
    echo("wrote " + ", ".join(str(p) for p in paths))


# Set to skip the quick exit below: the interpreter is torn down as usual (tools that
# look at the process's end, a debugger).
FULL_EXIT_VARIABLE = "SCENERENDER_FULL_EXIT"
OPENBLAS_THREADS_VARIABLE = "OPENBLAS_NUM_THREADS"
PYDANTIC_PLUGINS_VARIABLE = "PYDANTIC_DISABLE_PLUGINS"


def entry_point() -> None:
    """The process's entry (the ``scenerender`` script, ``python -m scenerender``): the
    command, then the process ends without tearing the interpreter down.

    Tearing down frees every module, runs the collector over all that start-up made and
    lets the GL driver unload: about 0.1 s of CPU time, a seventh of a one-frame render,
    for nothing a process that is ending needs. ``main`` itself stays an ordinary click
    command, so a caller running it in its own process (CliRunner) is unaffected.
    """
    # OpenBLAS starts a thread per core as NumPy loads it, which cost a one-frame render
    # 25 ms of CPU (50 ms wall on 2 busy cores). scenerender's products are of 4x4 matrices
    # and point arrays, and one thread gives the same bits as several (checked up to
    # 2,000,000 x 4 points and a 512 x 512 product). Set before NumPy is imported (this
    # module does not import it), and only where the user has not chosen.
    os.environ.setdefault(OPENBLAS_THREADS_VARIABLE, "1")
    # pydantic looks for plugins (observability hooks for an application's own models) in
    # every installed package's entry points as the scene model's validator is built: 8 to
    # 30 ms of a one-frame render with this project's test dependencies installed, for
    # hooks the scene model does not want. Also only where the user has not chosen.
    os.environ.setdefault(PYDANTIC_PLUGINS_VARIABLE, "1")
    try:
        main()
    except SystemExit as exc:
        _exit_quickly(exc.code)
    _exit_quickly(0)  # pragma: no cover (click's main always raises SystemExit)


def _exit_quickly(code) -> None:
    if not isinstance(code, int) and code is not None:
        sys.exit(code)  # a message as the code: Python prints it
    code = code or 0
    # A normal exit waits for threads that are not daemons; os._exit would cut them off.
    others = [thread for thread in threading.enumerate() if thread is not threading.main_thread()
              and not thread.daemon]
    if others or os.environ.get(FULL_EXIT_VARIABLE):
        sys.exit(code)
    # What a library asked to run at exit still runs (weakref finalizers, a thread pool's
    # or multiprocessing's clean-up); the handlers are cleared, so sys.exit below would not
    # run them twice.
    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):  # a closed pipe: Python's own exit reports it as usual
        sys.exit(code)
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    entry_point()
