// The environment visibility's blur, one axis a pass (ENV_VIS_AXIS): the weighted sums the
// visibility pass (post/environment_visibility.frag) left, added up over 2N - 1 pixels
// (N = ENV_VIS_INTERLEAVE) with tent weights N - |i|. Every place in the N-pixel pattern
// then counts N times in all, split between its two nearest pixels as linear
// interpolation would split it: each direction's lookups are interpolated between the
// pixels that made them, not repeated in blocks (which draws every shadow edge as a
// staircase of N-pixel steps). Where each direction's region has two halves that take
// turns from block to block, (bx + by) % 2 (ENV_VIS_HALVES:
// world/environment_visibility.region_halves), the second pass (along y) adds up 2N + 1
// pixels, weights 2 but 1 at either end: every place then counts as much in either half,
// the pixel's own (at 0 and +-N) too, so the halves' shadows mix rather than alternate
// in a checkerboard; it does so only where both ends lie on the pixel's surface (else the
// tent), so that beside an object's foot the window reaches no further from it than
// towards it. (The first pass keeps the tent: 2N + 1 taps there, read from the
// sub-images, cost a tenth of a frame on llvmpipe.)
// A pixel counts only on this pixel's surface: its distance from the camera within 3 %
// of this one's carried along the surface's slope (taken on the flatter side, so an edge
// beside the pixel does not tilt it), and its normal within 60 degrees of this one's (at
// a box's foot the ground and the box's side meet at one distance). Each pixel's sums,
// distance and normal come packed in one texel (halves, float bits, snorm bytes), so a
// tap is one fetch. The first pass reads them from the visibility pass's sub-images
// (ENV_VIS_SUB_IMAGES: pixel (x, y) at (x % N, y % N) * its sub-images' size + (x, y) /
// N, or with halves passes/environment.py sub_image_layout's place) and writes them
// packed the same way, a pixel where it lies; the second
// (ENV_VIS_RATIO) the ratios, V_d and V_s at the narrowest lobe, the distance and which
// way the surface faces, that shading's upsample compares, packed in one uint
// (common/seen_texel.glsl's pack_seen).
#include "common/halves.glsl"
#include "common/seen_texel.glsl"
uniform usampler2D u_env_vis_samples;  // the sums (xy, halves), the distance (z, float bits), the normal (w, snorm bytes)
#ifdef ENV_VIS_SUB_IMAGES
uniform ivec2 u_env_vis_size;  // the image's size (its sub-images may reach past it)
#endif
#ifdef ENV_VIS_RATIO
out uint result;
#else
out uvec4 result;
#endif

#if defined(ENV_VIS_HALVES) && defined(ENV_VIS_RATIO)
const int REACH = ENV_VIS_INTERLEAVE;  // the second pass's window, 2N + 1 pixels
#else
const int REACH = ENV_VIS_INTERLEAVE - 1;
#endif
// tap i's weight: the tent, N - |i|, or where the halves' window is whole, 2 but 1 at its ends
float tap_weight(int i, bool whole) {
    return whole ? (abs(i) == ENV_VIS_INTERLEAVE ? 1.0 : 2.0) : max(float(ENV_VIS_INTERLEAVE - abs(i)), 0.0);
}
const float SAME_NORMAL = 0.5;  // cos 60 degrees
const float FLAT_NORMAL = 0.985;  // cos 10 degrees

void main() {
    const int n = ENV_VIS_INTERLEAVE;
    const ivec2 axis = ENV_VIS_AXIS;
    ivec2 pixel = ivec2(gl_FragCoord.xy);
#ifdef ENV_VIS_SUB_IMAGES
    ivec2 last = u_env_vis_size - 1;
    ivec2 part = textureSize(u_env_vis_samples, 0) / n;
#else
    ivec2 last = textureSize(u_env_vis_samples, 0) - 1;
#endif
    uvec4 taps[2 * REACH + 1];
    for (int i = -REACH; i <= REACH; ++i) {
        ivec2 at = clamp(pixel + axis * i, ivec2(0), last);
#if defined(ENV_VIS_SUB_IMAGES) && defined(ENV_VIS_HALVES)
        ivec2 block = at / n;  // half h = (bx + by) % 2's blocks in the h-th column (passes/environment.py sub_image_layout)
        at = (at % n) * part + ivec2(block.x / 2 + ((block.x + block.y) & 1) * (part.x / 2), block.y);
#elif defined(ENV_VIS_SUB_IMAGES)
        at = (at % n) * part + at / n;
#endif
        taps[i + REACH] = texelFetch(u_env_vis_samples, at, 0);
    }
    float here = uintBitsToFloat(taps[REACH].z);
    vec3 normal = unpackSnorm4x8(taps[REACH].w).xyz;
    float before = here - uintBitsToFloat(taps[REACH - 1].z);  // the window reaches a pixel each side (n >= 2)
    float after = uintBitsToFloat(taps[REACH + 1].z) - here;
    float slope = abs(before) < abs(after) ? before : after;
    bool same[2 * REACH + 1];
    float turned[2 * REACH + 1];  // the cosine between this pixel's normal and each tap's
    for (int i = -REACH; i <= REACH; ++i) {
        ivec2 at = pixel + axis * i;
        uvec4 found = taps[i + REACH];
        turned[i + REACH] = dot(unpackSnorm4x8(found.w).xyz, normal);
        same[i + REACH] = all(greaterThanEqual(at, ivec2(0))) && all(lessThanEqual(at, last))
                          && abs(uintBitsToFloat(found.z) - (here + slope * float(i))) <= 0.03 * here
                          && turned[i + REACH] >= SAME_NORMAL;
    }
#if defined(ENV_VIS_HALVES) && defined(ENV_VIS_RATIO)
    // the wider window on a flat stretch only: on a curved one (a sphere a few pixels
    // across) the reflection turns within it, and the specular visibility it mixes moved
    // the copper sphere among three from +2.7 to +3.2 % at 128x96
    bool whole = same[0] && same[2 * REACH] && min(turned[0], turned[2 * REACH]) >= FLAT_NORMAL;
#else
    const bool whole = false;
#endif
    vec4 sum = vec4(0.0);
    for (int i = -REACH; i <= REACH; ++i) {
        uvec4 found = taps[i + REACH];
        sum += (same[i + REACH] ? tap_weight(i, whole) : 0.0) * vec4(unpackHalf2x16(found.x), unpackHalf2x16(found.y));
    }
#ifdef ENV_VIS_RATIO
    vec2 ratio = vec2(sum.x > 0.0 ? sum.y / sum.x : 1.0, sum.z > 0.0 ? sum.w / sum.z : 1.0);
    result = pack_seen(ratio, here, facing_class(normal));
#else
    result = uvec4(pack_halves(sum.xy), pack_halves(sum.zw), floatBitsToUint(here), taps[REACH].w);
#endif
}
