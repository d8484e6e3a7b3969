// The exact sRGB transfer function (IEC 61966-2-1, not pow(1/2.2)) of linear values in
// [0, 1]; 8-bit storage then rounds to nearest.
vec3 srgb_encode(vec3 c) {
    vec3 low = c * 12.92;
    vec3 high = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(low, high, step(vec3(0.0031308), c));
}
