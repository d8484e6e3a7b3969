// The environment visibility's read-back texel (post/environment_visibility_blur.frag
// writes it, lighting/environment_visibility.glsl gathers it): V_d (10 bits) and V_s
// (9 bits) as unsigned fractions, which way the surface faces (2 bits: seen_facing), and
// the surface's distance from the camera as an 11-bit float (5 exponent bits, 6 mantissa
// bits, rounded to the nearest: within 0.8 %, 2^-14 to about 130,000), all in one uint,
// so that one gather reads four texels' all.

// Which way a unit normal n faces: 1 up, 2 down, 0 sideways along x, 3 along z (the
// class changes where a curved surface turns past 45 degrees: the upsample then keeps
// the texels of its own class, or all, never none). At a box's foot the ground and the
// box's side meet at one distance; this tells them apart.
uint facing_class(vec3 n) {
    if (abs(n.y) >= max(abs(n.x), abs(n.z))) {
        return n.y > 0.0 ? 1u : 2u;
    }
    return abs(n.x) >= abs(n.z) ? 0u : 3u;
}

uint pack_seen(vec2 seen, float distance, uint facing) {
    uvec2 v = uvec2(clamp(seen, 0.0, 1.0) * vec2(1023.0, 511.0) + 0.5);
    uint bits = floatBitsToUint(distance) + (1u << 16u);  // half the dropped bits' step: rounds
    int e = int(bits >> 23u) - 112;  // float16's exponent bias 15 against float's 127
    uint d = e <= 0 ? 0u : (e > 31 ? 2047u : (uint(e) << 6u) | ((bits >> 17u) & 63u));
    return v.x | (v.y << 10u) | (facing << 19u) | (d << 21u);
}

vec4 seen_diffuse(uvec4 texels) { return vec4(texels & 1023u) / 1023.0; }
vec4 seen_specular(uvec4 texels) { return vec4((texels >> 10u) & 511u) / 511.0; }
uvec4 seen_facing(uvec4 texels) { return (texels >> 19u) & 3u; }
vec4 seen_distance(uvec4 texels) {
    uvec4 d = texels >> 21u;
    return uintBitsToFloat(((d >> 6u) + 112u) << 23u | (d & 63u) << 17u) * vec4(greaterThan(d, uvec4(0u)));
}
