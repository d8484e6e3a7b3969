// Percentage-closer soft shadows (Fernando 2005) for lights with a size: a blocker search
// finds the mean depth of what lies between the point and the light, the penumbra's width
// follows from it by similar triangles, and a comparison filter that wide gives the
// fraction of the light seen. The penumbra is sharp where a caster meets its receiver and
// widens with the distance between them. Near the umbra a perspective view's light fades
// out where the light's centre is hidden (CONTACT_FULL, CONTACT_FADE), which keeps the umbra
// beside a box's foot dark; with solid casters (SOLID_CASTERS, solid_fraction) each tap's
// ray is marched through the map and a second one of the casters' back faces instead.
// Included only where a shadowed light has a size
// (SOFT_SHADOWS); the atlas is read twice over: through its comparison sampler
// (u_shadow_atlas) and as plain depth (u_shadow_depth, the same texture with comparison
// off), which the blocker search needs.

uniform sampler2D u_shadow_depth;
#if SHADOW_PAGES > 1
uniform sampler2D u_shadow_depth_2;
#endif

// Plain depth at atlas uv on ``page`` (a compile-time constant where callers pass one).
float stored_depth(int page, vec2 uv) {
#if SHADOW_PAGES > 1
    return page == 0 ? textureLod(u_shadow_depth, uv, 0.0).r : textureLod(u_shadow_depth_2, uv, 0.0).r;
#else
    return textureLod(u_shadow_depth, uv, 0.0).r;
#endif
}

float compared_depth(int page, vec2 uv, float depth) {
#if SHADOW_PAGES > 1
    return page == 0 ? textureLod(u_shadow_atlas, vec3(uv, depth), 0.0) : textureLod(u_shadow_atlas_2, vec3(uv, depth), 0.0);
#else
    return textureLod(u_shadow_atlas, vec3(uv, depth), 0.0);
#endif
}

// Point k of ``count`` spread evenly over the unit disc (a Vogel spiral: golden-angle
// turns, radius sqrt of the area share), turned by ``turn`` radians.
vec2 disc_point(int k, int count, float turn) {
    float radius = sqrt((float(k) + 0.5) / float(count));
    float angle = float(k) * 2.39996323 + turn;
    return radius * vec2(cos(angle), sin(angle));
}

// A turn per pixel (interleaved gradient noise, Jimenez 2014), so neighbouring pixels'
// spirals differ and the filter's few samples blur into noise rather than bands.
float pixel_turn() {
    return 6.28318531 * fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
}

// The widest search and filter, in texels: a sixteenth of the view's tile.
const float SOFT_MAX_FRACTION = 0.0625;

// Fraction of a sized light reaching p, for one view. size: the sphere's radius (point,
// spot), or the tangent of a directional light's half angle. blockers, filters: the reads
// of each step (compile-time constants of the light: render.shadows.blocker_samples,
// filter_samples). Bias as shadow_lookup's, plus the receiver's own change in depth over
// each read's offset, so a tilted receiver does not shadow itself across a wide filter.
// A point of the square [-1, 1]^2, k of ``count``: the filter of a rectangle light. The
// Hammersley set, turned on the torus by ``shift`` (a different turn per axis): its points'
// projections on either axis are evenly spaced, so a shadow edge along one of the light's
// sides is counted within one tap, where the R2 sequence shifted along the diagonal drew
// stripes of a few percent along the box's edges.
vec2 square_point(int k, int count, float shift) {
    vec2 hammersley = vec2((float(k) + 0.5) / float(count), float(bitfieldReverse(uint(k))) * 2.3283064365386963e-10);
    return 2.0 * fract(hammersley + vec2(shift, fract(shift * 1.61803399))) - 1.0;
}

// What a point of an area light gives p, up to a constant: cos at p times cos at the light
// over the squared distance (the form factor's integrand). The filter's taps each stand for
// a point of the light; weighted by it, the lit fraction is the share of the light's
// irradiance that arrives, not of its area: seen from a point in the penumbra, the light's
// near part, which stays in view longest, gives more than its far part (twice as much
// across a 1 m rectangle 2.5 m up), and an unweighted filter darkens the band's outer half.
float light_point_weight(vec3 point, vec3 p, vec3 n, vec3 facing) {
    vec3 d = point - p;
    float distance2 = max(dot(d, d), 1e-12);
    return max(dot(n, d), 0.0) * max(-dot(facing, d), 0.0) / (distance2 * distance2);
}

