// Vertex shader of every pass that draws scene meshes from the camera.
// Instances carry camera-relative model matrices (the camera sits at the origin), so the
// view-projection holds only rotation and projection and float32 stays precise.
#include "common/math.glsl"

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
#ifdef HAS_TANGENTS
in vec4 in_tangent;
#endif
#ifdef HAS_VERTEX_COLOR
in vec4 in_color;
#endif
#ifdef HAS_UV1
in vec2 in_uv1;  // glTF TEXCOORD_1, for textures with texCoord: 1
#endif
in mat4 in_model;          // per instance: camera-relative world matrix
in mat3 in_normal_matrix;  // per instance: inverse transpose of the model's 3x3

uniform mat4 u_view_proj;  // camera-relative world -> clip

// The depth prepass and the shading pass are different programs drawing the same
// triangles; invariance makes their depths bit-identical so the 'equal' test passes.
invariant gl_Position;
#ifdef OUTLINE
uniform float u_outline_width;  // world units
#endif

out vec3 v_position;  // camera-relative world position (the eye is at the origin)
out vec3 v_normal;
out vec2 v_uv;
#ifdef HAS_TANGENTS
out vec4 v_tangent;
#endif
#ifdef HAS_VERTEX_COLOR
out vec4 v_color;
#endif
#ifdef HAS_UV1
out vec2 v_uv1;
#endif

void main() {
    vec4 world = in_model * vec4(in_position, 1.0);
    vec3 normal = safe_normalize(in_normal_matrix * in_normal);
#ifdef OUTLINE
    // inflate along the normal; drawn with front faces culled, only the rim shows
    world.xyz += normal * u_outline_width;
#endif
    v_position = world.xyz;
    v_normal = normal;
    v_uv = in_uv;
#ifdef HAS_UV1
    v_uv1 = in_uv1;
#endif
#ifdef HAS_VERTEX_COLOR
    v_color = in_color;
#endif
#ifdef HAS_TANGENTS
    v_tangent = vec4(safe_normalize(mat3(in_model) * in_tangent.xyz, vec3(1.0, 0.0, 0.0)), in_tangent.w);
#endif
    gl_Position = u_view_proj * world;
#ifdef DEPTH_NUDGE
    // overlay lines: pull slightly towards the camera so they win the depth test
#ifdef REVERSED_DEPTH
    // reversed-Z depth is ~ near / distance: a relative nudge (0.1% of the distance)
    gl_Position.z *= 1.001;
#else
    gl_Position.z -= 2e-4 * gl_Position.w;
#endif
#endif
}
