"""The ``scenerender`` command line. ``scenerender --help`` and ``scenerender COMMAND --help``
are the manual.

Exit codes: 0 success, 2 bad input (scene file, asset, option), 3 the machine lacks
something (no EGL driver), 1 a bug in scenerender.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from scenerender import __version__
from scenerender.errors import EnvironmentProblem, SceneErrors, UserError

SET_HELP = "Override any scene key, e.g. --set render.samples=8 or --set objects[0].position=[0,1,0] (repeatable)."


def _echo_error(text: str) -> None:
    from scenerender.errors import one_line

    click.echo(f"error: {one_line(text)}", err=True)


class _Command(click.Group):
    """Turns scenerender's own exceptions into one-line messages and exit codes."""

    def invoke(self, ctx):
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
        except KeyboardInterrupt:
            _echo_error("interrupted; frames already finished are complete, nothing partial was left")
            sys.exit(130)
        except (click.ClickException, click.exceptions.Exit, click.exceptions.Abort, SystemExit):
            raise
        except Exception as exc:  # a bug: say so plainly, keep the traceback for --debug
            if os.environ.get("SCENERENDER_DEBUG"):
                raise
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
      scenerender graph scene.yaml --dot | dot -Tpng > graph.png
      scenerender diff reference.png out/frame_0000.png --tolerance 2

    The scene format is described in SCENE_FORMAT.md; `scenerender schema` prints it as
    JSON Schema for editors.
    """


def _size_override(value: str | None) -> list[str]:
    if value is None:
        return []
    width, sep, height = value.lower().partition("x")
    if not sep or not width.isdigit() or not height.isdigit():
        raise click.BadParameter(f"expected WIDTHxHEIGHT such as 640x480, got '{value}'", param_hint="--size")
    return [f"render.size=[{int(width)}, {int(height)}]"]


def _overrides(sets, size, samples) -> list[str]:
    out = list(sets) + _size_override(size)
    if samples is not None:
        out.append(f"render.samples={samples}")
    return out


@main.command()
@click.argument("scene", type=click.Path(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), default=Path("out"), show_default=True,
              help="Folder for image sequences, or the video file / folder for MP4 and GIF.")
@click.option("--size", metavar="WxH", help="Image size, e.g. 1280x720 (overrides render.size).")
@click.option("--samples", type=click.IntRange(1, 64), help="MSAA samples; 1 turns anti-aliasing off.")
@click.option("--format", "fmt", type=click.Choice(["png", "jpg", "tga", "exr", "mp4", "gif"]),
              help="Output format (overrides output.format).")
@click.option("--frames", metavar="A:B", help="Render frames A to B-1 only (like a Python slice).")
@click.option("--set", "sets", multiple=True, metavar="KEY=VALUE", help=SET_HELP)
@click.option("--overwrite", is_flag=True, help="Render frames again even if complete files exist.")
@click.option("--strict", is_flag=True, help="Treat warnings (missing MTL textures...) as errors.")
@click.option("-q", "--quiet", is_flag=True, help="No progress and no summary line.")
def render(scene, output, size, samples, fmt, frames, sets, overwrite, strict, quiet):
    """Render SCENE to frames in OUTPUT.

    Frames that already exist complete are kept unless --overwrite; each file is written
    whole (temporary file + rename) or not at all.
    """
    from scenerender.job import RenderOptions, run_render

    def echo(text):
        if not quiet or text.startswith("warning"):
            click.echo(text, err=True)

    options = RenderOptions(output=output, overrides=_overrides(sets, size, samples), frames=frames,
                            overwrite=overwrite, strict=strict, quiet=quiet, format=fmt)
    summary = run_render(scene, options, echo=echo)
    if not quiet:
        if summary.rendered == 0:
            click.echo(f"nothing to do: all {summary.skipped} frame(s) already complete in {summary.target} "
                       "(--overwrite renders them again)", err=True)
        else:
            click.echo(summary.line(), err=True)


@main.command()
@click.argument("scene", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--set", "sets", multiple=True, metavar="KEY=VALUE", help=SET_HELP)
@click.option("--strict", is_flag=True, help="Treat warnings as errors.")
@click.option("--assets/--no-assets", default=True, show_default=True,
              help="Also load meshes, MTL files and textures to check them.")
def validate(scene, sets, strict, assets):
    """Check SCENE without rendering: keys, values, files, and (with --assets) the meshes
    and materials they name. Prints 'ok' and exits 0 when the scene is valid."""
    from scenerender.errors import Warnings
    from scenerender.scene import load_scene

    loaded = load_scene(scene, list(sets))
    if assets:
        from scenerender.world.build import build_world

        build_world(loaded, Warnings(strict=strict, echo=lambda t: click.echo(t, err=True)))
    spec = loaded.spec
    click.echo(f"ok: {scene} ({len(spec.objects)} objects, {len(spec.lights or [])} lights, "
               f"{spec.output.frame_count} frame(s), {spec.render.size[0]}x{spec.render.size[1]})")


@main.command()
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), help="Write to a file.")
def schema(output):
    """Print the scene format as JSON Schema (for editor completion and validation)."""
    from scenerender.scene.json_schema import scene_json_schema

    text = scene_json_schema()
    if output:
        output.write_text(text + "\n", encoding="utf-8")
    else:
        click.echo(text)


@main.command()
@click.argument("scene", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--dot", is_flag=True, help="Graphviz dot instead of text.")
@click.option("--set", "sets", multiple=True, metavar="KEY=VALUE", help=SET_HELP)
@click.option("--size", metavar="WxH", help="Image size (overrides render.size).")
@click.option("--samples", type=click.IntRange(1, 64), help="MSAA samples.")
def graph(scene, dot, sets, size, samples):
    """Print the render graph SCENE compiles to: passes kept (static ones render once per
    run), passes culled, and the resources between them. Needs no GL context."""
    from scenerender.errors import Warnings
    from scenerender.render.renderer import plan
    from scenerender.scene import load_scene
    from scenerender.world.build import build_world

    loaded = load_scene(scene, _overrides(sets, size, samples))
    world = build_world(loaded, Warnings(echo=lambda t: click.echo(t, err=True)))
    render_spec = world.render
    _, motion, compiled = plan(world, render_spec.size, render_spec.samples)
    if dot:
        click.echo(compiled.dot())
        return
    frames = loaded.spec.output.frame_count
    click.echo(f"render graph of {scene}: mode {render_spec.mode}, {render_spec.size[0]}x{render_spec.size[1]}, "
               f"{frames} frame(s); geometry {'static' if motion.geometry_static else 'animated'}, "
               f"camera {'static' if motion.camera_static else 'animated'}")
    click.echo(compiled.dump())


@main.command()
def info():
    """Print the OpenGL renderer, version and limits scenerender will use."""
    from scenerender.gpu.context import create_context, gl_info
    from scenerender.gpu.shaders import shader_dir

    ctx = create_context()
    for key, value in gl_info(ctx).items():
        click.echo(f"{key:<36} {value}")
    click.echo(f"{'shaders':<36} {shader_dir()}")


@main.command()
@click.argument("reference", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("candidate", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--tolerance", type=float, default=1.0, show_default=True,
              help="Largest allowed mean absolute difference, in 8-bit levels.")
@click.option("--max-bad-pixels", type=float, default=0.5, show_default=True,
              help="Largest allowed percentage of pixels differing by more than --pixel-threshold.")
@click.option("--pixel-threshold", type=int, default=24, show_default=True,
              help="A pixel is 'bad' when a channel differs by more than this many levels.")
@click.option("--max-tile", type=float, default=6.0, show_default=True,
              help="Largest allowed mean difference of any 8x8 block: catches small moved objects.")
@click.option("--heatmap", type=click.Path(dir_okay=False, path_type=Path), help="Write a difference image.")
def diff(reference, candidate, tolerance, max_bad_pixels, pixel_threshold, max_tile, heatmap):
    """Compare two images the way golden-image tests do. Exits 0 when CANDIDATE matches
    REFERENCE within the tolerances, 1 when it does not, 2 when they cannot be compared."""
    from scenerender.tools.imagediff import compare_files

    report = compare_files(reference, candidate, heatmap=heatmap, pixel_threshold=pixel_threshold)
    passed = report.within(tolerance, max_bad_pixels, max_tile)
    click.echo(report.line() + ("  PASS" if passed else "  FAIL"))
    sys.exit(0 if passed else 1)


if __name__ == "__main__":  # pragma: no cover
    main()
