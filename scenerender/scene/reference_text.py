"""The prose of ``docs/scene-format.md``: what the tables of keys cannot say.

Sections follow the order of a scene file. ``reference.py`` puts each section's tables of
keys (generated from the schema) between its ``intro`` and ``outro``, and fills in the
markers ``@animatable_keys@``, ``@limits_table@`` and ``@regenerate@``. Every ```yaml block
here is a complete scene, and the reference test validates each one.
"""
from __future__ import annotations

from typing import NamedTuple


class Section(NamedTuple):
    key: str | None  # the top-level key whose tables follow the intro ("" the top level; None: prose only)
    heading: str
    intro: str
    outro: str = ""


HEADER = """
# The scene file format

<!-- Generated from the schema models by `@regenerate@`.
     Edit scenerender/scene/reference_keys.py (what keys mean) or reference_text.py (this
     prose), never this file: tests/test_format_reference.py fails when it is stale. -->

A scene is one YAML file; everything a render depends on is in it, and `--set key=value`
on the command line can change any key. This page lists every key with its type, range or
choices, default, whether it can be animated, and an example. The tables are generated
from the models scenerender validates scenes with, so they cannot disagree with it.
Where this page leaves room (lighting formula, shadow bias units, what each render mode
shows, transparency order), [scene-notes.md](scene-notes.md) records what scenerender
decides and why.

For editors, `scenerender schema` prints the same format as JSON Schema; the repository
carries it as `scene.schema.json` ([usage.md](usage.md#editor-completion) says how to get completion and
checking in VS Code).

Contents: [conventions](#conventions) · [top level](#top-level) ·
[animatable values](#animatable-values) · [files](#files-and-where-they-may-come-from) ·
[render](#render) · [output](#output) · [camera](#camera) · [lights](#lights) ·
[materials](#materials) · [objects](#objects) · [limits](#limits)
"""

CONVENTIONS = """
- Right-handed coordinates, +Y up; the camera looks down -Z in view space.
- Angles are degrees, times are seconds, distances are world units.
- Colours are linear RGB (or RGBA) in [0, 1]: 3 or 4 numbers; a missing alpha is 1.
- Files named in a scene are relative to the scene file's folder (see [files](#files-and-where-they-may-come-from)).
- Unknown keys are errors, with a "did you mean" suggestion; nothing is silently ignored.
- Values follow YAML 1.2: `1e6` and `3e-05` are numbers; `yes` and `on` are text, so a flag
  is written `true` or `false`. A whole number is accepted wherever a number is (`[1, 1, 1]`
  is white); `.inf` and `.nan` are errors wherever a finite value is needed.
- A key given twice in one mapping is an error; merge keys (`<<: *defaults`) work.
- An empty file (nothing, or only comments) is an error; `objects: []` is a valid scene
  that renders the background.
- Every problem is reported as one line, `file:line:column: key.path: message`, and the
  command exits with status 2. `scenerender validate scene.yaml` checks a scene without
  rendering it.

A complete scene; everything left out has a default:

```yaml
objects:
  - mesh: models/duck.obj
```

That is 640x480, one frame at t = 0, Blinn-Phong shading, 4x MSAA, sRGB output, a PNG; the
camera frames the scene's bounds, and a headlight plus a weak ambient light it.
"""

TOP_LEVEL = """
A scene is a mapping with at most these keys, each optional:
"""

ANIMATABLE = """
A key marked *animatable* in the tables takes either a constant or a **track**: keyframes
over time, evaluated in double precision at each frame's time. These keys animate:
@animatable_keys@.

```yaml
camera:
  position:
    keys:                       # [time, value] pairs, in any order; sorted on load
      - [0.0, [0, 2, 8]]
      - [2.5, [4, 2, 4]]
      - {t: 5.0, value: [0, 2, -8], interpolation: step}
    interpolation: cosine       # step | linear (default) | cosine | catmull_rom
    loop: false                 # true: time wraps modulo the last key's time
  target: [0, 0, 0]
```

Between keys k1 at t1 and k2 at t2, with u = (t - t1) / (t2 - t1):

| interpolation | value at t |
|---|---|
| `linear` | k1 (1 - u) + k2 u |
| `cosine` | the same with u replaced by (1 - cos(pi u)) / 2: eases in and out |
| `step` | k1 until t2 |
| `catmull_rom` | a smooth curve through all keys (camera paths); uneven key spacing gives no kinks |

- A key written as a mapping (`{t, value, interpolation}`) sets the interpolation of the
  segment that starts at it.
- Before the first key the first value holds, after the last key the last value, unless
  `loop: true`.
- Every key of a track has the same shape (all numbers, all lists of 3, ...). Two keys at
  the same time are an error; a track of one key is a constant.
- Flags (`enabled`, `visible`) always step.
- Frame i is at time i / `output.fps`.
"""

