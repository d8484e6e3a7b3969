in vec3 v_direction;
uniform samplerCube u_skybox;
out vec4 frag_color;

void main() {
    frag_color = vec4(texture(u_skybox, v_direction).rgb, 1.0);
}
