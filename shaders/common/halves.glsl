// Two floats packed as float16s in one uint, rounded toward zero: as llvmpipe stores a
// float into a float16 target (packHalf2x16 rounds to nearest, one step apart in half the
// cases), so values that went through a packed uint are to the bit those that went
// through an rgba16f image (the environment visibility's, see
// post/environment_visibility_blur.frag).
float half_toward_zero(float x) {
    float m = abs(x);
    // float16's normal range: drop the 13 mantissa bits it lacks; below it, its steps of 2^-24
    float t = m >= 6.103515625e-05 ? uintBitsToFloat(floatBitsToUint(m) & 0xFFFFE000u) : floor(m * 16777216.0) / 16777216.0;
    return x < 0.0 ? -t : t;
}

uint pack_halves(vec2 v) {
    return packHalf2x16(vec2(half_toward_zero(v.x), half_toward_zero(v.y)));
}

// The environment visibility's read-back texel (post/environment_visibility_blur.frag
// writes it, lighting/environment_visibility.glsl gathers it): V_d (11 bits) and V_s
// (10 bits) as unsigned fractions and the surface's distance from the camera as an
// 11-bit float (5 exponent bits, 6 mantissa bits, rounded to the nearest: within 0.8 %,
// 2^-14 to about 130,000), all in one uint, so that one gather reads four texels' all.
uint pack_seen(vec2 seen, float distance) {
    uvec2 v = uvec2(clamp(seen, 0.0, 1.0) * vec2(2047.0, 1023.0) + 0.5);
    uint bits = floatBitsToUint(distance) + (1u << 16u);  // half the dropped bits' step: rounds
    int e = int(bits >> 23u) - 112;  // float16's exponent bias 15 against float's 127
    uint d = e <= 0 ? 0u : (e > 31 ? 2047u : (uint(e) << 6u) | ((bits >> 17u) & 63u));
    return v.x | (v.y << 11u) | (d << 21u);
}

vec4 seen_diffuse(uvec4 texels) { return vec4(texels & 2047u) / 2047.0; }
vec4 seen_specular(uvec4 texels) { return vec4((texels >> 11u) & 1023u) / 1023.0; }
vec4 seen_distance(uvec4 texels) {
    uvec4 d = texels >> 21u;
    return uintBitsToFloat(((d >> 6u) + 112u) << 23u | (d & 63u) << 17u) * vec4(greaterThan(d, uvec4(0u)));
}
