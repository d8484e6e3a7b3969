// The pbr model: glTF 2.0's metallic-roughness BRDF (specification, Appendix B), exact
// (no roughness filtering). With alpha = roughness^2, h the half vector:
//   D = alpha^2 / (pi ((N.H)^2 (alpha^2 - 1) + 1)^2)                    (GGX / Trowbridge-Reitz)
//   V = 0.5 / (N.L sqrt((N.V)^2 (1 - alpha^2) + alpha^2) + N.V sqrt((N.L)^2 (1 - alpha^2) + alpha^2))
//                                                                     (height-correlated Smith)
//   F = F0 + (1 - F0) (1 - V.H)^5, F0 = mix(0.04, base, metallic)    (Schlick)
//   f = (1 - F) (1 - metallic) base / pi + F D V
// Light units as for the other models: a light gives pi f E N.L (E its colour x intensity
// x attenuation), so Lambert's f = base / pi gives base E N.L. docs/scene-notes.md has it.
//
// Layers, each only in the programs of materials that have it (docs/scene-notes.md,
// "Layers of the pbr model"):
// - PBR_DIELECTRIC_SPECULAR (KHR_materials_ior, KHR_materials_specular): the dielectric's
//   F0 = min(((ior - 1) / (ior + 1))^2 specular_color, 1) specular and F90 = specular, so
//   F = F0 + (F90 - F0) (1 - V.H)^5 with F0 = mix(dielectric F0, base, metallic) and
//   F90 = mix(dielectric F90, 1, metallic).
// - PBR_SHEEN (KHR_materials_sheen): a Charlie lobe over the base (lighting/sheen.glsl):
//   f = f_base min(1 - max(sheen) E(N.V), 1 - max(sheen) E(N.L)) + sheen D_s V_s.
// - PBR_ANISOTROPY (KHR_materials_anisotropy): the base's GGX lobe with alpha_t =
//   mix(alpha, 1, strength^2) along the anisotropy's direction and alpha_b = alpha across it,
//   for point, spot and directional lights; sized and area lights take the lobe at alpha,
//   ambient and environment light weigh it by anisotropic_ambient_roughness's albedo
//   (docs/scene-notes.md).
// - PBR_IRIDESCENCE (KHR_materials_iridescence): the thin film's Fresnel F_i
//   (lighting/iridescence.glsl), taken at N.V once a pixel: specular F mixed towards F_i,
//   the diffuse part's towards max(F_i), by the iridescence.
// - PBR_CLEARCOAT (KHR_materials_clearcoat): a GGX layer of F0 0.04 (ior 1.5) and its own
//   roughness over the rest: f = f_rest (1 - c Fc) + c Fc D_c V_c, Fc = 0.04 + 0.96 (1 - N.V)^5,
//   at N.V rather than V.H as the extension writes it (its Layering section), so once a pixel.
// - PBR_TRANSMISSION (KHR_materials_transmission): the diffuse part times 1 - transmission;
//   what passes through instead is lighting/transmission.glsl's: the scene behind, and a
//   light behind the surface through the BTDF (pbr_through): the specular lobe with the
//   light's direction mirrored through the surface's plane, l_m = l - 2 (N.L) N, tinted:
//   pi f_t |N.L| = (1 - metallic) transmission base (1 - F(V.H_t)) pi D_t V_t N.L_m, h_t
//   the half vector of l_m and v, alpha_t = alpha clamp(2 ior - 2, 0, 1) (the Sample
//   Viewer's scaling; the refracted copy's blur takes the same).

#include "lighting/ambient_brdf.glsl"
#ifdef PBR_SHEEN
#include "lighting/sheen.glsl"
#endif
#ifdef PBR_IRIDESCENCE
#include "lighting/iridescence.glsl"
#endif

// alpha is kept above this (roughness about 0.045) so the distribution stays finite; a
// smoother surface's highlight from a point light would be narrower than a pixel anyway
const float PBR_MIN_ALPHA = 0.002;

// the layers' values are the Surface's (lighting/material.glsl, sample_layers)
#ifdef PBR_TRANSMISSION
uniform float u_transmission_ior;
#endif

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
#ifdef PBR_DIELECTRIC_SPECULAR
    vec3 f90;
