// The environment prefiltered for the pbr model's specular term (split sum, Karis 2013):
// ENV_LEVELS equirectangular strips, one above the other, of roughness 0, 1/(L-1) .. 1.
// Each texel is the GGX-weighted mean of the source's radiance around its direction, taken
// with normal = view = reflection direction. Level 0 (a mirror) is the source itself. The
// rough levels draw u_samples directions from the GGX distribution (Hammersley points)
// and read each from the source's mip level whose texel matches the sample's solid angle
// (filtered importance sampling, Krivanek and Colbert 2008), so few samples leave no
// speckles. The strip's rows run v = 0 (+Y) upwards from its bottom; the lookup
// (lighting/environment.glsl) uses the same rows.
#include "lighting/environment_map.glsl"

uniform sampler2D u_env_source;  // equirectangular linear radiance, with mip levels
uniform vec2 u_source_size;      // its base level's width and height
uniform int u_samples;
out vec4 frag_color;

const float PI = 3.141592653589793;

vec2 hammersley(uint i, uint count) {
    return vec2((float(i) + 0.5) / float(count), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

vec3 source(vec3 d, float lod) {
    return textureLod(u_env_source, env_uv(d), lod).rgb;
}

// The GGX-weighted mean around n: sum of L(l) N.L over half vectors drawn from D(h) N.H,
// divided by the sum of N.L (Karis' weighting).
vec3 prefiltered(vec3 n, float roughness) {
    float alpha = max(roughness * roughness, 0.002);
    float alpha2 = alpha * alpha;
    vec3 helper = abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 tangent = normalize(cross(helper, n));
    vec3 bitangent = cross(n, tangent);
    // solid angle of a source texel at the equator: the lod's reference
    float texel = 2.0 * PI * PI / (u_source_size.x * u_source_size.y);
    float max_lod = log2(max(u_source_size.x, u_source_size.y));
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    uint count = uint(u_samples);
    for (uint i = 0u; i < count; ++i) {
        vec2 xi = hammersley(i, count);
        float cos_h = sqrt((1.0 - xi.y) / (1.0 + (alpha2 - 1.0) * xi.y));
        float sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
        float phi = 2.0 * PI * xi.x;
        vec3 h = tangent * (sin_h * cos(phi)) + bitangent * (sin_h * sin(phi)) + n * cos_h;
        vec3 l = 2.0 * dot(n, h) * h - n;
        float n_dot_l = dot(n, l);
        if (n_dot_l <= 0.0) {
            continue;
        }
        // pdf of l: D(h) N.H / (4 V.H) = D(h) / 4 with V = N
        float k = cos_h * cos_h * (alpha2 - 1.0) + 1.0;
        float pdf = alpha2 / (PI * k * k) * 0.25;
        float sample_angle = 1.0 / (float(count) * pdf + 1e-6);
        float lod = clamp(0.5 * log2(sample_angle / texel) + 1.0, 0.0, max_lod);
        sum += source(l, lod) * n_dot_l;
        weight += n_dot_l;
    }
    return sum / max(weight, 1e-6);
}

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int level = texel.y / int(ENV_STRIP_HEIGHT);
    vec2 uv = vec2(gl_FragCoord.x / ENV_STRIP_WIDTH, (gl_FragCoord.y - float(level) * ENV_STRIP_HEIGHT) / ENV_STRIP_HEIGHT);
    vec3 n = env_direction(uv);
    if (level == 0) {
        frag_color = vec4(source(n, max(log2(u_source_size.x / ENV_STRIP_WIDTH), 0.0)), 1.0);
    } else {
        frag_color = vec4(prefiltered(n, float(level) / (ENV_LEVELS - 1.0)), 1.0);
    }
}
