// Material inputs of the forward pass. Each texture map exists only when the material
// has it (HAS_*_MAP), so untextured materials sample nothing; the pbr model's inputs
// exist only in its programs (SHADING_PBR).

uniform vec3 u_ka;          // ambient reflectance (scales the surface colour under ambient light)
uniform vec4 u_kd;          // diffuse colour (the pbr model's base colour), alpha
uniform vec3 u_ks;          // specular colour
uniform vec3 u_ke;          // emission (times its strength)
uniform float u_shininess;  // Ns
uniform float u_opacity;    // d
#ifdef SHADING_PBR
uniform float u_metallic;
uniform float u_roughness;
#endif
#ifdef ALPHA_MASK
uniform float u_alpha_cutoff;  // glTF MASK: pixels with less alpha are cut away
#endif

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
#ifdef HAS_METALLIC_ROUGHNESS_MAP
uniform sampler2D u_metallic_roughness_map;  // glTF: blue = metallic, green = roughness
uniform vec4 u_metallic_roughness_map_st;
#endif
#ifdef HAS_ROUGHNESS_MAP
uniform sampler2D u_roughness_map;  // MTL map_Pr: one channel
uniform vec4 u_roughness_map_st;
#endif
#ifdef HAS_METALLIC_MAP
uniform sampler2D u_metallic_map;   // MTL map_Pm: one channel
uniform vec4 u_metallic_map_st;
#endif
#ifdef HAS_OCCLUSION_MAP
uniform sampler2D u_occlusion_map;  // red: how much ambient light reaches the point
uniform vec4 u_occlusion_map_st;
uniform float u_occlusion_strength;
#endif
#ifdef HAS_EMISSIVE_MAP
uniform sampler2D u_emissive_map;
uniform vec4 u_emissive_map_st;
#endif
// the pbr layers' maps (glTF extension textures), each in the programs of materials with it
#ifdef HAS_CLEARCOAT_MAP
uniform sampler2D u_clearcoat_map;  // KHR_materials_clearcoat clearcoatTexture: red times clearcoat
uniform vec4 u_clearcoat_map_st;
#endif
#ifdef HAS_CLEARCOAT_ROUGHNESS_MAP
uniform sampler2D u_clearcoat_roughness_map;  // clearcoatRoughnessTexture: green times the coat's roughness
uniform vec4 u_clearcoat_roughness_map_st;
#endif
#ifdef HAS_SHEEN_COLOR_MAP
uniform sampler2D u_sheen_color_map;  // sheenColorTexture: rgb (sRGB) times the sheen colour
uniform vec4 u_sheen_color_map_st;
#endif
#ifdef HAS_SHEEN_ROUGHNESS_MAP
uniform sampler2D u_sheen_roughness_map;  // sheenRoughnessTexture: alpha times the sheen's roughness
uniform vec4 u_sheen_roughness_map_st;
#endif
#ifdef HAS_SPECULAR_FACTOR_MAP
uniform sampler2D u_specular_factor_map;  // KHR_materials_specular specularTexture: alpha times specular_factor
uniform vec4 u_specular_factor_map_st;
#endif
#ifdef HAS_ANISOTROPY_MAP
uniform sampler2D u_anisotropy_map;  // KHR_materials_anisotropy: direction rg (0..1 for -1..1), strength b
uniform vec4 u_anisotropy_map_st;
#endif
#ifdef HAS_SPECULAR_GLOSSINESS_MAP
uniform sampler2D u_specular_glossiness_map;  // KHR_materials_pbrSpecularGlossiness: specular rgb (sRGB), glossiness alpha
uniform vec4 u_specular_glossiness_map_st;
#endif
#ifdef HAS_SPECULAR_COLOR_MAP
uniform sampler2D u_specular_color_map;  // specularColorTexture: rgb (sRGB) times specular_color
uniform vec4 u_specular_color_map_st;
#endif
#ifdef HAS_TRANSMISSION_MAP
uniform sampler2D u_transmission_map;  // KHR_materials_transmission transmissionTexture: red times transmission
uniform vec4 u_transmission_map_st;
#endif
#ifdef HAS_CLEARCOAT_NORMAL_MAP
uniform sampler2D u_clearcoat_normal_map;  // clearcoatNormalTexture: the coat's own tangent-space normal
uniform vec4 u_clearcoat_normal_map_st;
uniform float u_clearcoat_normal_strength;  // its scale
#endif
#if defined(PBR_CLEARCOAT) && defined(HAS_CLEARCOAT_NORMAL_MAP)
#define PBR_COAT_NORMAL  // the coat's normal is its map's, the rest keeps the surface's
#endif
#ifdef HAS_IRIDESCENCE_MAP
uniform sampler2D u_iridescence_map;  // KHR_materials_iridescence iridescenceTexture: red times iridescence
uniform vec4 u_iridescence_map_st;
#endif
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
uniform sampler2D u_iridescence_thickness_map;  // iridescenceThicknessTexture: green mixes min .. max
uniform vec4 u_iridescence_thickness_map_st;
#endif
#ifdef HAS_THICKNESS_MAP
uniform sampler2D u_thickness_map;  // KHR_materials_volume thicknessTexture: green times thickness
uniform vec4 u_thickness_map_st;
#endif