#endif
#ifdef PBR_CLEARCOAT
    float coat_alpha2;
    float coat_view_term;
    float coat;  // c Fc(N.V): the share of every light the coat takes
#ifdef PBR_COAT_NORMAL
    vec3 coat_normal;      // the coat's own (its map's); N.V above is then the coat's
    float coat_n_dot_v;
#endif
#endif
#ifdef PBR_SHEEN
    float sheen_alpha;
    float sheen_through_view;  // 1 - max(sheen) E(N.V)
    vec3 sheen_color;
    float sheen_roughness;
#endif
#ifdef PBR_ANISOTROPY
    vec3 anisotropy_t;  // the direction of alpha_t
    vec3 anisotropy_b;  // across it, of alpha_b (the surface's own alpha)
    float alpha_t;
    float alpha_b;
    float anisotropic_view_term;  // |(alpha_t T.V, alpha_b B.V, N.V)|: view_term's anisotropic form
#endif
#ifdef PBR_IRIDESCENCE
    vec3 film_fresnel;  // the thin film's Fresnel at N.V
    float iridescence;
#endif
#ifdef PBR_TRANSMISSION
    vec3 through_tint;        // (1 - metallic) transmission base: the share of a light behind that passes
    float through_alpha2;     // alpha_t^2 of the transmitted lobe
    float through_view_term;  // view_term at alpha_t
    vec3 through_f0;          // the dielectric's Fresnel
    float through_f90;
#ifdef TRANSMISSION_VOLUME
    float thickness;          // the volume's at the point (its map's)
#endif
#endif
};

#if defined(PBR_DIELECTRIC_SPECULAR) || defined(PBR_TRANSMISSION)
vec3 fresnel_schlick_f90(vec3 f0, vec3 f90, float v_dot_h) {
    float m = 1.0 - v_dot_h;
    float m2 = m * m;
    return f0 + (f90 - f0) * (m2 * m2 * m);
}
#endif

// pi D V of GGX at roughness alpha^2 = alpha2 (pbr_direct's lobe), view_term the view's
// sqrt((N.V)^2 (1 - alpha2) + alpha2): the coat's, the transmitted light's, a sphere light's
float ggx_lobe(float n_dot_h, float n_dot_l, float n_dot_v, float alpha2, float view_term) {
    float k = 1.0 - n_dot_h * n_dot_h * (1.0 - alpha2);
    float light_term = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - alpha2) + alpha2);
    return 0.5 * alpha2 / max(k * k * (n_dot_l * view_term + light_term), 1e-20);
}

#ifdef PBR_CLEARCOAT

// c Fc: how much of the light a coat of weight c takes at an angle of cosine ``cosine``
float coat_fresnel(float c, float cosine) {
    float m = 1.0 - cosine;
    float m2 = m * m;
    return c * (0.04 + 0.96 * (m2 * m2 * m));
}
#endif

