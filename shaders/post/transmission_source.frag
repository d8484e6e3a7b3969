// The opaque scene that transmissive surfaces see through (rendering/passes/transmission.py):
// the colour target's pixel, averaged over its SAMPLES samples in linear light where it is
// multisampled, with the sky added behind them where the resolve adds it.
#include "post/sky_under.glsl"
#if SAMPLES > 1
uniform sampler2DMS u_color;
#else
uniform sampler2D u_color;
#endif
out vec4 frag_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
#if SAMPLES > 1
    vec4 sum = vec4(0.0);
    for (int i = 0; i < SAMPLES; ++i) {
        sum += texelFetch(u_color, p, i);
    }
    frag_color = sky_under(sum / float(SAMPLES));
#else
    frag_color = texelFetch(u_color, p, 0);
#endif
}
