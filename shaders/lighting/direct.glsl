// Sum of direct light from every light of the scene at one surface point.
#include "lighting/lights.glsl"
#ifdef SHADING_PBR
#include "lighting/pbr.glsl"
#ifdef PBR_TRANSMISSION
#include "lighting/transmission.glsl"
#endif
#else
#include "lighting/specular.glsl"
#endif
#ifdef HAS_SHADOWS
#include "lighting/shadows.glsl"
// First shadow view of each light, or -1, its filter's taps per side and its atlas page
// (compile-time constants, see rendering/features.py)
#ifdef DIR_SHADOW_VIEWS
const int dir_shadow_view[N_DIR_LIGHTS] = int[](DIR_SHADOW_VIEWS);
const int dir_shadow_taps[N_DIR_LIGHTS] = int[](DIR_SHADOW_TAPS);
const int dir_shadow_page[N_DIR_LIGHTS] = int[](DIR_SHADOW_PAGES);
#endif
#ifdef POINT_SHADOW_VIEWS
const int point_shadow_view[N_POINT_LIGHTS] = int[](POINT_SHADOW_VIEWS);
const int point_shadow_taps[N_POINT_LIGHTS] = int[](POINT_SHADOW_TAPS);
const int point_shadow_page[N_POINT_LIGHTS] = int[](POINT_SHADOW_PAGES);
#endif
#ifdef SPOT_SHADOW_VIEWS
const int spot_shadow_view[N_SPOT_LIGHTS] = int[](SPOT_SHADOW_VIEWS);
const int spot_shadow_taps[N_SPOT_LIGHTS] = int[](SPOT_SHADOW_TAPS);
const int spot_shadow_page[N_SPOT_LIGHTS] = int[](SPOT_SHADOW_PAGES);
#endif
#ifdef AREA_SHADOW_VIEWS
const int area_shadow_view[N_AREA_LIGHTS] = int[](AREA_SHADOW_VIEWS);
const int area_shadow_page[N_AREA_LIGHTS] = int[](AREA_SHADOW_PAGES);
#endif
#ifdef SOFT_SHADOWS
#include "lighting/soft_shadows.glsl"
// Per light, the reads of its soft shadow's blocker search and filter, 0 for a point light
// (rendering/features.py): only in scenes where a shadowed light has a size
#ifdef DIR_SOFT_BLOCKERS
const int dir_soft_blockers[N_DIR_LIGHTS] = int[](DIR_SOFT_BLOCKERS);
const int dir_soft_filter[N_DIR_LIGHTS] = int[](DIR_SOFT_FILTER);
#endif
#ifdef DIR_SOFT_SOLID
const bool dir_soft_solid[N_DIR_LIGHTS] = bool[](DIR_SOFT_SOLID);
#define DIR_SOLID(i) dir_soft_solid[i]
#else
#define DIR_SOLID(i) false
#endif
#ifdef POINT_SOFT_BLOCKERS
const int point_soft_blockers[N_POINT_LIGHTS] = int[](POINT_SOFT_BLOCKERS);
const int point_soft_filter[N_POINT_LIGHTS] = int[](POINT_SOFT_FILTER);
#endif
#ifdef POINT_SOFT_SOLID
const bool point_soft_solid[N_POINT_LIGHTS] = bool[](POINT_SOFT_SOLID);
#define POINT_SOLID(i) point_soft_solid[i]
#else
#define POINT_SOLID(i) false
#endif
#ifdef SPOT_SOFT_BLOCKERS
const int spot_soft_blockers[N_SPOT_LIGHTS] = int[](SPOT_SOFT_BLOCKERS);
const int spot_soft_filter[N_SPOT_LIGHTS] = int[](SPOT_SOFT_FILTER);
#endif
#ifdef SPOT_SOFT_SOLID
const bool spot_soft_solid[N_SPOT_LIGHTS] = bool[](SPOT_SOFT_SOLID);
#define SPOT_SOLID(i) spot_soft_solid[i]
#else
#define SPOT_SOLID(i) false
#endif
#ifdef AREA_SOFT_BLOCKERS
const int area_soft_blockers[N_AREA_LIGHTS] = int[](AREA_SOFT_BLOCKERS);
const int area_soft_filter[N_AREA_LIGHTS] = int[](AREA_SOFT_FILTER);
#endif
#ifdef AREA_SOFT_SOLID
const bool area_soft_solid[N_AREA_LIGHTS] = bool[](AREA_SOFT_SOLID);
#define AREA_SOLID(i) area_soft_solid[i]
#else
#define AREA_SOLID(i) false
#endif
#endif
#endif

