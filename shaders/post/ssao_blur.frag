// 4x4 box blur matching the 4x4 noise tile, which removes the noise pattern. Four
// gathers read the 16 texels (2 x 2 each; u_ao clamps to its edges); the sum is of whole
// 8-bit levels, exact in any order.
uniform sampler2D u_ao;
out float ao;

void main() {
    vec2 texel = 1.0 / vec2(textureSize(u_ao, 0));
    vec2 p = floor(gl_FragCoord.xy);  // a gather at a texel corner reads the four texels around it
    vec4 levels = round(textureGather(u_ao, (p + vec2(-1.0, -1.0)) * texel, 0) * 255.0)
                + round(textureGather(u_ao, (p + vec2(1.0, -1.0)) * texel, 0) * 255.0)
                + round(textureGather(u_ao, (p + vec2(-1.0, 1.0)) * texel, 0) * 255.0)
                + round(textureGather(u_ao, (p + vec2(1.0, 1.0)) * texel, 0) * 255.0);
    ao = (levels.x + levels.y + levels.z + levels.w) / (16.0 * 255.0);
}
