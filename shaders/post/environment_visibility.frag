// The environment visibility pass: each pixel looks up its share of the visibility
// directions (ENV_VIS_PER_PIXEL of them, by its place in an ENV_VIS_INTERLEAVE^2 block:
// world/environment_visibility.interleave_pattern; a place gets one fewer, and a program
// of its own, where N^2 does not divide ENV_VISIBILITY) at the surface it shows
// (mesh/environment_visibility_surface.frag left it), and writes their weighted sums
// (lighting/environment_visibility.glsl), for the blur
// (post/environment_visibility_blur.frag) to add up over the block: diffuse weight, of it
// lit, specular weight at the narrowest lobe (ENV_VIS_MIN_ALPHA), of it lit, as two pairs
// of halves; the surface's distance from the camera (0 where nothing is drawn), which
// the blur compares, as its float bits; and its normal, as snorm bytes, which the blur
// compares too. One image rather than a float16 one and an r32f one: each of the blur's
// taps is then one fetch (llvmpipe pays for a fetch more than for its bytes).
// Drawn once for each place in the block (u_env_vis_place), into a sub-image of its own
// (u_env_vis_place times its size, ENV_VIS_INTERLEAVE of them a side): the blur reads
// pixel (x, y) at (x % N, y % N) * size + (x, y) / N. Every pixel of a draw then looks
// up the same directions, whose data llvmpipe reads once for all of them rather than once
// a pixel (a fifth of the pass). Where each direction's region has two halves
// (ENV_VIS_REGIONS: world/environment_visibility.region_halves), block (bx, by) looks up
// half (bx + by) % 2, so that the blur mixes both halves' shadows rather than drawing
// either's edge; each place is then drawn once a half (u_env_vis_half), its blocks of that
// half in one column of its sub-image, for the same reason.
#define ENV_VIS_PASS
#include "common/math.glsl"
#include "common/halves.glsl"
#include "common/surface_normal.glsl"
#include "lighting/environment_visibility.glsl"
uniform sampler2D u_env_vis_surfaces;  // camera-relative position, normal facing the camera (encoded)
uniform ivec2 u_env_vis_place;         // this draw's place in the block
#ifdef ENV_VIS_REGIONS
uniform int u_env_vis_half;            // which half of each region this draw looks up
#endif
out uvec4 sums_and_distance;  // the sums (xy: diffuse, zw: specular), the distance, the normal

void main() {
    ivec2 size = textureSize(u_env_vis_surfaces, 0);
    ivec2 part = (size + ENV_VIS_INTERLEAVE - 1) / ENV_VIS_INTERLEAVE;  // a sub-image's size
#ifdef ENV_VIS_REGIONS
    // the blocks (bx, by) of half h = (bx + by) % 2, block (bx / 2, by) of the sub-image's
    // h-th column (passes/environment.py sub_image_layout)
    part.x = (part.x + 1) / 2 * 2;
    ivec2 local = ivec2(gl_FragCoord.xy) - u_env_vis_place * part - ivec2(u_env_vis_half * (part.x / 2), 0);
    ivec2 block = ivec2(2 * local.x + ((local.y + u_env_vis_half) & 1), local.y);
#else
    ivec2 block = ivec2(gl_FragCoord.xy) - u_env_vis_place * part;
#endif
    ivec2 pixel = block * ENV_VIS_INTERLEAVE + u_env_vis_place;
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
#ifdef ENV_VIS_REGIONS
        k += u_env_vis_half * ENV_VIS_REGIONS;  // the second halves' maps follow the first halves'
#endif
        float n_dot_l = dot(n, u_env_vis_light[k].xyz);
        float lit = n_dot_l > 0.0 ? env_vis_lookup(k, position, n, n_dot_l) : 1.0;
        vec2 w = env_vis_weights(k, n, v, a2);
        sum += vec4(w.x, w.x * lit, w.y, w.y * lit);
    }
    sums_and_distance = uvec4(pack_halves(sum.xy), pack_halves(sum.zw), floatBitsToUint(length(position)),
                             packSnorm4x8(vec4(n, 0.0)));
}
