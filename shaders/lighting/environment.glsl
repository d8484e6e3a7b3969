// Light from the environment (world/environment.py), both terms looked up in the image's
// frame (u_env_to_image) and scaled by colour x intensity (u_env_scale):
// - diffuse: irradiance / pi from the image's spherical harmonics, as a small
//   equirectangular map (the radiance a white Lambert surface facing n reflects);
// - specular: the prefiltered levels (environment/prefilter.frag) at the reflection
//   direction, linearly between the two levels around the roughness.
#include "lighting/environment_map.glsl"
#ifdef ENV_VISIBILITY
#include "lighting/environment_visibility.glsl"
#endif

uniform sampler2D u_env_diffuse;
uniform sampler2D u_env_specular;
uniform mat3 u_env_to_image;
uniform vec3 u_env_scale;

vec3 env_diffuse(vec3 n) {
    return u_env_scale * textureLod(u_env_diffuse, env_uv(u_env_to_image * n), 0.0).rgb;
}

vec3 env_specular_level(vec2 uv, float level) {
    // kept half a texel inside the strip, so filtering never reads the next one
    float row = clamp(uv.y * ENV_STRIP_HEIGHT, 0.5, ENV_STRIP_HEIGHT - 0.5);
    return textureLod(u_env_specular, vec2(uv.x, (level * ENV_STRIP_HEIGHT + row) / (ENV_LEVELS * ENV_STRIP_HEIGHT)),
                      0.0).rgb;
}

vec3 env_specular(vec3 r, float roughness) {
#ifdef ENV_FOOTPRINT
    // the option `footprint`: a reflection narrower than the pixel's spread of directions
    // (a sun in a smooth metal) is averaged over that spread, as the pixel's area would,
    // rather than taken at its centre: GGX alpha at least half the spread in radians
    float spread = max(length(dFdx(r)), length(dFdy(r)));
    roughness = sqrt(max(roughness * roughness, 0.5 * spread));
#endif
    vec2 uv = env_uv(u_env_to_image * r);
    float level = clamp(roughness, 0.0, 1.0) * (ENV_LEVELS - 1.0);
    float below = floor(level);
    float above = min(below + 1.0, ENV_LEVELS - 1.0);
    return u_env_scale * mix(env_specular_level(uv, below), env_specular_level(uv, above), level - below);
}

#ifdef SHADING_PBR
// What the environment gives the pbr model: the split sum, whose BRDF half is the fitted
// hemisphere integral the uniform ambient light uses (pbr_ambient_weights).
vec3 pbr_environment(vec3 n, vec3 v, Surface s) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    return w.diffuse * env_diffuse(n) + w.specular * env_specular(reflect(-v, n), s.roughness);
}

// The same with the diffuse and specular terms scaled by what reaches the surface of each
// (seen: env_visibility's (V_d, V_s), with the other occlusions applied).
vec3 pbr_environment_seen(vec3 n, vec3 v, Surface s, vec2 seen) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    return w.diffuse * env_diffuse(n) * seen.x + w.specular * env_specular(reflect(-v, n), s.roughness) * seen.y;
}
#endif