// The texture coordinates each map reads: the mesh's set 0 (``uv``), or set 1 where the
// map asks for it (glTF texCoord: 1; <MAP>_UV1).
#ifdef HAS_UV1
in vec2 v_uv1;
#endif
#ifdef DIFFUSE_MAP_UV1
#define UV_OF_u_diffuse_map(uv) v_uv1
#else
#define UV_OF_u_diffuse_map(uv) (uv)
#endif
#ifdef SPECULAR_MAP_UV1
#define UV_OF_u_specular_map(uv) v_uv1
#else
#define UV_OF_u_specular_map(uv) (uv)
#endif
#ifdef NORMAL_MAP_UV1
#define UV_OF_u_normal_map(uv) v_uv1
#else
#define UV_OF_u_normal_map(uv) (uv)
#endif
#ifdef OPACITY_MAP_UV1
#define UV_OF_u_opacity_map(uv) v_uv1
#else
#define UV_OF_u_opacity_map(uv) (uv)
#endif
#ifdef METALLIC_ROUGHNESS_MAP_UV1
#define UV_OF_u_metallic_roughness_map(uv) v_uv1
#else
#define UV_OF_u_metallic_roughness_map(uv) (uv)
#endif
#ifdef ROUGHNESS_MAP_UV1
#define UV_OF_u_roughness_map(uv) v_uv1
#else
#define UV_OF_u_roughness_map(uv) (uv)
#endif
#ifdef METALLIC_MAP_UV1
#define UV_OF_u_metallic_map(uv) v_uv1
#else
#define UV_OF_u_metallic_map(uv) (uv)
#endif
#ifdef OCCLUSION_MAP_UV1
#define UV_OF_u_occlusion_map(uv) v_uv1
#else
#define UV_OF_u_occlusion_map(uv) (uv)
#endif
#ifdef EMISSIVE_MAP_UV1
#define UV_OF_u_emissive_map(uv) v_uv1
#else
#define UV_OF_u_emissive_map(uv) (uv)
#endif
#ifdef CLEARCOAT_MAP_UV1
#define UV_OF_u_clearcoat_map(uv) v_uv1
#else
#define UV_OF_u_clearcoat_map(uv) (uv)
#endif
#ifdef CLEARCOAT_ROUGHNESS_MAP_UV1
#define UV_OF_u_clearcoat_roughness_map(uv) v_uv1
#else
#define UV_OF_u_clearcoat_roughness_map(uv) (uv)
#endif
#ifdef SHEEN_COLOR_MAP_UV1
#define UV_OF_u_sheen_color_map(uv) v_uv1
#else
#define UV_OF_u_sheen_color_map(uv) (uv)
#endif
#ifdef SHEEN_ROUGHNESS_MAP_UV1
#define UV_OF_u_sheen_roughness_map(uv) v_uv1
#else
#define UV_OF_u_sheen_roughness_map(uv) (uv)
#endif
#ifdef SPECULAR_FACTOR_MAP_UV1
#define UV_OF_u_specular_factor_map(uv) v_uv1
#else
#define UV_OF_u_specular_factor_map(uv) (uv)
#endif
#ifdef ANISOTROPY_MAP_UV1
#define UV_OF_u_anisotropy_map(uv) v_uv1
#else
#define UV_OF_u_anisotropy_map(uv) (uv)
#endif
#ifdef SPECULAR_GLOSSINESS_MAP_UV1
#define UV_OF_u_specular_glossiness_map(uv) v_uv1
#else
#define UV_OF_u_specular_glossiness_map(uv) (uv)
#endif
#ifdef SPECULAR_COLOR_MAP_UV1
#define UV_OF_u_specular_color_map(uv) v_uv1
#else
#define UV_OF_u_specular_color_map(uv) (uv)
#endif
#ifdef TRANSMISSION_MAP_UV1
#define UV_OF_u_transmission_map(uv) v_uv1
#else
#define UV_OF_u_transmission_map(uv) (uv)
#endif
#ifdef CLEARCOAT_NORMAL_MAP_UV1
#define UV_OF_u_clearcoat_normal_map(uv) v_uv1
#else
#define UV_OF_u_clearcoat_normal_map(uv) (uv)
#endif
#ifdef IRIDESCENCE_MAP_UV1
#define UV_OF_u_iridescence_map(uv) v_uv1
#else
#define UV_OF_u_iridescence_map(uv) (uv)
#endif
#ifdef IRIDESCENCE_THICKNESS_MAP_UV1
#define UV_OF_u_iridescence_thickness_map(uv) v_uv1
#else
#define UV_OF_u_iridescence_thickness_map(uv) (uv)
#endif
#ifdef THICKNESS_MAP_UV1
#define UV_OF_u_thickness_map(uv) v_uv1
#else
#define UV_OF_u_thickness_map(uv) (uv)
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

