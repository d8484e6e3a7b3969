"""scenerender beside the Khronos glTF Sample Viewer, on GLBs that exercise the material
extensions (models.py): each file drawn by the Sample Viewer's renderer in headless
Chromium and by scenerender, both through the file's camera and lit by its
KHR_lights_punctual lights alone; per model the mean difference (image_diff.py), a
side-by-side picture (viewer | scenerender | difference x4) and a table. Diagnostic rows
(``DIAGNOSTICS``) draw a model again with the viewer changed in one line (``VARIANTS``),
to show where a difference comes from. docs/gltf-viewer-comparison.md has the results.

    python benchmarks/viewer/compare_sample_viewer.py                 # into /tmp/scenerender-sample-viewer
    python benchmarks/viewer/compare_sample_viewer.py --docs          # docs/gltf-viewer/ and the page's table
    python benchmarks/viewer/compare_sample_viewer.py --docs --no-antialias   # the page's second table

Needs node's npm (the renderer is installed from the npm registry into --cache with the
pinned package-lock.json beside this file), Chromium and chromedriver (Debian's chromium
and chromium-driver; WebGL 2 on SwiftShader, no GPU needed) and selenium
(``pip install -e '.[test]'``). Nothing of it runs in the test suite.
"""
from __future__ import annotations

import argparse
import base64
import functools
import io
import json
import shutil
import subprocess
import sys
import threading
import time
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import numpy as np
from PIL import Image

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

import scenerender  # noqa: E402
from scenerender.mesh.gltf import READ_EXTENSIONS  # noqa: E402
from scenerender.raytrace.sheen_fit import albedo  # noqa: E402

import image_diff  # noqa: E402
import models  # noqa: E402

PACKAGE = "@khronosgroup/gltf-viewer"
DOCS_PAGE = ROOT / "docs" / "gltf-viewer-comparison.md"
DOCS_IMAGES = ROOT / "docs" / "gltf-viewer"
# the page's tables lie between these lines, one per mode (antialiased, no-antialias)
TABLE_START, TABLE_END = "<!-- table {}: written by compare_sample_viewer.py -->", "<!-- end of table -->"
SHEEN_LUT_SIZE = 32
# The environment's prefiltering (the renderer's iblSampler), made small: the environment
# here is black and lights nothing (useIBL off); at the renderer's own sizes (a 256 pixel
# cube, 1024 GGX samples, 1024 x 1024 tables) SwiftShader blocks the page for minutes.
SMALL_FILTERING = {"this.textureSize = 256;": "this.textureSize = 64;",
                   "this.ggxSampleCount = 1024;": "this.ggxSampleCount = 16;",
                   "this.lambertianSampleCount = 2048;": "this.lambertianSampleCount = 16;",
                   "this.sheenSamplCount = 64;": "this.sheenSamplCount = 16;",
                   "this.lutResolution = 1024;": "this.lutResolution = 64;"}
# The renderer as the npm package ships it, and two diagnostic variants, each a line or two
# away from it, that show where a model's difference comes from (rows NAME:VARIANT):
# - sheen_table: 1.1.0 marks its sheen albedo table "initialized" before anything is
#   uploaded, so the shader samples an empty texture (0) and the sheen takes nothing from
#   the layer under it; uploaded, the table (sheen_lut) scales the base as the extension says.
# - through_cosine: the viewer's punctual light through a transmissive surface (its BTDF
#   lobe, the light mirrored through the surface) as scenerender takes it, in two changes:
#   times the cosine N.L_m of the mirrored direction (the shipped lobe has none, so a light
#   in front of the surface, mirrored below it, N.L_m clamped to 0 where its V stays
#   0.5 / (N.V alpha), shines through too), and its Fresnel once (the shipped one weighs it
#   by 1 - F at the mirrored half vector and again, in its Fresnel mix with the
#   reflection, by 1 - F at the unmirrored one; divided out here).
VARIANTS = {
    "shipped": {},
    "sheen_table": {"sheenELut.initialized = true;": "sheenELut.initialized = false;"},
    "through_cosine": {"return(1.0-F)*baseColor*D*Vis;}": "return(1.0-F)*baseColor*D*Vis*clampedDot(n,l_mirror);}",
                       "l_diffuse=mix(l_diffuse,transmittedLight,materialInfo.transmissionFactor);":
                       "l_diffuse=mix(l_diffuse,transmittedLight/max(vec3(1.0)-dielectric_fresnel,vec3(1e-4)),"
                       "materialInfo.transmissionFactor);"},
    # KHR_materials_pbrSpecularGlossiness: c_diff = diffuse (1 - max(specular)), as its
    # specification writes (the shipped viewer takes the diffuse as it is)
    "diffuse_share": {"vec3 l_diffuse=lightIntensity*NdotL*BRDF_lambertian(baseColor.rgb);":
                      "vec3 l_diffuse=lightIntensity*NdotL*BRDF_lambertian(baseColor.rgb*(1.0-max3(u_SpecularFactor)));"},
}
DIAGNOSTICS = (("sheen", "sheen_table"), ("transmission", "through_cosine"), ("volume", "through_cosine"),
               ("specular_glossiness", "diffuse_share"))
