// The environment visibility's blur, one axis a pass (ENV_VIS_AXIS): the weighted sums the
// visibility pass (post/environment_visibility.frag) left, added up over 2N - 1 pixels
// (N = ENV_VIS_INTERLEAVE) with tent weights N - |i|. Every place in the N-pixel pattern
// then counts N times in all, split between its two nearest pixels as linear
// interpolation would split it: each direction's lookups are interpolated between the
// pixels that made them, not repeated in blocks (which draws every shadow edge as a
// staircase of N-pixel steps). A pixel counts only on this pixel's surface: its distance
// from the camera within 3 % of this one's carried along the surface's slope (taken on
// the flatter side, so an edge beside the pixel does not tilt it). Each pixel's sums and
// distance come packed in one texel (halves and float bits), so a tap is one fetch. The
// first pass reads them from the visibility pass's sub-images (ENV_VIS_SUB_IMAGES: pixel
// (x, y) at (x % N, y % N) * its sub-images' size + (x, y) / N) and writes them packed
// the same way, a pixel where it lies; the second (ENV_VIS_RATIO) the ratios, V_d
// and V_s at the narrowest lobe, and the distance, that shading's upsample compares,
// packed in one uint (common/seen_texel.glsl's pack_seen).
#include "common/halves.glsl"
#include "common/seen_texel.glsl"
uniform usampler2D u_env_vis_samples;  // the sums (xy, halves) and the distance (z, float bits)
#ifdef ENV_VIS_SUB_IMAGES
uniform ivec2 u_env_vis_size;  // the image's size (its sub-images may reach past it)
#endif
#ifdef ENV_VIS_RATIO
out uint result;
#else
out uvec4 result;
#endif

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
    uvec4 taps[2 * n - 1];
    for (int i = 1 - n; i < n; ++i) {
        ivec2 at = clamp(pixel + axis * i, ivec2(0), last);
#ifdef ENV_VIS_SUB_IMAGES
        at = (at % n) * part + at / n;
#endif
        taps[i + n - 1] = texelFetch(u_env_vis_samples, at, 0);
    }
    float here = uintBitsToFloat(taps[n - 1].z);
    float before = here - uintBitsToFloat(taps[n - 2].z);  // the window reaches a pixel each side (n >= 2)
    float after = uintBitsToFloat(taps[n].z) - here;
    float slope = abs(before) < abs(after) ? before : after;
    vec4 sum = vec4(0.0);
    for (int i = 1 - n; i < n; ++i) {
        ivec2 at = pixel + axis * i;
        bool inside = all(greaterThanEqual(at, ivec2(0))) && all(lessThanEqual(at, last));
        uvec4 found = taps[i + n - 1];
        bool same = inside && abs(uintBitsToFloat(found.z) - (here + slope * float(i))) <= 0.03 * here;
        sum += (same ? float(n - abs(i)) : 0.0) * vec4(unpackHalf2x16(found.x), unpackHalf2x16(found.y));
    }
#ifdef ENV_VIS_RATIO
    vec2 ratio = vec2(sum.x > 0.0 ? sum.y / sum.x : 1.0, sum.z > 0.0 ? sum.w / sum.z : 1.0);
    result = pack_seen(ratio, here);
#else
    result = uvec4(pack_halves(sum.xy), pack_halves(sum.zw), floatBitsToUint(here), 0u);
#endif
}