#ifdef UV_AFFINE
// A rotated texture transform (glTF KHR_texture_transform): the off-diagonal terms of
// each map's 2 x 2 matrix, whose diagonal is st.xy.
#ifdef HAS_DIFFUSE_MAP
uniform vec2 u_diffuse_map_skew;
#endif
#ifdef HAS_SPECULAR_MAP
uniform vec2 u_specular_map_skew;
#endif
#ifdef HAS_NORMAL_MAP
uniform vec2 u_normal_map_skew;
#endif
#ifdef HAS_OPACITY_MAP
uniform vec2 u_opacity_map_skew;
#endif
#ifdef HAS_METALLIC_ROUGHNESS_MAP
uniform vec2 u_metallic_roughness_map_skew;
#endif
#ifdef HAS_ROUGHNESS_MAP
uniform vec2 u_roughness_map_skew;
#endif
#ifdef HAS_METALLIC_MAP
uniform vec2 u_metallic_map_skew;
#endif
#ifdef HAS_OCCLUSION_MAP
uniform vec2 u_occlusion_map_skew;
#endif
#ifdef HAS_EMISSIVE_MAP
uniform vec2 u_emissive_map_skew;
#endif
#ifdef HAS_CLEARCOAT_MAP
uniform vec2 u_clearcoat_map_skew;
#endif
#ifdef HAS_CLEARCOAT_ROUGHNESS_MAP
uniform vec2 u_clearcoat_roughness_map_skew;
#endif
#ifdef HAS_SHEEN_COLOR_MAP
uniform vec2 u_sheen_color_map_skew;
#endif
#ifdef HAS_SHEEN_ROUGHNESS_MAP
uniform vec2 u_sheen_roughness_map_skew;
#endif
#ifdef HAS_SPECULAR_FACTOR_MAP
uniform vec2 u_specular_factor_map_skew;
#endif
#ifdef HAS_SPECULAR_COLOR_MAP
uniform vec2 u_specular_color_map_skew;
#endif
#ifdef HAS_SPECULAR_GLOSSINESS_MAP
uniform vec2 u_specular_glossiness_map_skew;
#endif
#ifdef HAS_ANISOTROPY_MAP
uniform vec2 u_anisotropy_map_skew;
#endif
#ifdef HAS_TRANSMISSION_MAP
uniform vec2 u_transmission_map_skew;
#endif
#ifdef HAS_THICKNESS_MAP
uniform vec2 u_thickness_map_skew;
#endif
#ifdef HAS_IRIDESCENCE_MAP
uniform vec2 u_iridescence_map_skew;
#endif
#ifdef HAS_CLEARCOAT_NORMAL_MAP
uniform vec2 u_clearcoat_normal_map_skew;
#endif
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
uniform vec2 u_iridescence_thickness_map_skew;
#endif