FILES = """
Meshes, textures and skybox faces are named by paths relative to the scene file's folder
(an MTL file's textures relative to the MTL file). Every file a scene reads, including the
MTL files of OBJ meshes and the textures they name, must resolve inside an allowed folder
once symbolic links are followed, whether it was written as a relative or an absolute path:

- the scene file's own folder (and everything below it);
- a folder allowed on the command line with `--asset-root DIR` (repeatable);
- a folder listed in the `SCENERENDER_ASSET_ROOTS` environment variable (separated like
  `PATH`).

A path outside them is an error that says how to allow it, whether or not a file is there
(where a path leads is decided before anything is looked up); so is anything that is not a
regular file (a folder, a device, a pipe). A file named in the scene itself that is
missing is always an error. A texture an MTL file names is also looked for by its file
name beside the MTL file (exporters write absolute paths from another machine), and with
the letter case ignored; one that cannot be found or read there either is a warning naming
the MTL file and line, and the surface shows a magenta and black checker; `--strict` turns
every warning into an error.
"""

RENDER = """
How each frame looks.

```yaml
render:
  size: [1280, 720]
  samples: 4
  shading: blinn_phong
  background: [0.4, 0.78, 1.0]
  skybox: textures/sky          # or {posx: ..., negx: ..., posy: ..., negy: ..., posz: ..., negz: ...}
  fog: {color: [0.5, 0.5, 0.5], density: 0.03, mode: exp2}
  ambient_occlusion: {radius: 0.5, samples: 16, strength: 1.0}
  shadows: {size: 2048, pcf: 3, bias: 0.002, slope_bias: 0.02}
  exposure: 0                   # stops; animatable
  tone_map: none                # none | aces | agx
  output_transform: srgb
```

Linear light becomes the stored image in three steps: times 2^`exposure`, through the
`tone_map` curve, then encoded by `output_transform`. EXR output holds the linear light
before all three.
"""

RENDER_MODES = """
`render.mode` picks what a pixel shows. `shaded`, `wireframe` and `points` show light and
are written as light is: through `exposure`, `tone_map` and `output_transform` (sRGB by
default). The data modes, `depth`, `normals`, `ambient_occlusion`, `shadow` and
`light_depth`, show values and are written as they are, without any of the three:

| mode | a pixel shows |
|---|---|
| `shaded` | the lit scene |
| `depth` | linear view depth, black at `near`, white at `far` and where nothing is |
| `normals` | the world-space normal mapped to colour (n * 0.5 + 0.5) |
| `wireframe`, `points` | the lit scene's triangle edges, or its vertices (transparent and outlined surfaces too) |
| `ambient_occlusion` | the occlusion term, white open, black occluded |
| `shadow` | the first shadowed light's visibility, white lit, black shadowed |
| `light_depth` | the first shadowed light's depth map, seen from the light |

`shadow` and `light_depth` need a light with `shadows`.
"""

OUTPUT = """
Which frames are made, and what they are written as.

```yaml
output:
  fps: 30
  duration: 4.0                 # or frames: 120; neither: one frame at t = 0
  format: png                   # png | jpg | tga | exr | mp4 | gif
  name: "frame_{frame:04d}"
  quality: 90
```
"""

OUTPUT_RUN = """
**Where frames go: `-o`.** `scenerender render scene.yaml -o PATH`:

- `PATH` ends in an image suffix (`.png`, `.jpg`, `.jpeg`, `.tga`, `.exr`): that one file
  is written, so the render must be one frame (a one-frame scene, or `--frames N`).
- `PATH` ends in a video suffix (`.mp4`, `.gif`): that video is written.
- Otherwise `PATH` is a folder: an image sequence goes in it as `frame_0000.png`,
  `frame_0001.png`, ..., a video as `<scene name>.mp4`. The default is `out/`.

A suffix also chooses the format; an `output.format` or `--format` that says otherwise is
an error, as is an image suffix for a render of several frames.

**File names: `output.name`.** A template for the names of an image sequence, without the
suffix. Its only field is `{frame}`, optionally with an integer format spec (`{frame:05d}`,
`{frame:>6}`); anything else in braces is an error, and so is a name with a `/` or `\\`, so
no frame can be written outside `-o`. With more than one frame the template must contain
`{frame}`. Write `{{` and `}}` for literal braces.

**Which frames: `--frames`.** `--frames A:B` renders frames A to B-1, like a Python slice;
`A:B:STEP` takes a step (`0:120:30` is frames 0, 30, 60 and 90), and `N` alone is one frame.

**Resume.** Each output records what made it (the scene after `--set`, the bytes of every
file it read, the scenerender version) beside the frames. A re-run keeps a frame only when
it was made from the same inputs and the file is the one that run wrote; anything else is
rendered again, and frames left by an earlier, different run are removed, so an output
never mixes two versions of a scene. An interrupted run therefore resumes where it stopped;
`--overwrite` renders every frame again. Each file is written under a temporary name and
renamed when complete: there are never half-written frames.

**Formats.** `exr` holds 32-bit float linear RGB from before the output transform. MP4 and
GIF frames stream to ffmpeg as they are rendered; an MP4 of odd width or height gets its
last column or row repeated (H.264 needs even sizes), never rescaled.
"""

