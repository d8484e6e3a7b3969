// The environment visibility's blur, one axis a pass (ENV_VIS_AXIS): the weighted sums the
// visibility pass (mesh/environment_visibility.frag) left, added up over 2N - 1 pixels
// (N = ENV_VIS_INTERLEAVE) with tent weights N - |i|. Every place in the N-pixel pattern
// then counts N times in all, split between its two nearest pixels as linear
// interpolation would split it: each direction's lookups are interpolated between the
// pixels that made them, not repeated in blocks (which draws every shadow edge as a
// staircase of N-pixel steps). A pixel counts only on this pixel's surface: its distance
// from the camera within 3 % of this one's carried along the surface's slope (taken on
// the flatter side, so an edge beside the pixel does not tilt it). The second pass
// (ENV_VIS_RATIO) writes the ratios, V_d (r) and V_s at the narrowest lobe (g), and the
// distance (b) that shading's upsample compares.
uniform sampler2D u_env_vis_samples;   // the weighted sums
uniform sampler2D u_env_vis_distance;  // the surface's distance from the camera, 0: none
out vec4 result;

void main() {
    const ivec2 axis = ENV_VIS_AXIS;
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_env_vis_distance, 0) - 1;
    float here = texelFetch(u_env_vis_distance, pixel, 0).r;
    float before = here - texelFetch(u_env_vis_distance, clamp(pixel - axis, ivec2(0), last), 0).r;
    float after = texelFetch(u_env_vis_distance, clamp(pixel + axis, ivec2(0), last), 0).r - here;
    float slope = abs(before) < abs(after) ? before : after;
    vec4 sum = vec4(0.0);
    for (int i = 1 - ENV_VIS_INTERLEAVE; i < ENV_VIS_INTERLEAVE; ++i) {
        ivec2 at = pixel + axis * i;
        bool inside = all(greaterThanEqual(at, ivec2(0))) && all(lessThanEqual(at, last));
        at = clamp(at, ivec2(0), last);
        float found = texelFetch(u_env_vis_distance, at, 0).r;
        bool same = inside && abs(found - (here + slope * float(i))) <= 0.03 * here;
        sum += (same ? float(ENV_VIS_INTERLEAVE - abs(i)) : 0.0) * texelFetch(u_env_vis_samples, at, 0);
    }
#ifdef ENV_VIS_RATIO
    result = vec4(sum.x > 0.0 ? sum.y / sum.x : 1.0, sum.z > 0.0 ? sum.w / sum.z : 1.0, here, 1.0);
#else
    result = sum;
#endif
}
