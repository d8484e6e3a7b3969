// Shadow lookups in the shadow atlas: every shadowed light's depth map is a tile (or six,
// for point lights) of an atlas page, a depth texture. Maps drawn once per run and maps
// redrawn every frame are on separate pages (world/shadows.py): page 0 (u_shadow_atlas)
// holds the maps drawn once, or the redrawn ones in a scene with only those; page 1
// (u_shadow_atlas_2) the redrawn ones in a scene with both. Stored depth is
// linear in the view's depth range; bias is worked out in world units from the texel's
// footprint at the receiver, so it means the same for every light type and at every
// scene scale.

struct ShadowView {
    mat4 to_atlas;    // camera-relative world -> (atlas u * w, atlas v * w, linear depth, w)
    vec4 light;       // xyz: the light's position, camera-relative; w: 1 = radial depth (point lights)
    vec4 tile;        // the view's tile in atlas uv: min (xy), max (zw)
    vec4 depth;       // near, 1 / (far - near), constant bias (texels), slope bias (texels per unit tan)
    vec4 sampling;    // atlas texel size u, v; pcf taps per side
    vec4 texel;       // world size of one texel: x per unit distance (perspective), y constant (orthographic)
};

// In a uniform block when the scene's N_SHADOW_VIEWS fit one, else a storage buffer.
#ifdef N_SHADOW_VIEWS
layout(std140, binding = 1) uniform ShadowViews {
    ShadowView shadow_views[N_SHADOW_VIEWS];
};
#else
layout(std430, binding = 1) readonly buffer ShadowViews {
    ShadowView shadow_views[];
};
#endif

uniform sampler2DShadow u_shadow_atlas;
#if SHADOW_PAGES > 1
uniform sampler2DShadow u_shadow_atlas_2;
#endif

// Fraction of light reaching p (1 lit, 0 shadowed) for one view. n is the surface normal.
//
// Bias, all in world units proportional to T, the world size of one shadow texel at p:
// the lookup point moves along the normal by 1.5 T sin(angle to the light), and the depth
// compared is nearer the light by T * (constant + slope * tan(angle)). A receiver's own
// depth in the map varies by T tan(angle) per texel, and the filter reads texels up to
// pcf / 2 away, so a slope term of that many texels keeps filtered lookups off the
// receiver's own surface (no acne), while a thin caster's shadow detaches by only a few
// texels however large the scene is.
//
// Filtering: each texture() of a comparison sampler with linear filtering already blends
// four depth comparisons, so an N x N texel footprint ("pcf: N") takes (N-1)^2 taps at
// half-texel offsets rather than N^2.
//
// perspective: the view is a perspective one (spot lights, cube faces), so a texel grows
// with distance from the light; radial: depth is the distance to the light (point lights).
// Callers that know the light type pass constants, and the compiler drops what the type
// does not need (a directional light computes no distances at all).
//
// Pixel footprint: dpdx, dpdy are p's change across one pixel (dFdx, dFdy taken where
// control flow is uniform). Where the pixel covers more than a shadow texel, visibility is
// averaged over points of the pixel on the surface's tangent plane (footprint_offsets or
// footprint_grid; SHADOW_FOOTPRINT_SAMPLES the MSAA samples): a shadow edge then gets the
// fraction of the pixel it covers, as MSAA gives a geometric edge (visibility is otherwise
// evaluated once per pixel, MSAA or not). With SHADOW_VISIBLE_SAMPLES only the points of
// the samples where this surface passed the depth test count: at a silhouette the others
// lie on the surface hidden behind the nearer object, in its shadow where it stands on it.
#ifndef SHADOW_FOOTPRINT_SAMPLES
#define SHADOW_FOOTPRINT_SAMPLES 1
#endif
#if SHADOW_FOOTPRINT_SAMPLES >= 16
const vec2 footprint_offsets[16] = vec2[](
    vec2(1, 1), vec2(-1, -3), vec2(-3, 2), vec2(4, -1), vec2(-5, -2), vec2(2, 5), vec2(5, 3), vec2(3, -5),
    vec2(-2, 6), vec2(0, -7), vec2(-4, -6), vec2(-6, 4), vec2(-8, 0), vec2(7, -4), vec2(6, 7), vec2(-7, -8));
#elif SHADOW_FOOTPRINT_SAMPLES >= 8
const vec2 footprint_offsets[8] = vec2[](
    vec2(1, -3), vec2(-1, 3), vec2(5, 1), vec2(-3, -5), vec2(-5, 5), vec2(-7, -1), vec2(3, 7), vec2(7, -7));
