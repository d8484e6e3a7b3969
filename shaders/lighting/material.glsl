// Material inputs of the forward pass. Each texture map exists only when the material
// has it (HAS_*_MAP), so untextured materials sample nothing.

uniform vec3 u_ka;          // ambient reflectance (scales the surface colour under ambient light)
uniform vec4 u_kd;          // diffuse colour, alpha
uniform vec3 u_ks;          // specular colour
uniform vec3 u_ke;          // emission
uniform float u_shininess;  // Ns
uniform float u_opacity;    // d

#ifdef HAS_DIFFUSE_MAP
uniform sampler2D u_diffuse_map;
uniform vec4 u_diffuse_map_st;   // uv scale (xy) and offset (zw)
#endif
#ifdef HAS_SPECULAR_MAP
uniform sampler2D u_specular_map;
uniform vec4 u_specular_map_st;
#endif
#ifdef HAS_NORMAL_MAP
uniform sampler2D u_normal_map;
uniform vec4 u_normal_map_st;
uniform float u_normal_strength;
#endif
#ifdef HAS_OPACITY_MAP
uniform sampler2D u_opacity_map;
uniform vec4 u_opacity_map_st;
#endif

// Texture coordinates for a map: MTL -s/-o scale and offset, then the wrap mode. Mirrored
// wrap folds coordinates here (a triangle wave, so derivatives stay continuous).
vec2 map_uv(vec2 uv, vec4 st) {
    vec2 t = uv * st.xy + st.zw;
#ifdef WRAP_MIRROR
    t = 1.0 - abs(1.0 - mod(t, 2.0));
#endif
    return t;
}

struct Surface {
    vec3 base;      // Kd times the diffuse map, linear
    vec3 specular;  // Ks times the specular map
    float alpha;
};

Surface sample_surface(vec2 uv) {
    Surface s;
    vec4 base = u_kd;
#ifdef HAS_DIFFUSE_MAP
    base *= texture(u_diffuse_map, map_uv(uv, u_diffuse_map_st));
#endif
    s.base = base.rgb;
    s.specular = u_ks;
#ifdef HAS_SPECULAR_MAP
    s.specular *= texture(u_specular_map, map_uv(uv, u_specular_map_st)).rgb;
#endif
    s.alpha = base.a * u_opacity;
#ifdef HAS_OPACITY_MAP
    s.alpha *= texture(u_opacity_map, map_uv(uv, u_opacity_map_st)).r;
#endif
    return s;
}

#ifdef HAS_NORMAL_MAP
// Tangent-space normal map (OpenGL convention: green = +V).
vec3 mapped_normal(vec3 n, vec4 tangent, vec2 uv) {
    vec3 t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3(1.0, 0.0, 0.0));
    vec3 b = cross(n, t) * tangent.w;
    vec3 m = texture(u_normal_map, map_uv(uv, u_normal_map_st)).xyz * 2.0 - 1.0;
    m.xy *= u_normal_strength;
    return safe_normalize(mat3(t, b, n) * m, n);
}
#endif
