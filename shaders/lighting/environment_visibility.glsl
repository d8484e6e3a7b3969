// How much of the environment's light reaches a point (world/environment_visibility.py):
// the image split into directions of about equal power, each with an orthographic shadow
// map (ENV_VISIBILITY maps: two for each direction where its region is halved, one for each
// half), tiles of one depth texture. With s_k the lookup (1 lit, 0
// shadowed) and w_k the direction's power share:
//   diffuse:  V_d = sum w_k (N.l_k) s_k / sum w_k (N.l_k)
//   specular: V_s = the same, each term also times GGX D(N.h_k) of the roughness (alpha
//             at least ENV_VIS_MIN_ALPHA, the directions' spacing, so a mirror still
//             weighs the few directions around its reflection)
// over the directions above the surface. Unblocked, both are exactly 1.
#include "common/seen_texel.glsl"

uniform sampler2D u_env_visibility;  // the maps' depths, read plain (no comparison)
uniform mat4 u_env_vis_to_map[ENV_VISIBILITY];  // camera-relative world -> (map u, v, linear depth)
uniform vec4 u_env_vis_params[ENV_VISIBILITY];  // texel world size, 1 / depth range, bias (texels), w unused
uniform vec4 u_env_vis_tile[ENV_VISIBILITY];    // the map's tile in map uv: min (xy), max (zw)
uniform vec4 u_env_vis_light[ENV_VISIBILITY];   // xyz: world direction towards the light; w: its power share

// 1 where direction k's light reaches p, 0 where a caster blocks it: the 2 x 2 texels
// around p's place on the map, each compared with the depth p's own plane has at that
// texel's centre, blended bilinearly. Against the plane, a surface never shadows itself
// however steeply the light grazes it, so the bias is a constant half texel; a bias that
// grows with the slope (what a single filtered comparison needs) lifted a ground point
// within bias x cos(elevation) of a box's foot out of the box's shadow: 10-30 cm for
// directions 15-35 degrees up, at 512 texels over a 24 m ground. A normal offset grows in
// from 79 degrees only (elsewhere it would lift a point beside a contact into the object
// resting there: the ring around a sphere's contact came out 13 % too dark).
float env_vis_lookup(int k, vec3 p, vec3 n, float n_dot_l) {
    vec4 params = u_env_vis_params[k];
    float grazing = sqrt(clamp(1.0 - n_dot_l * n_dot_l, 0.0, 1.0));
    float tan_angle = min(grazing / max(n_dot_l, 1e-4), 1e4);
    float offset_share = clamp(0.2 * tan_angle - 1.0, 0.0, 1.0);
    mat4 to_map = u_env_vis_to_map[k];
    vec4 q = to_map * vec4(p + n * (1.5 * offset_share * params.x * grazing), 1.0);
    vec4 tile = u_env_vis_tile[k];
    if (any(lessThan(q.xy, tile.xy)) || any(greaterThan(q.xy, tile.zw))) {
        return 1.0;  // outside every caster's footprint
    }
    // the plane's depth change per texel along the map's u and v: a step a across the
    // view (rows u, v, depth of to_map, orthogonal) moves along the depth row by t with
    // a . n = 0; the slope capped at 84 degrees, as the bias was
    vec3 along_u = vec3(to_map[0][0], to_map[1][0], to_map[2][0]);
    vec3 along_v = vec3(to_map[0][1], to_map[1][1], to_map[2][1]);
    vec3 along_depth = vec3(to_map[0][2], to_map[1][2], to_map[2][2]);
    vec2 size = vec2(textureSize(u_env_visibility, 0));
    float depth_n = dot(along_depth, n) / dot(along_depth, along_depth);
    vec2 per_texel = -vec2(dot(along_u, n) / dot(along_u, along_u), dot(along_v, n) / dot(along_v, along_v))
                     / (size * (abs(depth_n) > 1e-12 ? depth_n : 1e-12));
    float steepest = params.x * 10.0 * params.y;
    per_texel = clamp(per_texel, -steepest, steepest);
    vec2 at = q.xy * size - 0.5;
    vec2 low = floor(at);
    vec2 f = at - low;
    // texels (0, 1), (1, 1), (1, 0), (0, 0) of the square, in textureGather's order;
    // level 0 alone: the maps have no others
    vec4 stored = textureGather(u_env_visibility, (low + 1.0) / size, 0);
    vec4 receiver = q.z - params.x * params.z * params.y
                    + per_texel.x * (vec4(0.0, 1.0, 1.0, 0.0) - f.x) + per_texel.y * (vec4(1.0, 1.0, 0.0, 0.0) - f.y);
    vec4 tent = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    return dot(step(receiver, stored), tent);
}

// The weights of direction k at a surface facing n, towards the viewer v, of GGX a2 = alpha^2:
// (diffuse, specular); 0 where the direction lies below the surface.
vec2 env_vis_weights(int k, vec3 n, vec3 v, float a2) {
    vec4 light = u_env_vis_light[k];
    float diffuse = light.w * max(dot(n, light.xyz), 0.0);
    float n_dot_h = max(dot(n, normalize(v + light.xyz)), 0.0);
    float d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return vec2(diffuse, diffuse * a2 / (d * d));  // GGX D, its 1 / pi cancelling in the ratio
}

