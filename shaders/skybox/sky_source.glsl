// What the sky shows in direction d (camera-relative world): the cube-map skybox, or with
// SKY_ENVIRONMENT the environment light's equirectangular image, turned into the image's
// frame (u_env_to_image) and times colour x intensity (u_env_scale), at its full resolution.
#ifdef SKY_ENVIRONMENT
#include "lighting/environment_map.glsl"
uniform sampler2D u_env_source;
uniform mat3 u_env_to_image;
uniform vec3 u_env_scale;

vec3 sky_radiance(vec3 d) {
    return u_env_scale * textureLod(u_env_source, env_uv(u_env_to_image * normalize(d)), 0.0).rgb;
}
#else
uniform samplerCube u_skybox;

vec3 sky_radiance(vec3 d) {
    return texture(u_skybox, d).rgb;
}
#endif
