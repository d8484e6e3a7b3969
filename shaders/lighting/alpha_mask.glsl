// glTF alpha mode MASK in the passes that draw no colour (shadow maps, the geometry
// prepass): the alpha the forward pass compares with the cutoff, from the same material
// inputs, so a cut-away pixel casts no shadow and holds no depth.
#include "common/math.glsl"
#include "lighting/material.glsl"

in vec2 v_uv;
#ifdef HAS_VERTEX_COLOR
in vec4 v_color;
#endif

bool cut_away() {
    float alpha = sample_surface(v_uv).alpha;
#ifdef HAS_VERTEX_COLOR
    alpha *= v_color.a;
#endif
    return alpha < u_alpha_cutoff;
}