CAMERA = """
The view. Aim it with `target`, or with `yaw` and `pitch` (first-person angles), not both.
Looking straight along `up` gives a well-defined image, never NaN.

```yaml
camera:
  position: [0, 2, 8]
  target: [0, 0, 0]
  fov: 60
  near: auto
  far: auto
```
"""

LIGHTS = """
Any number of lights, of four types chosen by `type`; each directional, point or spot light
may cast shadows. The keys `name`, `color`, `intensity` and `enabled` apply to every type.

```yaml
lights:
  - {name: sun, type: directional, direction: [-1, -1, -0.5], shadows: true}
  - type: point
    position: [2, 3, 1]
    attenuation: [1.0, 0.09, 0.032]
    shadows: {size: 1024}
  - {type: spot, position: [0, 5, 0], direction: [0, -1, 0], inner_angle: 12.5, outer_angle: 17.5}
  - {type: spot, attach: camera, intensity: 2}
  - {type: ambient, color: [0.25, 0.25, 0.25]}
```
"""

MATERIALS = """
Named materials, referred to by objects (`material: name`), or written inline on an object.
A key left out keeps the value of the mesh's MTL material (for `material_overrides`) or the
default given in its row.

```yaml
materials:
  ground:
    diffuse: [0.6, 0.6, 0.6]
    specular: [0.1, 0.1, 0.1]
    shininess: 8
    diffuse_map: textures/ground.png
objects:
  - {mesh: {primitive: plane, size: 20, uv_repeat: 8}, material: ground}
```
"""

MATERIALS_MTL = """
An OBJ mesh keeps the materials of its MTL files unless the object sets `material` (which
replaces all of them) or `material_overrides` (by MTL material name). MTL files are read
for `Ka Kd Ks Ke Ns d Tr illum map_Ka map_Kd map_Ks map_Bump bump norm map_d`, texture
options in map lines included; other statements are ignored. Colour maps are decoded as
sRGB; normal and opacity maps are data.
"""

OBJECTS = """
What is drawn: a mesh file or an inline primitive, with a transform, a material and
optionally many instances.

```yaml
objects:
  - name: duck
    mesh: models/duck.obj
    normalize: true
    position: [0, 0.5, 0]
    rotation: [0, 45, 0]
    scale: 2
    outline: {color: [1, 0.6, 0.1], width: 0.02}
  - mesh: {primitive: plane, size: 20}
  - mesh: {primitive: sphere, radius: 0.3}
    instances:
      random: {count: 50, seed: 7, position: {min: [-5, 0.3, -5], max: [5, 0.3, 5]}}
```

The model matrix is T * Rz * Ry * Rx * S (scale first, then rotation X, Y, Z, then
translation); normals use its inverse transpose, so non-uniform scale shades correctly. An
instance's matrix applies inside its object's: world = M_object * M_instance. OBJ faces
with more than three vertices are triangulated (convex ones as fans, concave ones by ear
clipping); negative (relative) indices work; a texture coordinate or normal index that no
`vt`/`vn` defines is dropped with a warning (normals are then computed); a backslash
escapes a space in `mtllib` and texture names; curves and surfaces are skipped with a warning.

Frames are drawn in 32-bit floats, which reach about 3.4e38. A number in a mesh or MTL file
beyond that is an error at its line; so is a placement that, at any time of the animation,
could take an object's matrices (whose normal matrix multiplies two scale factors) or its
vertices in world space beyond it: `scale: 1e30` is refused, at the object's `scale`.
"""

PRIMITIVES = """
Primitives are centred at the origin with their axis along +Y. A plane lies in the XZ
plane facing +Y with UVs over [0, 1] times `uv_repeat`; a box spans -size/2 to size/2;
cylinder, prism and cone span y from -height/2 to height/2, the cone's apex at the top.
"""

LIMITS = """
Sizes a scene may ask for are bounded, so that a mistyped number cannot take hours or all
memory; a scene over a limit is an error before any work starts, and its message names
the option that raises the limit: `--limit NAME=N`.

@limits_table@
"""

SECTIONS: tuple[Section, ...] = (
    Section(None, "Conventions", CONVENTIONS),
    Section("", "Top level", TOP_LEVEL),
    Section(None, "Animatable values", ANIMATABLE),
    Section(None, "Files, and where they may come from", FILES),
    Section("render", "render", RENDER, RENDER_MODES),
    Section("output", "output", OUTPUT, OUTPUT_RUN),
    Section("camera", "camera", CAMERA),
    Section("lights", "lights", LIGHTS),
    Section("materials", "materials", MATERIALS, MATERIALS_MTL),
    Section("objects", "objects", OBJECTS, PRIMITIVES),
    Section(None, "Limits", LIMITS),
)
