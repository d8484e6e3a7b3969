// One direction of bloom's separable Gaussian blur of linear light (rendering/passes/bloom.py).
// TAPS texels either side, weights normalised to sum to 1 (u_weights[0] is the centre).
// Off the image the blur reads the image mirrored about its edge (texel -1 is texel 0):
// with a symmetric kernel every texel then gives away exactly the light it receives, so
// the blurred image holds the same total light as the original.
// MIX (the second, vertical direction): out = (1 - u_strength) * original + u_strength * blur.
uniform sampler2D u_color;
uniform float u_weights[TAPS + 1];
#ifdef MIX
uniform sampler2D u_original;
uniform float u_strength;
#endif
out vec4 frag_color;

#ifdef HORIZONTAL
const ivec2 STEP = ivec2(1, 0);
#else
const ivec2 STEP = ivec2(0, 1);
#endif

ivec2 mirrored(ivec2 p, ivec2 size) {
    ivec2 low = max(p, -p - 1);                       // -1 -> 0, -2 -> 1 ...
    return min(low, 2 * size - 1 - low);              // size -> size - 1 ...
}

void main() {
    ivec2 size = textureSize(u_color, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 sum = texelFetch(u_color, p, 0).rgb * u_weights[0];
    for (int i = 1; i <= TAPS; ++i) {
        sum += (texelFetch(u_color, mirrored(p + i * STEP, size), 0).rgb
                + texelFetch(u_color, mirrored(p - i * STEP, size), 0).rgb) * u_weights[i];
    }
#ifdef MIX
    vec4 original = texelFetch(u_original, p, 0);
    frag_color = vec4(mix(original.rgb, sum, u_strength), original.a);
#else
    frag_color = vec4(sum, 1.0);
#endif
}
