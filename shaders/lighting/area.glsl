// One-sided rectangle and disk lights (type: rect, type: disk), only in scenes with one.
// Their radiance is colour x intensity / pi, so a light filling the whole hemisphere above
// a surface gives what a directional light of that intensity gives it head-on.
//
// Diffuse: the polygon's irradiance by Lambert's edge integral, the form factor
// n . (1 / 2 pi) sum over edges of angle(w_i, w_i+1) normalize(w_i x w_i+1), w_i the unit
// vectors to its corners (exact while the light is above the surface's horizon); a disk is
// the regular 12-gon of its area. Specular, pbr model: linearly transformed cosines (below,
// ltc_specular), rectangles and disks alike. Specular, Phong and Blinn-Phong: the
// representative point (Karis 2013), the light's point nearest the mirror ray, with the
// lobe's peak normalised as a sphere light's of the same solid angle. docs/scene-notes.md
// has the equations of the representative point.

const int DISK_SIDES = 12;
// circumradius over radius of the regular 12-gon of a disk's area: sqrt(2 pi / (12 sin(pi / 6)))
const float DISK_POLYGON_SCALE = 1.0233267;

bool area_is_disk(AreaLight light) {
    return light.position.w > 0.5;
}

// Corner k of the light's polygon (4 for a rectangle, DISK_SIDES for a disk), wound so
// that seen from in front of the light they turn the same way.
vec3 area_corner(AreaLight light, int k) {
    if (area_is_disk(light)) {
        float angle = 6.28318531 * float(k) / float(DISK_SIDES);
        return light.position.xyz + DISK_POLYGON_SCALE * (cos(angle) * light.axis_u.xyz + sin(angle) * light.axis_v.xyz);
    }
    vec2 corner = k == 0 ? vec2(-1.0, -1.0) : (k == 1 ? vec2(1.0, -1.0) : (k == 2 ? vec2(1.0, 1.0) : vec2(-1.0, 1.0)));
    return light.position.xyz + corner.x * light.axis_u.xyz + corner.y * light.axis_v.xyz;
}

// angle(a, b) normalize(a x b) for unit vectors a, b
vec3 edge_vector(vec3 a, vec3 b) {
    vec3 normal = cross(a, b);
    float sine = length(normal);
    return sine > 1e-7 ? normal * (acos(clamp(dot(a, b), -1.0, 1.0)) / sine) : vec3(0.0);
}

// The light's irradiance vector at p over pi L: its dot product with the normal is the
// form factor.
vec3 area_irradiance_vector(AreaLight light, vec3 p) {
    int count = area_is_disk(light) ? DISK_SIDES : 4;
    vec3 first = safe_normalize(area_corner(light, 0) - p);
    vec3 previous = first;
    vec3 sum = vec3(0.0);
    for (int k = 1; k <= DISK_SIDES; ++k) {
        vec3 next = k >= count ? first : safe_normalize(area_corner(light, k) - p);
        sum += k <= count ? edge_vector(previous, next) : vec3(0.0);
        previous = next;
    }
    sum /= 6.28318531;
    // towards the light, whichever way the corners turn seen from p
    return dot(sum, light.position.xyz - p) < 0.0 ? -sum : sum;
}

// Whether any of the light is above the horizon of a surface at p with normal n (its
// bounding rectangle's corners, for a disk).
bool area_above_horizon(AreaLight light, vec3 p, vec3 n) {
    vec3 to_centre = light.position.xyz - p;
    return dot(to_centre, n) + abs(dot(light.axis_u.xyz, n)) + abs(dot(light.axis_v.xyz, n)) > 0.0;
}

// The solid angle the light subtends at p: a disk of its area facing p at its distance,
// tilted by its cosine (exact far away, 2 pi at its surface).
float area_solid_angle(AreaLight light, vec3 p) {
    vec3 to_light = light.position.xyz - p;
    float distance2 = max(dot(to_light, to_light), 1e-20);
    float area = area_is_disk(light) ? 3.14159265 * dot(light.axis_u.xyz, light.axis_u.xyz)
                                     : 4.0 * length(light.axis_u.xyz) * length(light.axis_v.xyz);
    float facing = max(dot(-to_light, light.normal.xyz), 0.0) * inversesqrt(distance2);
    float projected = area * facing / (3.14159265 * distance2);
    return 6.28318531 * (1.0 - inversesqrt(1.0 + projected));
}

