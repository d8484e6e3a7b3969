// KHR_materials_iridescence's thin-film Fresnel, for the pbr model's PBR_IRIDESCENCE layer
// (lighting/pbr.glsl); scenerender/raytrace/shading.py (thin_film_fresnel) has the same
// formulas for the reference. A film of index n and thickness d nanometres over a base of
// F0 f0, in air: Schlick's Fresnel at both interfaces, and the first two orders of their
// interference integrated over the spectrum (Belcour and Barla 2017, the extension's
// Gaussian fit of the XYZ sensitivities), the optical path difference 2 n d cos theta_2.

const mat3 XYZ_TO_REC709 = mat3(
     3.2404542, -0.9692660,  0.0556434,
    -1.5371385,  1.8760108, -0.2040259,
    -0.4985314,  0.0415560,  1.0572252);

// linear RGB of the spectral integral of a phase shift: opd nanometres, shift radians
vec3 film_sensitivity(float opd, vec3 shift) {
    float phase = 6.283185307179586 * opd * 1.0e-9;
    vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    vec3 xyz = val * sqrt(6.283185307179586 * var) * cos(pos * phase + shift) * exp(-phase * phase * var);
    xyz.x += 9.7470e-14 * sqrt(6.283185307179586 * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x)
             * exp(-4.5282e+09 * phase * phase);
    return XYZ_TO_REC709 * (xyz / 1.0685e-7);
}

vec3 thin_film_fresnel(float cos_theta, float film_ior, float thickness, vec3 base_f0) {
    float cos1 = clamp(cos_theta, 0.0, 1.0);
    float sin2_sq = (1.0 / (film_ior * film_ior)) * (1.0 - cos1 * cos1);
    float cos2_sq = 1.0 - sin2_sq;
    if (cos2_sq < 0.0) {
        return vec3(1.0);  // total internal reflection
    }
    float cos2 = sqrt(cos2_sq);
    float r0 = (film_ior - 1.0) / (film_ior + 1.0);
    r0 *= r0;
    float m1 = 1.0 - cos1;
    float r12 = r0 + (1.0 - r0) * (m1 * m1 * m1 * m1 * m1);
    float t121 = 1.0 - r12;
    float phi12 = film_ior < 1.0 ? 3.141592653589793 : 0.0;
    float phi21 = 3.141592653589793 - phi12;
    vec3 root = sqrt(clamp(base_f0, 0.0, 0.9999));
    vec3 base_ior = (1.0 + root) / (1.0 - root);
    vec3 r1 = (base_ior - film_ior) / (base_ior + film_ior);
    r1 *= r1;
    float m2 = 1.0 - cos2;
    vec3 r23 = r1 + (1.0 - r1) * (m2 * m2 * m2 * m2 * m2);
    vec3 phi23 = mix(vec3(0.0), vec3(3.141592653589793), lessThan(base_ior, vec3(film_ior)));
    float opd = 2.0 * film_ior * thickness * cos2;
    vec3 phi = vec3(phi21) + phi23;
    vec3 r123 = clamp(r12 * r23, 1e-5, 0.9999);
    vec3 amplitude = sqrt(r123);
    vec3 rs = t121 * t121 * r23 / (1.0 - r123);
    vec3 result = r12 + rs;
    vec3 cm = rs - t121;
    for (int order = 1; order <= 2; ++order) {
        cm *= amplitude;
        result += cm * 2.0 * film_sensitivity(float(order) * opd, float(order) * phi);
    }
    return max(result, vec3(0.0));
}