#elif SHADOW_FOOTPRINT_SAMPLES >= 4
const vec2 footprint_offsets[4] = vec2[](vec2(-2, -6), vec2(6, -2), vec2(-6, 2), vec2(2, 6));
#elif SHADOW_FOOTPRINT_SAMPLES >= 2
const vec2 footprint_offsets[2] = vec2[](vec2(4, 4), vec2(-4, -4));
#endif
// The points of a spreading footprint, in 1/16 pixel, and the sample each stands for: as
// many as the filter's own taps, which the loop below runs anyway (llvmpipe runs every
// trip of a loop, and both sides of a branch, for all the pixels it shades together). With
// 16 taps ("pcf" 5 or more) and 4 samples, a 4 x 4 grid, each point standing for the
// sample of its quarter of the pixel (0 lower left, 1 lower right, 2 upper left, 3 upper
// right); with fewer taps, or 2, 8 or 16 samples, the sample points themselves. Over
// random straight edges through a pixel the grid's covered fraction is off by 0.032 RMS,
// four sample points' by 0.091; the taps' bilinear filtering smooths both a little.
#if SHADOW_FOOTPRINT_SAMPLES == 4
#define SHADOW_FOOTPRINT_GRID 16
const vec2 footprint_grid[16] = vec2[](
    vec2(-6, -6), vec2(-2, -6), vec2(2, -6), vec2(6, -6), vec2(-6, -2), vec2(-2, -2), vec2(2, -2), vec2(6, -2),
    vec2(-6, 2), vec2(-2, 2), vec2(2, 2), vec2(6, 2), vec2(-6, 6), vec2(-2, 6), vec2(2, 6), vec2(6, 6));
const int footprint_grid_owner[16] = int[](0, 0, 1, 1, 0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 3, 3);
#endif

// One hardware-filtered lookup (2 x 2 texels) at the point whose atlas projection is q
// (to_atlas times the point; ``point`` itself is read only for radial depth), moved by
// ``offset`` atlas texels; 1 where the map recorded nothing there. page: 0 or 1, a
// compile-time constant wherever the caller passes one (then only that page's lookup is
// compiled).
float shadow_tap(int index, int page, vec4 q, vec3 point, vec2 offset, float bias, bool perspective, bool radial) {
    vec4 light = shadow_views[index].light;
    vec4 depth_params = shadow_views[index].depth;
    vec4 tile = shadow_views[index].tile;
    vec2 texel = shadow_views[index].sampling.xy;
    float depth = radial ? (distance(point, light.xyz) - depth_params.x) * depth_params.y : q.z;
    // an orthographic view's w is exactly 1: no division, and nothing is behind it
    vec2 uv = perspective ? q.xy / q.w : q.xy;
    // behind the light or beyond its range (nothing recorded), or outside the light's
    // view: lit, rather than a hard black edge
    bool outside = (perspective && q.w <= 0.0) || depth > 1.0 || any(lessThan(uv, tile.xy)) || any(greaterThan(uv, tile.zw));
    vec2 tap = clamp(uv + offset * texel, tile.xy + texel, tile.zw - texel);
#if SHADOW_PAGES > 1
    float visible = page == 0 ? textureLod(u_shadow_atlas, vec3(tap, depth - bias), 0.0)
                              : textureLod(u_shadow_atlas_2, vec3(tap, depth - bias), 0.0);
#else
    float visible = textureLod(u_shadow_atlas, vec3(tap, depth - bias), 0.0);
#endif
    return outside ? 1.0 : visible;
}

// Hardware-filtered taps per side for the view's "pcf: N" (each tap blends 2 x 2 texels).
int filter_taps(int index) {
    return max(int(shadow_views[index].sampling.z) - 1, 1);
}

