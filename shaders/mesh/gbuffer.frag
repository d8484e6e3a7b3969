// Geometry prepass: view-space normal and linear view depth per pixel, for screen-space
// ambient occlusion and the depth / normals views.
#include "common/math.glsl"
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#else
in vec2 v_uv;
#endif
in vec3 v_position;
in vec3 v_normal;
uniform mat3 u_view_rotation;  // world -> view
out vec4 g_normal_depth;

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
    vec3 n = safe_normalize(gl_FrontFacing ? v_normal : -v_normal);
    float view_depth = -(u_view_rotation * v_position).z;
    g_normal_depth = vec4(u_view_rotation * n, view_depth);
}
