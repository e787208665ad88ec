#version 450
// Time-dependent shadow maps (Akenine-Moller et al. 2007) as an engine builds them, for the
// deferred frame: the mask of one of the N maps. For every pixel of the host's G-buffer,
// rebuild the world point and normal exactly as visibility_mask.comp does (mask_gbuffer.glsl),
// move the point to where it is at the map's time (p + (t_i - time) * motion, when MOVING),
// test it against the map with the temporal map's receiver test (ms_receiver_texel: normal
// offset, receiver-plane depth, light bias) and count it lit or not. Map i of N adds its 0 or
// 1 to the host's R32_SFLOAT image (the first map writes); the last map divides by N, so the
// image ends as the lit fraction of the N times (exactly 1 where every map sees the light).
// Background pixels count as lit.
//
// The map is an ordinary depth attachment (post-projection z/w, 1 where nothing was drawn)
// read through a sampled image; with SECOND_LOOKUP the moving draws' map of this time and the
// static draws' map are both read (the nearer wins) instead of one map that holds both.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
// rgb: the point's world displacement over the shutter, p(1) - p(0) (read when MOVING).
layout(set = 0, binding = 2) uniform sampler2D motion_image;
layout(set = 0, binding = 3, r32f) uniform image2D mask;
// The map of time pc.map_time (z/w of the depth attachment).
layout(set = 0, binding = 4) uniform sampler2D map_depth;
// SECOND_LOOKUP: the static draws' map (z/w), drawn once and kept.
layout(set = 0, binding = 5) uniform sampler2D static_depth;

layout(constant_id = 0) const bool MOVING = false;
layout(constant_id = 1) const bool SECOND_LOOKUP = false;

const uint TSM_FIRST = 0x10u;   // the first of the N maps: write the count, do not add
const uint TSM_LAST = 0x20u;    // the last: divide the count by pc.maps

layout(push_constant) uniform Push {
    mat4 inv_view_proj;     // camera clip -> world (the host's matrices, Vulkan NDC)
    uint64_t light;         // MsLight (the start of the map's header)
    uvec2 size;             // pixels
    float background_depth; // the depth buffer's clear value: no surface there
    uint flags;             // MASK_* | TSM_*
    uvec2 map_size;         // texels of the map
    float time;             // the shutter time the G-buffer shows (read when MOVING)
    float map_time;         // the time of this map, (i + 0.5) / N
    float maps;             // N
    uint reserved;
} pc;

#include "mask_gbuffer.glsl"

// The light-view depth of a texel from the z/w its depth attachment kept (+inf where nothing
// was drawn: the clear value 1 is never written, the test being LESS). Inverts
// z/w = (P22 z + P32) / (P23 z + P33) for the view-space z (as resolve.comp's ordinary maps).
float stored_light_depth(MsLight light, float stored) {
    if (stored >= 1.0) return 1.0 / 0.0;
    float z = (light.proj[3][2] - stored * light.proj[3][3])
            / (stored * light.proj[2][3] - light.proj[2][2]);
    return -z;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    float depth = texelFetch(depth_image, pixel, 0).r;
    float lit = 1.0;
    if (depth != pc.background_depth) {
        vec3 p = world_at(pixel, depth);
        MsLight light = ms_load_light(pc.light);
        vec3 n = gbuffer_normal(pixel, p, light);
        if (MOVING) p += (pc.map_time - pc.time) * texelFetch(motion_image, pixel, 0).xyz;
        uint index;
        float receiver;
        if (ms_receiver_texel(light, pc.map_size, p, n, index, receiver)) {
            ivec2 texel = ivec2(index % pc.map_size.x, index / pc.map_size.x);
            // z/w grows with the light depth (both projections), so the nearer of the two
            // maps is the smaller z/w.
            float stored = texelFetch(map_depth, texel, 0).r;
            if (SECOND_LOOKUP) stored = min(stored, texelFetch(static_depth, texel, 0).r);
            if (stored_light_depth(light, stored) < receiver) lit = 0.0;
        }
    }
    // Counts add exactly in floats; one division at the end makes N lit maps exactly 1.
    float count = lit;
    if ((pc.flags & TSM_FIRST) == 0u) count += imageLoad(mask, pixel).r;
    imageStore(mask, pixel, vec4((pc.flags & TSM_LAST) != 0u ? count / pc.maps : count));
}
