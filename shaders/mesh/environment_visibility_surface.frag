// The environment visibility's surfaces: at each pixel of its image, the surface the camera
// sees there, its camera-relative position (xyz) and the normal facing the camera (xyz),
// whole floats, for the lookups (post/environment_visibility.frag) to run once a pixel.
// Shading the lookups here instead ran them once for every triangle over each of
// llvmpipe's 4x4 blocks: a finely divided mesh, at half the image's resolution, shaded its
// blocks several times over.
#include "common/math.glsl"
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#else
in vec2 v_uv;
#endif
in vec3 v_position;
in vec3 v_normal;
layout(location = 0) out vec4 surface_position;
layout(location = 1) out vec4 surface_normal;

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
    surface_position = vec4(v_position, 1.0);
    surface_normal = vec4(safe_normalize(gl_FrontFacing ? v_normal : -v_normal), 0.0);
}
