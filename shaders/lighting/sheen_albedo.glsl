// The directional albedo E(N.V, r) of KHR_materials_sheen's Charlie lobe
// (scenerender/raytrace/sheen_fit.py wrote this file; the reference reads the same
// numbers): a polynomial of degree 6 in sqrt(N.V) and the sheen roughness (kept at
// 0.07 or above).

const float SHEEN_ALBEDO[49] = float[](
    2.50953763,
    -17.8770141,
    73.0183339,
    -164.819156,
    209.808368,
    -139.152039,
    37.1610625,
    12.8770086,
    -116.913084,
    540.750838,
    -1312.31062,
    1735.40143,
    -1180.19202,
    322.446978,
    -203.877943,
    2328.83775,
    -11673.9411,
    29911.3585,
    -41004.3492,
    28560.4671,
    -7931.99976,
    710.32857,
    -9054.90382,
    47575.142,
    -125329.194,
    174882.686,
    -123281.561,
    34533.0432,
    -1089.38082,
    14903.7582,
    -80926.0008,
    217362.448,
    -307138.382,
    218392.35,
    -61556.9722,
    784.852918,
    -11284.6909,
    62788.0616,
    -171122.061,
    244135.126,
    -174763.012,
    49501.0062,
    -217.328395,
    3242.19579,
    -18379.7094,
    50661.8003,
    -72828.4765,
    52415.4019,
    -14905.5706);

float sheen_albedo(float n_dot_v, float roughness) {
    float s = sqrt(clamp(n_dot_v, 0.0, 1.0));
    float r = max(roughness, 0.07);
    float sum = 0.0;
    for (int i = 6; i >= 0; --i) {
        float row = 0.0;
        for (int j = 6; j >= 0; --j) {
            row = row * r + SHEEN_ALBEDO[i * 7 + j];
        }
        sum = sum * s + row;
    }
    return sum;
}
