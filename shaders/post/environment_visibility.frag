// The environment visibility pass: each pixel looks up its share of the visibility
// directions (ENV_VIS_PER_PIXEL of them, by its place in an ENV_VIS_INTERLEAVE^2 block:
// world/environment_visibility.interleave_pattern; a place gets one fewer, and a program
// of its own, where N^2 does not divide ENV_VISIBILITY) at the surface it shows
// (mesh/environment_visibility_surface.frag left it), and writes their weighted sums
// (lighting/environment_visibility.glsl), for the blur
// (post/environment_visibility_blur.frag) to add up over the block: diffuse weight, of it
// lit, specular weight at the narrowest lobe (ENV_VIS_MIN_ALPHA), of it lit, as two pairs
// of halves; and the surface's distance from the camera (0 where nothing is drawn), which
// the blur compares, as its float bits. One image rather than a float16 one and an r32f
// one: each of the blur's taps is then one fetch (llvmpipe pays for a fetch more than
// for its bytes).
// Drawn once for each place in the block (u_env_vis_place), into a sub-image of its own
// (u_env_vis_place times its size, ENV_VIS_INTERLEAVE of them a side): the blur reads
// pixel (x, y) at (x % N, y % N) * size + (x, y) / N. Every pixel of a draw then looks
// up the same directions, whose data llvmpipe reads once for all of them rather than once
// a pixel (a fifth of the pass).
#define ENV_VIS_PASS
#include "common/math.glsl"
#include "common/halves.glsl"
#include "common/surface_normal.glsl"
#include "lighting/environment_visibility.glsl"
uniform sampler2D u_env_vis_surfaces;  // camera-relative position, normal facing the camera (encoded)
uniform ivec2 u_env_vis_place;         // this draw's place in the block
out uvec4 sums_and_distance;  // the sums (xy: diffuse, zw: specular), the distance

void main() {
    ivec2 size = textureSize(u_env_vis_surfaces, 0);
    ivec2 part = (size + ENV_VIS_INTERLEAVE - 1) / ENV_VIS_INTERLEAVE;  // a sub-image's size
    ivec2 pixel = (ivec2(gl_FragCoord.xy) - u_env_vis_place * part) * ENV_VIS_INTERLEAVE + u_env_vis_place;
    vec4 surface = texelFetch(u_env_vis_surfaces, min(pixel, size - 1), 0);
    if (any(greaterThanEqual(pixel, size)) || surface.w == 0.0) {
        sums_and_distance = uvec4(0u);  // no surface: 0.0's bits, sums and distance
        return;
    }
    vec3 position = surface.xyz;
    vec3 n = decode_normal(surface.w);
    vec3 v = safe_normalize(-position, n);
    int start = u_env_vis_place.x + ENV_VIS_INTERLEAVE * u_env_vis_place.y;
    float a2 = ENV_VIS_MIN_ALPHA * ENV_VIS_MIN_ALPHA;
    vec4 sum = vec4(0.0);
    for (int j = 0; j < ENV_VIS_PER_PIXEL; ++j) {
        int k = start + j * ENV_VIS_INTERLEAVE * ENV_VIS_INTERLEAVE;
        float n_dot_l = dot(n, u_env_vis_light[k].xyz);
        float lit = n_dot_l > 0.0 ? env_vis_lookup(k, position, n, n_dot_l) : 1.0;
        vec2 w = env_vis_weights(k, n, v, a2);
        sum += vec4(w.x, w.x * lit, w.y, w.y * lit);
    }
    sums_and_distance = uvec4(pack_halves(sum.xy), pack_halves(sum.zw), floatBitsToUint(length(position)), 0u);
}
