// One flat colour: outlines and wireframe overlays.
uniform vec4 u_color;
out vec4 frag_color;

void main() {
    frag_color = vec4(u_color.rgb, 1.0);  // opaque: alpha is coverage (post/sky_under.glsl)
}
