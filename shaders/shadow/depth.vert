// Shadow pass: scene meshes seen from a light, into one tile of the shadow atlas.
in vec3 in_position;
in mat4 in_model;  // per instance, relative to the eye of the light's first view

uniform mat4 u_light_view;        // eye-relative world -> light view
uniform mat4 u_light_projection;  // light view -> clip

out vec3 v_light_position;  // light-view position, for linear depth
#ifdef ALPHA_MASK
// what a cut-away material's alpha needs (shaders/lighting/material.glsl)
in vec2 in_uv;
out vec2 v_uv;
#ifdef HAS_VERTEX_COLOR
in vec4 in_color;
out vec4 v_color;
#endif
#endif

void main() {
#ifdef ALPHA_MASK
    v_uv = in_uv;
#ifdef HAS_VERTEX_COLOR
    v_color = in_color;
#endif
#endif
    vec4 light_p = u_light_view * (in_model * vec4(in_position, 1.0));
    v_light_position = light_p.xyz;
    gl_Position = u_light_projection * light_p;
}
