// One spherical-harmonic coefficient of one probe's irradiance: the captured radiance
// projected onto Y_lm (a sum over the cube map's texels, each weighted by its solid
// angle) and convolved with the clamped cosine (Ramamoorthi and Hanrahan 2001: pi,
// 2 pi / 3, pi / 4 for bands 0, 1, 2), so a lookup sums coefficient x Y_lm(n).
// Texel (u_column + i, b) of the target: coefficient i of probe b (each bounce's nine
// coefficients have their own columns).
#include "indirect/probes.glsl"
#include "indirect/capture.glsl"

uniform int u_column;  // the first of this bounce's columns
out vec4 frag_color;

void main() {
    int coefficient = int(gl_FragCoord.x) - u_column;
    int probe = int(gl_FragCoord.y);
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    for (int face = 0; face < 6; ++face) {
        for (int y = 0; y < CAPTURE_SIZE; ++y) {
            for (int x = 0; x < CAPTURE_SIZE; ++x) {
                vec3 place = capture_texel_place(x, y);
                float basis[9];
                sh_basis(normalize(cube_direction(face, place.xy)), basis);
                vec3 radiance = texelFetch(u_capture, capture_texel(probe, face, x, y), 0).rgb;
                sum += radiance * (basis[coefficient] * place.z);
                weights += place.z;
            }
        }
    }
    // the texels' solid angles sum to 4 pi exactly in the limit; normalise to it
    float band = coefficient == 0 ? 3.14159265 : (coefficient < 4 ? 2.09439510 : 0.78539816);
    frag_color = vec4(sum * (4.0 * 3.14159265 / weights) * band, 1.0);
}
