// Light data in a storage buffer, one array per light type. The counts are compile-time
// constants of the scene (N_DIR_LIGHTS...), so a scene without spot lights has no spot
// code at all, and there is no fixed cap on lights of any type.
//
// Positions are camera-relative world space, like v_position; directions are the way the
// light travels. color = rgb * intensity (zero while disabled).

struct DirLight {
    vec4 direction;
    vec4 color;
    vec4 shadow;       // x: first shadow view, or -1
};

struct PointLight {
    vec4 position;
    vec4 color;
    vec4 attenuation;  // constant, linear, quadratic
    vec4 shadow;       // x: first of its six shadow views, or -1
};

struct SpotLight {
    vec4 position;
    vec4 direction;
    vec4 color;
    vec4 attenuation;  // constant, linear, quadratic
    vec4 cone;         // cos(inner), cos(outer)
    vec4 shadow;
};

layout(std430, binding = 0) readonly buffer Lights {
#if N_DIR_LIGHTS > 0
    DirLight dir_lights[N_DIR_LIGHTS];
#endif
#if N_POINT_LIGHTS > 0
    PointLight point_lights[N_POINT_LIGHTS];
#endif
#if N_SPOT_LIGHTS > 0
    SpotLight spot_lights[N_SPOT_LIGHTS];
#endif
    vec4 lights_end;
};

float attenuation(vec4 coefficients, float distance) {
    float denominator = coefficients.x + coefficients.y * distance + coefficients.z * distance * distance;
    return 1.0 / max(denominator, 1e-6);
}

// 1 inside the inner cone, 0 outside the outer, smooth between; inner == outer is a hard edge.
float spot_cone(vec4 cone, float cos_angle) {
    float width = cone.x - cone.y;
    if (width <= 0.0) {
        return cos_angle >= cone.y ? 1.0 : 0.0;
    }
    return smoothstep(0.0, 1.0, clamp((cos_angle - cone.y) / width, 0.0, 1.0));
}
