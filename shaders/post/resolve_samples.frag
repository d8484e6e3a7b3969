// MSAA resolve: the average of the pixel's SAMPLES samples, in linear light (sampling an
// sRGB texture decodes, and writing an sRGB target encodes).
#include "post/sky_under.glsl"
uniform sampler2DMS u_color;
out vec4 frag_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < SAMPLES; ++i) {
        sum += texelFetch(u_color, p, i);
    }
    frag_color = sky_under(sum / float(SAMPLES));
}
