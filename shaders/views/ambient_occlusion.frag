// mode: ambient_occlusion. The blurred AO term as grey: white open, black occluded.
uniform sampler2D u_ao;
out vec4 frag_color;

void main() {
    frag_color = vec4(vec3(texelFetch(u_ao, ivec2(gl_FragCoord.xy), 0).r), 1.0);
}
