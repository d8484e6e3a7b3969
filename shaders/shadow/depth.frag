// Writes linear depth in [0, 1] over the view's range: distance from the light for point
// lights (RADIAL_DEPTH), distance along the light's axis otherwise. An orthographic view
// (ORTHOGRAPHIC: directional lights) needs no fragment work at all: its window depth is
// already linear over the range, and a shader that writes no depth lets the rasterizer
// test and store depth on its own fast path.
#ifndef ORTHOGRAPHIC
in vec3 v_light_position;
uniform vec2 u_depth_range;  // near, far
#endif
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#endif

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
#ifndef ORTHOGRAPHIC
#ifdef RADIAL_DEPTH
    float distance = length(v_light_position);
#else
    float distance = -v_light_position.z;
#endif
    gl_FragDepth = clamp((distance - u_depth_range.x) / (u_depth_range.y - u_depth_range.x), 0.0, 1.0);
#endif
}