// The direction to the light's point nearest the mirror ray r: where r meets its plane
// (or, where r runs away from it, the point as far along r as the light's centre), held to
// the rectangle or disk.
vec3 area_representative(AreaLight light, vec3 p, vec3 r) {
    vec3 centre = light.position.xyz;
    vec3 facing = light.normal.xyz;
    float across = dot(r, facing);
    float along = across < -1e-4 ? dot(centre - p, facing) / across : length(centre - p);
    vec3 offset = p + r * max(along, 0.0) - centre;
    offset -= facing * dot(offset, facing);
    float half_u = length(light.axis_u.xyz);
    float half_v = length(light.axis_v.xyz);
    vec3 u = light.axis_u.xyz / half_u;
    vec3 v = light.axis_v.xyz / half_v;
    vec2 local = vec2(dot(offset, u), dot(offset, v));
    if (area_is_disk(light)) {
        local *= min(1.0, half_u / max(length(local), 1e-20));
    } else {
        local = clamp(local, -vec2(half_u, half_v), vec2(half_u, half_v));
    }
    return safe_normalize(centre + u * local.x + v * local.y - p, -facing);
}

// sin^2 of the angular radius of the cone of solid angle omega (2 pi (1 - cos))
float cone_sin2(float omega) {
    float cosine = 1.0 - omega / 6.28318531;
    return clamp(1.0 - cosine * cosine, 0.0, 0.9999);
}

#ifdef SHADING_PBR
// Specular: linearly transformed cosines (Heitz, Dupuy, Hill and Neubelt 2016). The GGX
// lobe f cos at (roughness, N.V) is, to a fitted approximation, the cosine distribution
// transformed by a matrix M, in the frame of N and V's tangent T (x) and N x T (y), times
// its magnitude; the lobe's integral over the polygon is then the cosine's over the
// polygon transformed by M^-1: the clipped form factor below. u_ltc holds the fit
// (benchmarks/ltc/fit_ltc.py wrote scenerender/rendering/ltc_ggx.npy): rows 0 .. n-1 M^-1's
// (m02, m11, m20, m22) with m00 = 1, rows n .. 2n-1 the magnitude and its Fresnel part.
uniform sampler2D u_ltc;

// angle(a, b) normalize(a x b) for unit vectors a, b: edge_vector with angle / sin(angle) as
// a polynomial in the cosine x on [0, 1] (fitted here, relative error under 4e-5), and for
// x < 0 through angle(-x) = pi - angle(x).
vec3 ltc_edge(vec3 a, vec3 b) {
    float x = dot(a, b);
    float y = abs(x);
    float ratio = ((((-0.0666625 * y + 0.27372869) * y - 0.53832206) * y + 0.75800197) * y - 0.99752641) * y + 1.57074165;
    ratio = x < 0.0 ? 3.14159265 * inversesqrt(max(1.0 - x * x, 1e-12)) - ratio : ratio;
    return cross(a, b) * ratio;
}

