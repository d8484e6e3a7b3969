// The pbr model: glTF 2.0's metallic-roughness BRDF (specification, Appendix B), exact
// (no roughness filtering). With alpha = roughness^2, h the half vector:
//   D = alpha^2 / (pi ((N.H)^2 (alpha^2 - 1) + 1)^2)                    (GGX / Trowbridge-Reitz)
//   V = 0.5 / (N.L sqrt((N.V)^2 (1 - alpha^2) + alpha^2) + N.V sqrt((N.L)^2 (1 - alpha^2) + alpha^2))
//                                                                     (height-correlated Smith)
//   F = F0 + (1 - F0) (1 - V.H)^5, F0 = mix(0.04, base, metallic)    (Schlick)
//   f = (1 - F) (1 - metallic) base / pi + F D V
// Light units as for the other models: a light gives pi f E N.L (E its colour x intensity
// x attenuation), so Lambert's f = base / pi gives base E N.L. docs/scene-notes.md has it.

#include "lighting/ambient_brdf.glsl"

const float PBR_PI = 3.14159265358979;
// alpha is kept above this (roughness about 0.045) so the distribution stays finite; a
// smoother surface's highlight from a point light would be narrower than a pixel anyway
const float PBR_MIN_ALPHA = 0.002;

// D, from |N x H|^2 rather than 1 - (N.H)^2: no cancellation near the highlight's peak.
float ggx_distribution(vec3 n, vec3 h, float n_dot_h, float alpha) {
    vec3 n_cross_h = cross(n, h);
    float a = n_dot_h * alpha;
    float k = alpha / (dot(n_cross_h, n_cross_h) + a * a);
    return k * k * (1.0 / PBR_PI);
}

float smith_visibility(float n_dot_v, float n_dot_l, float alpha) {
    float a2 = alpha * alpha;
    float from_view = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float from_light = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (from_view + from_light);
}

vec3 fresnel_schlick(vec3 f0, float v_dot_h) {
    float m = 1.0 - v_dot_h;
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// pi f(l, v) N.L for a light in direction l (N.L = n_dot_l > 0).
vec3 pbr_direct(vec3 n, vec3 l, vec3 v, float n_dot_l, Surface s) {
    vec3 h = safe_normalize(l + v, n);
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    float n_dot_h = clamp(dot(n, h), 0.0, 1.0);
    float v_dot_h = clamp(dot(v, h), 0.0, 1.0);
    float alpha = max(s.roughness * s.roughness, PBR_MIN_ALPHA);
    vec3 f0 = mix(vec3(0.04), s.base, s.metallic);
    vec3 fresnel = fresnel_schlick(f0, v_dot_h);
    vec3 diffuse = (1.0 - fresnel) * s.base * (1.0 - s.metallic);
    float specular = PBR_PI * ggx_distribution(n, h, n_dot_h, alpha) * smith_visibility(n_dot_v, n_dot_l, alpha);
    return (diffuse + fresnel * specular) * n_dot_l;
}

// What a uniform ambient light of radiance 1 gives: the BRDF integrated over the
// hemisphere, from the fitted integrals of lighting/ambient_brdf.glsl: specular F0 A + B,
// diffuse (1 - metallic) base (1 - F0) (1 - Cd).
vec3 pbr_ambient(vec3 n, vec3 v, Surface s) {
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    vec2 scale_bias = ambient_specular(n_dot_v, s.roughness);
    vec3 f0 = mix(vec3(0.04), s.base, s.metallic);
    vec3 diffuse = s.base * (1.0 - s.metallic) * (1.0 - f0) * (1.0 - ambient_diffuse_fresnel(n_dot_v));
    return diffuse + f0 * scale_bias.x + scale_bias.y;
}
