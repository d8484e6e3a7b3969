// What the probe grid's bake and its lookup share (rendering/passes/indirect.py): the cube
// faces a probe sees the scene through, the octahedral map of directions its depth tile
// holds, and the nine real spherical harmonics (bands 0-2) its irradiance is kept in.

// Cube face f looks along CUBE_FORWARD[f] with CUBE_UP[f] up; its right is
// cross(forward, up). The same table is passes/indirect.py's CUBE_FACES.
const vec3 CUBE_FORWARD[6] = vec3[](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0),
                                    vec3(0, 0, 1), vec3(0, 0, -1));
const vec3 CUBE_UP[6] = vec3[](vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, -1),
                               vec3(0, 1, 0), vec3(0, 1, 0));

// The (unnormalised) direction through (u, v) in [-1, 1]^2 of face f's image.
vec3 cube_direction(int f, vec2 uv) {
    vec3 forward = CUBE_FORWARD[f];
    vec3 up = CUBE_UP[f];
    return forward + uv.x * cross(forward, up) + uv.y * up;
}

// Octahedral map: unit direction <-> [-1, 1]^2.
vec2 octahedral_encode(vec3 d) {
    vec2 p = d.xy / (abs(d.x) + abs(d.y) + abs(d.z));
    if (d.z < 0.0) {
        p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
    }
    return p;
}

vec3 octahedral_decode(vec2 p) {
    vec3 d = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (d.z < 0.0) {
        d.xy = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
    }
    return normalize(d);
}

// The real spherical harmonics Y_00, Y_1-1, Y_10, Y_11, Y_2-2, Y_2-1, Y_20, Y_21, Y_22 at
// the unit direction d.
void sh_basis(vec3 d, out float y[9]) {
    y[0] = 0.282095;
    y[1] = 0.488603 * d.y;
    y[2] = 0.488603 * d.z;
    y[3] = 0.488603 * d.x;
    y[4] = 1.092548 * d.x * d.y;
    y[5] = 1.092548 * d.y * d.z;
    y[6] = 0.315392 * (3.0 * d.z * d.z - 1.0);
    y[7] = 1.092548 * d.x * d.z;
    y[8] = 0.546274 * (d.x * d.x - d.y * d.y);
}