vec2 map_uv(vec2 uv, vec4 st, vec2 skew) {
    vec2 t = vec2(uv.x * st.x + uv.y * skew.x, uv.x * skew.y + uv.y * st.y) + st.zw;
#ifdef WRAP_MIRROR
    t = 1.0 - abs(1.0 - mod(t, 2.0));
#endif
    return t;
}
#define MAP_UV(map, uv) map_uv(UV_OF_##map(uv), map##_st, map##_skew)
#else
#define MAP_UV(map, uv) map_uv(UV_OF_##map(uv), map##_st)
#endif

struct Surface {
    vec3 base;      // Kd times the diffuse map, linear
    vec3 specular;  // Ks times the specular map
    float alpha;
#ifdef SHADING_PBR
    float metallic;
    float roughness;
#ifdef PBR_DIELECTRIC_SPECULAR
    vec3 dielectric_f0;     // lighting/pbr.glsl's layers, per pixel: their factors times their maps
    float dielectric_f90;
#endif
#ifdef PBR_CLEARCOAT
    float clearcoat;
    float clearcoat_roughness;
#endif
#ifdef PBR_COAT_NORMAL
    vec3 clearcoat_normal;  // unit, in the world: from its map over the geometric normal (forward.frag)
#endif
#ifdef PBR_SHEEN
    vec3 sheen_color;
    float sheen_roughness;
#endif
#ifdef PBR_ANISOTROPY
    float anisotropy;    // its strength
    vec2 anisotropy_xy;  // that direction in the tangent frame, (cos, sin)
    vec3 anisotropy_t;   // unit, in the world: the direction its roughness is raised along
#endif
#ifdef PBR_IRIDESCENCE
    float iridescence;
    float iridescence_ior;
    float iridescence_thickness;  // nanometres
#endif
#ifdef PBR_TRANSMISSION
    float transmission;
#ifdef TRANSMISSION_VOLUME
    float thickness;
#endif
#endif
#endif
};

#ifdef SHADING_PBR
// The pbr model's layers (lighting/pbr.glsl), each only in the programs of materials with it
#ifdef PBR_DIELECTRIC_SPECULAR
uniform vec3 u_dielectric_f0;    // min(((ior - 1) / (ior + 1))^2 specular_color, 1) specular
uniform float u_dielectric_f90;  // specular
#if defined(HAS_SPECULAR_COLOR_MAP) || defined(HAS_SPECULAR_GLOSSINESS_MAP)
uniform vec3 u_dielectric_reflectance;  // ((ior - 1) / (ior + 1))^2 specular_color, before the clamp
#endif
#endif
#ifdef PBR_CLEARCOAT
uniform float u_clearcoat;            // the layer's weight c
uniform float u_clearcoat_roughness;
#endif
#ifdef PBR_SHEEN
uniform vec3 u_sheen_color;
uniform float u_sheen_roughness;
#endif
#ifdef PBR_IRIDESCENCE
uniform float u_iridescence;           // KHR_materials_iridescence: its weight,
uniform float u_iridescence_ior;       // the film's index of refraction
uniform float u_iridescence_thickness; // and thickness, nanometres
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
uniform float u_iridescence_thickness_min;  // the thickness where its map's green is 0
#endif
#endif
#ifdef PBR_TRANSMISSION
uniform float u_transmission;  // the share of the diffuse part that lets light through
#ifdef TRANSMISSION_VOLUME
uniform float u_thickness;     // the volume's, scene units
#endif
#endif
#ifdef PBR_ANISOTROPY
uniform float u_anisotropy;            // KHR_materials_anisotropy's strength
uniform vec2 u_anisotropy_direction;   // (cos, sin) of its rotation from the tangent
#endif

