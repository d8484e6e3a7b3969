// ACES tone curve: Stephen Hill's fit of the ACES reference rendering transform and sRGB
// output transform (RRT + ODT), as published in MJP's BakingLab. Scene-linear sRGB in,
// display-linear in [0, 1] out. The same numbers as scenerender/colorspace.py (aces_fitted).

// GLSL matrices are built column by column: each line below is a column.
// sRGB -> XYZ -> D65 to D60 -> AP1, with the RRT's saturation adjustment
const mat3 ACES_INPUT = mat3(0.59719, 0.07600, 0.02840,
                             0.35458, 0.90834, 0.13383,
                             0.04823, 0.01566, 0.83777);
// the ODT's saturation adjustment -> XYZ -> D60 to D65 -> sRGB
const mat3 ACES_OUTPUT = mat3(1.60475, -0.10208, -0.00327,
                              -0.53108, 1.10813, -0.07276,
                              -0.07367, -0.00605, 1.07602);

vec3 tone_map(vec3 c) {
    vec3 v = ACES_INPUT * c;
    v = (v * (v + 0.0245786) - 0.000090537) / (v * (0.983729 * v + 0.4329510) + 0.238081);
    return clamp(ACES_OUTPUT * v, 0.0, 1.0);
}
