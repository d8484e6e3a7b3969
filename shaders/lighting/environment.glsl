// Light from the environment (world/environment.py), both terms looked up in the image's
// frame (u_env_to_image) and scaled by colour x intensity (u_env_scale):
// - diffuse: irradiance / pi from the image's spherical harmonics, as a small
//   equirectangular map (the radiance a white Lambert surface facing n reflects);
// - specular: the prefiltered levels (environment/prefilter.frag) at the reflection
//   direction, linearly between the two levels around the roughness (the split sum); or,
//   with ENV_SPECULAR_SAMPLES (the option `specular: sampled`), that many GGX samples of
//   the source image at shading time around the real normal and view (env_specular_sampled).
#include "lighting/environment_map.glsl"
#ifdef ENV_VISIBILITY
#include "lighting/environment_visibility.glsl"
#endif

uniform sampler2D u_env_diffuse;
uniform sampler2D u_env_specular;
uniform mat3 u_env_to_image;
uniform vec3 u_env_scale;

vec3 env_diffuse(vec3 n) {
    return u_env_scale * textureLod(u_env_diffuse, env_uv(u_env_to_image * n), 0.0).rgb;
}

vec3 env_specular_level(vec2 uv, float level) {
    // kept half a texel inside the strip, so filtering never reads the next one
    float row = clamp(uv.y * ENV_STRIP_HEIGHT, 0.5, ENV_STRIP_HEIGHT - 0.5);
    return textureLod(u_env_specular, vec2(uv.x, (level * ENV_STRIP_HEIGHT + row) / (ENV_LEVELS * ENV_STRIP_HEIGHT)),
                      0.0).rgb;
}

vec3 env_specular(vec3 r, float roughness) {
#ifdef ENV_FOOTPRINT
    // the option `footprint`: a reflection narrower than the pixel's spread of directions
    // (a sun in a smooth metal) is averaged over that spread, as the pixel's area would,
    // rather than taken at its centre: GGX alpha at least half the spread in radians
    float spread = max(length(dFdx(r)), length(dFdy(r)));
    roughness = sqrt(max(roughness * roughness, 0.5 * spread));
#endif
    vec2 uv = env_uv(u_env_to_image * r);
    float level = clamp(roughness, 0.0, 1.0) * (ENV_LEVELS - 1.0);
    float below = floor(level);
    float above = min(below + 1.0, ENV_LEVELS - 1.0);
    return u_env_scale * mix(env_specular_level(uv, below), env_specular_level(uv, above), level - below);
}

#if defined(ENV_SPECULAR_SAMPLES) && defined(SHADING_PBR)
uniform sampler2D u_env_source;  // equirectangular linear radiance, with mip levels

// The specular integral, integral of f_s(l, v) L(l) N.L dl, estimated by filtered
// importance sampling (Colbert and Krivanek 2007) at the pixel's own n and v: the split
// sum's N = V = R lookup misses how the lobe stretches and shifts off the reflection
// direction, which a small bright feature (a sun, a window) in a rough metal shows.
// ENV_SPECULAR_SAMPLES half vectors from the distribution of visible normals (Heitz 2018,
// the same fixed Hammersley set at every pixel, so the error is smooth rather than noise),
// each l = reflect(-v, h) weighted by f_s N.L / pdf = F G2 / G1(v), where
// pdf = G1(v) D / (4 N.V); each read from the source's mip level whose texel matches the
// sample's share of the lobe, 1 / (count pdf) steradians: the wide filter stands in for
// the samples a brute-force sum would need. Not the prefilter's +1 level: that blurred a
// small bright patch out of the lobe (a copper sphere 4.7 % dark at 16 samples, against
// 1.4 % without; docs/scene-notes.md).
vec2 env_hammersley(uint i) {
    return vec2((float(i) + 0.5) / float(ENV_SPECULAR_SAMPLES), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// A visible normal of the GGX lobe of ``alpha`` seen from ``ve`` (tangent space, z the normal).
vec3 env_visible_normal(vec3 ve, float alpha, vec2 xi) {
    vec3 vh = normalize(vec3(alpha * ve.x, alpha * ve.y, ve.z));
    float lensq = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = lensq > 0.0 ? vec3(-vh.y, vh.x, 0.0) * inversesqrt(lensq) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(xi.x);
    float phi = 6.283185307179586 * xi.y;
    float p1 = r * cos(phi);
    float s = 0.5 * (1.0 + vh.z);
    float p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    vec3 nh = p1 * t1 + p2 * t2 + sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0)) * vh;
    return normalize(vec3(alpha * nh.x, alpha * nh.y, max(nh.z, 0.0)));
}

