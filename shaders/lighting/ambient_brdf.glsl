// The pbr model under a uniform ambient light: the fitted hemisphere integrals of its
// BRDF (scenerender/raytrace/ambient_fit.py wrote this file; the reference reads the
// same numbers). Specular: F0 A + B, A and B polynomials of degree 6 in sqrt(N.V) and
// roughness; diffuse: (1 - F0) (1 - Cd), Cd of degree 4 in 1 - N.V.

const vec2 AMBIENT_SPECULAR[49] = vec2[](
    vec2(0.0408043308, 0.949882644),
    vec2(-0.0711299608, 0.138289272),
    vec2(18.3892199, -18.2057442),
    vec2(-63.8396684, 61.9882028),
    vec2(97.9378737, -93.6744465),
    vec2(-72.4755536, 68.4611258),
    vec2(20.9769217, -19.6138311),
    vec2(0.0328371165, 0.731330158),
    vec2(-44.9119569, 2.08145068),
    vec2(431.647941, -183.224783),
    vec2(-1456.95039, 964.14014),
    vec2(2266.39097, -1944.9121),
    vec2(-1666.32385, 1729.66435),
    vec2(469.880969, -568.699673),
    vec2(2.9022267, -9.11928056),
    vec2(347.952408, 56.7047579),
    vec2(-4188.71506, 1163.70393),
    vec2(15783.3218, -7413.13291),
    vec2(-26545.8326, 15920.6593),
    vec2(20791.2421, -14620.9563),
    vec2(-6194.32399, 4903.67552),
    vec2(10.1209749, 9.13466619),
    vec2(-1008.85574, -342.981245),
    vec2(13249.0034, -1921.15969),
    vec2(-53182.997, 17981.8173),
    vec2(93459.8343, -42533.1433),
    vec2(-75671.137, 40891.1542),
    vec2(23153.4138, -14090.1146),
    vec2(-33.9323491, 5.63400788),
    vec2(1391.97256, 694.544235),
    vec2(-19331.1614, 681.343976),
    vec2(81114.2436, -19523.6806),
    vec2(-146972.338, 52373.2911),
    vec2(121739.867, -53029.3575),
    vec2(-37921.655, 18806.5754),
    vec2(31.4960011, -11.5301558),
    vec2(-924.681763, -600.603227),
    vec2(13411.7858, 789.621929),
    vec2(-58187.0079, 9511.36504),
    vec2(107871.961, -30479.53),
    vec2(-90880.5598, 32773.1471),
    vec2(28686.3284, -11988.604),
    vec2(-9.6619183, 4.19923082),
    vec2(238.729309, 190.145017),
    vec2(-3592.97823, -512.313152),
    vec2(16004.0637, -1581.81067),
    vec2(-30203.8942, 6756.37296),
    vec2(25783.0511, -7811.51265),
    vec2(-8221.97524, 2956.6354));
const float AMBIENT_DIFFUSE[5] = float[](8.16307641e-05, 0.00204188384, 0.0092009068, 0.00799564472, 0.00883911473);

// (A, B) at N.V = n_dot_v and roughness r
vec2 ambient_specular(float n_dot_v, float r) {
    float s = sqrt(clamp(n_dot_v, 0.0, 1.0));
    vec2 sum = vec2(0.0);
    for (int i = 6; i >= 0; --i) {
        vec2 row = vec2(0.0);
        for (int j = 6; j >= 0; --j) {
            row = row * r + AMBIENT_SPECULAR[i * 7 + j];
        }
        sum = sum * s + row;
    }
    return sum;
}

// Cd at N.V = n_dot_v
float ambient_diffuse_fresnel(float n_dot_v) {
    float t = 1.0 - clamp(n_dot_v, 0.0, 1.0);
    float sum = 0.0;
    for (int k = 4; k >= 0; --k) {
        sum = sum * t + AMBIENT_DIFFUSE[k];
    }
    return sum;
}
