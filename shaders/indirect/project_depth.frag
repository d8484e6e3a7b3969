// One texel of a probe's depth tile: the mean distance and mean squared distance to the
// surfaces it sees around the texel's octahedral direction, each captured texel weighted
// by max(0, cos)^DEPTH_SHARPNESS and its solid angle (Majercik et al. 2019's moments, for
// the lookup's Chebyshev visibility test). Tiles are PROBE_DEPTH_SIZE texels a side,
// PROBE_DEPTH_TILES_X to a row, in probe order.
#include "indirect/probes.glsl"
#include "indirect/capture.glsl"

#define DEPTH_SHARPNESS 50.0

uniform int u_probes;  // how many there are (the last row of tiles may have fewer)
out vec4 frag_color;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    ivec2 tile = texel / PROBE_DEPTH_SIZE;
    int probe = tile.y * PROBE_DEPTH_TILES_X + tile.x;
    if (probe >= u_probes) {
        frag_color = vec4(0.0);
        return;
    }
    vec2 inside = (vec2(texel - tile * PROBE_DEPTH_SIZE) + 0.5) * (2.0 / float(PROBE_DEPTH_SIZE)) - 1.0;
    vec3 towards = octahedral_decode(inside);
    vec2 moments = vec2(0.0);
    float weights = 0.0;
    for (int face = 0; face < 6; ++face) {
        if (dot(CUBE_FORWARD[face], towards) < -0.1) {
            continue;  // its texels lie 41 degrees or more off the lobe: cos^50 < 1e-6
        }
        for (int y = 0; y < CAPTURE_SIZE; ++y) {
            for (int x = 0; x < CAPTURE_SIZE; ++x) {
                vec3 place = capture_texel_place(x, y);
                float cosine = dot(normalize(cube_direction(face, place.xy)), towards);
                if (cosine <= 0.0) {
                    continue;
                }
                float weight = pow(cosine, DEPTH_SHARPNESS) * place.z;
                float distance = texelFetch(u_capture, capture_texel(probe, face, x, y), 0).a;
                moments += weight * vec2(distance, distance * distance);
                weights += weight;
            }
        }
    }
    frag_color = vec4(moments / max(weights, 1e-20), 0.0, 1.0);
}