PbrView pbr_view(vec3 n, vec3 v, Surface s) {
    PbrView p;
    p.n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    float alpha = max(s.roughness * s.roughness, PBR_MIN_ALPHA);
    p.alpha2 = alpha * alpha;
    p.view_term = sqrt(p.n_dot_v * p.n_dot_v * (1.0 - p.alpha2) + p.alpha2);
#ifdef PBR_DIELECTRIC_SPECULAR
    p.f0 = mix(s.dielectric_f0, s.base, s.metallic);
    p.f90 = mix(vec3(s.dielectric_f90), vec3(1.0), s.metallic);
#else
    p.f0 = mix(vec3(0.04), s.base, s.metallic);
#endif
    p.diffuse = s.base * (1.0 - s.metallic);
#ifdef PBR_TRANSMISSION
    p.diffuse *= 1.0 - s.transmission;
#endif
#ifdef PBR_CLEARCOAT
    float coat_alpha = max(s.clearcoat_roughness * s.clearcoat_roughness, PBR_MIN_ALPHA);
    p.coat_alpha2 = coat_alpha * coat_alpha;
#ifdef PBR_COAT_NORMAL
    p.coat_normal = s.clearcoat_normal;
    p.coat_n_dot_v = clamp(dot(s.clearcoat_normal, v), 0.0, 1.0);
    p.coat_view_term = sqrt(p.coat_n_dot_v * p.coat_n_dot_v * (1.0 - p.coat_alpha2) + p.coat_alpha2);
    p.coat = coat_fresnel(s.clearcoat, p.coat_n_dot_v);
#else
    p.coat_view_term = sqrt(p.n_dot_v * p.n_dot_v * (1.0 - p.coat_alpha2) + p.coat_alpha2);
    p.coat = coat_fresnel(s.clearcoat, p.n_dot_v);
#endif
#endif
#ifdef PBR_SHEEN
    p.sheen_color = s.sheen_color;
    p.sheen_roughness = s.sheen_roughness;
    p.sheen_alpha = sheen_alpha(s.sheen_roughness);
    p.sheen_through_view = sheen_through(s.sheen_color, s.sheen_roughness, p.n_dot_v);
#endif
#ifdef PBR_IRIDESCENCE
    p.film_fresnel = thin_film_fresnel(p.n_dot_v, s.iridescence_ior, s.iridescence_thickness, p.f0);
    p.iridescence = s.iridescence;
#endif
#ifdef PBR_TRANSMISSION
    p.through_tint = s.base * (1.0 - s.metallic) * s.transmission;
#ifdef TRANSMISSION_VOLUME
    p.thickness = s.thickness;
#endif
    float through_alpha = max(alpha * clamp(2.0 * u_transmission_ior - 2.0, 0.0, 1.0), PBR_MIN_ALPHA);
    p.through_alpha2 = through_alpha * through_alpha;
    p.through_view_term = sqrt(p.n_dot_v * p.n_dot_v * (1.0 - p.through_alpha2) + p.through_alpha2);
#ifdef PBR_DIELECTRIC_SPECULAR
    p.through_f0 = s.dielectric_f0;
    p.through_f90 = s.dielectric_f90;
#else
    p.through_f0 = vec3(0.04);
    p.through_f90 = 1.0;
#endif
#endif
#ifdef PBR_ANISOTROPY
    p.anisotropy_t = s.anisotropy_t;
    p.anisotropy_b = cross(n, s.anisotropy_t);
    p.alpha_t = mix(alpha, 1.0, s.anisotropy * s.anisotropy);
    p.alpha_b = alpha;
    p.anisotropic_view_term = length(vec3(p.alpha_t * dot(p.anisotropy_t, v), p.alpha_b * dot(p.anisotropy_b, v),
                                          p.n_dot_v));
#endif
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
#ifdef PBR_ANISOTROPY
    // KHR_materials_anisotropy: Burley's GGX of alpha_t along t, alpha_b along b, pi D =
    // 1 / (alpha_t alpha_b k^2), k = (T.H / alpha_t)^2 + (B.H / alpha_b)^2 + (N.H)^2, with its
    // height-correlated Smith V (the isotropic forms at alpha_t = alpha_b)
    float t_dot_h = dot(p.anisotropy_t, l_plus_v) * inverse_length / p.alpha_t;
    float b_dot_h = dot(p.anisotropy_b, l_plus_v) * inverse_length / p.alpha_b;
    float k = t_dot_h * t_dot_h + b_dot_h * b_dot_h + n_dot_h * n_dot_h;
    float light_term = p.n_dot_v * length(vec3(p.alpha_t * dot(p.anisotropy_t, l), p.alpha_b * dot(p.anisotropy_b, l),
                                               n_dot_l));
    float specular = 0.5 / (p.alpha_t * p.alpha_b * k * k * (n_dot_l * p.anisotropic_view_term + light_term));
#else
    float k = 1.0 - n_dot_h * n_dot_h * (1.0 - p.alpha2);
    float light_term = p.n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - p.alpha2) + p.alpha2);
    float specular = 0.5 * p.alpha2 / (k * k * (n_dot_l * p.view_term + light_term));  // pi D V
#endif
#ifdef PBR_DIELECTRIC_SPECULAR
    vec3 fresnel = fresnel_schlick_f90(p.f0, p.f90, v_dot_h);
#else
    vec3 fresnel = fresnel_schlick(p.f0, v_dot_h);