CHROMIUM_ARGUMENTS = ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--use-angle=swiftshader",
                      "--enable-unsafe-swiftshader", "--window-size=1200,800")


def install_viewer(cache: Path) -> Path:
    """The pinned renderer in ``cache``/node_modules (``npm ci`` with this folder's lock file,
    once); returns that node_modules folder."""
    cache.mkdir(parents=True, exist_ok=True)
    for name in ("package.json", "package-lock.json"):
        if not (cache / name).exists() or (cache / name).read_bytes() != (HERE / name).read_bytes():
            shutil.copyfile(HERE / name, cache / name)
            shutil.rmtree(cache / "node_modules", ignore_errors=True)
    if not (cache / "node_modules" / PACKAGE / "package.json").exists():
        subprocess.run(["npm", "ci", "--no-audit", "--no-fund"], cwd=cache, check=True)
    return cache / "node_modules"


def radiance_hdr(width: int = 16, height: int = 8) -> bytes:
    """A black equirectangular Radiance .hdr (flat RGBE scanlines)."""
    header = f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {height} +X {width}\n".encode()
    return header + bytes(4 * width * height)


def sheen_lut(size: int = SHEEN_LUT_SIZE) -> np.ndarray:
    """(size, size) uint8: the Charlie sheen's directional albedo E(N.V, roughness), N.V along
    a row and roughness down the rows at texel centres, as the Sample Viewer samples its
    lut_sheen_E.png (texture(u_SheenELUT, vec2(NdotV, roughness)).r, no flip). The npm
    package does not ship that file; this is the same integral, int D V N.L over the
    hemisphere, by scenerender.raytrace.sheen_fit.albedo (which keeps the roughness at
    0.07 or above; the models here use 0.3 and more). Only the ``sheen_table`` variant
    reads it: as shipped, 1.1.0 never uploads the table (see VARIANTS)."""
    centres = (np.arange(size) + 0.5) / size
    table = np.array([[albedo(c, r, steps=128) for c in centres] for r in centres])
    return np.round(255.0 * np.clip(table, 0.0, 1.0)).astype(np.uint8)


def patched_module(module: str, variant: str) -> str:
    """The renderer's module text with SMALL_FILTERING's and the variant's replacements,
    each found exactly once."""
    for old, new in {**SMALL_FILTERING, **VARIANTS[variant]}.items():
        if module.count(old) != 1:
            raise RuntimeError(f"{PACKAGE}'s module does not hold {old!r} once: another version?")
        module = module.replace(old, new)
    return module


class QuietHandler(SimpleHTTPRequestHandler):
    def log_message(self, *args):  # the page's requests are not news
        pass


def serve(folder: Path) -> ThreadingHTTPServer:
    """A local HTTP server on ``folder`` (port chosen by the system), serving in a thread."""
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(QuietHandler, directory=str(folder)))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def chromium():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium") or shutil.which("chromium-browser")
    for argument in CHROMIUM_ARGUMENTS:
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)


def decode_png(data_url: str) -> np.ndarray:
    """(H, W, 3) uint8 of a PNG data URL."""
    raw = base64.b64decode(data_url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(raw)).convert("RGB"))


def wait_for_page(driver, url: str) -> None:
    """Open the page at ``url`` and wait until its renderer is ready (its environment
    filtered); raise with the page's error or after 600 s."""
    driver.get(url)
    deadline = time.monotonic() + 600
    while not driver.execute_script("return window.viewerReady === true"):
        error = driver.execute_script("return window.viewerError || null")
        if error or time.monotonic() > deadline:
            raise RuntimeError(f"the Sample Viewer page did not start: {error or 'no answer in 600 s'}; "
                               f"browser console: {driver.get_log('browser')}")
        time.sleep(0.5)


