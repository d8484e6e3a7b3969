// mode: shadow. How much of the first shadowed light reaches each surface: white lit,
// black in shadow.
#include "common/math.glsl"
#include "lighting/shadows.glsl"
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#else
in vec2 v_uv;
#endif
in vec3 v_position;
in vec3 v_normal;
uniform int u_first_view;
uniform int u_point_light;   // 1 when the light is a point light (six views)
uniform vec3 u_light_vector; // directional/spot: travel direction; point: light position
out vec4 frag_color;

void main() {
    vec3 n = safe_normalize(gl_FrontFacing ? v_normal : -v_normal);
    vec3 dpdx = dFdx(v_position);
    vec3 dpdy = dFdy(v_position);
    int view = u_first_view;
    vec3 l;
    if (u_point_light == 1) {
        view += cube_face(v_position - u_light_vector);
        l = safe_normalize(u_light_vector - v_position, n);
    } else {
        l = -u_light_vector;
    }
    float visibility = shadow_visibility(view, v_position, n, max(dot(n, l), 0.0), dpdx, dpdy);
    frag_color = vec4(vec3(visibility), 1.0);
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
}
