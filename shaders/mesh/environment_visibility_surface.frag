// The environment visibility's surfaces: at each pixel of its image, the surface the camera
// sees there, its camera-relative position (xyz, whole floats) and the normal facing the
// camera (w, common/surface_normal.glsl's code; 0 where nothing is drawn), for the lookups
// (post/environment_visibility.frag) to run once a pixel. One target rather than a
// position and a normal image: the pass and each lookup then move half the bytes.
// Shading the lookups here instead ran them once for every triangle over each of
// llvmpipe's 4x4 blocks: a finely divided mesh, at half the image's resolution, shaded its
// blocks several times over.
#include "common/math.glsl"
#include "common/surface_normal.glsl"
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#else
in vec2 v_uv;
#endif
in vec3 v_position;
in vec3 v_normal;
out vec4 surface;

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
    surface = vec4(v_position, encode_normal(safe_normalize(gl_FrontFacing ? v_normal : -v_normal)));
}
