// The longest smear of a tile of the velocity buffer (TILE: its side in pixels), or, with
// NEIGHBOURS, of a tile's 3 x 3 neighbourhood of such tiles (rendering/passes/motion_blur.py).
// A pixel's smear reaches at most one tile away, so the neighbourhood's longest smear is
// the longest that can reach any pixel of the tile.
uniform sampler2D u_velocity;
out vec4 frag_velocity;

vec2 longer(vec2 a, vec2 b) {
    return dot(b, b) > dot(a, a) ? b : a;
}

void main() {
    ivec2 tile = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_velocity, 0) - 1;
    vec2 longest = vec2(0.0);
#ifdef NEIGHBOURS
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            longest = longer(longest, texelFetch(u_velocity, clamp(tile + ivec2(x, y), ivec2(0), last), 0).xy);
        }
    }
#else
    ivec2 first = tile * TILE;
    for (int y = 0; y < TILE; ++y) {
        for (int x = 0; x < TILE; ++x) {
            longest = longer(longest, texelFetch(u_velocity, min(first + ivec2(x, y), last), 0).xy);
        }
    }
#endif
    frag_velocity = vec4(longest, 0.0, 1.0);
}
