// mode: normals. World-space normals mapped to colour, n * 0.5 + 0.5; black where empty.
uniform sampler2D u_gbuffer;
uniform mat3 u_view_rotation;  // world -> view
out vec4 frag_color;

void main() {
    vec4 g = texelFetch(u_gbuffer, ivec2(gl_FragCoord.xy), 0);
    vec3 world = transpose(u_view_rotation) * g.xyz;
    frag_color = g.w <= 0.0 ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(world * 0.5 + 0.5, 1.0);
}
