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
