"""The floor: the comparison scene in a minimal hand-written moderngl loop.

What any renderer of this scene has to do and nothing more: a shadow pass every frame
(2048px depth texture, orthographic), Blinn-Phong with one directional light (3x3 PCF,
nine hardware depth-compare taps) and one point light, the texture on the knot, sRGB
encoded in the shader into an RGBA8 MSAA target, resolved by a framebuffer blit, read
back and PNG-encoded (zlib level 1) on a background thread.
"""
from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from common import parse_args, run_frames  # noqa: E402

import numpy as np  # noqa: E402
import scene_def as S  # noqa: E402

VERTEX = """
#version 330
uniform mat4 u_view_proj;
uniform mat4 u_light_view_proj;
uniform vec3 u_offset;
in vec3 in_position; in vec3 in_normal; in vec2 in_uv;
out vec3 v_position; out vec3 v_normal; out vec2 v_uv; out vec4 v_light;
void main() {
    vec3 p = in_position + u_offset;
    v_position = p; v_normal = in_normal; v_uv = in_uv;
    v_light = u_light_view_proj * vec4(p, 1.0);
    gl_Position = u_view_proj * vec4(p, 1.0);
}
"""
FRAGMENT = """
#version 330
uniform sampler2D u_texture;
uniform sampler2DShadow u_shadow;
uniform bool u_textured;
uniform vec3 u_color, u_eye, u_sun_dir, u_sun_color, u_point_pos, u_point_color, u_ambient;
uniform float u_texel;
in vec3 v_position; in vec3 v_normal; in vec2 v_uv; in vec4 v_light;
out vec4 frag_color;
vec3 blinn(vec3 n, vec3 l, vec3 v, vec3 base) {
    float d = max(dot(n, l), 0.0);
    float s = d > 0.0 ? pow(max(dot(n, normalize(l + v)), 0.0), 40.0) : 0.0;
    return base * d + 0.3 * s;
}
void main() {
    vec3 base = u_textured ? pow(texture(u_texture, v_uv).rgb, vec3(2.2)) : u_color;
    vec3 n = normalize(v_normal);
    vec3 v = normalize(u_eye - v_position);
    vec3 l = -u_sun_dir;
    vec3 s = v_light.xyz / v_light.w * 0.5 + 0.5;
    float lit = 0.0;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
            lit += texture(u_shadow, vec3(s.xy + vec2(i, j) * u_texel, s.z - 0.002));
    vec3 color = u_ambient * base + u_sun_color * blinn(n, l, v, base) * lit / 9.0;
    vec3 to_point = u_point_pos - v_position;
    float d = length(to_point);
    color += u_point_color * blinn(n, to_point / d, v, base) / (1.0 + 0.2 * d + 0.1 * d * d);
    vec3 c = clamp(color, 0.0, 1.0);
    frag_color = vec4(mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c)), 1.0);
}
"""
DEPTH_VERTEX = """
#version 330
uniform mat4 u_light_view_proj;
uniform vec3 u_offset;
in vec3 in_position;
void main() { gl_Position = u_light_view_proj * vec4(in_position + u_offset, 1.0); }
"""
DEPTH_FRAGMENT = "#version 330\nvoid main() {}\n"


def load_meshes(ctx):
    """[(name, interleaved vertex buffer, vertex count)] from the shared OBJ files."""
    import trimesh

    meshes = []
    for name in S.MESHES:
        mesh = trimesh.load(S.mesh_path(name), force="mesh", process=False)
        uv = getattr(mesh.visual, "uv", None)
        uv = np.zeros((len(mesh.vertices), 2)) if uv is None else uv
        data = np.hstack([mesh.vertices, mesh.vertex_normals, uv]).astype("f4")[mesh.faces.reshape(-1)]
        meshes.append((name, ctx.buffer(data.tobytes()), len(data)))
    return meshes


def sun_view_proj() -> np.ndarray:
    direction = np.asarray(S.SUN_DIRECTION) / np.linalg.norm(S.SUN_DIRECTION)
    view = S.look_at(-direction * 10.0, (0.0, 0.0, 0.0))
    half, near, far = 4.0, 1.0, 25.0
    ortho = np.diag([1.0 / half, 1.0 / half, -2.0 / (far - near), 1.0])
    ortho[2, 3] = -(far + near) / (far - near)
    return ortho @ view


