// AgX tone curve: Benjamin Wrensch's (Missing Deadlines) minimal AgX, after Troy Sobotka's
// AgX. Inset matrix, log2 encoding over [2^AGX_MIN_EV, 2^AGX_MAX_EV], a 6th-order
// polynomial fit of the default contrast curve, outset matrix; the curve's output is
// display-encoded with a 2.2 power, so it is raised to 2.2 to give display-linear light in
// [0, 1]. The same numbers as scenerender/colorspace.py (agx).

// GLSL matrices are built column by column: each line below is a column.
const mat3 AGX_INSET = mat3(0.842479062253094, 0.0423282422610123, 0.0423756549057051,
                            0.0784335999999992, 0.878468636469772, 0.0784336,
                            0.0792237451477643, 0.0791661274605434, 0.879142973793104);
const mat3 AGX_OUTSET = mat3(1.19687900512017, -0.0528968517574562, -0.0529716355144438,
                             -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
                             -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
const float AGX_MIN_EV = -12.47393;
const float AGX_MAX_EV = 4.026069;

vec3 agx_contrast(vec3 x) {
    vec3 x2 = x * x;
    vec3 x4 = x2 * x2;
    return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x - 0.00232;
}

vec3 tone_map(vec3 c) {
    vec3 v = AGX_INSET * c;
    v = clamp(log2(max(v, vec3(1e-10))), AGX_MIN_EV, AGX_MAX_EV);
    v = agx_contrast((v - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV));
    return pow(clamp(AGX_OUTSET * v, 0.0, 1.0), vec3(2.2));
}
