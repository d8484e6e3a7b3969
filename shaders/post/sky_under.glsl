// The sky behind a pixel's samples, added in the MSAA resolve (rendering/passes/sky.py).
// The forward passes store coverage in alpha (opaque surfaces 1, nothing 0, a
// transparent surface over nothing its blended alpha) over a transparent-black clear, so
// the mean of the samples is the image "over" an empty background, premultiplied: the
// sky fills what is left, 1 - alpha. Without SKY_UNDER the mean passes through.
#ifdef SKY_UNDER
in vec3 v_direction;  // skybox/skybox.vert
#include "skybox/sky_source.glsl"

vec4 sky_under(vec4 mean) {
    return vec4(mean.rgb + (1.0 - mean.a) * sky_radiance(v_direction), 1.0);
}
#else
vec4 sky_under(vec4 mean) {
    return mean;
}
#endif
