// mode: depth. Linear view depth (the distance along the view axis) mapped from
// [near, far] to [0, 1]: black near, white far (and where nothing is drawn). With
// DEPTH_IN_SCENE_UNITS (EXR output) the depth itself, in scene units, and 0 where nothing is.
uniform sampler2D u_gbuffer;
uniform vec2 u_near_far;
out vec4 frag_color;

void main() {
    float depth = texelFetch(u_gbuffer, ivec2(gl_FragCoord.xy), 0).w;
#ifdef DEPTH_IN_SCENE_UNITS
    float value = max(depth, 0.0);
#else
    float value = depth <= 0.0 ? 1.0 : clamp((depth - u_near_far.x) / (u_near_far.y - u_near_far.x), 0.0, 1.0);
#endif
    frag_color = vec4(vec3(value), 1.0);
}
