// Shadow lookups in the shadow atlas: every shadowed light's depth map is a tile (or six,
// for point lights) of one depth texture. Stored depth is linear in the view's depth
// range, so bias means the same for every light type.

struct ShadowView {
    mat4 view;        // camera-relative world -> light view
    mat4 projection;  // light view -> clip
    vec4 tile;        // atlas uv origin (xy) and size (zw)
    vec4 depth;       // near, far, constant bias, slope bias
    vec4 sampling;    // radial (1 = distance to light), pcf taps per side, texel size u, v
    vec4 texel;       // world size of one texel: x at distance 1 (perspective) or y (orthographic)
};

layout(std430, binding = 1) readonly buffer ShadowViews {
    ShadowView shadow_views[];
};

uniform sampler2DShadow u_shadow_atlas;

// Fraction of light reaching p (1 lit, 0 shadowed) for one view. n is the surface normal.
//
// Besides the depth bias, the lookup point moves along the normal by about one shadow
// texel, more as the light grazes the surface: that removes acne on steep surfaces without
// a depth bias large enough to detach shadows from their casters.
//
// Filtering: each texture() of a comparison sampler with linear filtering already blends
// four depth comparisons, so an N x N texel footprint ("pcf: N") takes (N-1)^2 taps at
// half-texel offsets rather than N^2.
float shadow_visibility(int index, vec3 p, vec3 n, float n_dot_l) {
    mat4 view = shadow_views[index].view;
    vec4 depth_params = shadow_views[index].depth;
    vec4 sampling = shadow_views[index].sampling;
    vec4 tile = shadow_views[index].tile;
    vec4 light_p = view * vec4(p, 1.0);
    vec4 texel_world = shadow_views[index].texel;
    float grazing = sqrt(clamp(1.0 - n_dot_l * n_dot_l, 0.0, 1.0));
    float offset = 1.5 * (texel_world.y + texel_world.x * length(light_p.xyz)) * grazing;
    light_p.xyz += mat3(view) * n * offset;
    float distance = sampling.x > 0.5 ? length(light_p.xyz) : -light_p.z;
    float depth = (distance - depth_params.x) / (depth_params.y - depth_params.x);
    vec4 clip = shadow_views[index].projection * light_p;
    if (clip.w <= 0.0 || depth > 1.0) {
        return 1.0;  // behind the light or beyond its range: nothing recorded, so lit
    }
    vec2 ndc = clip.xy / clip.w;
    if (any(greaterThan(abs(ndc), vec2(1.0)))) {
        return 1.0;  // outside the light's view: lit rather than a hard black edge
    }
    float bias = max(depth_params.z, depth_params.w * (1.0 - clamp(n_dot_l, 0.0, 1.0)));
    vec3 coord = vec3(tile.xy + (ndc * 0.5 + 0.5) * tile.zw, depth - bias);
    vec2 texel = sampling.zw;
    vec2 lo = tile.xy + texel;
    vec2 hi = tile.xy + tile.zw - texel;
    int taps = max(int(sampling.y) - 1, 1);
    float first = -0.5 * float(taps - 1);
    float lit = 0.0;
    for (int j = 0; j < taps; ++j) {
        for (int i = 0; i < taps; ++i) {
            vec2 uv = coord.xy + vec2(first + float(i), first + float(j)) * texel;
            lit += texture(u_shadow_atlas, vec3(clamp(uv, lo, hi), coord.z));
        }
    }
    return lit / float(taps * taps);
}

// Which of a point light's six views sees direction d (+X -X +Y -Y +Z -Z).
int cube_face(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
    if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
    return d.z >= 0.0 ? 4 : 5;
}
