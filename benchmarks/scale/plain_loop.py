"""The many-objects scene (many_objects.py) in a loop of plain moderngl draws: what any
renderer of it has to do. One vertex array for the sphere, one draw per sphere with its
offset as a uniform (each sphere is an object of its own), the ground; the sun's shadow
map drawn once (nothing moves but the camera), 3x3 PCF with hardware depth compare,
Blinn-Phong, sRGB encoded in the shader into an RGBA8 MSAA target resolved by a blit,
read back and written as PNG (zlib level 1) on a background thread.

    python benchmarks/scale/plain_loop.py --count 1000 -o /tmp/plain
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import moderngl
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "compare"))
import many_objects as M  # noqa: E402
from common import PngWriter  # noqa: E402
import scene_def as S  # noqa: E402  (look_at, perspective)
# the floor loop's shadow-map shaders and matrix upload, the same here
from run_floor import DEPTH_FRAGMENT, DEPTH_VERTEX, matrix  # noqa: E402

VERTEX = """
#version 330
uniform mat4 u_view_proj;
uniform mat4 u_light_view_proj;
uniform vec3 u_offset;
in vec3 in_position; in vec3 in_normal;
out vec3 v_position; out vec3 v_normal; out vec4 v_light;
void main() {
    vec3 p = in_position + u_offset;
    v_position = p; v_normal = in_normal;
    v_light = u_light_view_proj * vec4(p, 1.0);
    gl_Position = u_view_proj * vec4(p, 1.0);
}
"""
FRAGMENT = """
#version 330
uniform sampler2DShadow u_shadow;
uniform vec3 u_color, u_eye, u_sun_dir, u_ambient;
uniform float u_texel;
in vec3 v_position; in vec3 v_normal; in vec4 v_light;
out vec4 frag_color;
void main() {
    vec3 n = normalize(v_normal);
    vec3 v = normalize(u_eye - v_position);
    vec3 l = -u_sun_dir;
    vec3 s = v_light.xyz / v_light.w * 0.5 + 0.5;
    float lit = 0.0;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
            lit += texture(u_shadow, vec3(s.xy + vec2(i, j) * u_texel, s.z - 0.002));
    float d = max(dot(n, l), 0.0);
    float spec = d > 0.0 ? pow(max(dot(n, normalize(l + v)), 0.0), 40.0) : 0.0;
    vec3 color = u_ambient * u_color + (u_color * d + 0.3 * spec) * lit / 9.0;
    vec3 c = clamp(color, 0.0, 1.0);
    frag_color = vec4(mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c)), 1.0);
}
"""
SHADOW_SIZE = 2048


def uv_sphere(radius: float, segments: int, rings: int) -> np.ndarray:
    """Unindexed triangles, position and normal per corner: 2 * segments * (rings - 1)."""
    def point(i, j):
        theta, phi = math.pi * j / rings, 2.0 * math.pi * i / segments
        n = (math.sin(theta) * math.sin(phi), math.cos(theta), math.sin(theta) * math.cos(phi))
        return [radius * n[0], radius * n[1], radius * n[2], *n]
    corners = []
    for j in range(rings):
        for i in range(segments):
            a, b, c, d = point(i, j), point(i + 1, j), point(i, j + 1), point(i + 1, j + 1)
            if j > 0:
                corners += [a, c, b]
            if j < rings - 1:
                corners += [b, c, d]
    return np.array(corners, dtype="f4")


def ground(half: float) -> np.ndarray:
    quad = [(-half, half), (half, half), (half, -half), (-half, half), (half, -half), (-half, -half)]
    return np.array([[x, 0.0, z, 0.0, 1.0, 0.0] for x, z in quad], dtype="f4")


def sun_view_proj(extent: float) -> np.ndarray:
    direction = np.asarray(M.SUN_DIRECTION) / np.linalg.norm(M.SUN_DIRECTION)
    view = S.look_at(-direction * extent * 2.0, (0.0, 0.0, 0.0))
    near, far = 0.1, extent * 4.0
    ortho = np.diag([1.0 / extent, 1.0 / extent, -2.0 / (far - near), 1.0])
    ortho[2, 3] = -(far + near) / (far - near)
    return ortho @ view


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("-o", "--out", type=Path)
    args = parser.parse_args()
    ctx = moderngl.create_context(standalone=True, backend="egl", require=330)
    size = M.SIZE
    program = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
    depth_program = ctx.program(vertex_shader=DEPTH_VERTEX, fragment_shader=DEPTH_FRAGMENT)
    sphere = ctx.buffer(uv_sphere(M.SPHERE["radius"], M.SPHERE["segments"], M.SPHERE["rings"]).tobytes())
    side = math.ceil(math.sqrt(args.count)) * 0.8 + 2.0
    floor = ctx.buffer(ground(side).tobytes())
    sphere_vertices = 2 * M.SPHERE["segments"] * (M.SPHERE["rings"] - 1) * 3
    shaded = ctx.vertex_array(program, [(sphere, "3f 3f", "in_position", "in_normal")])
    shaded_ground = ctx.vertex_array(program, [(floor, "3f 3f", "in_position", "in_normal")])
    caster = ctx.vertex_array(depth_program, [(sphere, "3f 12x", "in_position")])
    positions = [tuple(float(v) for v in p) for p in M.sphere_positions(args.count)]
    light = sun_view_proj(side * 1.5)
    shadow_map = ctx.depth_texture((SHADOW_SIZE, SHADOW_SIZE))
    shadow_map.compare_func = "<="
    shadow_map.filter = (moderngl.LINEAR, moderngl.LINEAR)
    shadow_fbo = ctx.framebuffer(depth_attachment=shadow_map)
    msaa = ctx.framebuffer([ctx.renderbuffer(size, 4, samples=M.SAMPLES)],
                           ctx.depth_renderbuffer(size, samples=M.SAMPLES))
    resolved = ctx.framebuffer([ctx.renderbuffer(size, 4)])
    program["u_shadow"] = 0
    program["u_light_view_proj"].write(matrix(light))
    depth_program["u_light_view_proj"].write(matrix(light))
    program["u_texel"] = 1.0 / SHADOW_SIZE
    program["u_sun_dir"] = tuple(float(v) for v in np.asarray(M.SUN_DIRECTION) / np.linalg.norm(M.SUN_DIRECTION))
    program["u_ambient"] = (0.2, 0.22, 0.26)
    ctx.enable(moderngl.DEPTH_TEST)
    shadow_fbo.use()
    shadow_fbo.clear(depth=1.0)
    for p in positions:  # drawn once: nothing moves but the camera
        depth_program["u_offset"] = p
        caster.render(vertices=sphere_vertices)
    projection = S.perspective(50.0, size[0] / size[1], 0.1, side * 6.0)
    keys = M.orbit(args.count)
    writer = PngWriter(args.out) if args.out else None
    for frame in range(M.FRAMES):
        eye = np.asarray(keys[frame][1])
        msaa.use()
        msaa.clear(0.5, 0.6, 0.75, 1.0)
        program["u_view_proj"].write(matrix(projection @ S.look_at(eye, (0.0, 0.0, 0.0))))
        program["u_eye"] = tuple(float(v) for v in eye)
        shadow_map.use(0)
        program["u_offset"] = (0.0, 0.0, 0.0)
        program["u_color"] = (0.45, 0.45, 0.4)
        shaded_ground.render(vertices=6)
        program["u_color"] = (0.8, 0.55, 0.35)
        for p in positions:
            program["u_offset"] = p
            shaded.render(vertices=sphere_vertices)
        ctx.copy_framebuffer(resolved, msaa)
        pixels = np.frombuffer(resolved.read(components=3, alignment=1), dtype=np.uint8)
        pixels = pixels.reshape(size[1], size[0], 3)[::-1].copy()
        if writer is not None:
            writer.write(frame, pixels)
    if writer is not None:
        writer.close()


if __name__ == "__main__":
    main()
