// Sum of direct light from every light of the scene at one surface point.
#include "lighting/lights.glsl"
#include "lighting/specular.glsl"
#ifdef HAS_SHADOWS
#include "lighting/shadows.glsl"
#endif

vec3 shade_one(vec3 l, vec3 radiance, vec3 n, vec3 v, Surface s) {
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    return radiance * (s.base * n_dot_l + s.specular * specular_lobe(n, l, v, u_shininess));
}

vec3 direct_light(vec3 p, vec3 n, vec3 v, Surface s) {
    vec3 total = vec3(0.0);
#if N_DIR_LIGHTS > 0
    for (int i = 0; i < N_DIR_LIGHTS; ++i) {
        DirLight light = dir_lights[i];
        vec3 l = -light.direction.xyz;
        vec3 radiance = light.color.rgb;
#ifdef HAS_SHADOWS
        if (light.shadow.x >= 0.0 && dot(n, l) > 0.0) {
            radiance *= shadow_visibility(int(light.shadow.x), p, n, dot(n, l));
        }
#endif
        total += shade_one(l, radiance, n, v, s);
    }
#endif
#if N_POINT_LIGHTS > 0
    for (int i = 0; i < N_POINT_LIGHTS; ++i) {
        PointLight light = point_lights[i];
        vec3 to_light = light.position.xyz - p;
        float distance = length(to_light);
        vec3 l = safe_normalize(to_light, n);
        vec3 radiance = light.color.rgb * attenuation(light.attenuation, distance);
#ifdef HAS_SHADOWS
        if (light.shadow.x >= 0.0 && dot(n, l) > 0.0 && max_component(radiance) > 1e-4) {
            radiance *= shadow_visibility(int(light.shadow.x) + cube_face(-to_light), p, n, dot(n, l));
        }
#endif
        total += shade_one(l, radiance, n, v, s);
    }
#endif
#if N_SPOT_LIGHTS > 0
    for (int i = 0; i < N_SPOT_LIGHTS; ++i) {
        SpotLight light = spot_lights[i];
        vec3 to_light = light.position.xyz - p;
        float distance = length(to_light);
        vec3 l = safe_normalize(to_light, n);
        float cone = spot_cone(light.cone, dot(-l, light.direction.xyz));
        vec3 radiance = light.color.rgb * attenuation(light.attenuation, distance) * cone;
#ifdef HAS_SHADOWS
        if (light.shadow.x >= 0.0 && dot(n, l) > 0.0 && max_component(radiance) > 1e-4) {
            radiance *= shadow_visibility(int(light.shadow.x), p, n, dot(n, l));
        }
#endif
        total += shade_one(l, radiance, n, v, s);
    }
#endif
    return total;
}
