// Motion blur along the velocity buffer (render.motion_blur: velocity;
// rendering/passes/motion_blur.py), after McGuire et al., "A reconstruction filter for
// plausible motion blur" (I3D 2012). Each pixel X reads up to TAPS points Y along its
// neighbourhood's longest smear v_N (u_velocity_tiles), from X - v_N to X + v_N and the half
// pixel beyond, every pixel once where that path is TAPS pixels or fewer. X's own motion and
// depth are its 3 x 3 neighbourhood's nearest surface's (nearest_around). A point whose
// colour moves with smear radius r spreads it evenly over 2r pixels of its path, so a tap
// standing for `spacing` pixels adds spacing / (2r) of its colour where its path covers X:
//  - Y in front of X: by Y's own smear (a moving object in front blurs over X);
//  - Y behind X: by X's smear (X moving uncovers what lies behind it);
//  - Y at X's depth: by Y's smear (one moving surface).
// What lies in front is laid over the rest, which is normalised to fill what it leaves:
// a static background next to a moving box keeps 1 - (the box's share), not a mean.
// Depths compare softly over SOFT_DEPTH of their distance.
uniform sampler2D u_color;
uniform sampler2D u_velocity;  // rg: smear radius vector (pixels), b: view depth
uniform sampler2D u_velocity_tiles;  // rg: the neighbourhood's longest smear
out vec4 frag_color;

const float SOFT_DEPTH = 0.02;
const float SMALLEST_RADIUS = 0.5;  // a still pixel covers itself

// 1 where depth a lies in front of depth b by SOFT_DEPTH of b or more, 0 at b and behind
float in_front(float a, float b) {
    return clamp((b - a) / (SOFT_DEPTH * min(a, b)), 0.0, 1.0);
}

// the share of a colour moving with smear radius `radius` that lands `distance` away, per
// pixel of path: its path's end covers part of a pixel (a very bright colour shows it)
float spread(float distance, float radius) {
    return clamp(radius + 0.5 - distance, 0.0, 1.0) * 0.5 / radius;
}

// interleaved gradient noise (Jimenez 2014): a per-pixel offset of the taps, so their
// spacing shows as fine noise rather than bands
float jitter(vec2 p) {
    return fract(52.9829189 * fract(dot(p, vec2(0.06711056, 0.00583715)))) - 0.5;
}

// the pixel's own motion and depth: of the nearest surface among its 3 x 3 neighbours. The
// velocity image holds one surface a pixel while the colour's edge pixels mix two; an edge
// pixel taken for the still background would keep its share of a moving edge's colour
// where it is, unblurred, on top of that edge's blur (a bright seam along the instant's
// edges); taken for the moving surface, its colour is one tap of that surface's blur.
vec3 nearest_around(ivec2 x, ivec2 last) {
    vec3 nearest = texelFetch(u_velocity, x, 0).xyz;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            vec3 there = texelFetch(u_velocity, clamp(x + ivec2(dx, dy), ivec2(0), last), 0).xyz;
            nearest = there.z < nearest.z ? there : nearest;
        }
    }
    return nearest;
}

// the longer of a unit direction's two components: pixels along the major axis per pixel of path
float major(vec2 direction) {
    return max(abs(direction.x), abs(direction.y));
}

void main() {
    ivec2 x = ivec2(gl_FragCoord.xy);
    vec4 centre = texelFetch(u_color, x, 0);
    vec2 leading = texelFetch(u_velocity_tiles, x / TILE, 0).xy;
    float reach = length(leading);
    if (reach <= SMALLEST_RADIUS) {
        frag_color = centre;
        return;
    }
    ivec2 last = textureSize(u_color, 0) - 1;
    vec3 here = nearest_around(x, last);
    float radius_x = max(length(here.xy), SMALLEST_RADIUS);
    // the taps span the smear's reach and the half pixel its end covers (spread): taps over
    // the reach alone sample the two end pixels half as often as the rest, and the smear
    // comes out short by about a pixel
    float span = reach + 0.5;
    vec3 front_sum = vec3(0.0);
    float front_weight = 0.0;
    vec3 rest_sum = centre.rgb * (0.5 / radius_x);
    float rest_weight = 0.5 / radius_x;
    // every other tap along the pixel's own motion, where it has one (after Guertin et al.,
    // "A fast and stable feature-aware motion blur filter", 2014): where motion turns
    // across the neighbourhood (a camera turning: the corners move along curves), the
    // longest smear alone would lead the taps off the pixel's own path
    vec2 lead_direction = leading / reach;
    vec2 own_direction = length(here.xy) > 1.0 ? normalize(here.xy) : lead_direction;
    // a path of up to TAPS pixels (along its major axis) is read one tap a pixel, no pixel
    // twice or skipped, so a short smear has no noise; a longer one by TAPS jittered taps
    int whole = int(span * major(lead_direction));
    bool every_pixel = 2 * whole <= TAPS;
    float offset = jitter(gl_FragCoord.xy);
    for (int i = 0; i < TAPS; ++i) {
        vec2 direction = (i % 2 == 0) ? lead_direction : own_direction;
        float along, spacing;
        if (every_pixel) {
            if (i >= 2 * whole) {
                break;
            }
            // steps 1..whole each way; the two directions take turns on each side
            float side = ((i / 2) % 2 == i % 2) ? 1.0 : -1.0;
            spacing = 1.0 / major(direction);
            along = side * float(i / 2 + 1) * spacing;
        } else {
            spacing = 2.0 * span / float(TAPS);
            along = ((float(i) + 0.5 + offset) / float(TAPS) * 2.0 - 1.0) * span;
        }
        ivec2 y = clamp(x + ivec2(round(direction * along)), ivec2(0), last);
        if (y == x) {
            continue;
        }
        vec3 there = texelFetch(u_velocity, y, 0).xyz;
        vec3 colour = texelFetch(u_color, y, 0).rgb;
        float distance = length(vec2(y - x));
        float radius_y = max(length(there.xy), SMALLEST_RADIUS);
        float front = in_front(there.z, here.z);
        float behind = in_front(here.z, there.z);
        float over = front * spacing * spread(distance, radius_y);
        float under = (behind * spread(distance, radius_x) + (1.0 - front - behind) * spread(distance, radius_y))
                      * spacing;
        front_sum += colour * over;
        front_weight += over;
        rest_sum += colour * under;
        rest_weight += under;
    }
    vec3 colour = front_weight >= 1.0 ? front_sum / front_weight
                                      : front_sum + (1.0 - front_weight) * rest_sum / rest_weight;
    frag_color = vec4(colour, centre.a);
}
