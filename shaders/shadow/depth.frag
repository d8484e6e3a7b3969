// Writes linear depth in [0, 1] over the view's range: distance from the light for point
// lights (RADIAL_DEPTH), distance along the light's axis otherwise.
in vec3 v_light_position;
uniform vec2 u_depth_range;  // near, far

void main() {
#ifdef RADIAL_DEPTH
    float distance = length(v_light_position);
#else
    float distance = -v_light_position.z;
#endif
    gl_FragDepth = clamp((distance - u_depth_range.x) / (u_depth_range.y - u_depth_range.x), 0.0, 1.0);
}
