"""What each key of the scene format means, with an example: the hand-written half of
``docs/scene-format.md`` (the generated half, types, ranges, defaults, tracks, comes from
the schema models; see ``reference.py`` for key-path notation).

An example is the YAML value written after ``key:``. Each one must validate on its own in a
scene that holds only it (plus a mesh for an object and a tag for a union member); file
examples name ``models/duck.obj``, ``textures/ground.png`` and the folder ``textures/sky``,
which the reference test creates. ``tests/test_format_reference.py`` checks every entry.
"""
from __future__ import annotations

from typing import NamedTuple


class Key(NamedTuple):
    meaning: str
    example: str


COLOUR_TRACK = "{keys: [[0, [1, 0.5, 0.2]], [4, [0.1, 0.1, 0.3]]]}"

KEYS: dict[str, Key] = {
    # -- top level ------------------------------------------------------------------------
    "scenerender": Key("Format version. Optional; a later version of the format will migrate files that carry it.", "1"),
    "render": Key("How frames look: size, anti-aliasing, shading, background, fog, shadows.", "{size: [1280, 720]}"),
    "output": Key("Which frames are rendered and what they are written as.", "{duration: 4, format: mp4}"),
    "camera": Key("Where the view is from. Not set: the scene's bounds at t = 0 are framed from the front and a little above, fov 60.",
                  "{position: [0, 2, 8], target: [0, 0, 0]}"),
    "lights": Key("Any number of lights, each chosen by `type`. Not set: a white directional headlight that follows the camera, and ambient 0.12.",
                  "[{type: point, position: [2, 3, 1]}]"),
    "materials": Key("Named materials that objects refer to by name.", "{red: {diffuse: [0.8, 0.1, 0.1]}}"),
    "objects": Key("What is drawn. `[]` is a valid scene: the background alone.", "[{mesh: models/duck.obj}]"),
    # -- render ---------------------------------------------------------------------------
    "render.size": Key("Image width and height in pixels (`--size WxH`).", "[1280, 720]"),
    "render.samples": Key("MSAA samples per pixel: 1 (anti-aliasing off), 2, 4, 8, 16, 32 or 64, the counts GL offers (any other is an error). More than the device offers is lowered to its maximum, with a warning.", "8"),
    "render.shading": Key("Specular model: `phong` (R.V), `blinn_phong` (N.H), or `unlit` (surface colour only).", "phong"),
    "render.mode": Key("What each pixel shows: the shaded image, or one of the diagnostic views in the table of modes below.", "depth"),
    "render.background": Key("Colour where nothing is drawn; hidden behind a skybox.", "[0.4, 0.78, 1.0]"),
    "render.skybox": Key("A folder holding six images named `posx negx posy negy posz negz` (any image suffix), or a mapping naming each face.",
                         "textures/sky"),
    "render.fog": Key("Distance fog; no fog when not set.", "{density: 0.05}"),
    "render.ambient_occlusion": Key("Screen-space ambient occlusion; off when not set.", "{radius: 0.8}"),
    "render.shadows": Key("Shadow-map settings for every shadowed light; a light may override any of them.", "{size: 4096, pcf: 5}"),
    "render.exposure": Key("Brightness in stops, applied to linear light before the tone curve: values are multiplied by 2^exposure (+1 doubles them, -1 halves them). At 0 the output shader leaves it out. Not applied to EXR output.", "0.5"),
    "render.tone_map": Key("The tone curve that brings linear light above 1 into the image, after `exposure` and before `output_transform`: `none` clips at 1 (the image is as without the key); `aces` is Stephen Hill's fit of the ACES RRT + sRGB ODT; `agx` is the minimal AgX fit (Missing Deadlines). Not applied to EXR output.", "agx"),
    "render.output_transform": Key("How linear light becomes stored values: the exact sRGB curve, a power curve (`gamma`), or none.", "gamma"),
    "render.gamma": Key("The exponent of `output_transform: gamma` (values are raised to 1 / gamma).", "2.4"),
    "render.wireframe_overlay": Key("Draw the triangle edges over the shaded image.", "true"),
    "render.line_width": Key("Line width in pixels for `wireframe` mode and the overlay.", "2"),
    "render.point_size": Key("Point size in pixels for `points` mode.", "5"),
    "render.skybox.posx": Key("The face seen looking along +X.", "textures/sky/posx.png"),
    "render.skybox.negx": Key("The face seen looking along -X.", "textures/sky/negx.png"),
    "render.skybox.posy": Key("The face seen looking up (+Y).", "textures/sky/posy.png"),
    "render.skybox.negy": Key("The face seen looking down (-Y).", "textures/sky/negy.png"),
    "render.skybox.posz": Key("The face seen looking along +Z.", "textures/sky/posz.png"),
    "render.skybox.negz": Key("The face seen looking along -Z.", "textures/sky/negz.png"),
    "render.fog.color": Key("The colour distant surfaces fade to (mixed in linear light).", "[0.7, 0.75, 0.8]"),
    "render.fog.density": Key("rho in `exp(-d rho)` (`exp`) or `exp(-(d rho)^2)` (`exp2`), d the distance from the eye.", "0.08"),
    "render.fog.mode": Key("Falloff with distance: exponential, squared exponential, or linear from `start` to `end`.", "linear"),
    "render.fog.start": Key("Distance where linear fog begins (must be below `end`).", "10"),
    "render.fog.end": Key("Distance where linear fog is complete.", "60"),
    "render.ambient_occlusion.radius": Key("World-space radius of the occlusion search around each point.", "1.0"),
    "render.ambient_occlusion.samples": Key("Samples per pixel; more is smoother and slower.", "32"),
    "render.ambient_occlusion.strength": Key("How strongly occlusion darkens ambient light (0 = none).", "1.5"),
    "render.shadows.size": Key("Width and height of each shadow map in texels (a point light has six). Spot lights "
                               "default to 1024 unless this is set: their map covers only the cone. A directional "
                               "light's map covers the shadow casters the camera can see; where only the camera "
                               "moves, it may instead cover them all, drawn once at up to twice this size, when "
                               "its texels then come out no larger in any frame.", "4096"),
    "render.shadows.pcf": Key("Filter width in texels: N x N percentage-closer filtering; 1 gives hard, aliased edges. "
                              "Spot lights default to 5 unless this is set.", "5"),
    "render.shadows.bias": Key("Depth bias, as a fraction of the light view's depth range; removes shadow acne.", "0.005"),
    "render.shadows.slope_bias": Key("Extra bias where light grazes the surface: the bias used is max(bias, slope_bias (1 - N.L)).", "0.05"),
    # -- output ---------------------------------------------------------------------------
    "output.fps": Key("Frames per second: frame i is at time i / fps.", "24"),
    "output.duration": Key("Length of the animation in seconds; frames = round(duration x fps). Not set, with `frames` not set: one frame at t = 0.", "4.0"),
    "output.frames": Key("Number of frames, instead of `duration`; when both are given they must agree.", "120"),
    "output.format": Key("Image sequence (`png`, `jpg`, `tga`, `exr`) or video (`mp4`, `gif`) (`--format`).", "mp4"),
    "output.name": Key("File-name template of an image sequence; `{frame}` is the only field, with an optional format spec. Not set: `frame_{frame:04d}` (more digits past frame 9999).",
                       '"shot_{frame:05d}"'),
    "output.quality": Key("JPG quality, and MP4 quality (x264 CRF = 51 - 0.39 x quality).", "95"),
    # -- camera ---------------------------------------------------------------------------
    "camera.position": Key("The eye. Not set: placed to frame the scene.", "[0, 2, 8]"),
    "camera.target": Key("The point looked at; a fixed target must differ from a fixed `position`. Give `target`, or `yaw`/`pitch`, not both.", "[0, 0.5, 0]"),
    "camera.yaw": Key("Heading in degrees, first-person style: -90 (the default when only `pitch` is given) looks along -Z. Needs `position`.", "-90"),
    "camera.pitch": Key("Elevation in degrees, clamped to [-89, 89]; 0 is level. Needs `position`.", "-15"),
    "camera.up": Key("The world's up direction for the view; need not be unit length.", "[0, 0, 1]"),
    "camera.fov": Key("Vertical field of view in degrees (perspective).", "45"),
    "camera.projection": Key("`orthographic` shows a view `height` units tall with no perspective.", "orthographic"),
    "camera.height": Key("Height of an orthographic view in world units. Not set: the bounds' diagonal at t = 0.", "10"),
    "camera.near": Key("Near clipping distance; `auto` fits the scene's bounds every frame.", "0.1"),
    "camera.far": Key("Far clipping distance; `auto` fits the scene's bounds every frame.", "500"),
    # -- lights (entries with [] cover every light type) -----------------------------------
    "lights[].type": Key("The kind of light; it decides which other keys apply.", "directional"),
    "lights[].name": Key("A label, used in messages and by `scenerender graph`. Not set: the type and index, e.g. `spot2`.", "sun"),
    "lights[].color": Key("Light colour, multiplied by `intensity`.", "[1, 0.9, 0.8]"),
    "lights[].intensity": Key("Brightness multiplier.", "{keys: [[0, 0], [2, 1.5]], interpolation: cosine}"),
    "lights[].enabled": Key("Switches the light on and off over time (a disabled light gives no light).", "{keys: [[0, false], [3, true]]}"),
    "lights[].shadows": Key("Cast shadows (`true`), or a mapping overriding `render.shadows` for this light.", "{size: 1024}"),
    "lights[].attenuation": Key("Falloff with distance d: light x 1 / (c + l d + q d^2), as [c, l, q]; `[1, 0, 0]` is no falloff.", "[1.0, 0.09, 0.032]"),
    "lights[directional].direction": Key("The way the light travels (from the light towards the scene); need not be unit length.", "[-1, -1, -0.5]"),
    "lights[point].position": Key("Where the light is; shadows use a cube map.", "[2, 3, 1]"),
    "lights[spot].position": Key("Where the light is; required unless `attach: camera` (then it is in camera space, default the eye).", "[0, 5, 0]"),
    "lights[spot].direction": Key("The way the cone points. Not set: along -Z, which with `attach: camera` is where the camera looks.", "[0, -1, 0]"),
    "lights[spot].inner_angle": Key("Half-angle in degrees of the fully lit cone; not above `outer_angle`.", "10"),
    "lights[spot].outer_angle": Key("Half-angle in degrees beyond which there is no light; smooth between inner and outer; equal angles give a hard edge.", "25"),
    "lights[spot].attach": Key("`camera`: position and direction follow the camera, like a torch.", "camera"),
    # -- materials ------------------------------------------------------------------------
    "materials.<name>.ambient": Key("Ka: how much of the ambient light the surface colour reflects. Not set: the MTL value, else `[1, 1, 1]`.", "[0.5, 0.5, 0.5]"),
    "materials.<name>.diffuse": Key("Kd: the surface colour (alpha included). Not set: the MTL value, else `[0.8, 0.8, 0.8]`.", "[0.6, 0.4, 0.2]"),
    "materials.<name>.specular": Key("Ks: colour of the highlight. Not set: the MTL value, else `[0.25, 0.25, 0.25]`.", "[0.4, 0.4, 0.4]"),
    "materials.<name>.shininess": Key("Ns: highlight exponent; 0 gives a flat lobe. Not set: the MTL value, else 32.", "64"),
    "materials.<name>.emissive": Key("Ke: light the surface gives off by itself (it lights nothing else). Not set: the MTL value, else black.", "[0.2, 0.05, 0]"),
    "materials.<name>.opacity": Key("d: below 1 the surface is drawn in the transparent pass, sorted far to near. Not set: the MTL value, else 1.", "0.4"),
    "materials.<name>.diffuse_map": Key("map_Kd: texture multiplying `diffuse`; decoded as sRGB.", "textures/ground.png"),
    "materials.<name>.specular_map": Key("map_Ks: texture multiplying `specular`; decoded as sRGB.", "textures/ground.png"),
    "materials.<name>.normal_map": Key("Tangent-space normal map, OpenGL convention (green = +V); data, not colour.", "textures/ground.png"),
    "materials.<name>.opacity_map": Key("map_d: texture multiplying `opacity`; data, not colour.", "textures/ground.png"),
    "materials.<name>.wrap": Key("Texture addressing outside [0, 1]. Not set: `repeat`.", "clamp"),
    "materials.<name>.filter": Key("Texture filtering: `linear` is trilinear with mipmaps. Not set: `linear`.", "nearest"),
    "materials.<name>.unlit": Key("Draw the surface colour plus emissive, without lighting (MTL `illum 0`). Not set: the MTL value, else false.", "true"),
    # -- objects --------------------------------------------------------------------------
    "objects[].name": Key("A label, used in messages.", "crate"),
    "objects[].mesh": Key("A mesh file (OBJ with its MTL; PLY, STL, GLB/GLTF, OFF through trimesh), or an inline primitive chosen by `primitive`.",
                          "models/duck.obj"),
    "objects[].normalize": Key("Centre the mesh's bounds at the origin and scale its diagonal to 1.", "true"),
    "objects[].normals": Key("`auto` uses the file's normals, else smooth ones; `smooth` and `flat` recompute them.", "flat"),
    "objects[].position": Key("Translation.", "{keys: [[0, [0, 0, 0]], [4, [2, 0, 0]]]}"),
    "objects[].rotation": Key("Euler angles in degrees, applied X, then Y, then Z.", "[0, 45, 0]"),
    "objects[].scale": Key("Uniform, or per axis (non-uniform scale keeps normals right).", "[1, 2, 1]"),
    "objects[].material": Key("A name from `materials`, or an inline material. Replaces every material of the mesh file.", "{diffuse: [0.8, 0.1, 0.1]}"),
    "objects[].material_overrides": Key("Changes to the file's own materials, by MTL material name; keys left out keep the MTL value.",
                                        "{Wood: {diffuse: [0.5, 0.3, 0.1]}}"),
    "objects[].visible": Key("Shows and hides the object over time.", "{keys: [[0, true], [2, false]]}"),
    "objects[].cast_shadows": Key("Whether the object is drawn into shadow maps.", "false"),
    "objects[].outline": Key("A silhouette outline around the object (a selection look).", "{color: [1, 1, 1]}"),
    "objects[].instances": Key("Draw the mesh many times in one draw call: a list of transforms, or `random:` placements. Each instance's transform applies inside the object's.",
                               "[{position: [1, 0, 2]}, {position: [-3, 0, 1], scale: 1.2}]"),
    "objects[].mesh[].primitive": Key("The kind of inline mesh; centred at the origin, axis along +Y.", "box"),
    "objects[].mesh[plane].size": Key("Extent in X and Z (one number for a square); the plane faces +Y.", "[20, 10]"),
    "objects[].mesh[plane].uv_repeat": Key("How many times UVs [0, 1] repeat across the plane, in U and V.", "8"),
    "objects[].mesh[box].size": Key("Edge lengths in X, Y and Z; the box spans -size/2 to size/2.", "[2, 1, 1]"),
    "objects[].mesh[].radius": Key("Radius.", "1.5"),
    "objects[].mesh[].height": Key("Height along Y, centred at the origin (a cone's apex at +height/2).", "2"),
    "objects[].mesh[].segments": Key("Divisions around the axis; cylinder and cone sides are smooth-shaded.", "64"),
    "objects[].mesh[sphere].rings": Key("Divisions from pole to pole; UVs are longitude and latitude.", "24"),
    "objects[].mesh[prism].sides": Key("Number of flat sides.", "8"),
    "objects[].outline.color": Key("Outline colour.", "[1, 1, 1]"),
    "objects[].outline.width": Key("Outline thickness in world units (the mesh inflated along its smooth normals).", "0.05"),
    "objects[].instances[].position": Key("Translation of this instance, inside the object's transform.", "[1, 0, 2]"),
    "objects[].instances[].rotation": Key("Euler degrees of this instance, X then Y then Z.", "[0, 90, 0]"),
    "objects[].instances[].scale": Key("Scale of this instance.", "0.8"),
    "objects[].instances.random": Key("Random placements; the same seed gives the same scene on every machine.", "{count: 50, seed: 7}"),
    "objects[].instances.random.count": Key("Number of instances.", "50"),
    "objects[].instances.random.seed": Key("Seed of the random generator.", "7"),
    "objects[].instances.random.position": Key("Positions drawn uniformly per axis between `min` and `max`.", "{min: [-15, 2, -15], max: [15, 12, 15]}"),
    "objects[].instances.random.rotation": Key("Euler degrees drawn uniformly per axis between `min` and `max`.", "{min: [0, 0, 0], max: [0, 360, 0]}"),
    "objects[].instances.random.scale": Key("A uniform scale drawn between `min` and `max`.", "{min: 0.8, max: 1.2}"),
    "objects[].instances.random.position.min": Key("Lower corner (per axis, not above `max`).", "[-15, 2, -15]"),
    "objects[].instances.random.position.max": Key("Upper corner.", "[15, 12, 15]"),
    "objects[].instances.random.scale.min": Key("Smallest scale (not above `max`).", "0.8"),
    "objects[].instances.random.scale.max": Key("Largest scale.", "1.2"),
}
