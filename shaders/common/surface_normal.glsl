// A unit normal in one float, for an rgba32f target beside a position: its octahedral
// coordinates (Cigolle et al., "A survey of efficient representations for independent unit
// vectors", 2014) at 12 bits each, as the integer 1 + 4096 a + b, exact in a float (below
// 2^24) and never 0, which stays "nothing drawn". Steps of about 0.05 degrees.
vec2 octahedral(vec3 n) {
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    return n.z >= 0.0 ? p : (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
}

float encode_normal(vec3 n) {
    vec2 q = floor((clamp(octahedral(n), -1.0, 1.0) * 0.5 + 0.5) * 4095.0 + 0.5);
    return 1.0 + q.x * 4096.0 + q.y;
}

vec3 decode_normal(float code) {
    float c = code - 1.0;
    float a = floor(c / 4096.0);
    vec2 p = vec2(a, c - a * 4096.0) / 4095.0 * 2.0 - 1.0;
    vec3 n = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    float fold = max(-n.z, 0.0);
    n.xy += vec2(n.x >= 0.0 ? -fold : fold, n.y >= 0.0 ? -fold : fold);
    return normalize(n);
}
