// Lights with a size: a uniform sphere (point and spot lights with a radius; a directional
// light with an angular diameter is a sphere at distance 1 whose radius is the tangent of
// its half angle). Included only where the scene has such a light, so a scene without one
// compiles the programs it always did. Power is that of the point light of the same
// intensity: the sphere's radiance is E / (pi sin^2 sigma), E the light's colour x
// intensity x attenuation at its centre and sigma the sphere's angular radius, which gives
// E N.L wherever the whole sphere is above the horizon. docs/scene-notes.md has the
// equations.

const float SIZED_PI = 3.14159265358979;

// The stand-in for N.L of a sphere of angular radius sigma (sin2 = sin^2 sigma) whose centre
// lies at cos_theta from the normal: its irradiance over pi L sin^2(sigma). N.L itself while
// the whole sphere is above the horizon (or 0 while it is wholly below); where the horizon
// cuts it, the exact integral over the visible part (Snyder 1996).
float sphere_cosine(float cos_theta, float sin2) {
    if (cos_theta * cos_theta >= sin2) {
        return max(cos_theta, 0.0);
    }
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 1e-12));
    float cot_sigma = sqrt(max(1.0 / sin2 - 1.0, 0.0));
    float y = clamp(-cot_sigma * cos_theta / sin_theta, -1.0, 1.0);
    float s = sin_theta * sqrt(max(1.0 - y * y, 0.0));
    float irradiance = (cos_theta * acos(y) - cot_sigma * s) * sin2 + atan(s, cot_sigma);
    return max(irradiance, 0.0) / (SIZED_PI * sin2);
}

// The representative point (Karis 2013): the direction to the point of the sphere nearest
// the mirror ray r, so the highlight takes the sphere's shape.
vec3 representative_direction(vec3 to_light, float radius, vec3 r) {
    vec3 centre_to_ray = dot(to_light, r) * r - to_light;
    float miss = length(centre_to_ray);
    return safe_normalize(to_light + centre_to_ray * clamp(radius / max(miss, 1e-20), 0.0, 1.0), r);
}

// A lobe of width alpha spread over the representative points keeps its energy if its
// peak drops by (alpha / alpha')^2, alpha' the width widened by the light's angular radius
// (Karis 2013's normalisation; widened here by half of sin sigma).
float sphere_normalization(float alpha, float sin2) {
    float widened = min(alpha + 0.5 * sqrt(sin2), 1.0);
    return (alpha * alpha) / max(widened * widened, 1e-12);
}

// sin^2 of the angular radius of a sphere of ``radius`` whose centre is ``to_light`` away;
// a point inside it sees a whole hemisphere of it (kept just below 1).
float sphere_sin2(vec3 to_light, float radius) {
    return min(radius * radius / max(dot(to_light, to_light), 1e-20), 0.9999);
}

#ifdef SHADING_PBR
// pi f E for a sphere light: the diffuse part from the sphere's irradiance (diffuse_cos,
// sphere_cosine), the specular part at the representative direction ls, its peak
// normalised.
vec3 pbr_sized(vec3 n, vec3 ls, vec3 v, float diffuse_cos, float normalization, PbrView p) {
    float n_dot_l = max(dot(n, ls), 0.0);
    vec3 l_plus_v = ls + v;
    float length2 = dot(l_plus_v, l_plus_v);
    float inverse_length = inversesqrt(max(length2, 1e-20));
    float n_dot_h = dot(n, l_plus_v) * inverse_length;
    float v_dot_h = min(0.5 * length2 * inverse_length, 1.0);
    float specular = ggx_lobe(n_dot_h, n_dot_l, p.n_dot_v, p.alpha2, p.view_term);
    vec3 fresnel = fresnel_schlick(p.f0, v_dot_h);
    return p.diffuse * (1.0 - fresnel) * diffuse_cos + fresnel * (specular * normalization * n_dot_l);
}

vec3 shade_sized(vec3 to_light, float radius, vec3 radiance, vec3 n, vec3 v, PbrView p) {
    float sin2 = sphere_sin2(to_light, radius);
    float diffuse_cos = sphere_cosine(dot(n, safe_normalize(to_light, n)), sin2);
    vec3 ls = representative_direction(to_light, radius, reflect(-v, n));
    float normalization = sphere_normalization(sqrt(p.alpha2), sin2);
    return radiance * pbr_sized(n, ls, v, diffuse_cos, normalization, p);
}
#define SHADE_SIZED(to_light, radius, radiance) shade_sized(to_light, radius, radiance, n, v, pbr)
#else
// Phong and Blinn-Phong: the lobe's width as a GGX alpha (Blinn-Phong's exponent s is
// close to GGX with alpha^2 = 2 / (s + 2)), widened and normalised as above.
vec3 shade_sized(vec3 to_light, float radius, vec3 radiance, vec3 n, vec3 v, Surface s) {
    float sin2 = sphere_sin2(to_light, radius);
    float diffuse_cos = sphere_cosine(dot(n, safe_normalize(to_light, n)), sin2);
    vec3 ls = representative_direction(to_light, radius, reflect(-v, n));
    float alpha = sqrt(2.0 / (max(u_shininess, 0.0) + 2.0));
    float lobe = dot(n, ls) > 0.0 ? specular_lobe(n, ls, v, u_shininess) * sphere_normalization(alpha, sin2) : 0.0;
    return radiance * (s.base * diffuse_cos + s.specular * lobe);
}
#define SHADE_SIZED(to_light, radius, radiance) shade_sized(to_light, radius, radiance, n, v, s)
#endif

// Whether a sized light can reach a point: part of the sphere above its horizon.
bool sized_faces(vec3 n, vec3 to_light, float radius) {
    return dot(n, to_light) > -radius;
}