#endif
#if defined(PBR_SHEEN) || defined(PBR_CLEARCOAT) || defined(PBR_IRIDESCENCE)
#ifdef PBR_IRIDESCENCE
    // the film's Fresnel mixed into the specular one, its largest channel into what the
    // diffuse part loses
    vec3 diffuse_fresnel = mix(fresnel, vec3(max(p.film_fresnel.r, max(p.film_fresnel.g, p.film_fresnel.b))),
                               p.iridescence);
    vec3 layered = (1.0 - diffuse_fresnel) * p.diffuse + mix(fresnel, p.film_fresnel, p.iridescence) * specular;
#else
    vec3 layered = p.diffuse + fresnel * (specular - p.diffuse);
#endif
#ifdef PBR_SHEEN
    float through = min(p.sheen_through_view, sheen_through(p.sheen_color, p.sheen_roughness, n_dot_l));
    layered = layered * through + p.sheen_color * sheen_lobe(n_dot_h, n_dot_l, p.n_dot_v, p.sheen_alpha);
#endif
#ifdef PBR_CLEARCOAT
#ifdef PBR_COAT_NORMAL
    // the coat's lobe about its own normal (none where the light is below it)
    float coat_n_dot_l = dot(p.coat_normal, l);
    float coat_specular = coat_n_dot_l > 0.0
        ? ggx_lobe(dot(p.coat_normal, l_plus_v) * inverse_length, coat_n_dot_l, p.coat_n_dot_v, p.coat_alpha2,
                    p.coat_view_term) * coat_n_dot_l / n_dot_l
        : 0.0;
#else
    float coat_specular = ggx_lobe(n_dot_h, n_dot_l, p.n_dot_v, p.coat_alpha2, p.coat_view_term);
#endif
    layered = layered * (1.0 - p.coat) + p.coat * coat_specular;
#endif
    return layered * n_dot_l;
#else
    return (p.diffuse + fresnel * (specular - p.diffuse)) * n_dot_l;
#endif
}

#ifdef PBR_TRANSMISSION
// pi f_t(l, v) |N.L| for a light in direction l behind the surface (N.L < 0; zero in front):
// KHR_materials_transmission's BTDF (see the header). The base layer's alone: a coat or a
// sheen over it does not dim it, as they do not dim the refracted copy.
vec3 pbr_through(vec3 n, vec3 l, vec3 v, PbrView p) {
    float n_dot_l = -dot(n, l);  // N.L_m of the mirrored direction
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    vec3 l_plus_v = l + 2.0 * n_dot_l * n + v;
    float length2 = dot(l_plus_v, l_plus_v);
    float inverse_length = inversesqrt(max(length2, 1e-20));
    float n_dot_h = dot(n, l_plus_v) * inverse_length;
    float v_dot_h = min(0.5 * length2 * inverse_length, 1.0);
    float specular = ggx_lobe(n_dot_h, n_dot_l, p.n_dot_v, p.through_alpha2, p.through_view_term);
    vec3 fresnel = fresnel_schlick_f90(p.through_f0, vec3(p.through_f90), v_dot_h);
    return p.through_tint * (1.0 - fresnel) * (specular * n_dot_l);
}
#endif

// What a uniform ambient light of radiance 1 gives: the BRDF integrated over the
// hemisphere, from the fitted integrals of lighting/ambient_brdf.glsl: specular F0 A + B,
// diffuse (1 - metallic) base (1 - F0) (1 - Cd). Kept apart, since the environment light
// weighs its diffuse and specular lookups by them.
struct PbrAmbientWeights {
    vec3 diffuse;
    vec3 specular;
#if defined(PBR_SHEEN) || defined(PBR_CLEARCOAT)
    float base_scale;  // what the sheen and coat let through to the base (diffuse and specular carry it)
#endif
#ifdef PBR_SHEEN
    vec3 sheen;        // sheen E(N.V) (times what the coat lets through): the sheen's own reflection
#endif
#ifdef PBR_CLEARCOAT
    float coat;        // c (0.04 A_c + B_c): the coat's own reflection, at its roughness
#endif
};

