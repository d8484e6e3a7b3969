// KHR_materials_sheen's lobe (the "Charlie" sheen of Estevez and Kulla), for the pbr
// model's PBR_SHEEN layer (lighting/pbr.glsl); scenerender/raytrace/sheen_fit.py has the
// same functions for the reference and fitted the albedo E (lighting/sheen_albedo.glsl).
//   D = (2 + 1 / alpha) sin(theta_h)^(1 / alpha) / (2 pi),  alpha = r^2, r >= MIN_SHEEN_ROUGHNESS
//   V = 1 / ((1 + Lambda(N.V) + Lambda(N.L)) 4 N.V N.L), clamped to [0, 1]

#include "lighting/sheen_albedo.glsl"

const float MIN_SHEEN_ROUGHNESS = 0.07;

float sheen_alpha(float roughness) {
    float r = max(roughness, MIN_SHEEN_ROUGHNESS);
    return r * r;
}

float sheen_lambda_helper(float x, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t);
    float b = mix(3.82987, 3.32435, t);
    float c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t);
    float e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(x, c)) + d * x + e;
}

float sheen_lambda(float cosine, float alpha) {
    cosine = abs(cosine);
    if (cosine < 0.5) {
        return exp(sheen_lambda_helper(cosine, alpha));
    }
    return exp(2.0 * sheen_lambda_helper(0.5, alpha) - sheen_lambda_helper(1.0 - cosine, alpha));
}

// pi D V of the sheen (its colour apart)
float sheen_lobe(float n_dot_h, float n_dot_l, float n_dot_v, float alpha) {
    float sin2 = clamp(1.0 - n_dot_h * n_dot_h, 0.0, 1.0);
    float d = (2.0 + 1.0 / alpha) * pow(sin2, 0.5 / alpha) * 0.5;  // pi D
    float product = 4.0 * n_dot_v * n_dot_l;
    if (product <= 0.0) {
        return 0.0;
    }
    float v = clamp(1.0 / ((1.0 + sheen_lambda(n_dot_v, alpha) + sheen_lambda(n_dot_l, alpha)) * product), 0.0, 1.0);
    return d * v;
}

// 1 - max(sheen colour) E(cosine): what the sheen lets through to the layer beneath, kept at 0 or above
float sheen_through(vec3 color, float roughness, float cosine) {
    return max(1.0 - max(color.r, max(color.g, color.b)) * sheen_albedo(cosine, roughness), 0.0);
}
