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
float shadow_visibility(int index, vec3 p, vec3 n, float n_dot_l) {
    ShadowView sv = shadow_views[index];
    float grazing = sqrt(clamp(1.0 - n_dot_l * n_dot_l, 0.0, 1.0));
    float distance_estimate = length((sv.view * vec4(p, 1.0)).xyz);
    float texel_world = sv.texel.y + sv.texel.x * distance_estimate;
    vec4 light_p = sv.view * vec4(p + n * (1.5 * texel_world * grazing), 1.0);
    float distance = sv.sampling.x > 0.5 ? length(light_p.xyz) : -light_p.z;
    float depth = (distance - sv.depth.x) / (sv.depth.y - sv.depth.x);
    vec4 clip = sv.projection * light_p;
    if (clip.w <= 0.0 || depth > 1.0) {
        return 1.0;  // behind the light or beyond its range: nothing recorded, so lit
    }
    vec2 ndc = clip.xy / clip.w;
    if (any(greaterThan(abs(ndc), vec2(1.0)))) {
        return 1.0;  // outside the light's view: lit rather than a hard black edge
    }
    float bias = max(sv.depth.z, sv.depth.w * (1.0 - clamp(n_dot_l, 0.0, 1.0)));
    float reference = depth - bias;
    vec2 uv = sv.tile.xy + (ndc * 0.5 + 0.5) * sv.tile.zw;
    vec2 texel = sv.sampling.zw;
    vec2 lo = sv.tile.xy + 0.5 * texel;
    vec2 hi = sv.tile.xy + sv.tile.zw - 0.5 * texel;
    int taps = int(sv.sampling.y);
    float first = -0.5 * float(taps - 1);
    float lit = 0.0;
    for (int j = 0; j < taps; ++j) {
        for (int i = 0; i < taps; ++i) {
            vec2 offset = vec2(first + float(i), first + float(j)) * texel;
            lit += texture(u_shadow_atlas, vec3(clamp(uv + offset, lo, hi), reference));
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
