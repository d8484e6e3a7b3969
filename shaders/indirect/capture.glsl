// Reading the probes' captured cube maps (passes/indirect.py): probe b has the tile at
// column b % CAPTURE_COLUMNS, row b / CAPTURE_COLUMNS, its six CAPTURE_SIZE x CAPTURE_SIZE
// faces side by side; rgb radiance, a distance.
uniform sampler2D u_capture;

ivec2 capture_texel(int probe, int face, int x, int y) {
    ivec2 tile = ivec2(probe % CAPTURE_COLUMNS, probe / CAPTURE_COLUMNS);
    return ivec2((tile.x * 6 + face) * CAPTURE_SIZE + x, tile.y * CAPTURE_SIZE + y);
}

// (u, v) in [-1, 1]^2 of texel (x, y)'s centre, and its solid angle over 4 / CAPTURE_SIZE^2
vec3 capture_texel_place(int x, int y) {
    vec2 uv = (vec2(x, y) + 0.5) * (2.0 / float(CAPTURE_SIZE)) - 1.0;
    float r2 = 1.0 + dot(uv, uv);
    return vec3(uv, 1.0 / (r2 * sqrt(r2)));
}
