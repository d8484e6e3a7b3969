// Light bounced between surfaces (render.indirect): the irradiance the probe grid holds
// (rendering/passes/indirect.py), read at a surface as Majercik et al. 2019 ("Dynamic
// Diffuse Global Illumination with Ray-Traced Irradiance Fields") read theirs: the eight
// probes around the point, each weighted by the trilinear weight, by how much it lies
// in front of the surface, and by the Chebyshev bound of its depth moments that the point
// is visible from it, so light does not come through walls.
// PROBE_COUNTS: the grid's probes along x, y, z; positions relative to v_position's origin.
#include "indirect/probes.glsl"

uniform sampler2D u_probe_irradiance;  // octahedral tiles: irradiance towards each direction
uniform sampler2D u_probe_depth;       // octahedral tiles: mean distance, mean squared distance
uniform vec3 u_probe_origin;           // probe (0, 0, 0)
uniform vec3 u_probe_spacing;          // between neighbours along x, y, z

// where the unit direction d lies in the probe's tile of the irradiance and the depth
// images (one layout), to filter within it: kept half a texel inside the tile, so no
// neighbour's texels mix in
vec2 probe_tile_uv(int probe, vec3 d) {
    ivec2 tile = ivec2(probe % PROBE_DEPTH_TILES_X, probe / PROBE_DEPTH_TILES_X);
    vec2 inside = clamp((octahedral_encode(d) * 0.5 + 0.5) * float(PROBE_DEPTH_SIZE),
                        vec2(0.5), vec2(float(PROBE_DEPTH_SIZE) - 0.5));
    return (vec2(tile * PROBE_DEPTH_SIZE) + inside) / vec2(textureSize(u_probe_depth, 0));
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
    vec3 sum = vec3(0.0);
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
        vec2 moments = textureLod(u_probe_depth, probe_tile_uv(probe, safe_normalize(from_probe, n)), 0.0).rg;
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
        sum += weight * textureLod(u_probe_irradiance, probe_tile_uv(probe, n), 0.0).rgb;
        total += weight;
    }
    return sum / max(total, 1e-20);
}
