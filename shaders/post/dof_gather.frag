// Depth of field by gathering (render.depth_of_field: gather; rendering/passes/depth_of_field.py).
// Each pixel's circle of confusion from its inverse linear view depth (u_lens_depth: the
// nearest of its 3 x 3 neighbours', shaders/post/dof_nearest.frag; 0 where empty: infinitely
// far): radius r(z) = u_coc_scale * |1/S - 1/z| pixels, at most u_max_radius.
// TAPS points of a Vogel spiral cover this pixel's own circle; a tap adds its colour where its
// own circle reaches this pixel, weighted by 1 / its area (its light is spread over it), so a
// sharp subject does not bleed into the blur around it. A tap behind this pixel spreads no
// wider than this pixel's circle, so a blurred background does not wash over a sharp subject
// in front of it. Left out: a blurred near edge spreading over a sharp background (the
// background pixel does not look that far).
uniform sampler2D u_color;
uniform sampler2D u_lens_depth;
uniform float u_coc_scale;    // pixels per unit of |1/S - 1/z|
uniform float u_inv_focus;    // 1/S
uniform float u_max_radius;   // pixels
out vec4 frag_color;

const float GOLDEN_ANGLE = 2.39996323;

float coc_radius(float inv_depth) {
    return min(u_coc_scale * abs(u_inv_focus - inv_depth), u_max_radius);
}

void main() {
    ivec2 size = textureSize(u_color, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 centre = texelFetch(u_color, p, 0);
    float centre_inv = texelFetch(u_lens_depth, p, 0).r;
    float centre_radius = coc_radius(centre_inv);
    float search = max(centre_radius, 0.5);
    float floor_area = search * search / float(TAPS) + 0.25;  // the area one tap stands for
    float weight = 1.0 / max(centre_radius * centre_radius, floor_area);
    vec3 sum = centre.rgb * weight;
    float total = weight;
    for (int i = 0; i < TAPS; ++i) {
        float along = sqrt((float(i) + 0.5) / float(TAPS)) * search;
        vec2 offset = along * vec2(cos(float(i) * GOLDEN_ANGLE), sin(float(i) * GOLDEN_ANGLE));
        ivec2 q = clamp(p + ivec2(round(offset)), ivec2(0), size - 1);
        float inv = texelFetch(u_lens_depth, q, 0).r;
        float radius = coc_radius(inv);
        if (inv < centre_inv) {  // behind this pixel
            radius = min(radius, centre_radius);
        }
        float reach = clamp(radius - length(vec2(q - p)) + 0.5, 0.0, 1.0);
        float w = reach / max(radius * radius, floor_area);
        sum += texelFetch(u_color, q, 0).rgb * w;
        total += w;
    }
    frag_color = vec4(sum / total, centre.a);
}
