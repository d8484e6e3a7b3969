// Forward shading of scene meshes: ambient (times screen-space AO when on), every light
// with its shadows, emission, fog. Which of these exist is decided per scene, and the
// shading model (Phong, Blinn-Phong, pbr, unlit) per material.
#ifdef SHADOW_VISIBLE_SAMPLES
#extension GL_ARB_post_depth_coverage : require
#endif
#include "common/math.glsl"
#include "lighting/material.glsl"
#ifndef UNLIT
#include "lighting/direct.glsl"
#endif
#ifdef PBR_TRANSMISSION
#include "lighting/transmission.glsl"
#endif
#ifdef HAS_FOG
#include "lighting/fog.glsl"
#endif
#ifdef HAS_ENVIRONMENT
#include "lighting/environment.glsl"
#endif
#ifdef ENCODE_SRGB
#include "common/srgb.glsl"
#endif
#ifdef HAS_INDIRECT
#include "lighting/indirect.glsl"
#endif

#ifdef SHADOW_VISIBLE_SAMPLES
// gl_SampleMaskIn after the depth test (the depth prepass has laid down the final depth)
layout(early_fragment_tests) in;
layout(post_depth_coverage) in;
#endif

in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
#ifdef HAS_TANGENTS
in vec4 v_tangent;
#endif
#ifdef HAS_VERTEX_COLOR
in vec4 v_color;  // multiplies the base colour (glTF COLOR_0)
#endif

uniform vec3 u_ambient;  // summed ambient light
#ifdef HAS_AO
uniform sampler2D u_ao;  // screen-space ambient occlusion, 1 = open
#endif

#ifdef INDIRECT_CAPTURE
// drawn into a probe's cube map (rendering/passes/indirect.py), seen from u_capture_eye:
// the light the surface gives and the distance to it (at most u_capture_far); what
// multiplies the irradiance it gets / pi (its diffuse reflectance); the normal it is
// shaded with and the distance itself. A later bounce adds the probes' light from these.
uniform vec3 u_capture_eye;
uniform float u_capture_far;
layout(location = 0) out vec4 frag_color;
layout(location = 1) out vec4 capture_reflectance;
layout(location = 2) out vec4 capture_normal;
#else
out vec4 frag_color;
#endif