def matrix(m) -> bytes:
    return np.ascontiguousarray(m.T, dtype="f4").tobytes()


def main() -> None:
    import moderngl
    from PIL import Image

    args = parse_args(__doc__)
    ctx = moderngl.create_context(standalone=True, backend="egl", require=330)
    size = (args.width, args.height)
    program = ctx.program(vertex_shader=VERTEX, fragment_shader=FRAGMENT)
    depth_program = ctx.program(vertex_shader=DEPTH_VERTEX, fragment_shader=DEPTH_FRAGMENT)
    meshes = load_meshes(ctx)
    shaded = [(n, ctx.vertex_array(program, [(b, "3f 3f 2f", "in_position", "in_normal", "in_uv")]), c)
              for n, b, c in meshes]
    casters = [(n, ctx.vertex_array(depth_program, [(b, "3f 20x", "in_position")]), c)
               for n, b, c in meshes if n != "ground"]
    image = Image.open(S.SCENE_DIR / "knot.png").convert("RGB").transpose(Image.FLIP_TOP_BOTTOM)
    texture = ctx.texture(image.size, 3, image.tobytes())
    texture.build_mipmaps()
    shadow_map = ctx.depth_texture((S.SUN_SHADOW_SIZE, S.SUN_SHADOW_SIZE))
    shadow_map.compare_func = "<="
    shadow_map.filter = (moderngl.LINEAR, moderngl.LINEAR)
    shadow_map.repeat_x = shadow_map.repeat_y = False  # outside the light's view: the cleared edge, lit
    shadow_fbo = ctx.framebuffer(depth_attachment=shadow_map)
    samples = args.samples if args.samples > 1 else 0
    msaa = ctx.framebuffer([ctx.renderbuffer(size, 4, samples=samples)], ctx.depth_renderbuffer(size, samples=samples))
    resolved = ctx.framebuffer([ctx.renderbuffer(size, 4)])
    light = sun_view_proj()
    projection = S.perspective(S.FOV_Y, size[0] / size[1], 0.1, 50.0)
    program["u_texture"], program["u_shadow"] = 0, 1
    program["u_light_view_proj"].write(matrix(light))
    depth_program["u_light_view_proj"].write(matrix(light))
    program["u_texel"] = 1.0 / S.SUN_SHADOW_SIZE
    for name, value in (("u_sun_dir", S.SUN_DIRECTION / np.linalg.norm(S.SUN_DIRECTION)), ("u_sun_color", S.SUN_COLOR),
                        ("u_point_pos", S.POINT_POSITION), ("u_point_color", S.POINT_COLOR), ("u_ambient", S.AMBIENT)):
        program[name] = tuple(float(v) for v in value)

    def render_frame(i):
        ctx.enable(moderngl.DEPTH_TEST)
        shadow_fbo.use()
        shadow_fbo.clear(depth=1.0)
        for name, vao, count in casters:
            depth_program["u_offset"] = S.MESHES[name][1]
            vao.render(vertices=count)
        eye = S.camera_position(i)
        msaa.use()
        msaa.clear(*S.BACKGROUND, 1.0)
        program["u_view_proj"].write(matrix(projection @ S.look_at(eye)))
        program["u_eye"] = tuple(eye)
        texture.use(0)
        shadow_map.use(1)
        for name, vao, count in shaded:
            program["u_offset"] = S.MESHES[name][1]
            program["u_textured"] = name == "knot"
            program["u_color"] = (0.05, 0.19, 0.6) if name == "vase" else (0.45, 0.45, 0.4)
            vao.render(vertices=count)
        ctx.copy_framebuffer(resolved, msaa)
        rgba = np.frombuffer(resolved.read(components=3, alignment=1), dtype=np.uint8)
        return rgba.reshape(size[1], size[0], 3)[::-1].copy()

    run_frames(args, render_frame)


if __name__ == "__main__":
    main()