// The layers' factors times their maps (KHR_materials_specular, _clearcoat, _sheen,
// _anisotropy, _iridescence, _transmission, _volume textures); a material without maps takes its
// factors as they are.
void sample_layers(inout Surface s, vec2 uv) {
#ifdef PBR_DIELECTRIC_SPECULAR
    s.dielectric_f0 = u_dielectric_f0;
    s.dielectric_f90 = u_dielectric_f90;
#ifdef HAS_SPECULAR_COLOR_MAP
    s.dielectric_f0 = min(u_dielectric_reflectance * texture(u_specular_color_map, MAP_UV(u_specular_color_map, uv)).rgb,
                          vec3(1.0)) * u_dielectric_f90;
#endif
#ifdef HAS_SPECULAR_GLOSSINESS_MAP
    // KHR_materials_pbrSpecularGlossiness's texture (mesh.gltf): F0 = specular factor x texel,
    // roughness = 1 - glossiness factor x texel, c_diff = diffuse (1 - max(F0))
    vec4 specular_glossiness = texture(u_specular_glossiness_map, MAP_UV(u_specular_glossiness_map, uv));
    s.dielectric_f0 = min(u_dielectric_reflectance * specular_glossiness.rgb, vec3(1.0)) * u_dielectric_f90;
    s.roughness = 1.0 - (1.0 - s.roughness) * specular_glossiness.a;
    s.base *= 1.0 - max(s.dielectric_f0.r, max(s.dielectric_f0.g, s.dielectric_f0.b));
#endif
#ifdef HAS_SPECULAR_FACTOR_MAP
    float specular = texture(u_specular_factor_map, MAP_UV(u_specular_factor_map, uv)).a;
    s.dielectric_f0 *= specular;
    s.dielectric_f90 *= specular;
#endif
#endif
#ifdef PBR_CLEARCOAT
    s.clearcoat = u_clearcoat;
    s.clearcoat_roughness = u_clearcoat_roughness;
#ifdef HAS_CLEARCOAT_MAP
    s.clearcoat *= texture(u_clearcoat_map, MAP_UV(u_clearcoat_map, uv)).r;
#endif
#ifdef HAS_CLEARCOAT_ROUGHNESS_MAP
    s.clearcoat_roughness *= texture(u_clearcoat_roughness_map, MAP_UV(u_clearcoat_roughness_map, uv)).g;
#endif
#endif
#ifdef PBR_SHEEN
    s.sheen_color = u_sheen_color;
    s.sheen_roughness = u_sheen_roughness;
#ifdef HAS_SHEEN_COLOR_MAP
    s.sheen_color *= texture(u_sheen_color_map, MAP_UV(u_sheen_color_map, uv)).rgb;
#endif
#ifdef HAS_SHEEN_ROUGHNESS_MAP
    s.sheen_roughness *= texture(u_sheen_roughness_map, MAP_UV(u_sheen_roughness_map, uv)).a;
#endif
#endif
#ifdef PBR_ANISOTROPY
    s.anisotropy = u_anisotropy;
    s.anisotropy_xy = u_anisotropy_direction;
#ifdef HAS_ANISOTROPY_MAP
    // the texel's direction turned by the rotation, its strength times the factor
    vec3 anisotropy_texel = texture(u_anisotropy_map, MAP_UV(u_anisotropy_map, uv)).rgb;
    vec2 texel_direction = safe_normalize(vec3(anisotropy_texel.rg * 2.0 - 1.0, 0.0), vec3(1.0, 0.0, 0.0)).xy;
    s.anisotropy_xy = mat2(u_anisotropy_direction.x, u_anisotropy_direction.y,
                           -u_anisotropy_direction.y, u_anisotropy_direction.x) * texel_direction;
    s.anisotropy *= anisotropy_texel.b;
#endif
#endif
#ifdef PBR_IRIDESCENCE
    s.iridescence = u_iridescence;
    s.iridescence_ior = u_iridescence_ior;
    s.iridescence_thickness = u_iridescence_thickness;
#ifdef HAS_IRIDESCENCE_MAP
    s.iridescence *= texture(u_iridescence_map, MAP_UV(u_iridescence_map, uv)).r;
#endif
#ifdef HAS_IRIDESCENCE_THICKNESS_MAP
    s.iridescence_thickness = mix(u_iridescence_thickness_min, u_iridescence_thickness,
                                  texture(u_iridescence_thickness_map, MAP_UV(u_iridescence_thickness_map, uv)).g);
#endif
#endif
#ifdef PBR_TRANSMISSION
    s.transmission = u_transmission;
#ifdef HAS_TRANSMISSION_MAP
    s.transmission *= texture(u_transmission_map, MAP_UV(u_transmission_map, uv)).r;
#endif
#ifdef TRANSMISSION_VOLUME
    s.thickness = u_thickness;
#ifdef HAS_THICKNESS_MAP
    s.thickness *= texture(u_thickness_map, MAP_UV(u_thickness_map, uv)).g;
#endif
#endif
#endif
}

