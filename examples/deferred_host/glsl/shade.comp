#version 450
// The deferred host's shading pass: per pixel, the world position from the depth buffer, the
// normal and albedo from the G-buffer, and for every light
//
//     radiance += albedo / pi * E * cos(theta) * falloff * mask
//
// (spot light: E = intensity, falloff = 1 / d^2 inside its hard cone, 0 outside; directional
// light: E = irradiance), plus ambient * albedo. `mask` is the lit share of the shutter the
// library's visibility mask wrote; each light is read from its map's header (the library's
// include: `ms_load_light`). The radiance and the masks go to the slot's readback
// buffer by device address (an engine would present or post-process instead).
#include "motion_shadows.glsl"
#include "frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
layout(set = 0, binding = 2) uniform sampler2D albedo_image;
// One binding per light: indexing an array of images by a variable needs a device feature.
layout(set = 0, binding = 3) uniform sampler2D mask0;
layout(set = 0, binding = 4) uniform sampler2D mask1;

layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer Radiance {
    vec4 v[];
};
layout(buffer_reference, std430, buffer_reference_align = 4) writeonly buffer Masks {
    float v[];
};

layout(push_constant) uniform Push {
    uint64_t frame;
    uint64_t radiance;  // width x height rgba (a = 1 where a surface is)
    uint64_t masks;     // then each light's mask, width x height
    uint64_t maps[2];   // each light's map header (ShadowFrame::map_header)
} pc;

const float PI = 3.14159265358979323846;

void main() {
    Frame frame = Frame(pc.frame);
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    uvec2 size = frame.info.xy;
    if (any(greaterThanEqual(uvec2(pixel), size))) return;
    uint i = uint(pixel.y) * size.x + uint(pixel.x);
    float mask[2] = float[](texelFetch(mask0, pixel, 0).r, texelFetch(mask1, pixel, 0).r);
    for (uint l = 0u; l < frame.info.z; ++l) Masks(pc.masks).v[l * size.x * size.y + i] = mask[l];
    float depth = texelFetch(depth_image, pixel, 0).r;
    if (depth == 1.0) {     // the depth buffer's clear value: no surface, black
        Radiance(pc.radiance).v[i] = vec4(0.0);
        return;
    }
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 h = frame.inv_view_proj * vec4(ndc, depth, 1.0);
    vec3 p = h.xyz / h.w;
    vec3 n = normalize(texelFetch(normal_image, pixel, 0).xyz);
    vec3 albedo = texelFetch(albedo_image, pixel, 0).rgb;
    float direct = 0.0;
    for (uint l = 0u; l < frame.info.z; ++l) {
        MsLight light = ms_load_light(pc.maps[l]);
        bool spot = light.position.w > 0.5;
        vec3 to_light = spot ? light.position.xyz - p : -light.direction.xyz;
        float dist2 = spot ? dot(to_light, to_light) : 1.0;
        vec3 dir = normalize(to_light);
        float cos_theta = dot(n, dir);
        if (cos_theta <= 0.0) continue;                                             // behind
        if (spot && dot(-dir, light.direction.xyz) < light.direction.w) continue;   // cone
        direct += light.emission.x * cos_theta / dist2 * mask[l];
    }
    Radiance(pc.radiance).v[i] = vec4(albedo / PI * direct + frame.ambient.x * albedo, 1.0);
}