// Near the umbra, the filter's light fades out where the light's centre is hidden from p.
// One mean depth of the casters makes the penumbra as wide as the nearest caster's top
// would cast it, so beside a box's foot, where the box's side (which the map cannot see)
// blocks the light, the filter lets light into the umbra. Seen from the light, the map is
// a heightfield: what lies behind a stored depth is solid (a box standing on the floor is
// solid down to it), and a segment from such a p towards the light passes through it. The
// segment to the light's centre projects to p's own texel, so the test is the centre's
// own depth comparison; segments to the light's other points, marched through the map,
// gave the same image there (within 0.02 % of the lit floor, benchmarks/quality/
// rect_umbra.md). Below CONTACT_FULL of the light seen the fade is whole, none from
// CONTACT_FADE on: the heightfield also fills the empty space behind a caster as the
// light's centre sees it, and would darken the penumbra's inner half.
const float CONTACT_FULL = 0.1;
const float CONTACT_FADE = 0.2;

#ifdef SOLID_CASTERS
// Solid casters (render.shadows.casters: solid): a second map holds, per texel, the depth
// of the casters' far side as the light sees it (their faces turned away from it), so a
// closed caster fills the depths between the two maps and the space behind it is empty.
// Each filter tap's ray towards its point of the light is marched through the two maps and
// blocked where it lies inside a caster: beside a box's foot the box's side blocks it,
// behind the box's top it passes. An open surface (a plane) is drawn on both sides, thin:
// a ray is blocked where it crosses it, within one step.
uniform sampler2D u_shadow_back;
#if SHADOW_PAGES > 1
uniform sampler2D u_shadow_back_2;
#endif

float back_depth(int page, vec2 uv) {
#if SHADOW_PAGES > 1
    return page == 0 ? textureLod(u_shadow_back, uv, 0.0).r : textureLod(u_shadow_back_2, uv, 0.0).r;
#else
    return textureLod(u_shadow_back, uv, 0.0).r;
#endif
}

// Points looked at along each ray, evenly spread over the map (in 1 / depth) from p's
// depth to the nearest caster the blocker search found.
const int SOLID_STEPS = 8;

// World point x in a view of the map: (atlas uv, depth as the map stores it).
vec3 map_point(int index, vec3 x, bool radial) {
    vec4 q = shadow_views[index].to_atlas * vec4(x, 1.0);
    vec4 depth_params = shadow_views[index].depth;
    float depth = radial ? (distance(x, shadow_views[index].light.xyz) - depth_params.x) * depth_params.y : q.z;
    return vec3(q.xy / q.w, depth);
}

// Whether the segment from p towards ``point`` of the light passes inside a caster.
// d_receiver, d_nearest: p's and the nearest caster's distances (along the view's depth);
// margin: the receiver's bias, in the map's depth units.
bool segment_blocked(int index, int page, vec3 p, vec3 point, bool radial, float d_receiver, float d_nearest,
                     float margin) {
    vec4 tile = shadow_views[index].tile;
    float last = map_point(index, p, radial).z;
    for (int j = 1; j <= SOLID_STEPS; ++j) {
        float inverse = mix(1.0 / d_receiver, 1.0 / d_nearest, float(j) / float(SOLID_STEPS));
        // towards the light's centre, depth falls as d_receiver (1 - t) along the segment
        vec3 x = map_point(index, mix(p, point, 1.0 - 1.0 / (inverse * d_receiver)), radial);
        if (any(lessThan(x.xy, tile.xy)) || any(greaterThan(x.xy, tile.zw))) {
            return false;  // off this view of the map
        }
        // a thin (open) surface counts as one step thick, so the march cannot step over
        // it; a closed caster as thick as it is
        // the receiver's bias keeps its own surface from blocking the ray where the ray
        // leaves it; past the first point a tenth of it
        float bias = j == 1 ? margin : 0.1 * margin;
        float step = max(last - x.z, bias);
        last = x.z;
        float front = stored_depth(page, x.xy);
        if (x.z > front + bias && x.z < max(back_depth(page, x.xy), front + step)) {
            return true;
        }
    }
    return false;
}

