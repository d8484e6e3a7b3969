// Distance fog, mixed in linear space before the output transform.
uniform vec3 u_fog_color;
uniform float u_fog_density;
uniform vec2 u_fog_range;  // start, end (linear fog)

vec3 apply_fog(vec3 color, float distance) {
#if defined(FOG_EXP)
    float visibility = exp(-distance * u_fog_density);
#elif defined(FOG_EXP2)
    float d = distance * u_fog_density;
    float visibility = exp(-d * d);
#else
    float visibility = clamp((u_fog_range.y - distance) / (u_fog_range.y - u_fog_range.x), 0.0, 1.0);
#endif
    return mix(u_fog_color, color, visibility);
}