#ifdef SHADING_PBR
vec3 shade_one(vec3 l, vec3 radiance, vec3 n, vec3 v, PbrView p) {
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    return radiance * pbr_direct(n, l, v, n_dot_l, p);
}
// each light's term from what the point's view gives once (pbr_view)
#define SHADE_ONE(l, radiance) shade_one(l, radiance, n, v, pbr)
#ifdef PBR_TRANSMISSION
// A light behind a transmissive surface shines through it (lighting/transmission.glsl). Its
// shadow is looked up from the surface's far side (the normal turned over), so the surface
// itself does not block it and every other caster does; a light with a size shines
// through as from its centre, an area light not at all.
#define SHADE_THROUGH(to_light, directional, radiance) light_through(to_light, directional, radiance, n, v, pbr)
#endif
#else
vec3 shade_one(vec3 l, vec3 radiance, vec3 n, vec3 v, Surface s) {
    float n_dot_l = dot(n, l);
    if (n_dot_l <= 0.0) {
        return vec3(0.0);
    }
    return radiance * (s.base * n_dot_l + s.specular * specular_lobe(n, l, v, u_shininess));
}
#define SHADE_ONE(l, radiance) shade_one(l, radiance, n, v, s)
#endif

// Lights with a size (lighting/sized.glsl), and which ones have one: compile-time constants,
// only in scenes with such a light
#if defined(DIR_LIGHT_SIZED) || defined(POINT_LIGHT_SIZED) || defined(SPOT_LIGHT_SIZED) || defined(N_AREA_LIGHTS)
#include "lighting/sized.glsl"
#endif
#ifdef N_AREA_LIGHTS
#include "lighting/area.glsl"
#endif
#ifdef DIR_LIGHT_SIZED
const bool dir_sized[N_DIR_LIGHTS] = bool[](DIR_LIGHT_SIZED);
#endif
#ifdef POINT_LIGHT_SIZED
const bool point_sized[N_POINT_LIGHTS] = bool[](POINT_LIGHT_SIZED);
#endif
#ifdef SPOT_LIGHT_SIZED
const bool spot_sized[N_SPOT_LIGHTS] = bool[](SPOT_LIGHT_SIZED);
#endif

