// The depth the gather blur (shaders/post/dof_gather.frag) gives each pixel: the inverse
// linear view depth of the nearest surface among its 3 x 3 neighbours (0: nothing drawn,
// infinitely far). The geometry prepass holds one surface a pixel, the resolved colour's
// edge pixels mix two: an edge pixel of a small light taken for the background behind it
// would spread the light's share over the background's wider circle (a halo round a sharp
// light, a far light's disc too wide); taken for the light, it spreads it as the light does.
uniform sampler2D u_gbuffer;
out vec4 frag_inverse_depth;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_gbuffer, 0) - 1;
    float nearest = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            float depth = texelFetch(u_gbuffer, clamp(p + ivec2(dx, dy), ivec2(0), last), 0).w;
            nearest = max(nearest, depth > 0.0 ? 1.0 / depth : 0.0);
        }
    }
    frag_inverse_depth = vec4(nearest, 0.0, 0.0, 1.0);
}
