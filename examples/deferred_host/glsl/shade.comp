#version 450
// The deferred host's own shading pass: per pixel, the world position from the depth
// buffer, the normal and albedo from the G-buffer, and for every light
//
//     radiance += albedo / pi * E * cos(theta) * falloff * visibility
//
// (spot light: E = intensity, falloff = 1 / d^2 inside its hard cone, 0 outside; directional
// light: E = irradiance), plus ambient * albedo. `visibility` is the fraction of the shutter
// the pixel sees the light, taken one of three ways (push constant `lookup`):
//   LOOKUP_MASKS:        the library's visibility-mask pass wrote it into a mask image;
//   LOOKUP_LIT_FRACTION: this shader asks the temporal shadow map itself, through the
//                        library's GLSL include (ms_lit_fraction_moving: the point followed
//                        from p - motion at t = 0 to p at t = 1), with the map's header
//                        address in the push constants;
//   LOOKUP_AT_TIME:      ms_visibility at one shutter time (a sharp shadow at that instant).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"
#include "frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0) uniform sampler2D depth_image;
layout(set = 1, binding = 1) uniform sampler2D normal_image;
layout(set = 1, binding = 2) uniform sampler2D albedo_image;
// One binding per light rather than an array: indexing an array of samplers with a
// non-constant index needs an optional device feature.
layout(set = 1, binding = 3) uniform sampler2D mask0;
layout(set = 1, binding = 4) uniform sampler2D mask1;
layout(set = 1, binding = 5, rgba32f) uniform writeonly image2D radiance;
// World displacement of each pixel's surface point over the shutter (the G-buffer's motion).
layout(set = 1, binding = 6) uniform sampler2D motion_image;

const uint LOOKUP_MASKS = 0u;
const uint LOOKUP_LIT_FRACTION = 1u;
const uint LOOKUP_AT_TIME = 2u;

layout(push_constant) uniform Push {
    uint64_t maps[MAX_LIGHTS]; // TemporalShadowMap::header_address() of each light's map
    uint lookup;                // LOOKUP_*
    float time;                 // LOOKUP_AT_TIME: the shutter time in [0, 1]
} pc;

const float PI = 3.14159265358979323846;

// `n` faces the light here (the caller skips lights behind the surface): that is the side
// the library's receiver offset must go to.
float visibility(uint light, ivec2 pixel, vec3 p, vec3 n) {
    if (pc.lookup == LOOKUP_MASKS) {
        return light == 0u ? texelFetch(mask0, pixel, 0).r : texelFetch(mask1, pixel, 0).r;
    }
    MsShadowMap map = MsShadowMap(pc.maps[light]);
    // MS_NO_TRIANGLE: a G-buffer does not know which triangle a pixel shows (the receiver
    // offset keeps a surface from shadowing itself instead).
    vec3 motion = texelFetch(motion_image, pixel, 0).xyz;
    if (pc.lookup == LOOKUP_LIT_FRACTION) {
        return ms_lit_fraction_moving(map, p - motion, p, n, MS_NO_TRIANGLE);
    }
    // The point where it is at that time.
    return ms_visibility(map, p - (1.0 - pc.time) * motion, n, pc.time, MS_NO_TRIANGLE);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uvec2 size = frame.info.xy;
    if (any(greaterThanEqual(uvec2(pixel), size))) return;
    float depth = texelFetch(depth_image, pixel, 0).r;
    if (depth == 1.0) {     // the depth buffer's clear value: no surface, black
        imageStore(radiance, pixel, vec4(0.0));
        return;
    }
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
    vec3 p = h.xyz / h.w;
    vec3 n = normalize(texelFetch(normal_image, pixel, 0).xyz);
    vec3 albedo = texelFetch(albedo_image, pixel, 0).rgb;

    float direct = 0.0;
    for (uint l = 0u; l < frame.info.z; ++l) {
        Light light = frame.lights[l];
        bool spot = light.position.w > 0.5;
        vec3 to_light = spot ? light.position.xyz - p : -light.direction.xyz;
        float dist2 = spot ? dot(to_light, to_light) : 1.0;
        vec3 dir = normalize(to_light);
        float cos_theta = dot(n, dir);
        if (cos_theta <= 0.0) continue;                                             // behind
        if (spot && dot(-dir, light.direction.xyz) < light.direction.w) continue;   // cone
        direct += light.emission.x * cos_theta / dist2 * visibility(l, pixel, p, n);
    }
    imageStore(radiance, pixel, vec4(albedo / PI * direct + frame.shading.x * albedo, 1.0));
}