vec2 env_vis_ratio(vec4 sum) {  // diffuse weight, of it lit, specular weight, of it lit
    return vec2(sum.x > 0.0 ? sum.y / sum.x : 1.0, sum.z > 0.0 ? sum.w / sum.z : 1.0);
}

#ifndef ENV_VIS_INTERLEAVE
// (V_d, V_s) at p, normal n, towards the viewer v: every direction looked up here (both
// halves of each region, where they have two).
vec2 env_visibility(vec3 p, vec3 n, vec3 v, float roughness) {
    float alpha = max(roughness * roughness, ENV_VIS_MIN_ALPHA);
    vec4 sum = vec4(0.0);
    for (int k = 0; k < ENV_VISIBILITY; ++k) {
        float n_dot_l = dot(n, u_env_vis_light[k].xyz);
        if (n_dot_l <= 0.0) {
            continue;
        }
        float lit = env_vis_lookup(k, p, n, n_dot_l);
        vec2 w = env_vis_weights(k, n, v, alpha * alpha);
        sum += vec4(w.x, w.x * lit, w.y, w.y * lit);
    }
    return env_vis_ratio(sum);
}
#elif !defined(ENV_VIS_PASS)
// The directions shared out over ENV_VIS_INTERLEAVE^2 pixel blocks: the visibility pass
// (post/environment_visibility.frag) and its blur (post/environment_visibility_blur.frag)
// left, at u_env_vis_scale of this pass's resolution, packed in one uint: V_d and V_s at
// the narrowest lobe, alpha = ENV_VIS_MIN_ALPHA, and the surface's distance from the
// camera, and which way the surface faces. Read bilinearly among the four texels around
// the pixel that lie on its surface (distance within 3 % of this one's, carried along its
// slope) and face its way (common/seen_texel.glsl's facing_class), those on its surface
// where none faces its way, the nearest in distance where none is on it. The widest lobe, alpha = 1, is GGX D = 1 / pi everywhere, which makes V_s = V_d:
// between the two, V_s is taken linearly in alpha (exact at both ends; the pass draws no
// material, so it knows no roughness).
uniform usampler2D u_env_vis_samples;
uniform vec2 u_env_vis_scale;  // the visibility image's texels a pixel

vec2 env_visibility(vec3 p, vec3 n, vec3 v, float roughness) {
    float dist = length(p);
    vec2 slope = vec2(dFdx(dist), dFdy(dist));
    // the four texels around the pixel (texels (0, 1), (1, 1), (1, 0), (0, 0) of the
    // square, in textureGather's order) in one gather: llvmpipe pays for each gather,
    // whatever its bytes, so each texel holds all three (common/seen_texel.glsl's pack_seen)
    vec2 at = gl_FragCoord.xy * u_env_vis_scale;
    vec2 uv = at / vec2(textureSize(u_env_vis_samples, 0));
    uvec4 found = textureGather(u_env_vis_samples, uv, 0);
    vec4 found_d = seen_diffuse(found);
    vec4 found_s = seen_specular(found);
    vec4 found_distance = seen_distance(found);
    vec2 low = floor(at - 0.5) + 0.5;  // the centre of texel (0, 0)
    vec2 away0 = low / u_env_vis_scale - gl_FragCoord.xy;  // in this pass's pixels
    vec2 away1 = (low + 1.0) / u_env_vis_scale - gl_FragCoord.xy;
    vec4 expected = dist + slope.x * vec4(away0.x, away1.x, away1.x, away0.x)
                         + slope.y * vec4(away1.y, away1.y, away0.y, away0.y);
    vec4 gap = abs(found_distance - expected);
    vec2 f = at - low;
    vec4 tent = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));
    vec4 on_surface = tent * step(gap, vec4(0.03 * dist));
    // of those, the ones facing the way this pixel faces (seen_facing): at a box's foot the
    // ground's texels, not the box side's, whose distance is the same there
    vec4 weight = on_surface * vec4(equal(seen_facing(found), uvec4(facing_class(n))));
    weight = dot(weight, vec4(1.0)) > 1e-4 ? weight : on_surface;
    float closest = min(min(gap.x, gap.y), min(gap.z, gap.w));
    vec4 nearest = step(gap, vec4(closest));
    weight = dot(weight, vec4(1.0)) > 1e-4 ? weight : nearest;
    vec2 seen = vec2(dot(weight, found_d), dot(weight, found_s)) / dot(weight, vec4(1.0));
    float alpha = max(roughness * roughness, ENV_VIS_MIN_ALPHA);
    return vec2(seen.x, mix(seen.y, seen.x, (alpha - ENV_VIS_MIN_ALPHA) / max(1.0 - ENV_VIS_MIN_ALPHA, 1e-6)));
}
#endif
