// Depth prepass: depth only, so the shading pass runs once per visible pixel. An
// alpha-masked material cuts away the pixels the shading pass discards.
#ifdef ALPHA_MASK
#include "lighting/alpha_mask.glsl"
#endif

void main() {
#ifdef ALPHA_MASK
    if (cut_away()) {
        discard;
    }
#endif
}