def viewer_renders(work: Path, jobs: list[tuple[str, str]], size: tuple[int, int],
                   antialias: bool = True) -> tuple[dict, dict]:
    """{(model, variant): (H, W, 3) uint8} of the Sample Viewer's canvas for each (model
    name, variant) of ``jobs`` (work/models/NAME.glb), one page load per variant, and what
    the browser said about itself."""
    server = serve(work)
    driver = chromium()
    pictures, about = {}, {}
    try:
        driver.set_script_timeout(600)
        address = f"http://127.0.0.1:{server.server_address[1]}"
        for variant in dict.fromkeys(variant for _, variant in jobs):
            wait_for_page(driver, f"{address}/sample_viewer.html?width={size[0]}&height={size[1]}"
                                  f"&module=gltf-viewer.{variant}.module.js&antialias={int(antialias)}")
            about = {"chromium": driver.capabilities.get("browserVersion"), "webgl": driver.execute_script(
                "const gl = document.getElementById('canvas').getContext('webgl2');"
                "const info = gl.getExtension('WEBGL_debug_renderer_info');"
                "return info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);")}
            for name in [name for name, v in jobs if v == variant]:
                data_url = driver.execute_async_script(
                    "const done = arguments[arguments.length - 1];"
                    "window.renderModel(arguments[0]).then(done, e => done('error: ' + e));", f"models/{name}.glb")
                if data_url.startswith("error"):
                    raise RuntimeError(f"{name}: the Sample Viewer failed: {data_url}")
                pictures[name, variant] = decode_png(data_url)
            problems = [entry["message"] for entry in driver.get_log("browser") if entry["level"] == "SEVERE"]
            if problems:
                print(f"browser console ({variant}):", *problems, sep="\n  ", file=sys.stderr)
        return pictures, about
    finally:
        driver.quit()
        server.shutdown()


def scenerender_render(path: Path, size: tuple[int, int], samples: int | None = None) -> tuple:
    """scenerender's 8-bit output, its linear colour ((H, W, 3) uint8 and float32) and GL
    renderer for the GLB as it stands (the file's camera and lights), on black, with
    ``samples`` MSAA samples (None: the scene's default, 4)."""
    scene = scenerender.load(path, overrides=[f"render.size=[{size[0]},{size[1]}]", "render.background=[0,0,0]"])
    with scenerender.Renderer(scene, want_linear=True, samples=samples) as renderer:
        frame = renderer.render(0)
        return frame.pixels[..., :3], frame.linear[..., :3], renderer.gl_renderer


def prepare_work(work: Path, node_modules: Path, chosen: list) -> None:
    """The served folder: the page, the renderer, the black environment, the sheen table and
    the models."""
    (work / "models").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(HERE / "sample_viewer.html", work / "sample_viewer.html")
    link = work / "node_modules"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(node_modules, target_is_directory=True)
    module = (node_modules / PACKAGE / "dist" / "gltf-viewer.module.js").read_text()
    for variant in VARIANTS:
        (work / f"gltf-viewer.{variant}.module.js").write_text(patched_module(module, variant))
    (work / "environment.hdr").write_bytes(radiance_hdr())
    lut = work / "lut_sheen_E.png"
    if not lut.exists():
        Image.fromarray(sheen_lut(), mode="L").convert("RGBA").save(lut)
    for model in chosen:
        models.write_model(model, work / "models" / f"{model.name}.glb")


def write_page_table(table: str, about: dict, mode: str) -> None:
    """Put ``table`` and the versions between the page's table markers of ``mode``."""
    text = DOCS_PAGE.read_text()
    start = text.index(TABLE_START.format(mode)) + len(TABLE_START.format(mode))
    end = text.index(TABLE_END, start)
    versions = (f"Measured with {PACKAGE} {about['gltf_viewer']} in Chromium {about['chromium']} "
                f"({about['webgl']}) and scenerender {about['scenerender']} ({about['scenerender_gl']}), "
                f"{about['size'][0]} x {about['size'][1]}, "
                + ("MSAA on both sides (the canvas's antialias, scenerender's 4 samples).\n" if about["antialias"]
                   else "no MSAA on either side.\n"))
    DOCS_PAGE.write_text(text[:start] + "\n\n" + table + "\n" + versions + "\n" + text[end:])