#ifdef PBR_ANISOTROPY
// The roughness of the isotropic lobe that reflects about what the anisotropic one does of
// a uniform light: alpha = sqrt((alpha_t^2 + alpha_b^2) / 2), within 0.016 of the
// anisotropic lobe's directional albedo (docs/scene-notes.md)
float anisotropic_ambient_roughness(float roughness, float anisotropy) {
    float alpha = max(roughness * roughness, PBR_MIN_ALPHA);
    float alpha_t = mix(alpha, 1.0, anisotropy * anisotropy);
    return sqrt(sqrt(0.5 * (alpha_t * alpha_t + alpha * alpha)));
}
#endif

PbrAmbientWeights pbr_ambient_weights(vec3 n, vec3 v, Surface s) {
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
#ifdef PBR_ANISOTROPY
    vec2 scale_bias = ambient_specular(n_dot_v, anisotropic_ambient_roughness(s.roughness, s.anisotropy));
#else
    vec2 scale_bias = ambient_specular(n_dot_v, s.roughness);
#endif
    PbrAmbientWeights w;
#ifdef PBR_DIELECTRIC_SPECULAR
    // with F90: the diffuse part keeps (1 - F0) - (F90 - F0) Cd, the specular F0 A + F90 B
    vec3 f0 = mix(s.dielectric_f0, s.base, s.metallic);
    vec3 f90 = mix(vec3(s.dielectric_f90), vec3(1.0), s.metallic);
    w.diffuse = s.base * (1.0 - s.metallic) * ((1.0 - f0) - (f90 - f0) * ambient_diffuse_fresnel(n_dot_v));
    w.specular = f0 * scale_bias.x + f90 * scale_bias.y;
#else
    vec3 f0 = mix(vec3(0.04), s.base, s.metallic);
    w.diffuse = s.base * (1.0 - s.metallic) * (1.0 - f0) * (1.0 - ambient_diffuse_fresnel(n_dot_v));
    w.specular = f0 * scale_bias.x + scale_bias.y;
#endif
#ifdef PBR_IRIDESCENCE
    vec3 film = thin_film_fresnel(n_dot_v, s.iridescence_ior, s.iridescence_thickness, f0);
    w.specular = mix(w.specular, film * scale_bias.x + scale_bias.y, s.iridescence);
    w.diffuse = mix(w.diffuse, s.base * (1.0 - s.metallic) * (1.0 - max(film.r, max(film.g, film.b))), s.iridescence);
#endif
#ifdef PBR_TRANSMISSION
    w.diffuse *= 1.0 - s.transmission;
#endif
#if defined(PBR_SHEEN) || defined(PBR_CLEARCOAT)
    w.base_scale = 1.0;
#endif
#ifdef PBR_SHEEN
    w.base_scale = sheen_through(s.sheen_color, s.sheen_roughness, n_dot_v);
    w.sheen = s.sheen_color * sheen_albedo(n_dot_v, s.sheen_roughness);
#endif
#ifdef PBR_CLEARCOAT
#ifdef PBR_COAT_NORMAL
    float coat_n_dot_v = clamp(dot(s.clearcoat_normal, v), 0.0, 1.0);
#else
    float coat_n_dot_v = n_dot_v;
#endif
    vec2 coat_scale_bias = ambient_specular(coat_n_dot_v, s.clearcoat_roughness);
    float coat_through = 1.0 - coat_fresnel(s.clearcoat, coat_n_dot_v);
    w.base_scale *= coat_through;
#ifdef PBR_SHEEN
    w.sheen *= coat_through;
#endif
    w.coat = s.clearcoat * (0.04 * coat_scale_bias.x + coat_scale_bias.y);
#endif
#if defined(PBR_SHEEN) || defined(PBR_CLEARCOAT)
    w.diffuse *= w.base_scale;
    w.specular *= w.base_scale;
#endif
    return w;
}

vec3 pbr_ambient(vec3 n, vec3 v, Surface s) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    vec3 reflected = w.diffuse + w.specular;
#ifdef PBR_SHEEN
    reflected += w.sheen;
#endif
#ifdef PBR_CLEARCOAT
    reflected += vec3(w.coat);
#endif
    return reflected;
}
