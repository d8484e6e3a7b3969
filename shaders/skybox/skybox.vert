// Background cube map: a full-screen triangle on the far plane; each pixel looks up the
// world direction through it.
uniform mat4 u_inverse_view_proj;  // clip -> camera-relative world
uniform vec2 u_ndc_near_far;       // NDC z of the near and far planes (reversed-Z: 1, 0)
out vec3 v_direction;

void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
    vec4 far_point = u_inverse_view_proj * vec4(corner, u_ndc_near_far.y, 1.0);
    vec4 near_point = u_inverse_view_proj * vec4(corner, u_ndc_near_far.x, 1.0);
    v_direction = far_point.xyz / far_point.w - near_point.xyz / near_point.w;
    gl_Position = vec4(corner, u_ndc_near_far.y, 1.0);
}