void main() {
#ifdef INDIRECT_CAPTURE
    vec3 bounce_reflectance = vec3(0.0);  // unlit surfaces give what they show, nothing more
    vec3 bounce_normal = vec3(0.0, 0.0, 1.0);
#endif
    Surface s = sample_surface(v_uv);
#ifdef HAS_VERTEX_COLOR
    s.base *= v_color.rgb;
    s.alpha *= v_color.a;
#endif
#ifdef UNLIT
    vec3 color = s.base + surface_emission(v_uv);
#else
    // two-sided: a face seen from behind is lit as if its normal pointed at the viewer
    vec3 n = safe_normalize(gl_FrontFacing ? v_normal : -v_normal);
#ifdef PBR_COAT_NORMAL
    s.clearcoat_normal = coat_mapped_normal(n, gl_FrontFacing ? v_tangent : vec4(-v_tangent.xyz, v_tangent.w), v_uv);
#endif
#ifdef HAS_NORMAL_MAP
    n = mapped_normal(n, gl_FrontFacing ? v_tangent : vec4(-v_tangent.xyz, v_tangent.w), v_uv);
#endif
#ifdef PBR_ANISOTROPY
    s.anisotropy_t = anisotropy_direction(n, gl_FrontFacing ? v_tangent : vec4(-v_tangent.xyz, v_tangent.w),
                                          s.anisotropy_xy);
#endif
#ifdef INDIRECT_CAPTURE
    vec3 v = safe_normalize(u_capture_eye - v_position, n);
#else
    vec3 v = safe_normalize(-v_position, n);
#endif
    float screen_ao = 1.0;
#ifdef HAS_AO
    screen_ao = texelFetch(u_ao, ivec2(gl_FragCoord.xy), 0).r;
#endif
    float material_occlusion = 1.0;
#ifdef HAS_OCCLUSION_MAP
    material_occlusion = surface_occlusion(v_uv);
#endif
    float ambient_visibility = screen_ao * material_occlusion;
#ifdef ENV_VISIBILITY
    // what reaches the surface of the environment's light, diffuse and specular; SSAO
    // darkens it only where it finds more occlusion than the visibility maps did (the
    // smaller of the two, so no occluder counts twice); the occlusion map multiplies
    // (detail the maps cannot resolve)
#ifdef SHADING_PBR
    float env_roughness = s.roughness;
#else
    float env_roughness = 1.0;
#endif
    vec2 env_seen = min(env_visibility(v_position, n, v, env_roughness), vec2(screen_ao)) * material_occlusion;
#endif
#ifdef SHADING_PBR
    vec3 color = u_ambient * u_ka * pbr_ambient(n, v, s) * ambient_visibility + direct_light(v_position, n, v, s)
               + surface_emission(v_uv);
#if defined(ENV_VISIBILITY)
    color += u_ka * pbr_environment_seen(n, v, s, env_seen);
#elif defined(HAS_ENVIRONMENT)
    color += u_ka * pbr_environment(n, v, s) * ambient_visibility;
#endif
#else
    vec3 color = u_ambient * u_ka * s.base * ambient_visibility + direct_light(v_position, n, v, s) + surface_emission(v_uv);
#if defined(ENV_VISIBILITY)
    color += u_ka * s.base * env_diffuse(n) * env_seen.x;  // classic: its diffuse term, as an ambient
#elif defined(HAS_ENVIRONMENT)
    color += u_ka * s.base * env_diffuse(n) * ambient_visibility;  // classic: its diffuse term, as an ambient
#endif
#endif
#ifdef PBR_TRANSMISSION
    color += pbr_transmission(v_position, n, v, s);  // the opaque scene seen through it
#endif
#if defined(HAS_INDIRECT) || defined(INDIRECT_CAPTURE)
    // bounced light is diffuse: the probes' irradiance times the diffuse reflectance / pi
#ifdef SHADING_PBR
    vec3 diffuse_reflectance = pbr_ambient_weights(n, v, s).diffuse * material_occlusion;
#else
    vec3 diffuse_reflectance = s.base * material_occlusion;
#endif
#endif
#ifdef HAS_INDIRECT
    color += diffuse_reflectance * probe_irradiance(v_position, n, v) / 3.14159265;
#endif
#ifdef INDIRECT_CAPTURE
    bounce_reflectance = diffuse_reflectance;
    bounce_normal = n;
#endif
#endif
#ifdef HAS_FOG
    color = apply_fog(color, length(v_position));
#endif
#ifdef TRANSPARENT
    frag_color = vec4(color, s.alpha);
#else
    // alpha is coverage: an opaque surface hides the sky composited behind the samples
    // (post/sky_under.glsl), whatever alpha its maps hold
#ifdef ENCODE_SRGB
    // an 8-bit sRGB target written without the device's encoding (the opaque pass turns
    // it off): the shader encodes once per pixel, where the device would per sample
    frag_color = vec4(srgb_encode(clamp(color, 0.0, 1.0)), 1.0);
#else
    frag_color = vec4(color, 1.0);
#endif
#endif
#ifdef INDIRECT_CAPTURE
    float distance = length(v_position - u_capture_eye);
    frag_color = vec4(color, min(distance, u_capture_far));
    capture_reflectance = vec4(bounce_reflectance, 1.0);
    capture_normal = vec4(bounce_normal, distance);
#endif
#ifdef ALPHA_MASK
    // cut last: the derivatives the lighting takes need every pixel of the quad
    if (s.alpha < u_alpha_cutoff) {
        discard;
    }
#endif
}