// The form factor of the light's polygon whose corners relative to the shaded point go
// through to_lobe, cut by the horizon z = 0. Not clipped: the polygon's vector form factor F
// (its irradiance vector over pi L) stands for a sphere of the same form factor |F| = sin^2
// sigma in the same direction, and the horizon cuts that sphere (sphere_cosine, exact for
// the sphere; Heitz and Hill 2017's approximation); exact while all of it is above.
float ltc_form_factor(AreaLight light, vec3 p, mat3 to_lobe) {
    vec3 centre = to_lobe * (light.position.xyz - p);
    vec3 sum = vec3(0.0);
    if (area_is_disk(light)) {
        vec3 first = normalize(to_lobe * (area_corner(light, 0) - p));
        vec3 previous = first;
        for (int k = 1; k <= DISK_SIDES; ++k) {
            vec3 next = k == DISK_SIDES ? first : normalize(to_lobe * (area_corner(light, k) - p));
            sum += ltc_edge(previous, next);
            previous = next;
        }
    } else {
        vec3 u = to_lobe * light.axis_u.xyz;
        vec3 v = to_lobe * light.axis_v.xyz;
        vec3 w0 = normalize(centre - u - v);
        vec3 w1 = normalize(centre + u - v);
        vec3 w2 = normalize(centre + u + v);
        vec3 w3 = normalize(centre - u + v);
        sum = ltc_edge(w0, w1) + ltc_edge(w1, w2) + ltc_edge(w2, w3) + ltc_edge(w3, w0);
    }
    sum /= 6.28318531;
    float form = length(sum);
    // towards the light, whichever way the corners turn
    float cosine = (dot(sum, centre) < 0.0 ? -sum.z : sum.z) / max(form, 1e-20);
    float sin2 = min(form, 0.9999);
    return sin2 * sphere_cosine(cosine, sin2);
}

vec3 ltc_specular(AreaLight light, vec3 p, vec3 n, vec3 v, PbrView view) {
    vec3 tangent = v - n * dot(v, n);
    float tangent2 = dot(tangent, tangent);
    if (tangent2 < 1e-10) {
        tangent = abs(n.x) < 0.9 ? cross(n, vec3(1.0, 0.0, 0.0)) : cross(n, vec3(0.0, 1.0, 0.0));
        tangent2 = dot(tangent, tangent);
    }
    tangent *= inversesqrt(tangent2);
    mat3 to_frame = transpose(mat3(tangent, cross(n, tangent), n));
    vec2 size = vec2(textureSize(u_ltc, 0));  // (view columns, 2 x roughness rows)
    float rows = 0.5 * size.y;
    float roughness = sqrt(sqrt(view.alpha2));
    vec2 cell = vec2(sqrt(1.0 - view.n_dot_v), roughness) * (vec2(size.x, rows) - 1.0) + 0.5;
    vec4 m = texture(u_ltc, cell / size);
    vec2 lobe = texture(u_ltc, (cell + vec2(0.0, rows)) / size).xy;
    // columns: M^-1 = [[1, 0, m02], [0, m11, 0], [m20, 0, m22]]
    mat3 inverse_m = mat3(vec3(1.0, 0.0, m.z), vec3(0.0, m.y, 0.0), vec3(m.x, 0.0, m.w));
    float form = ltc_form_factor(light, p, inverse_m * to_frame);
    return (view.f0 * (lobe.x - lobe.y) + lobe.y) * form;
}

vec3 shade_area(AreaLight light, vec3 radiance, vec3 p, vec3 n, vec3 v, PbrView view) {
    float form = max(dot(area_irradiance_vector(light, p), n), 0.0);
    // the diffuse part as before (its Fresnel weight at the representative point)
    vec3 ls = area_representative(light, p, reflect(-v, n));
    return radiance * (pbr_sized(n, ls, v, form, 0.0, view) + ltc_specular(light, p, n, v, view));
}
#define SHADE_AREA(light, radiance) shade_area(light, radiance, p, n, v, pbr)
#else
vec3 shade_area(AreaLight light, vec3 radiance, vec3 p, vec3 n, vec3 v, Surface s) {
    float form = max(dot(area_irradiance_vector(light, p), n), 0.0);
    vec3 ls = area_representative(light, p, reflect(-v, n));
    float omega = area_solid_angle(light, p);
    float alpha = sqrt(2.0 / (max(u_shininess, 0.0) + 2.0));
    float lobe = dot(n, ls) > 0.0 ? specular_lobe(n, ls, v, u_shininess) * sphere_normalization(alpha, cone_sin2(omega)) : 0.0;
    return radiance * (s.base * form + s.specular * lobe * omega / 3.14159265);
}
#define SHADE_AREA(light, radiance) shade_area(light, radiance, p, n, v, s)
#endif
