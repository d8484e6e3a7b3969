// The environment visibility pass: each pixel looks up its share of the visibility
// directions (ENV_VIS_PER_PIXEL of them, by its place in an ENV_VIS_INTERLEAVE^2 block:
// world/environment_visibility.interleave_pattern) at the surface it shows, for forward
// shading to gather over the block (lighting/environment_visibility.glsl). Out: the lookups
// (xyz, 1 where none or the direction is below the surface) and the surface's distance
// from the camera (w; 0 where nothing is drawn).
#include "common/math.glsl"
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#else
in vec2 v_uv;
#endif
#include "lighting/environment_visibility.glsl"
in vec3 v_position;
in vec3 v_normal;
out vec4 lookups;

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
    vec3 n = safe_normalize(gl_FrontFacing ? v_normal : -v_normal);
    ivec2 place = ivec2(gl_FragCoord.xy) % ENV_VIS_INTERLEAVE;
    int start = place.x + ENV_VIS_INTERLEAVE * place.y;
    vec3 lit = vec3(1.0);
    for (int j = 0; j < ENV_VIS_PER_PIXEL; ++j) {
        int k = min(start + j * ENV_VIS_INTERLEAVE * ENV_VIS_INTERLEAVE, ENV_VISIBILITY - 1);
        float n_dot_l = dot(n, u_env_vis_light[k].xyz);
        lit[j] = n_dot_l > 0.0 ? env_vis_lookup(k, v_position, n, n_dot_l) : 1.0;
    }
    lookups = vec4(lit, length(v_position));
}
