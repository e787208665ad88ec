#version 450
// Time-dependent shadow maps (Akenine-Moller et al. 2007) as an engine builds them, for the
// deferred frame: the mask of one batch of the N maps (the layers of the working map). For
// every pixel of the host's G-buffer, rebuild the world point and normal as the temporal
// map's mask does (mask_gbuffer.glsl), and for each map i of the batch move the point to
// where it is at the map's time t_i = (i + 0.5) / N (p + (t_i - time) * motion, when MOVING),
// test it with the temporal map's receiver test (ms_receiver_texel: normal offset,
// receiver-plane depth, light bias) against the map, and count it lit or not. The first batch
// writes its count into the host's R32_SFLOAT image, later ones add theirs; the last turns the
// count into the lit fraction of the N times (exactly 1 where every map sees the light).
// Background pixels count as lit.
//
// The maps are ordinary depth attachments (post-projection z/w, 1 where nothing was drawn)
// read through sampled images; with SECOND_LOOKUP each layer holds the moving draws alone and
// the static draws' map is read too (the nearer depth wins), instead of layers that hold both.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"
#include "light_motion.glsl"

// Where a moving light's pose at t = 1 (MsLightEnd) follows the light in the maps' header
// (src/technique/engine_tsm/map.rs LIGHT_END_OFFSET; shared.glsl's PLAIN_LIGHT_END_OFFSET,
// as shadow_depth.vert reads it). Each map i was drawn with the light at its time t_i and is
// read with that same light.
const uint64_t TSM_LIGHT_END_OFFSET = 224UL;

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
// rgb: the point's world displacement over the shutter, p(1) - p(0) (read when MOVING).
layout(set = 0, binding = 2) uniform sampler2D motion_image;
layout(set = 0, binding = 3, r32f) uniform image2D mask;
// Layer k: the map of time t_(first_map + k) (z/w of the depth attachment).
layout(set = 0, binding = 4) uniform sampler2DArray maps;
// SECOND_LOOKUP: the static draws' map (z/w), drawn once and kept.
layout(set = 0, binding = 5) uniform sampler2D static_map;
// xyz: the point's world position at pc.time (read with MASK_HAS_POSITIONS).
layout(set = 0, binding = 6) uniform sampler2D position_image;

layout(constant_id = 0) const bool MOVING = false;
layout(constant_id = 1) const bool SECOND_LOOKUP = false;

// MASK_* and TSM_FIRST_BATCH (write the count, do not add), TSM_LAST_BATCH (turn the count
// into the lit fraction), from src/technique/gpu_constants.rs.
#include "gpu_constants.glsl"

#include "image_push.glsl"
layout(push_constant) uniform Push { TsmMaskPush pc; };

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

// Is a receiver tested at light depth `receiver` in `texel` lit in layer k? z/w grows with
// the light depth (both projections), so the nearer of a layer and the static map is the
// smaller z/w (`static_stored`: the static map's, 1 when there is none to read).
bool lit_in_layer(MsLight light, ivec2 texel, uint k, float static_stored, float receiver) {
    float stored = min(texelFetch(maps, ivec3(texel, int(k)), 0).r, static_stored);
    return !(stored_light_depth(light, stored) < receiver);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    float depth = texelFetch(depth_image, pixel, 0).r;
    float lit = float(pc.batch);    // maps of the batch that see the light at this pixel
    if (depth != pc.background_depth) {
        vec3 p = world_at(pixel, depth);
        MsLight light = ms_load_light(pc.light);
        vec3 n = gbuffer_normal(pixel, p, light);
        uint index;
        float receiver;
        if (MOVING || ms_light_moves(light)) {
            // A moving receiver, or any under a moving light: a texel per map, the receiver
            // where it is at the map's time, projected by the light where it is then (a still
            // light's own: ms_light_at leaves it as it is).
            vec3 motion = MOVING ? texelFetch(motion_image, pixel, 0).xyz : vec3(0.0);
            for (uint k = 0u; k < pc.batch; ++k) {
                float t = (float(pc.first_map + k) + 0.5) * pc.inv_maps;
                MsLight at = ms_light_at(light, pc.light + TSM_LIGHT_END_OFFSET, t);
                if (!ms_receiver_texel(at, pc.map_size, p + (t - pc.time) * motion, n,
                                       index, receiver)) continue;
                ivec2 texel = ivec2(index % pc.map_size.x, index / pc.map_size.x);
                float static_stored = SECOND_LOOKUP ? texelFetch(static_map, texel, 0).r : 1.0;
                if (!lit_in_layer(at, texel, k, static_stored, receiver)) lit -= 1.0;
            }
        } else if (ms_receiver_texel(light, pc.map_size, p, n, index, receiver)) {
            // A receiver standing still: one texel for every map.
            ivec2 texel = ivec2(index % pc.map_size.x, index / pc.map_size.x);
            float static_stored = SECOND_LOOKUP ? texelFetch(static_map, texel, 0).r : 1.0;
            for (uint k = 0u; k < pc.batch; ++k) {
                if (!lit_in_layer(light, texel, k, static_stored, receiver)) lit -= 1.0;
            }
        }
    }
    // Counts add exactly in floats; the last batch scales them once.
    if ((pc.flags & TSM_FIRST_BATCH) == 0u) lit += imageLoad(mask, pixel).r;
    if ((pc.flags & TSM_LAST_BATCH) != 0u) lit = lit == pc.maps ? 1.0 : lit * pc.inv_maps;
    imageStore(mask, pixel, vec4(lit));
}
