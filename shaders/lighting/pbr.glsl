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

// alpha is kept above this (roughness about 0.045) so the distribution stays finite; a
// smoother surface's highlight from a point light would be narrower than a pixel anyway
const float PBR_MIN_ALPHA = 0.002;

vec3 fresnel_schlick(vec3 f0, float v_dot_h) {
    float m = 1.0 - v_dot_h;
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// What the BRDF needs of a point that no light changes, worked out once per pixel rather
// than once per light.
struct PbrView {
    float n_dot_v;
    float alpha2;
    float view_term;  // sqrt((N.V)^2 (1 - alpha^2) + alpha^2), V's half that depends on V alone
    vec3 f0;
    vec3 diffuse;     // (1 - metallic) base
};

PbrView pbr_view(vec3 n, vec3 v, Surface s) {
    PbrView p;
    p.n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    float alpha = max(s.roughness * s.roughness, PBR_MIN_ALPHA);
    p.alpha2 = alpha * alpha;
    p.view_term = sqrt(p.n_dot_v * p.n_dot_v * (1.0 - p.alpha2) + p.alpha2);
    p.f0 = mix(vec3(0.04), s.base, s.metallic);
    p.diffuse = s.base * (1.0 - s.metallic);
    return p;
}

// pi f(l, v) N.L for a light in direction l (N.L = n_dot_l > 0):
// ((1 - F) diffuse + F pi D V) N.L. The half vector is never formed: N.H = N.(L + V) / |L + V|
// and V.H = |L + V| / 2. pi D V is one division; pi D's denominator 1 - (N.H)^2 (1 - alpha^2)
// loses a few percent to float32 rounding at the peak of the smoothest lobes (roughness
// below 0.1, alpha^2 = 1e-4). Measured on llvmpipe, 8 lights: 1.11x Blinn-Phong's per-light
// cost, against 1.27x with the half vector normalised and |N x H|^2 for 1 - (N.H)^2.
vec3 pbr_direct(vec3 n, vec3 l, vec3 v, float n_dot_l, PbrView p) {
    vec3 l_plus_v = l + v;
    float length2 = dot(l_plus_v, l_plus_v);
    float inverse_length = inversesqrt(max(length2, 1e-20));
    float n_dot_h = dot(n, l_plus_v) * inverse_length;
    float v_dot_h = min(0.5 * length2 * inverse_length, 1.0);
    float k = 1.0 - n_dot_h * n_dot_h * (1.0 - p.alpha2);
    float light_term = p.n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - p.alpha2) + p.alpha2);
    float specular = 0.5 * p.alpha2 / (k * k * (n_dot_l * p.view_term + light_term));  // pi D V
    vec3 fresnel = fresnel_schlick(p.f0, v_dot_h);
    return (p.diffuse + fresnel * (specular - p.diffuse)) * n_dot_l;
}

// What a uniform ambient light of radiance 1 gives: the BRDF integrated over the
// hemisphere, from the fitted integrals of lighting/ambient_brdf.glsl: specular F0 A + B,
// diffuse (1 - metallic) base (1 - F0) (1 - Cd). Kept apart, since the environment light
// weighs its diffuse and specular lookups by them.
struct PbrAmbientWeights {
    vec3 diffuse;
    vec3 specular;
};

PbrAmbientWeights pbr_ambient_weights(vec3 n, vec3 v, Surface s) {
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    vec2 scale_bias = ambient_specular(n_dot_v, s.roughness);
    vec3 f0 = mix(vec3(0.04), s.base, s.metallic);
    PbrAmbientWeights w;
    w.diffuse = s.base * (1.0 - s.metallic) * (1.0 - f0) * (1.0 - ambient_diffuse_fresnel(n_dot_v));
    w.specular = f0 * scale_bias.x + scale_bias.y;
    return w;
}

vec3 pbr_ambient(vec3 n, vec3 v, Surface s) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    return w.diffuse + w.specular;
}
