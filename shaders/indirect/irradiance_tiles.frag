// One texel of a probe's irradiance tile: the irradiance its nine spherical-harmonic
// coefficients (project_irradiance.frag) give towards the texel's octahedral direction,
// so that a lookup reads one filtered texel a probe instead of nine coefficients. Tiles
// as the depth tiles lie: PROBE_DEPTH_SIZE texels a side, PROBE_DEPTH_TILES_X to a row.
#include "indirect/probes.glsl"

uniform sampler2D u_capture;  // the coefficients: texel (u_column + i, probe)
uniform int u_column;
uniform int u_probes;
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
    float basis[9];
    sh_basis(octahedral_decode(inside), basis);
    vec3 irradiance = vec3(0.0);
    for (int i = 0; i < 9; ++i) {
        irradiance += basis[i] * texelFetch(u_capture, ivec2(u_column + i, probe), 0).rgb;
    }
    frag_color = vec4(max(irradiance, 0.0), 1.0);
}
