#version 450
// The visibility-mask pass for deferred engines: for every pixel of the host's depth image,
// rebuild the world position (and the normal, from the host's normal image or the depth
// neighbours), and write the fraction of the shutter during which that point sees the light
// into the host's single-channel image, ready for its own lighting. Background pixels get 1.
// Two variants (specialization constant MOVING): receivers standing still (ms_lit_fraction)
// or moving as the host's motion image says (ms_lit_fraction_moving: each range tested
// where the point is at that time).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"
#include "exact_lookup.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
layout(set = 0, binding = 2) writeonly uniform image2D mask;
// rgb: the point's world displacement over the shutter, p(1) - p(0) (read when MOVING).
layout(set = 0, binding = 3) uniform sampler2D motion_image;
// The triangle each pixel shows (read with MASK_HAS_IDS): never shadows its own pixels.
layout(set = 0, binding = 4) uniform usampler2D id_image;
// xyz: the point's world position at pc.time (read with MASK_HAS_POSITIONS).
layout(set = 0, binding = 5) uniform sampler2D position_image;

layout(constant_id = 0) const bool MOVING = false;
// A map built for the exact lookup (Lookup::Exact, triangle records in its header): its own
// pipeline, so that the exact test's code is not compiled into the depth-line masks (beside
// them it made the default mask 1.65x slower on lavapipe).
layout(constant_id = 1) const bool EXACT = false;

// MASK_* flags (MASK_HAS_IDS: read the triangle-id image), from src/technique/gpu_constants.rs.
#include "gpu_constants.glsl"

#include "image_push.glsl"
layout(push_constant) uniform Push { MaskPush pc; };

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Counter { uint count; };

// world_at, normal_from_depth, gbuffer_normal and the MASK_* flags (shared with
// tsm_mask.comp, so both masks test the same receivers).
#include "mask_gbuffer.glsl"

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    float depth = texelFetch(depth_image, pixel, 0).r;
    if (depth == pc.background_depth) {
        imageStore(mask, pixel, vec4(1.0));
        return;
    }
    vec3 p = world_at(pixel, depth);
    MsShadowMap map = MsShadowMap(pc.map);
    MsLight light = map.light;
    // The receiver offset goes to the side the light is tested from.
    vec3 n = gbuffer_normal(pixel, p, light);
    uint own =
        (pc.flags & MASK_HAS_IDS) != 0u ? texelFetch(id_image, pixel, 0).r : MS_NO_TRIANGLE;
    MsMap tested = ms_load(map);
    float lit;
    vec3 motion = MOVING ? texelFetch(motion_image, pixel, 0).xyz : vec3(0.0);
    if (EXACT) {
        // A map built for the exact lookup (Lookup::Exact): the receiver's own shadow ray
        // against the triangles named along its path; no normal, offset or bias.
        vec3 p0 = p - pc.time * motion;
        lit = ms_lit_fraction_exact_moving(tested, p0, p0 + motion, own);
    } else if (MOVING) {
        if (motion == vec3(0.0) && (pc.flags & MASK_STILL_PIXELS_PLANE) != 0u) {
            // A point that stands still keeps its plane all frame: the standing receiver's
            // test (its plane's depth at the texel centre, no offset), which the offset meant
            // for moving receivers (whose surface may turn away from the G-buffer's plane)
            // would cost contact shadows and detail. One call for both kinds of pixel (the
            // moving lookup of a still point is the standing one): a second lookup beside it
            // made the mask slower on lavapipe.
            tested.light.bias.x = 0.0;
            tested.light.bias.w = 1.0;
        }
        vec3 p0 = p - pc.time * motion;
        lit = ms_lit_fraction_moving(tested, p0, p0 + motion, n, own);
    } else {
        lit = ms_lit_fraction(tested, p, n, own);
    }
    imageStore(mask, pixel, vec4(lit));
    // The device leaves loops past a fixed count: say so when this pixel's lookup may have
    // come near it (the value above may then be cut short).
    if (pc.loop_budget > 0u && ms_loop_iterations > pc.loop_budget) {
        atomicAdd(Counter(pc.over_budget).count, 1u);
    }
}
