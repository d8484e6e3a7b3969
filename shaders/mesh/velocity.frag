// The velocity buffer (render.motion_blur: velocity; rendering/passes/motion_blur.py):
// where this surface point was when the shutter opened and where it is when it closes, on
// screen. u_open and u_close take the camera-relative world point the frame shows
// (v_position) to clip space at those instants (world/motion.py). Written: half the motion
// in pixels (the smear's radius, at most MAX_RADIUS, its direction kept) and the distance
// along the view axis.
in vec3 v_position;
uniform mat4 u_open;
uniform mat4 u_close;
uniform vec2 u_half_size;  // pixels from the image's centre to its edges
uniform vec3 u_forward;    // the camera's view direction
out vec4 frag_velocity;

void main() {
    vec4 opened = u_open * vec4(v_position, 1.0);
    vec4 closed = u_close * vec4(v_position, 1.0);
    vec2 half_motion = vec2(0.0);
    if (opened.w > 0.0 && closed.w > 0.0) {  // a point behind the camera at either end has no place on screen
        half_motion = 0.5 * (closed.xy / closed.w - opened.xy / opened.w) * u_half_size;
    }
    float radius = length(half_motion);
    if (radius > MAX_RADIUS) {
        half_motion *= MAX_RADIUS / radius;
    }
    frag_velocity = vec4(half_motion, dot(v_position, u_forward), 1.0);
}
