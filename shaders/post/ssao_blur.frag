// 4x4 box blur matching the 4x4 noise tile, which removes the noise pattern.
uniform sampler2D u_ao;
out float ao;

void main() {
    ivec2 size = textureSize(u_ao, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    float sum = 0.0;
    for (int y = -2; y < 2; ++y) {
        for (int x = -2; x < 2; ++x) {
            sum += texelFetch(u_ao, clamp(p + ivec2(x, y), ivec2(0), size - 1), 0).r;
        }
    }
    ao = sum / 16.0;
}
