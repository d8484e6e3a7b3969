in vec3 v_direction;
#include "skybox/sky_source.glsl"
out vec4 frag_color;

void main() {
    frag_color = vec4(sky_radiance(v_direction), 1.0);
}
