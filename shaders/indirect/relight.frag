// A later bounce without drawing the scene again: each texel of the probes' captures gives
// the light it gave in the first (direct light, emission, ambient, environment) plus its
// diffuse reflectance times the irradiance the last bounce's probes hold at the surface it
// shows (position: the probe's, out along the texel's direction by the distance), / pi.
#include "common/math.glsl"
#include "lighting/indirect.glsl"
#include "indirect/capture.glsl"

uniform sampler2D u_capture_reflectance;
uniform sampler2D u_capture_normal;  // the shading normal, the distance
out vec4 frag_color;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    vec4 first = texelFetch(u_capture, texel, 0);
    vec4 normal = texelFetch(u_capture_normal, texel, 0);
    vec3 reflectance = texelFetch(u_capture_reflectance, texel, 0).rgb;
    vec3 color = first.rgb;
    if (max_component(reflectance) > 0.0) {  // not a miss, nor an unlit surface
        ivec2 tile = texel / CAPTURE_SIZE;
        int probe = tile.y * CAPTURE_COLUMNS + tile.x / 6;
        ivec3 counts = ivec3(PROBE_COUNTS);
        ivec3 cell = ivec3(probe % counts.x, (probe / counts.x) % counts.y, probe / (counts.x * counts.y));
        vec3 place = capture_texel_place(texel.x - tile.x * CAPTURE_SIZE, texel.y - tile.y * CAPTURE_SIZE);
        vec3 towards = normalize(cube_direction(tile.x % 6, place.xy));
        vec3 p = u_probe_origin + vec3(cell) * u_probe_spacing + towards * normal.w;
        color += reflectance * probe_irradiance(p, normal.xyz, -towards) / 3.14159265;
    }
    frag_color = vec4(color, first.a);
}
