// Light bounced between surfaces (render.indirect): the irradiance the probe grid holds
// (rendering/passes/indirect.py), read at a surface as Majercik et al. 2019 ("Dynamic
// Diffuse Global Illumination with Ray-Traced Irradiance Fields") read theirs: the eight
// probes around the point, each weighted by the trilinear weight, by how much it lies
// in front of the surface, and by the Chebyshev bound of its depth moments that the point
// is visible from it, so light does not come through walls.
// PROBE_COUNTS: the grid's probes along x, y, z; positions relative to v_position's origin.
#include "indirect/probes.glsl"

uniform sampler2D u_probe_irradiance;  // texel (i, probe): SH coefficient i (cosine-convolved)
uniform sampler2D u_probe_depth;       // octahedral tiles: mean distance, mean squared distance
uniform vec3 u_probe_origin;           // probe (0, 0, 0)
uniform vec3 u_probe_spacing;          // between neighbours along x, y, z

// the probe's (mean, mean squared) distance towards the unit direction d, filtered
// within its tile (kept half a texel inside it, so no neighbour's texels mix in)
vec2 probe_depth_moments(int probe, vec3 d) {
    ivec2 tile = ivec2(probe % PROBE_DEPTH_TILES_X, probe / PROBE_DEPTH_TILES_X);
    vec2 inside = clamp((octahedral_encode(d) * 0.5 + 0.5) * float(PROBE_DEPTH_SIZE),
                        vec2(0.5), vec2(float(PROBE_DEPTH_SIZE) - 0.5));
    vec2 texel = vec2(tile * PROBE_DEPTH_SIZE) + inside;
    return textureLod(u_probe_depth, texel / vec2(textureSize(u_probe_depth, 0)), 0.0).rg;
}

// Irradiance at p (normal n, v towards the viewer), from the probes.
vec3 probe_irradiance(vec3 p, vec3 n, vec3 v) {
    ivec3 counts = ivec3(PROBE_COUNTS);
    float reach = min(u_probe_spacing.x, min(u_probe_spacing.y, u_probe_spacing.z));
    // off the surface, towards the viewer mostly: the point a probe's depth is compared
    // at must not lie behind the surface it shades
    vec3 biased = p + (0.2 * n + 0.8 * v) * (0.3 * reach);
    vec3 grid = (biased - u_probe_origin) / u_probe_spacing;
    ivec3 base = clamp(ivec3(floor(grid)), ivec3(0), max(counts - 2, ivec3(0)));
    vec3 alpha = clamp(grid - vec3(base), 0.0, 1.0);
    vec3 sum[9];
    for (int i = 0; i < 9; ++i) {
        sum[i] = vec3(0.0);
    }
    float total = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        ivec3 cell = min(base + offset, counts - 1);
        int probe = cell.x + counts.x * (cell.y + counts.y * cell.z);
        vec3 position = u_probe_origin + vec3(cell) * u_probe_spacing;
        // a probe behind the surface sees its back: weighted down smoothly, never to 0
        vec3 to_probe = safe_normalize(position - p, n);
        float facing = 0.5 * (dot(to_probe, n) + 1.0);
        float weight = facing * facing + 0.2;
        // Chebyshev: the chance the point lies no farther than what the probe sees
        vec3 from_probe = biased - position;
        float distance = length(from_probe);
        vec2 moments = probe_depth_moments(probe, safe_normalize(from_probe, n));
        if (distance > moments.x) {
            float variance = abs(moments.y - moments.x * moments.x);
            float gap = distance - moments.x;
            float chebyshev = variance / (variance + gap * gap);
            weight *= max(chebyshev * chebyshev * chebyshev, 0.0);
        }
        weight = max(weight, 1e-6);
        // small weights crushed further: light leaks least where visibility says little
        if (weight < 0.2) {
            weight *= weight * weight * 25.0;
        }
        vec3 trilinear = mix(1.0 - alpha, alpha, vec3(offset));
        weight *= trilinear.x * trilinear.y * trilinear.z;
        for (int i = 0; i < 9; ++i) {
            sum[i] += weight * texelFetch(u_probe_irradiance, ivec2(i, probe), 0).rgb;
        }
        total += weight;
    }
    float basis[9];
    sh_basis(n, basis);
    vec3 irradiance = vec3(0.0);
    for (int i = 0; i < 9; ++i) {
        irradiance += sum[i] * basis[i];
    }
    return max(irradiance / max(total, 1e-20), 0.0);
}