// The weighted share of the light's points (the filter's taps) whose rays reach p.
// Arguments as shadow_lookup_shaped's; d_nearest: the nearest caster's distance.
float solid_fraction(int index, int page, int filters, vec3 p, vec3 n, vec2 uv, float margin, float d_receiver,
                     float d_nearest, bool radial, float size, vec3 extent_u, vec3 extent_v, vec3 facing,
                     bool shaped, bool square, float turn) {
    vec3 centre = shadow_views[index].light.xyz;
    // a sphere's tap stands for the point of its disc facing p that far along the map's
    // axes (their directions in the world at p: the gradients of u and v, (row - uv * row
    // 3) / w, the 1 / w dropped)
    vec3 toward = normalize(centre - p);
    mat4 m = shadow_views[index].to_atlas;
    vec3 row_w = vec3(m[0][3], m[1][3], m[2][3]);
    vec3 grad_u = vec3(m[0][0], m[1][0], m[2][0]) - uv.x * row_w;
    vec3 grad_v = vec3(m[0][1], m[1][1], m[2][1]) - uv.y * row_w;
    vec3 across_u = normalize(grad_u - dot(grad_u, toward) * toward);
    vec3 across_v = cross(toward, across_u);
    across_v *= dot(across_v, grad_v) < 0.0 ? -1.0 : 1.0;
    float lit = 0.0;
    float total = 0.0;
    for (int k = 0; k < filters; ++k) {
        vec2 unit = square ? square_point(k, filters, turn * 0.159154943) : disc_point(k, filters, turn + 1.0);
        vec3 point = shaped ? centre + unit.x * extent_u + unit.y * extent_v
                            : centre + size * (unit.x * across_u + unit.y * across_v);
        float weight = shaped ? light_point_weight(point, p, n, facing) : 1.0;
        lit += segment_blocked(index, page, p, point, radial, d_receiver, d_nearest, margin) ? 0.0 : weight;
        total += weight;
    }
    return total > 0.0 ? lit / total : 1.0;
}
#endif

