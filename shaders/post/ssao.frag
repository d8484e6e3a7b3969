// Screen-space ambient occlusion: hemisphere samples around each pixel's view-space
// position, compared against the prepass depth. 1 = fully open, 0 = fully occluded.
in vec2 v_uv;
uniform sampler2D u_gbuffer;     // view-space normal (xyz), linear depth (w; 0 = sky)
uniform sampler2D u_noise;       // 4x4 random rotations
uniform vec3 u_kernel[AO_SAMPLES];
uniform mat4 u_projection;
uniform vec2 u_screen;
uniform float u_radius;
uniform float u_strength;
out float ao;

vec3 view_position(vec2 uv, float depth) {
    // Invert the projection for a point at linear depth `depth` seen through uv.
    vec2 ndc = uv * 2.0 - 1.0;
#ifdef ORTHO_CAMERA
    return vec3(ndc.x / u_projection[0][0] - u_projection[3][0] / u_projection[0][0],
                ndc.y / u_projection[1][1] - u_projection[3][1] / u_projection[1][1], -depth);
#else
    return vec3(ndc.x * depth / u_projection[0][0], ndc.y * depth / u_projection[1][1], -depth);
#endif
}

void main() {
    // drawn only where the prepass drew a surface (the depth test skips the sky)
    vec4 g = texelFetch(u_gbuffer, ivec2(gl_FragCoord.xy), 0);
    vec3 p = view_position(v_uv, g.w);
    vec3 n = normalize(g.xyz);
    vec3 random = texture(u_noise, gl_FragCoord.xy / 4.0).xyz * 2.0 - 1.0;
    vec3 t = normalize(random - n * dot(random, n) + vec3(1e-4, 0.0, 0.0) * step(abs(dot(random, n)), 0.999));
    // The kernel's offsets scaled to the radius, and their projections: a sample's clip
    // position is the pixel's plus a linear map of the kernel point, so each sample costs
    // one 4x3 product rather than a rotation and a full projection.
    mat3 basis = mat3(t, cross(n, t), n) * u_radius;
    vec4 clip_p = u_projection * vec4(p, 1.0);
    mat3x4 clip_basis = mat3x4(u_projection) * basis;
    vec3 depth_row = -vec3(basis[0].z, basis[1].z, basis[2].z);  // a sample's view depth, less the pixel's
    float occluded_at = -p.z - 0.02 * u_radius;
    float occlusion = 0.0;
    // No branches in the loop: a sample off screen or on the sky is read (clamped) and
    // counted as nothing. llvmpipe runs both sides of a branch anyway, and a fetch
    // under a branch costs more than one outside it (1.4 ms of 18 on the showcase).
    for (int i = 0; i < AO_SAMPLES; ++i) {
        vec4 clip = clip_p + clip_basis * u_kernel[i];
        vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
        bool inside = !(any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))));
        ivec2 texel = clamp(ivec2(uv * u_screen), ivec2(0), ivec2(u_screen) - 1);
        float scene_depth = texelFetch(u_gbuffer, texel, 0).w;
        float range = smoothstep(0.0, 1.0, u_radius / max(abs(g.w - scene_depth), 1e-4));
        bool counts = inside && scene_depth > 0.0 && scene_depth <= occluded_at + dot(depth_row, u_kernel[i]);
        occlusion += counts ? range : 0.0;
    }
    ao = clamp(1.0 - u_strength * occlusion / float(AO_SAMPLES), 0.0, 1.0);
}
