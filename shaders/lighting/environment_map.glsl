// The equirectangular mapping of environment images (world/environment.py):
//   u = 1/2 + atan2(d.x, -d.z) / (2 pi),  v = acos(d.y) / pi   (v = 0: +Y)
// ENV_LEVELS, ENV_STRIP_WIDTH and ENV_STRIP_HEIGHT (floats) describe the prefiltered
// specular image: ENV_LEVELS strips of ENV_STRIP_WIDTH x ENV_STRIP_HEIGHT texels.

vec2 env_uv(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) * 0.15915494309189535, acos(clamp(d.y, -1.0, 1.0)) * 0.3183098861837907);
}

vec3 env_direction(vec2 uv) {
    float phi = (uv.x - 0.5) * 6.283185307179586;
    float theta = uv.y * 3.141592653589793;
    return vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}