#ifdef PBR_ANISOTROPY
// The anisotropy's direction in the world: ``xy`` in the frame of the tangent (made
// orthogonal to n) and the bitangent cross(n, t) w
vec3 anisotropy_direction(vec3 n, vec4 tangent, vec2 xy) {
    vec3 t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3(1.0, 0.0, 0.0));
    vec3 b = cross(n, t) * tangent.w;
    return safe_normalize(t * xy.x + b * xy.y, t);
}
#endif
#endif

Surface sample_surface(vec2 uv) {
    Surface s;
    vec4 base = u_kd;
#ifdef HAS_DIFFUSE_MAP
    base *= texture(u_diffuse_map, MAP_UV(u_diffuse_map, uv));
#endif
    s.base = base.rgb;
    s.specular = u_ks;
#ifdef HAS_SPECULAR_MAP
    s.specular *= texture(u_specular_map, MAP_UV(u_specular_map, uv)).rgb;
#endif
    s.alpha = base.a * u_opacity;
#ifdef HAS_OPACITY_MAP
    s.alpha *= texture(u_opacity_map, MAP_UV(u_opacity_map, uv)).r;
#endif
#ifdef SHADING_PBR
    s.metallic = u_metallic;
    s.roughness = u_roughness;
#ifdef HAS_METALLIC_ROUGHNESS_MAP
    vec4 metallic_roughness = texture(u_metallic_roughness_map, MAP_UV(u_metallic_roughness_map, uv));
    s.metallic *= metallic_roughness.b;
    s.roughness *= metallic_roughness.g;
#endif
#ifdef HAS_ROUGHNESS_MAP
    s.roughness *= texture(u_roughness_map, MAP_UV(u_roughness_map, uv)).r;
#endif
#ifdef HAS_METALLIC_MAP
    s.metallic *= texture(u_metallic_map, MAP_UV(u_metallic_map, uv)).r;
#endif
    sample_layers(s, uv);
#endif
    return s;
}

// The light the surface gives off by itself.
vec3 surface_emission(vec2 uv) {
#ifdef HAS_EMISSIVE_MAP
    return u_ke * texture(u_emissive_map, MAP_UV(u_emissive_map, uv)).rgb;
#else
    return u_ke;
#endif
}

// How much ambient light reaches the point: 1, or the occlusion map's red channel
// weighted by its strength (glTF occlusionTexture).
float surface_occlusion(vec2 uv) {
#ifdef HAS_OCCLUSION_MAP
    return 1.0 + u_occlusion_strength * (texture(u_occlusion_map, MAP_UV(u_occlusion_map, uv)).r - 1.0);
#else
    return 1.0;
#endif
}

#ifdef HAS_NORMAL_MAP
// Tangent-space normal map (OpenGL convention: green = +V).
vec3 mapped_normal(vec3 n, vec4 tangent, vec2 uv) {
    vec3 t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3(1.0, 0.0, 0.0));
    vec3 b = cross(n, t) * tangent.w;
    vec3 m = texture(u_normal_map, MAP_UV(u_normal_map, uv)).xyz * 2.0 - 1.0;
    m.xy *= u_normal_strength;
    return safe_normalize(mat3(t, b, n) * m, n);
}
#endif

#ifdef PBR_COAT_NORMAL
// The clear coat's normal (KHR_materials_clearcoat clearcoatNormalTexture): its tangent-space
// map over the geometric normal n, not the base's normal map (the specification)
vec3 coat_mapped_normal(vec3 n, vec4 tangent, vec2 uv) {
    vec3 t = safe_normalize(tangent.xyz - n * dot(n, tangent.xyz), vec3(1.0, 0.0, 0.0));
    vec3 b = cross(n, t) * tangent.w;
    vec3 m = texture(u_clearcoat_normal_map, MAP_UV(u_clearcoat_normal_map, uv)).xyz * 2.0 - 1.0;
    m.xy *= u_clearcoat_normal_strength;
    return safe_normalize(mat3(t, b, n) * m, n);
}
#endif
