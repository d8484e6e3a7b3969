// KHR_materials_transmission and KHR_materials_volume on the GPU (docs/scene-notes.md,
// "Transmission and volume"), as the Khronos sample viewer draws them: what lies behind a
// transmissive surface is the opaque scene already drawn (u_transmission_source, a copy
// with its mip chain, rendering/passes/transmission.py), looked up where the refracted
// ray leaves the surface:
// - thin-walled (thickness 0): straight behind the point;
// - TRANSMISSION_VOLUME: at p + refract(-v, n, 1 / ior) * thickness, attenuated by
//   Beer-Lambert over that path, attenuation_color^(length / attenuation_distance);
// blurred by roughness: the mip level log2(width) * roughness * clamp(2 ior - 2, 0, 1).
// The light that passes is what the GGX lobe does not reflect, 1 - (F0 A + F90 B) (the
// split sum's hemispherical albedo), tinted by the base colour, and it replaces
// (1 - metallic) transmission of the diffuse part (pbr.glsl scales that part down).
// A light behind the surface shines through it (light_through, called per light from
// lighting/direct.glsl): pbr.glsl's BTDF, for a volume from where the refracted ray leaves
// it, as the Sample Viewer takes it.
// The transmission and the thickness are the Surface's (lighting/material.glsl's
// sample_layers: their factors times their maps).
uniform sampler2D u_transmission_source;
#ifdef TRANSMISSION_VOLUME
uniform vec3 u_attenuation_color;
uniform float u_attenuation_distance;  // 0: no attenuation (an infinite distance)
#endif
uniform mat4 u_view_proj;  // camera-relative world -> clip (mesh/mesh.vert's)

// From the point to where the view's refracted ray leaves a volume ``thickness`` thick
vec3 transmission_ray(vec3 n, vec3 v, float thickness) {
    return safe_normalize(refract(-v, n, 1.0 / u_transmission_ior), -v) * thickness;
}

// The volume's thickness at the point: 0 for a thin wall
float surface_thickness(Surface s) {
#ifdef TRANSMISSION_VOLUME
    return s.thickness;
#else
    return 0.0;
#endif
}

#ifdef TRANSMISSION_VOLUME
// Beer-Lambert over a path of ``path`` through the volume
vec3 volume_attenuation(float path) {
    return u_attenuation_distance > 0.0 ? pow(u_attenuation_color, vec3(path / u_attenuation_distance)) : vec3(1.0);
}
#endif

// The opaque scene seen through the surface at camera-relative ``position``
vec3 transmitted_radiance(vec3 position, vec3 n, vec3 v, float roughness, float thickness) {
    vec3 ray = transmission_ray(n, v, thickness);
    vec4 clip = u_view_proj * vec4(position + ray, 1.0);
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    float width = float(textureSize(u_transmission_source, 0).x);
    float lod = log2(width) * roughness * clamp(u_transmission_ior * 2.0 - 2.0, 0.0, 1.0);
    vec3 behind = textureLod(u_transmission_source, uv, lod).rgb;
#ifdef TRANSMISSION_VOLUME
    behind *= volume_attenuation(length(ray));
#endif
    return behind;
}

// What a light of ``radiance`` behind the surface gives through it towards the eye (its
// shadow is the caller's): ``to_light`` from the point to a point or spot light, or the
// unit direction towards a directional one (``directional``). For a volume the light's
// direction is taken from where the refracted ray leaves it (a directional light's does
// not change), attenuated over the thickness; its radiance stays the point's.
vec3 light_through(vec3 to_light, bool directional, vec3 radiance, vec3 n, vec3 v, PbrView p) {
#ifdef TRANSMISSION_VOLUME
    vec3 l = directional ? to_light : safe_normalize(to_light - transmission_ray(n, v, p.thickness), -n);
    return radiance * pbr_through(n, l, v, p) * volume_attenuation(p.thickness);
#else
    vec3 l = directional ? to_light : safe_normalize(to_light, -n);
    return radiance * pbr_through(n, l, v, p);
#endif
}

// What the surface lets through towards the eye: (1 - metallic) transmission base
// (1 - (F0 A + F90 B)) times the scene behind
vec3 pbr_transmission(vec3 position, vec3 n, vec3 v, Surface s) {
    float n_dot_v = clamp(dot(n, v), 0.0, 1.0);
    vec2 scale_bias = ambient_specular(n_dot_v, s.roughness);
#ifdef PBR_DIELECTRIC_SPECULAR
    vec3 reflected = u_dielectric_f0 * scale_bias.x + u_dielectric_f90 * scale_bias.y;
#else
    vec3 reflected = vec3(0.04 * scale_bias.x + scale_bias.y);
#endif
    vec3 weight = (1.0 - s.metallic) * s.transmission * s.base * (1.0 - reflected);
    return weight * transmitted_radiance(position, n, v, s.roughness, surface_thickness(s));
}
