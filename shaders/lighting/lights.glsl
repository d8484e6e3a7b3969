// Light data, one array per light type. The counts are compile-time constants of the
// scene (N_DIR_LIGHTS...), so a scene without spot lights has no spot code at all. The
// arrays sit in a uniform block when they fit (LIGHTS_IN_UNIFORM_BLOCK: the cheapest
// memory for a shader to read), else in a storage buffer, so there is no fixed cap on
// lights of any type. Every member is a vec4: std140 and std430 lay them out alike.
//
// Positions are camera-relative world space, like v_position; directions are the way the
// light travels. color = rgb * intensity (zero while disabled).

struct DirLight {
    vec4 direction;
    vec4 color;
    vec4 shadow;       // x: first shadow view, or -1
};

struct PointLight {
    vec4 position;     // w: 1 / its range (KHR_lights_punctual), 0 without one
    vec4 color;
    vec4 attenuation;  // constant, linear, quadratic
    vec4 shadow;       // x: first of its six shadow views, or -1
};

struct SpotLight {
    vec4 position;     // w: 1 / its range, 0 without one
    vec4 direction;
    vec4 color;
    vec4 attenuation;  // constant, linear, quadratic
    vec4 cone;         // cos(inner), cos(outer), the falloff between them: 0 smoothstep, 1 squared
    vec4 shadow;
};

#ifdef N_AREA_LIGHTS
// A one-sided rectangle or disk (lighting/area.glsl), only in scenes with one.
struct AreaLight {
    vec4 position;     // centre; w: 0 rectangle, 1 disk
    vec4 normal;       // the way it faces; w: the radius of the disk of its area (soft shadows)
    vec4 axis_u;       // half its width along its u axis
    vec4 axis_v;       // half its height along its v axis
    vec4 color;        // rgb * intensity: its radiance times pi
    vec4 shadow;
};
#endif

#ifdef LIGHTS_IN_UNIFORM_BLOCK
layout(std140, binding = 0) uniform Lights {
#else
layout(std430, binding = 0) readonly buffer Lights {
#endif
#if N_DIR_LIGHTS > 0
    DirLight dir_lights[N_DIR_LIGHTS];
#endif
#if N_POINT_LIGHTS > 0
    PointLight point_lights[N_POINT_LIGHTS];
#endif
#if N_SPOT_LIGHTS > 0
    SpotLight spot_lights[N_SPOT_LIGHTS];
#endif
#ifdef N_AREA_LIGHTS
    AreaLight area_lights[N_AREA_LIGHTS];
#endif
    vec4 lights_end;
};

float attenuation(vec4 coefficients, float distance) {
    float denominator = coefficients.x + coefficients.y * distance + coefficients.z * distance * distance;
    return 1.0 / max(denominator, 1e-6);
}

#ifdef LIGHT_RANGE
// KHR_lights_punctual's range, the specification's recommended window over the falloff:
// clamp(1 - (d / range)^4, 0, 1), no light at the range and beyond. Only in scenes where a
// light has a range; inverse_range 0 (a light without one) gives 1.
float range_window(float inverse_range, float distance) {
    float x = distance * inverse_range;
    x *= x;
    return clamp(1.0 - x * x, 0.0, 1.0);
}
#endif

// Fraction of a pixel square where f >= 0, for f linear across it: t its value at the
// centre, g its change across the whole pixel along x and along y (absolute values). That
// is the distribution function of a sum of two uniform variables: a ramp |g.x| + |g.y|
// wide, with quadratic ends as wide as the smaller of the two (a box filter, what the
// pixel's samples converge to; a straight ramp is up to 0.125 off near an edge at 45
// degrees). A point exactly on the edge of a pixel-less edge (g = 0) counts as inside.
float edge_coverage(float t, vec2 g) {
    float hi = max(g.x, g.y);
    float lo = max(min(g.x, g.y), 1e-3 * hi);
    if (hi < 1e-20) {
        return t >= 0.0 ? 1.0 : 0.0;
    }
    float w = clamp(t + 0.5 * (hi + lo), 0.0, hi + lo);  // from where the pixel starts to cover
    float v = hi + lo - w;                                // to where it is fully covered
    float middle = (w - 0.5 * lo) / hi;
    return w < lo ? w * w / (2.0 * hi * lo) : (v < lo ? 1.0 - v * v / (2.0 * hi * lo) : middle);
}

// 1 inside the inner cone, 0 outside the outer, between them smoothstep of the linear ramp t
// from cos(outer) to cos(inner) (cone.z 0, a scene's spots) or t^2 (cone.z 1: a glTF file's,
// KHR_lights_punctual's implementation note); inner == outer is a hard edge.
// An edge sharper than the pixel is anti-aliased: the factor is the fraction of the pixel
// square inside the cone (edge_coverage), from cos_angle's change across the pixel along
// x and y (spot_pixel), for an edge at the middle of inner and outer.
float spot_cone(vec4 cone, float cos_angle, vec2 pixel) {
    float width = cone.x - cone.y;
    if (width <= pixel.x + pixel.y) {
        return edge_coverage(cos_angle - (cone.y + 0.5 * max(width, 0.0)), pixel);
    }
    float t = clamp((cos_angle - cone.y) / width, 0.0, 1.0);
    return cone.z > 0.5 ? t * t : smoothstep(0.0, 1.0, t);
}

// How much cos_angle = dot(-l, direction) changes across one pixel along x and along y,
// (|d/dx|, |d/dy|), from the position's derivatives dpdx, dpdy: analytic rather than
// fwidth(cos_angle), whose value some drivers get wrong for data read from storage buffers
// at triangle edges.
vec2 spot_pixel(vec3 to_light, float cos_angle, vec3 direction, vec3 dpdx, vec3 dpdy) {
    float distance = max(length(to_light), 1e-20);
    // gradient of dot(normalize(p - light), direction) with respect to p
    vec3 gradient = (direction + cos_angle * to_light / distance) / distance;
    return vec2(abs(dot(gradient, dpdx)), abs(dot(gradient, dpdy)));
}
