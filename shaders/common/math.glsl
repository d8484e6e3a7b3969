// Small helpers shared by every program.

// normalize() of a zero vector is undefined (NaN on most drivers); fall back instead.
vec3 safe_normalize(vec3 v, vec3 fallback) {
    float len2 = dot(v, v);
    return len2 > 1e-20 ? v * inversesqrt(len2) : fallback;
}

vec3 safe_normalize(vec3 v) {
    return safe_normalize(v, vec3(0.0, 1.0, 0.0));
}

float max_component(vec3 v) {
    return max(v.x, max(v.y, v.z));
}
