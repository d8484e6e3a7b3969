// The velocity buffer (render.motion_blur: velocity; rendering/passes/motion_blur.py):
// where this surface point was when the shutter opened and where it is when it closes, on
// screen. u_open and u_close take the camera-relative world point the frame shows
// (v_position) to clip space at those instants (world/motion.py). Written: half the motion
// in pixels (the smear's radius, at most MAX_RADIUS, its direction kept) and the distance
// along the view axis. With SKY (drawn over the whole image before the objects, through
// skybox/skybox.vert): the skybox's motion, a direction infinitely far (w = 0), at EMPTY_DEPTH.
#ifdef SKY
in vec3 v_direction;
#else
in vec3 v_position;
#endif
uniform mat4 u_open;
uniform mat4 u_close;
uniform vec2 u_half_size;  // pixels from the image's centre to its edges
uniform vec3 u_forward;    // the camera's view direction
out vec4 frag_velocity;

void main() {
#ifdef SKY
    vec4 point = vec4(v_direction, 0.0);
#else
    vec4 point = vec4(v_position, 1.0);
#endif
    vec4 opened = u_open * point;
    vec4 closed = u_close * point;
    vec2 half_motion = vec2(0.0);
    if (opened.w > 0.0 && closed.w > 0.0) {  // a point behind the camera at either end has no place on screen
        half_motion = 0.5 * (closed.xy / closed.w - opened.xy / opened.w) * u_half_size;
    }
    float radius = length(half_motion);
    if (radius > MAX_RADIUS) {
        half_motion *= MAX_RADIUS / radius;
    }
#ifdef SKY
    frag_velocity = vec4(half_motion, EMPTY_DEPTH, 1.0);
#else
    frag_velocity = vec4(half_motion, dot(v_position, u_forward), 1.0);
#endif
}
