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