VARIANT_NOTES = {"sheen_table": "the viewer with its sheen albedo table uploaded",
                 "through_cosine": "the viewer's light through a transmissive surface with N.L and one Fresnel, as scenerender's",
                 "diffuse_share": "the viewer's specular-glossiness diffuse times 1 - max(specular), as the extension writes"}


def chosen_models(names) -> list:
    """The models of ``names`` (all when empty) that scenerender reads, saying which are skipped."""
    chosen = []
    for model in models.MODELS:
        if names and model.name not in names:
            continue
        unread = sorted(model.extensions() - set(READ_EXTENSIONS))
        if unread:
            print(f"{model.name}: skipped, scenerender does not read {', '.join(unread)} yet")
            continue
        chosen.append(model)
    return chosen


def compare(work: Path, images: Path, model, variant: str, viewer_pixels: np.ndarray, size, samples) -> tuple:
    """One row: scenerender's render of ``model`` against the viewer's, its picture written
    to ``images``; returns (row name, what it shows, Difference, scenerender's GL renderer)."""
    ours_pixels, ours_linear, gl_renderer = scenerender_render(work / "models" / f"{model.name}.glb", size, samples)
    viewer_linear = image_diff.gamma_to_linear(viewer_pixels)
    result = image_diff.difference(viewer_linear, ours_linear, models.sphere_columns(size[0]))
    row = model.name if variant == "shipped" else f"{model.name}:{variant}"
    picture = image_diff.side_by_side(viewer_pixels, ours_pixels, viewer_linear, ours_linear)
    Image.fromarray(picture).save(images / f"{row.replace(':', '-')}.png", optimize=True)
    shows = ", ".join(model.labels) if variant == "shipped" else VARIANT_NOTES[variant]
    print(f"{row:24s} linear {result.linear:5.2f} %  surfaces {result.surface:5.2f} %  levels {result.levels:5.2f}  "
          f"light {result.light_ratio:.3f}  spheres {' '.join(f'{r:.3f}' for r in result.sphere_ratios)}")
    return row, shows, result, gl_renderer


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", type=Path, default=Path("/tmp/scenerender-sample-viewer"))
    parser.add_argument("--cache", type=Path, default=Path.home() / ".cache" / "scenerender" / "gltf-viewer")
    parser.add_argument("--size", default="400x200", help="image size WxH (the files' cameras are 2:1)")
    parser.add_argument("--models", nargs="*", help="model names (default: all that scenerender reads)")
    parser.add_argument("--no-antialias", action="store_true",
                        help="no MSAA on either side (the browser resolves its MSAA in 8-bit 1/2.2 values, "
                             "scenerender in linear light: their outlines differ)")
    parser.add_argument("--docs", action="store_true", help="write docs/gltf-viewer/ (pictures and JSON) and the "
                                                             "table in docs/gltf-viewer-comparison.md")
    args = parser.parse_args(argv)
    size = tuple(int(v) for v in args.size.lower().split("x"))
    chosen = chosen_models(args.models)
    names = [model.name for model in chosen]
    jobs = [(name, "shipped") for name in names] + [job for job in DIAGNOSTICS if job[0] in names]

    node_modules = install_viewer(args.cache)
    prepare_work(args.work, node_modules, chosen)
    viewer, about = viewer_renders(args.work, jobs, size, antialias=not args.no_antialias)
    about.update(gltf_viewer=json.loads((node_modules / PACKAGE / "package.json").read_text())["version"],
                 scenerender=scenerender.__version__, size=list(size), antialias=not args.no_antialias)

    mode = "no-antialias" if args.no_antialias else "antialiased"
    # the docs keep the antialiased pictures (what a user sees) and both modes' tables
    images = DOCS_IMAGES if args.docs and not args.no_antialias else args.work / "pictures"
    tables = DOCS_IMAGES if args.docs else images
    images.mkdir(parents=True, exist_ok=True)
    by_name = {model.name: model for model in chosen}
    rows = []
    for name, variant in jobs:
        row, shows, result, about["scenerender_gl"] = compare(args.work, images, by_name[name], variant,
                                                              viewer[name, variant], size,
                                                              1 if args.no_antialias else None)
        rows.append((row, shows, result))

    table = image_diff.markdown_table(rows)
    (tables / f"results-{mode}.json").write_text(image_diff.json_table(rows, about))
    if args.docs:
        write_page_table(table, about, mode)
    else:
        (tables / f"results-{mode}.md").write_text(table)
    print(f"pictures in {images}, tables in {tables}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