// Rectangle and disk lights pass their half axes (world vectors, ``extent_u``,
// ``extent_v``; zero for a sphere) and whether they are a rectangle: the filter then takes
// the light's own shape, its axes carried onto the map at p, instead of a disc of radius
// ``size``. solid: the light's casters are solid (solid_fraction; a compile-time constant,
// false unless SOLID_CASTERS).
float shadow_lookup_shaped(int index, int page, int blockers, int filters, vec3 p, vec3 n, float n_dot_l,
                           bool perspective, bool radial, float size, vec3 extent_u, vec3 extent_v, bool square,
                           bool solid) {
    vec4 light = shadow_views[index].light;
    vec4 depth_params = shadow_views[index].depth;
    vec4 texel_world = shadow_views[index].texel;
    vec4 tile = shadow_views[index].tile;
    vec2 texel = shadow_views[index].sampling.xy;
    float cos_l = clamp(n_dot_l, 1e-4, 1.0);
    float grazing = sqrt(clamp(1.0 - cos_l * cos_l, 0.0, 1.0));
    float texel_size = perspective ? texel_world.x * distance(p, light.xyz) : texel_world.y;
    float tan_angle = min(grazing / cos_l, 10.0);
    float bias = texel_size * (depth_params.z + depth_params.w * tan_angle) * depth_params.y;
    float slope = texel_size * tan_angle * depth_params.y;  // the receiver's depth change per texel
    vec4 q = shadow_views[index].to_atlas * vec4(p, 1.0);
    vec2 uv = perspective ? q.xy / q.w : q.xy;
    float receiver = radial ? (distance(p, light.xyz) - depth_params.x) * depth_params.y : q.z;
    if ((perspective && q.w <= 0.0) || receiver > 1.0 || any(lessThan(uv, tile.xy)) || any(greaterThan(uv, tile.zw))) {
        return 1.0;
    }
    float range = 1.0 / depth_params.y;
    float near = max(depth_params.x, 1e-6);
    float d_receiver = depth_params.x + receiver * range;
    float widest = SOFT_MAX_FRACTION * (tile.z - tile.x) / texel.x;
    // Texels of the map across the light's disc seen from p through a plane at depth d:
    // perspective, size (1 / d - 1 / d_receiver) on the view's image plane at distance 1
    // (depths along the view's axis; a radial depth times the cosine of p's angle off the
    // axis, q.w / distance, is one), over its texel there; orthographic, size (d_receiver - d)
    // over the texel. The search covers every caster from the near plane on.
    float axial = radial ? q.w / max(d_receiver, 1e-20) : 1.0;
    float per_inverse_depth = size / (axial * texel_world.x);
    // a shaped light's half axes on the map, in texels per unit of 1 / d (radial depths:
    // over the cosine, as above): how a move along each axis moves p's projection, times
    // p's depth along the view's axis (q.w, which cancels: (q_u.xy - uv q_u.w) / q.w x q.w)
    bool shaped = dot(extent_u, extent_u) > 0.0;
    // the side the light shines to (one-sided area lights face p)
    vec3 facing = cross(extent_u, extent_v);
    facing *= dot(facing, p - light.xyz) < 0.0 ? -1.0 : 1.0;
    vec2 axis_u = vec2(0.0);
    vec2 axis_v = vec2(0.0);
    if (shaped) {
        vec4 q_u = shadow_views[index].to_atlas * vec4(extent_u, 0.0);
        vec4 q_v = shadow_views[index].to_atlas * vec4(extent_v, 0.0);
        axis_u = (q_u.xy - uv * q_u.w) / (texel * axial);
        axis_v = (q_v.xy - uv * q_v.w) / (texel * axial);
        per_inverse_depth = length(axis_u) + length(axis_v);
    }
    float search = perspective ? per_inverse_depth * (1.0 / near - 1.0 / max(d_receiver, near))
                               : size * receiver * range / texel_world.y;
    search = clamp(search, 1.0, widest);
    float turn = pixel_turn();
    float blocker_sum = 0.0;
    float blocker_count = 0.0;
    float blocker_nearest = 1.0;
    for (int k = 0; k < blockers; ++k) {
        vec2 offset = disc_point(k, blockers, turn) * search;
        vec2 tap = clamp(uv + offset * texel, tile.xy + texel, tile.zw - texel);
        float depth = stored_depth(page, tap);
        bool blocks = depth < receiver - bias - slope * length(offset);
        blocker_sum += blocks ? depth : 0.0;
        blocker_count += blocks ? 1.0 : 0.0;
        blocker_nearest = blocks ? min(blocker_nearest, depth) : blocker_nearest;
    }
    if (blocker_count == 0.0) {
        return 1.0;
    }
#ifdef SOLID_CASTERS
    if (solid) {
        float d_nearest = max(depth_params.x + blocker_nearest * range, near);
        return solid_fraction(index, page, filters, p, n, uv, bias + slope, d_receiver, d_nearest, radial, size,
                              extent_u, extent_v, facing, shaped, square, turn);
    }
#endif
    float d_blocker = depth_params.x + blocker_sum / blocker_count * range;
    // the light's disc seen from p through the blockers' plane, in texels: the penumbra
    float penumbra = perspective ? per_inverse_depth * (1.0 / max(d_blocker, near) - 1.0 / d_receiver)
                                 : size * (d_receiver - d_blocker) / texel_world.y;
    float narrowest = 0.5 * float(max(int(shadow_views[index].sampling.z) - 1, 1));
    float radius = clamp(penumbra, narrowest, widest);
    // a shaped light's axes at the blockers' depth, each at least the pcf filter's half width
    float scale = perspective ? 1.0 / max(d_blocker, near) - 1.0 / d_receiver : 0.0;
    vec2 along_u = axis_u * clamp(scale, narrowest / max(length(axis_u), 1e-20), widest / max(length(axis_u), 1e-20));
    vec2 along_v = axis_v * clamp(scale, narrowest / max(length(axis_v), 1e-20), widest / max(length(axis_v), 1e-20));
    float lit = 0.0;
    float total = 0.0;
    for (int k = 0; k < filters; ++k) {
        vec2 unit = square ? square_point(k, filters, turn * 0.159154943) : disc_point(k, filters, turn + 1.0);
        vec2 offset = shaped ? along_u * unit.x + along_v * unit.y : unit * radius;
        vec2 tap = clamp(uv + offset * texel, tile.xy + texel, tile.zw - texel);
        // a shaped light's tap stands for its point centre + unit.x extent_u + unit.y extent_v
        float weight = shaped ? light_point_weight(light.xyz + unit.x * extent_u + unit.y * extent_v, p, n, facing) : 1.0;
        lit += weight * compared_depth(page, tap, receiver - bias - slope * length(offset));
        total += weight;
    }
    float fraction = total > 0.0 ? lit / total : 1.0;
    // nearly in umbra (a perspective view's: a directional light's penumbra is left as filtered)
    if (perspective && fraction > 0.0 && fraction < CONTACT_FADE) {
        float share = clamp((CONTACT_FADE - fraction) / (CONTACT_FADE - CONTACT_FULL), 0.0, 1.0);
        fraction *= 1.0 - share * (1.0 - compared_depth(page, uv, receiver - bias));
    }
    return fraction;
}

// A sphere light (or a sun): a disc of radius ``size``.
float shadow_lookup_soft(int index, int page, int blockers, int filters, vec3 p, vec3 n, float n_dot_l,
                         bool perspective, bool radial, float size, bool solid) {
    return shadow_lookup_shaped(index, page, blockers, filters, p, n, n_dot_l, perspective, radial, size,
                                vec3(0.0), vec3(0.0), false, solid);
}
