// Linear HDR colour -> display values: times the exposure (EXPOSURE), through a tone curve
// (TONE_MAP_ACES, TONE_MAP_AGX), then the exact sRGB transfer function (IEC 61966-2-1,
// not pow(1/2.2)), a plain gamma, or linear; then 8-bit storage rounds to nearest.
uniform float u_gamma;
#ifdef EXPOSURE
uniform float u_exposure;  // 2^render.exposure
#endif
#if defined(TONE_MAP_ACES)
#include "post/tone_aces.glsl"
#elif defined(TONE_MAP_AGX)
#include "post/tone_agx.glsl"
#endif
#include "common/srgb.glsl"

vec4 encode_output(vec4 c) {
    vec3 scene = c.rgb;
#ifdef EXPOSURE
    scene *= u_exposure;
#endif
#if defined(TONE_MAP_ACES) || defined(TONE_MAP_AGX)
    scene = tone_map(scene);
#endif
    vec3 linear = clamp(scene, 0.0, 1.0);
#if defined(OUTPUT_SRGB)
    vec3 encoded = srgb_encode(linear);
#elif defined(OUTPUT_GAMMA)
    vec3 encoded = pow(linear, vec3(1.0 / u_gamma));
#else
    vec3 encoded = linear;
#endif
    return vec4(encoded, clamp(c.a, 0.0, 1.0));
}
