// One triangle that covers the viewport; no vertex buffer needed. FAR_PLANE_Z: its
// normalised-device depth on the far plane, for passes that shade only in front of it.
out vec2 v_uv;
#ifndef FAR_PLANE_Z
#define FAR_PLANE_Z 0.0
#endif

void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = corner;
    gl_Position = vec4(corner * 2.0 - 1.0, FAR_PLANE_Z, 1.0);
}