vec3 env_specular_sampled(vec3 n, vec3 v, Surface s) {
    float roughness = s.roughness;
#ifdef ENV_FOOTPRINT
    vec3 r = reflect(-v, n);
    float spread = max(length(dFdx(r)), length(dFdy(r)));
    roughness = sqrt(max(roughness * roughness, 0.5 * spread));
#endif
    float alpha = max(roughness * roughness, PBR_MIN_ALPHA);
    float alpha2 = alpha * alpha;
    vec3 helper = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 tangent = normalize(cross(helper, n));
    vec3 bitangent = cross(n, tangent);
    // a view below the surface (interpolated normals at a silhouette) is kept just above it
    vec3 ve = normalize(vec3(dot(v, tangent), dot(v, bitangent), max(dot(v, n), 1e-4)));
    float n_dot_v = ve.z;
    float view_term = sqrt(n_dot_v * n_dot_v * (1.0 - alpha2) + alpha2);
    float g1_view = 2.0 * n_dot_v / (n_dot_v + view_term);
#ifdef PBR_DIELECTRIC_SPECULAR
    vec3 f0 = mix(s.dielectric_f0, s.base, s.metallic);
    vec3 f90 = mix(vec3(s.dielectric_f90), vec3(1.0), s.metallic);
#else
    vec3 f0 = mix(vec3(0.04), s.base, s.metallic);
#endif
    vec2 size = vec2(textureSize(u_env_source, 0));
    float texel = 19.739208802178716 / (size.x * size.y);  // a base texel's solid angle at the equator, 2 pi^2 / (W H)
    float max_lod = log2(max(size.x, size.y));
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < uint(ENV_SPECULAR_SAMPLES); ++i) {
        vec3 h = env_visible_normal(ve, alpha, env_hammersley(i));
        float v_dot_h = dot(ve, h);
        vec3 l = 2.0 * v_dot_h * h - ve;
        if (l.z <= 0.0) {
            continue;
        }
        float k = h.z * h.z * (alpha2 - 1.0) + 1.0;
        float pdf = g1_view * alpha2 / (3.141592653589793 * k * k) / (4.0 * n_dot_v);
        float lod = clamp(0.5 * log2(1.0 / (float(ENV_SPECULAR_SAMPLES) * pdf * texel)), 0.0, max_lod);
        // G2 / G1(v) with the height-correlated G2 = 4 N.L N.V V (lighting/pbr.glsl's V)
        float g2 = 2.0 * l.z * n_dot_v / (l.z * view_term + n_dot_v * sqrt(l.z * l.z * (1.0 - alpha2) + alpha2));
        vec3 world = tangent * l.x + bitangent * l.y + n * l.z;
        vec3 radiance = textureLod(u_env_source, env_uv(u_env_to_image * world), lod).rgb;
#ifdef PBR_DIELECTRIC_SPECULAR
        sum += radiance * fresnel_schlick_f90(f0, f90, clamp(v_dot_h, 0.0, 1.0)) * (g2 / g1_view);
#else
        sum += radiance * fresnel_schlick(f0, clamp(v_dot_h, 0.0, 1.0)) * (g2 / g1_view);
#endif
    }
    return u_env_scale * sum / float(ENV_SPECULAR_SAMPLES);
}
#endif

#ifdef SHADING_PBR
// Where the split sum looks its prefiltered image up: the GGX lobe f cos, seen at an angle,
// leans from the mirror direction towards the normal the rougher the surface (the
// prefilter took it as seen head-on, N = V = R): Lagarde and de Rousiers 2014's fit of the
// lobe's dominant direction, between n and r by (1 - alpha)(sqrt(1 - alpha) + alpha).
// Taken at r, the copper-like metal of roughness 0.5 alone under a sky with a bright
// patch came out 3.2 % dark against the reference; here 1.4 %
// (benchmarks/quality/three_spheres.md).
vec3 env_dominant_direction(vec3 n, vec3 v, float roughness) {
    float alpha = roughness * roughness;
    float smoothness = 1.0 - alpha;
    return normalize(mix(n, reflect(-v, n), smoothness * (sqrt(smoothness) + alpha)));
}

// The specular term the environment gives the pbr model: w_s x the prefiltered lookup
// (the split sum), or the sampled integral (ENV_SPECULAR_SAMPLES), which holds its own
// BRDF weight.
vec3 pbr_environment_specular(vec3 n, vec3 v, Surface s, PbrAmbientWeights w) {
#ifdef ENV_SPECULAR_SAMPLES
    vec3 specular = env_specular_sampled(n, v, s);
#if defined(PBR_SHEEN) || defined(PBR_CLEARCOAT)
    specular *= w.base_scale;
#endif
#else
    vec3 specular = w.specular * env_specular(env_dominant_direction(n, v, s.roughness), s.roughness);
#endif
#ifdef PBR_CLEARCOAT
    // the coat's reflection by the split sum (also where the base's is sampled)
#ifdef PBR_COAT_NORMAL
    vec3 coat_n = s.clearcoat_normal;
#else
    vec3 coat_n = n;
#endif
    specular += w.coat * env_specular(env_dominant_direction(coat_n, v, s.clearcoat_roughness), s.clearcoat_roughness);
#endif
    return specular;
}

// The weight of the irradiance: the diffuse part's, and the sheen's (its broad lobe lit by
// the irradiance, as a uniform light of that radiance would light it)
vec3 pbr_environment_diffuse(PbrAmbientWeights w) {
#ifdef PBR_SHEEN
    return w.diffuse + w.sheen;
#else
    return w.diffuse;
#endif
}

// What the environment gives the pbr model: the split sum, whose BRDF half is the fitted
// hemisphere integral the uniform ambient light uses (pbr_ambient_weights).
vec3 pbr_environment(vec3 n, vec3 v, Surface s) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    return pbr_environment_diffuse(w) * env_diffuse(n) + pbr_environment_specular(n, v, s, w);
}

// The same with the diffuse and specular terms scaled by what reaches the surface of each
// (seen: env_visibility's (V_d, V_s), with the other occlusions applied).
vec3 pbr_environment_seen(vec3 n, vec3 v, Surface s, vec2 seen) {
    PbrAmbientWeights w = pbr_ambient_weights(n, v, s);
    return pbr_environment_diffuse(w) * env_diffuse(n) * seen.x + pbr_environment_specular(n, v, s, w) * seen.y;
}
#endif