vec3 direct_light(vec3 p, vec3 n, vec3 v, Surface s) {
    vec3 total = vec3(0.0);
    // derivatives here, in uniform control flow, for the shadow and cone filters
    vec3 dpdx = dFdx(p);
    vec3 dpdy = dFdy(p);
#ifdef SHADING_PBR
    PbrView pbr = pbr_view(n, v, s);
#endif
#if N_DIR_LIGHTS > 0
    for (int i = 0; i < N_DIR_LIGHTS; ++i) {
        DirLight light = dir_lights[i];
        vec3 l = -light.direction.xyz;
        vec3 radiance = light.color.rgb;
#ifdef PBR_TRANSMISSION
        if (dot(n, l) < 0.0) {
            vec3 through = radiance;
#ifdef HAS_SHADOWS
            if (dir_shadow_view[i] >= 0) {
                through *= shadow_lookup(dir_shadow_view[i], dir_shadow_page[i], dir_shadow_taps[i], p, -n, -dot(n, l), false, false, dpdx, dpdy);
            }
#endif
            total += SHADE_THROUGH(l, true, through);
        }
#endif
#ifdef DIR_LIGHT_SIZED
        if (dir_sized[i]) {
            // a sphere at distance 1, radius tan(half angle)
            float size = light.direction.w;
#ifdef DIR_SOFT_BLOCKERS
            if (dir_shadow_view[i] >= 0 && sized_faces(n, l, size)) {
                radiance *= shadow_lookup_soft(dir_shadow_view[i], dir_shadow_page[i], dir_soft_blockers[i], dir_soft_filter[i], p, n, dot(n, l), false, false, size, DIR_SOLID(i));
            }
#endif
            total += SHADE_SIZED(l, size, radiance);
            continue;
        }
#endif
#ifdef HAS_SHADOWS
        if (dir_shadow_view[i] >= 0 && dot(n, l) > 0.0) {
            radiance *= shadow_lookup(dir_shadow_view[i], dir_shadow_page[i], dir_shadow_taps[i], p, n, dot(n, l), false, false, dpdx, dpdy);
        }
#endif
        total += SHADE_ONE(l, radiance);
    }
#endif
#if N_POINT_LIGHTS > 0
    for (int i = 0; i < N_POINT_LIGHTS; ++i) {
        PointLight light = point_lights[i];
        vec3 to_light = light.position.xyz - p;
        float distance = length(to_light);
        vec3 l = safe_normalize(to_light, n);
        vec3 radiance = light.color.rgb * attenuation(light.attenuation, distance);
#ifdef LIGHT_RANGE
        radiance *= range_window(light.position.w, distance);
#endif
#ifdef PBR_TRANSMISSION
        if (dot(n, l) < 0.0) {
            vec3 through = radiance;
#ifdef HAS_SHADOWS
            if (point_shadow_view[i] >= 0 && max_component(radiance) > 1e-4) {
                through *= shadow_lookup(point_shadow_view[i] + cube_face(-to_light), point_shadow_page[i], point_shadow_taps[i], p, -n, -dot(n, l), true, true, dpdx, dpdy);
            }
#endif
            total += SHADE_THROUGH(to_light, false, through);
        }
#endif
#ifdef POINT_LIGHT_SIZED
        if (point_sized[i]) {
            float radius = light.attenuation.w;
#ifdef POINT_SOFT_BLOCKERS
            if (point_shadow_view[i] >= 0 && sized_faces(n, to_light, radius) && max_component(radiance) > 1e-4) {
                radiance *= shadow_lookup_soft(point_shadow_view[i] + cube_face(-to_light), point_shadow_page[i], point_soft_blockers[i], point_soft_filter[i], p, n, dot(n, l), true, true, radius, POINT_SOLID(i));
            }
#endif
            total += SHADE_SIZED(to_light, radius, radiance);
            continue;
        }
#endif
#ifdef HAS_SHADOWS
        if (point_shadow_view[i] >= 0 && dot(n, l) > 0.0 && max_component(radiance) > 1e-4) {
            radiance *= shadow_lookup(point_shadow_view[i] + cube_face(-to_light), point_shadow_page[i], point_shadow_taps[i], p, n, dot(n, l), true, true, dpdx, dpdy);
        }
#endif
        total += SHADE_ONE(l, radiance);
    }
#endif
#if N_SPOT_LIGHTS > 0
    for (int i = 0; i < N_SPOT_LIGHTS; ++i) {
        SpotLight light = spot_lights[i];
        vec3 to_light = light.position.xyz - p;
        float distance = length(to_light);
        vec3 l = safe_normalize(to_light, n);
        float cos_angle = dot(-l, light.direction.xyz);
        float cone = spot_cone(light.cone, cos_angle,
                               spot_pixel(to_light, cos_angle, light.direction.xyz, dpdx, dpdy));
        vec3 radiance = light.color.rgb * attenuation(light.attenuation, distance) * cone;
#ifdef LIGHT_RANGE
        radiance *= range_window(light.position.w, distance);
#endif
#ifdef PBR_TRANSMISSION
        if (dot(n, l) < 0.0) {
            vec3 through = radiance;
#ifdef HAS_SHADOWS
            if (spot_shadow_view[i] >= 0 && max_component(radiance) > 1e-4) {
                through *= shadow_lookup(spot_shadow_view[i], spot_shadow_page[i], spot_shadow_taps[i], p, -n, -dot(n, l), true, false, dpdx, dpdy);
            }
#endif
            total += SHADE_THROUGH(to_light, false, through);
        }
#endif
#ifdef SPOT_LIGHT_SIZED
        if (spot_sized[i]) {
            float radius = light.attenuation.w;
#ifdef SPOT_SOFT_BLOCKERS
            if (spot_shadow_view[i] >= 0 && sized_faces(n, to_light, radius) && max_component(radiance) > 1e-4) {
                radiance *= shadow_lookup_soft(spot_shadow_view[i], spot_shadow_page[i], spot_soft_blockers[i], spot_soft_filter[i], p, n, dot(n, l), true, false, radius, SPOT_SOLID(i));
            }
#endif
            total += SHADE_SIZED(to_light, radius, radiance);
            continue;
        }
#endif
#ifdef HAS_SHADOWS
        if (spot_shadow_view[i] >= 0 && dot(n, l) > 0.0 && max_component(radiance) > 1e-4) {
            radiance *= shadow_lookup(spot_shadow_view[i], spot_shadow_page[i], spot_shadow_taps[i], p, n, dot(n, l), true, false, dpdx, dpdy);
        }
#endif
        total += SHADE_ONE(l, radiance);
    }
#endif
#ifdef N_AREA_LIGHTS
    for (int i = 0; i < N_AREA_LIGHTS; ++i) {
        AreaLight light = area_lights[i];
        vec3 to_light = light.position.xyz - p;
        // one-sided: nothing behind its plane, nor on a surface facing away from all of it
        if (dot(to_light, light.normal.xyz) >= 0.0 || !area_above_horizon(light, p, n)) {
            continue;
        }
        vec3 radiance = light.color.rgb;
#ifdef AREA_SOFT_BLOCKERS
        if (area_shadow_view[i] >= 0) {
            radiance *= shadow_lookup_shaped(area_shadow_view[i] + cube_face(-to_light), area_shadow_page[i], area_soft_blockers[i], area_soft_filter[i], p, n, max(dot(n, safe_normalize(to_light, n)), 0.0), true, true, light.normal.w, light.axis_u.xyz, light.axis_v.xyz, !area_is_disk(light), AREA_SOLID(i));
        }
#endif
        total += SHADE_AREA(light, radiance);
    }
#endif
    return total;
}