// taps: filter_taps(index), passed in by callers that know it at compile time (then every
// loop below unrolls: a software rasterizer such as llvmpipe runs both sides of every
// branch, and every loop trip, for all the pixels it shades together).
float shadow_lookup(int index, int page, int taps, vec3 p, vec3 n, float n_dot_l, bool perspective, bool radial, vec3 dpdx, vec3 dpdy) {
    vec4 light = shadow_views[index].light;
    vec4 depth_params = shadow_views[index].depth;
    vec4 texel_world = shadow_views[index].texel;
    float grazing = sqrt(clamp(1.0 - n_dot_l * n_dot_l, 0.0, 1.0));
    float texel_size = perspective ? texel_world.x * distance(p, light.xyz) : texel_world.y;
    // tan(angle) of the light to the surface. The depth bias's is capped at grazing
    // incidence (84 degrees); the normal offset makes up for the cap, growing in from 79
    // degrees. Below that it stays off, as the depth bias alone keeps acne away there: the
    // offset moves the lookup across the map, by 1.5 sin^2(angle) texels, and so every
    // shadow edge towards its caster (a 6 cm slab 16 degrees below a point light lost the
    // outermost row of its shadow's pixels: 12 % of the light the shadow blocks came through).
    float tan_angle = min(grazing / max(n_dot_l, 1e-4), 1e4);
    float offset_share = clamp(0.2 * tan_angle - 1.0, 0.0, 1.0);
    vec3 shifted = p + n * (1.5 * offset_share * texel_size * grazing);
    tan_angle = min(tan_angle, 10.0);
    float bias = texel_size * (depth_params.z + depth_params.w * tan_angle) * depth_params.y;
    mat4 to_atlas = shadow_views[index].to_atlas;
#if SHADOW_FOOTPRINT_SAMPLES > 1
    // the pixel's extent in texels, along the light's view plane (an estimate: the
    // footprint on the surface seen from the light is no larger)
    float footprint = max(length(dpdx), length(dpdy)) / max(texel_size, 1e-30);
    // Where the pixel spreads over more than a texel its points are themselves the
    // filter: one hardware-filtered tap each, as many points as "pcf" has taps.
    bool spread = footprint > 1.0;
    // The view's projection is linear in homogeneous coordinates, so a point's projection
    // is the pixel's plus the projected derivatives, scaled: one matrix product per
    // lookup rather than one per tap.
    vec4 q_dx = to_atlas * vec4(dpdx, 0.0);
    vec4 q_dy = to_atlas * vec4(dpdy, 0.0);
#ifdef SHADOW_VISIBLE_SAMPLES
    // the samples of the pixel where this surface is the one seen (the depth test's result,
    // after a depth prepass): only their points count, and the filter of a pixel smaller
    // than a texel sits at their centroid
    int seen = gl_SampleMaskIn[0];
    vec2 seen_centre = vec2(0.0);
    for (int k = 0; k < SHADOW_FOOTPRINT_SAMPLES; ++k) {
        seen_centre += ((seen >> k) & 1) != 0 ? footprint_offsets[k] : vec2(0.0);
    }
    seen_centre /= 16.0 * float(max(bitCount(seen & ((1 << SHADOW_FOOTPRINT_SAMPLES) - 1)), 1));
    if (!spread) {
        shifted += dpdx * seen_centre.x + dpdy * seen_centre.y;
    }
#else
    const int seen = -1;
#endif
#ifdef SHADOW_FOOTPRINT_GRID
    bool grid = taps * taps >= SHADOW_FOOTPRINT_GRID;
#else
    const bool grid = false;
#endif
    int points = grid ? 16 : SHADOW_FOOTPRINT_SAMPLES;
    int count = spread ? points : taps * taps;
    int bound = max(SHADOW_FOOTPRINT_SAMPLES, taps * taps);
#else
    const bool spread = false;
    int count = taps * taps;
    int bound = count;
#endif
    vec4 q_centre = to_atlas * vec4(shifted, 1.0);
    // Either the "pcf" filter's taps around one point, or one tap at each of the pixel's
    // points; one loop does both.
    float first = -0.5 * float(taps - 1);
    float lit = 0.0;
    float weights = 0.0;
    int column = 0, row = 0;  // of the filter's taps (no integer division: it is slow on SIMD)
    for (int k = 0; k < bound; ++k) {
        vec3 point = shifted;
        vec4 q = q_centre;
        vec2 offset = vec2(first + float(column), first + float(row));
        if (++column == taps) {
            column = 0;
            ++row;
        }
        bool counted = k < count;
#if SHADOW_FOOTPRINT_SAMPLES > 1
        if (spread) {
            int j = min(k, points - 1);
#ifdef SHADOW_FOOTPRINT_GRID
            vec2 o = (grid ? footprint_grid[min(j, 15)] : footprint_offsets[min(j, SHADOW_FOOTPRINT_SAMPLES - 1)]) / 16.0;
            int owner = grid ? footprint_grid_owner[min(j, 15)] : j;
#else
            vec2 o = footprint_offsets[min(j, SHADOW_FOOTPRINT_SAMPLES - 1)] / 16.0;
            int owner = j;
#endif
            point = shifted + dpdx * o.x + dpdy * o.y;
            q = q_centre + q_dx * o.x + q_dy * o.y;
            offset = vec2(0.0);
            counted = counted && ((seen >> owner) & 1) != 0;
        }
#endif
        float visible = shadow_tap(index, page, q, point, offset, bias, perspective, radial);
        lit += counted ? visible : 0.0;
        weights += counted ? 1.0 : 0.0;
    }
    return lit / max(weights, 1.0);
}

// The same for a view of any light type (read from the view itself), on the first page.
float shadow_visibility(int index, vec3 p, vec3 n, float n_dot_l, vec3 dpdx, vec3 dpdy) {
    return shadow_lookup(index, 0, filter_taps(index), p, n, n_dot_l, shadow_views[index].texel.x > 0.0,
                         shadow_views[index].light.w > 0.5, dpdx, dpdy);
}

// Which of a point light's six views sees direction d (+X -X +Y -Y +Z -Z).
int cube_face(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
    if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
    return d.z >= 0.0 ? 4 : 5;
}
