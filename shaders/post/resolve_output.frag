// MSAA resolve and output transform in one pass: the average of the pixel's SAMPLES linear
// samples (what a resolve blit computes), then encoded as post/encode.glsl says. One
// full-screen pass instead of two, and no single-sampled HDR image in between.
#include "post/encode.glsl"
#include "post/sky_under.glsl"
uniform sampler2DMS u_color;
out vec4 frag_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < SAMPLES; ++i) {
        sum += texelFetch(u_color, p, i);
    }
    frag_color = encode_output(sky_under(sum / float(SAMPLES)));
}
