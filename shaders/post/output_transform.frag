// The output transform of a single-sampled linear image (see post/encode.glsl).
#include "post/encode.glsl"
uniform sampler2D u_color;
out vec4 frag_color;

void main() {
    frag_color = encode_output(texelFetch(u_color, ivec2(gl_FragCoord.xy), 0));
}
