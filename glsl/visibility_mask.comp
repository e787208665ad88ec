#version 450
// The visibility-mask pass for deferred engines: for every pixel of the host's depth image,
// rebuild the world position (and the normal, from the host's normal image or the depth
// neighbours), and write the fraction of the shutter during which that point sees the light
// into the host's single-channel image, ready for its own lighting. Background pixels get 1.
// Two variants (specialization constant MOVING): receivers standing still (ms_lit_fraction)
// or moving as the host's motion image says (ms_lit_fraction_moving: each range tested
// where the point is at that time).
//
// On a device that leaves loops after a fixed count (lavapipe), a moving receiver's walk along
// its path may be longer than one invocation can run: it stops between two texels and joins
// the overflow queue, and follow-up dispatches (rounds 1 .. pc.rounds, indirect, sized by the
// queue's count) go on from where it stopped (MsWalk), each with a fresh budget.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_KHR_shader_subgroup_vote : require
#include "motion_shadows.glsl"
#include "light_motion.glsl"
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
// The follow-up rounds' own pipelines (pc.round > 0): only they stop walks on the way. Round 0
// walks as a device without a loop limit does and hands what ran too long to round 1 from its
// start: the stop's test in the walk's loop, even with a budget of 0 at run time, made the
// default frame's mask 1.3x slower on lavapipe, folded away here.
layout(constant_id = 2) const bool FOLLOW_UP = false;
// Round 0 of a mask that walks paths (moving receivers, the exact lookup) on a device with
// follow-up rounds, under a still light (the host picks it only there: under a moving one
// nothing stands still relative to it): receivers standing still take their one texel's walk
// (ms_walk_exact_still, ms_walk_moving_still), moving ones go to round 1 from their start.
// llvmpipe runs a branch's code (masked) for every SIMD group that reaches it, whichever
// lanes take it: kept out of this pipeline, the general walk (texel stepping, the moving
// receivers' loops) costs the still receivers, most of a frame's, nothing.
layout(constant_id = 3) const bool STILL_FIRST = false;
// With STILL_FIRST, an exact mask over a map with static name lists (the static layer): a
// receiver standing still walks its texel's static names alone and goes to round 1 where the
// texel names moving triangles too and no static one blocks it (ms_walk_exact_still). Without
// static names every triangle is a range: round 0 walks them.
layout(constant_id = 4) const bool STATIC_NAMES_FIRST = false;

// MASK_* flags (MASK_HAS_IDS: read the triangle-id image), from src/technique/gpu_constants.rs.
#include "gpu_constants.glsl"

#include "image_push.glsl"
layout(push_constant) uniform Push { MaskPush pc; };

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Counter { uint count; };
// The overflow queues (src/technique/mask_queue.rs): per follow-up round r = 1 .. rounds, the
// indirect dispatch of round r, its count of entries and its count of carried unions (header
// r - 1); then two queues of pc.capacity entries, round r reading queue r % 2 (written by
// round r - 1); then two pools of carry_capacity() unions, read and written the same way.
layout(buffer_reference, std430, buffer_reference_align = 4) buffer MaskQueue { uint v[]; };
// QUEUE_HEADER_WORDS: groups x, y, z (the indirect dispatch), count, carries.
// QUEUE_ENTRY_WORDS: pixel, t, texel (or QUEUE_FROM_START), sum, limit, cursor, carry slot
// (where cursor is not MS_EXACT_CURSOR_START: an exact walk that stopped within a texel's
// list). Both, CARRY_WORDS and CARRY_SHARE are generated from src/technique/gpu_constants.rs,
// which mask_queue.rs sizes the buffer by.
const uint QUEUE_FROM_START = 0xffffffffu;
const uint GROUP_SIZE = 64u;            // local_size_x * local_size_y
// A union of shadowed intervals, CARRY_WORDS: its vectors s0, s1, e0, e1 (ms_exact_Union).
// The fewest loop iterations a follow-up invocation of the exact walk is asked to stop at
// after its group's loops were cut: enough for its texel and one triangle (ms_walk_exact
// tests one before it stops), so every invocation gets on.
const uint EXACT_MIN_LIMIT = 16u;

// Unions per pool: one per CARRY_SHARE of the queue's entries (mask_queue.rs's
// carry_capacity). An exact walk that stops within a texel's list while its pool is full goes
// on from the texel's start.
uint carry_capacity() {
    return (pc.capacity + CARRY_SHARE - 1u) / CARRY_SHARE;
}

uint queue_entry(uint round, uint index) {
    return QUEUE_HEADER_WORDS * pc.rounds
        + ((round & 1u) * pc.capacity + index) * QUEUE_ENTRY_WORDS;
}

uint carry_at(uint round, uint slot) {
    return QUEUE_HEADER_WORDS * pc.rounds + 2u * pc.capacity * QUEUE_ENTRY_WORDS
        + ((round & 1u) * carry_capacity() + slot) * CARRY_WORDS;
}

// Entry `index` of round `round`'s queue: its pixel and where its walk goes on from (and, for
// an exact walk stopped within a texel's list, that texel's union so far).
MsWalk queue_read(uint round, uint index, out ivec2 pixel, out ms_exact_Union carried) {
    MaskQueue q = MaskQueue(pc.queue);
    uint at = queue_entry(round, index);
    uint packed_pixel = q.v[at], packed_texel = q.v[at + 2u];
    pixel = ivec2(packed_pixel & 0xffffu, packed_pixel >> 16u);
    MsWalk walk = ms_walk_start();
    carried = ms_exact_union_empty();
    if (packed_texel != QUEUE_FROM_START) {
        walk.state = MS_WALK_RESUME;
        walk.t = uintBitsToFloat(q.v[at + 1u]);
        walk.texel = ivec2(packed_texel & 0xffffu, packed_texel >> 16u);
        walk.sum = uintBitsToFloat(q.v[at + 3u]);
        walk.cursor = q.v[at + 5u];
        if (walk.cursor != MS_EXACT_CURSOR_START) {
            uint c = carry_at(round, q.v[at + 6u]);
            for (uint k = 0u; k < 4u; ++k) {
                carried.s0[k] = uintBitsToFloat(q.v[c + k]);
                carried.s1[k] = uintBitsToFloat(q.v[c + 4u + k]);
                carried.e0[k] = uintBitsToFloat(q.v[c + 8u + k]);
                carried.e1[k] = uintBitsToFloat(q.v[c + 12u + k]);
            }
        }
    }
    walk.limit = q.v[at + 4u];
    return walk;
}

// Puts the pixel's walk into the next round's queue (with `carried`, the union of the texel
// an exact walk stopped in); false where there is no next round or the queue is full (the
// pixel is then over budget).
bool queue_append(ivec2 pixel, MsWalk walk, ms_exact_Union carried) {
    uint next = pc.round + 1u;
    if (next > pc.rounds) return false;
    MaskQueue q = MaskQueue(pc.queue);
    uint header = QUEUE_HEADER_WORDS * (next - 1u);
    uint index = atomicAdd(q.v[header + 3u], 1u);
    if (index >= pc.capacity) return false;
    uint at = queue_entry(next, index);
    bool resume = walk.state == MS_WALK_RESUME;
    uint cursor = resume ? walk.cursor : MS_EXACT_CURSOR_START;
    if (cursor != MS_EXACT_CURSOR_START) {
        uint slot = atomicAdd(q.v[header + 4u], 1u);
        if (slot < carry_capacity()) {
            uint c = carry_at(next, slot);
            for (uint k = 0u; k < 4u; ++k) {
                q.v[c + k] = floatBitsToUint(carried.s0[k]);
                q.v[c + 4u + k] = floatBitsToUint(carried.s1[k]);
                q.v[c + 8u + k] = floatBitsToUint(carried.e0[k]);
                q.v[c + 12u + k] = floatBitsToUint(carried.e1[k]);
            }
            q.v[at + 6u] = slot;
        } else {
            // No room for the union: the walk goes on from the texel's start (walk.sum is
            // what the texels before it shadowed), doing the texel's tests again.
            cursor = MS_EXACT_CURSOR_START;
        }
    }
    q.v[at] = uint(pixel.x) | (uint(pixel.y) << 16u);
    q.v[at + 1u] = floatBitsToUint(walk.t);
    q.v[at + 2u] = resume ? uint(walk.texel.x) | (uint(walk.texel.y) << 16u) : QUEUE_FROM_START;
    q.v[at + 3u] = floatBitsToUint(walk.sum);
    q.v[at + 4u] = walk.limit;
    q.v[at + 5u] = cursor;
    atomicMax(q.v[header], index / GROUP_SIZE + 1u);
    return true;
}

// world_at, normal_from_depth, gbuffer_normal and the MASK_* flags (shared with
// tsm_mask.comp, so both masks test the same receivers).
#include "mask_gbuffer.glsl"

// Whether the device's loop limiter (lavapipe) has run out in this SIMD group: every loop then
// leaves after its first iteration, and this one, of pc.probe iterations (2; from the host,
// so that it is not unrolled), runs once. The walks' own counts are upper bounds of their
// loops but not of every loop inside the exact test: this catches what they miss.
bool loops_were_cut() {
    uint ran = 0u;
    for (uint i = 0u; i < pc.probe; ++i) ++ran;
    return ran < pc.probe;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    // Where this invocation's walk starts (moving receivers and the exact lookup).
    MsWalk walk = ms_walk_start();
    // An exact walk's union of the texel it stopped in (read where walk.cursor says so).
    ms_exact_Union carried = ms_exact_union_empty();
    uint index = gl_WorkGroupID.x * GROUP_SIZE + gl_LocalInvocationIndex;
    // (Keyed on the pipeline, not on pc.round: round 0's walk then starts from constants, and
    // its loop's texel-limit test folds away.)
    if (!FOLLOW_UP) {
        if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    } else {
        uint count = MaskQueue(pc.queue).v[QUEUE_HEADER_WORDS * (pc.round - 1u) + 3u];
        if (index >= min(count, pc.capacity)) return;
        walk = queue_read(pc.round, index, pixel, carried);
    }
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
    vec3 motion = MOVING ? texelFetch(motion_image, pixel, 0).xyz : vec3(0.0);
    vec3 p0 = p - pc.time * motion;
    // A moving receiver in a STILL_FIRST round 0: walked by round 1 from its start.
    bool to_round_1 = false;
    if (EXACT) {
        // A map built for the exact lookup (Lookup::Exact): the receiver's own shadow ray
        // against the triangles named along its path; no normal, offset or bias.
        // The same per-lane budget as the depth lines': ms_loop_iterations counts the exact
        // test's own loops too (its roots, its sort). A moving light: its motion (and turn),
        // for the rays toward it and the walk in its frame (exact_shadow.glsl).
        // (Never in a STILL_FIRST round, which the host picks under a still light only: folded
        // away there, since llvmpipe would load the pose for every SIMD group, taken or not.)
        if (!STILL_FIRST && ms_light_moves(tested.light)) {
            MsLightEnd end = ms_light_end(pc.map);
            ms_exact_light_motion = end.position.xyz - tested.light.position.xyz;
            // A turning light (the host takes it only over still geometry, and a spot only
            // turning in place: LightView::refuse_turning_exact): a sun's ray turns with it,
            // and the walk takes the receiver through the turned frame.
            ms_exact_light_turning = end.direction.xyz != tested.light.direction.xyz;
            if (ms_exact_light_turning) {
                ms_exact_light_frame = end.frame;
                if (tested.light.position.w == 0.0) {
                    ms_exact_light_turn =
                        normalize(end.direction.xyz) - normalize(tested.light.direction.xyz);
                }
            }
        }
        if (!STILL_FIRST) {
            ms_walk_exact(tested, p0, p0 + motion, own, FOLLOW_UP ? pc.loop_budget : 0u, walk,
                          carried);
        } else if (motion == vec3(0.0)) {
            to_round_1 = !ms_walk_exact_still(tested, p0, own, STATIC_NAMES_FIRST, walk, carried);
        } else {
            to_round_1 = true;
        }
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
        // (A moving light: the path's end seen as the t = 1 view sees it, and under a turning
        // one the normal turned with it, light_motion.glsl.)
        vec3 p1 = ms_light_frame_end(tested.light, pc.map, p0 + motion);
        if (!STILL_FIRST) {
            mat3 turn;
            bool turns = ms_light_turns(tested.light, pc.map, turn);
            ms_walk_moving_turned(tested, p0, p1, n, turns, turn, own,
                                  FOLLOW_UP ? pc.loop_budget : 0u, walk);
        } else if (motion == vec3(0.0)) {
            ms_walk_moving_still(tested, p0, n, own, walk);
        } else {
            to_round_1 = true;
        }
    } else {
        float lit = ms_lit_fraction(tested, p, n, own);
        imageStore(mask, pixel, vec4(lit));
        // The device leaves loops past a fixed count: say so when this pixel's lookup may
        // have come near it (the value above may then be cut short).
        if (pc.loop_budget > 0u && ms_loop_iterations > pc.loop_budget) {
            atomicAdd(Counter(pc.over_budget).count, 1u);
        }
        return;
    }
    // llvmpipe's loop counter is shared by the lanes of a SIMD group (a subgroup): one lane
    // past its budget may have cut the loops of the others, whose answers are then unsure.
    // (Round 0's walks run their course: the probe catches what the limiter cut.)
    bool past = walk.state == MS_WALK_PAST
        || (!FOLLOW_UP && pc.loop_budget > 0u && ms_loop_iterations > pc.loop_budget);
    bool cut = subgroupAny(past || loops_were_cut());
    bool over = false;
    if (!FOLLOW_UP) {
        // Round 0: what ran too long, or shared a group with it, goes on from its start.
        if (!cut && !to_round_1) {
            imageStore(mask, pixel, vec4(walk.sum));
        } else {
            over = !queue_append(pixel, ms_walk_start(), carried);
        }
    } else if (walk.state == MS_WALK_DONE && !cut) {
        imageStore(mask, pixel, vec4(walk.sum));
    } else if (walk.state == MS_WALK_STOPPED && !cut) {
        walk.state = MS_WALK_RESUME;
        over = !queue_append(pixel, walk, carried);
    } else if (EXACT) {
        // Read again rather than kept: a copy live across the walk made the mask slower.
        ivec2 same_pixel;
        MsWalk start = queue_read(pc.round, index, same_pixel, carried);
        // Again from where this invocation started, stopping after half the iterations it
        // ran (it stops within a texel's list too, after one triangle at least), down to
        // EXACT_MIN_LIMIT: cut even there, it is over budget.
        over = start.limit <= EXACT_MIN_LIMIT;
        start.limit = max(min(start.limit, walk.walked) / 2u, EXACT_MIN_LIMIT);
        if (!over) over = !queue_append(pixel, start, carried);
    } else if (walk.state == MS_WALK_PAST && walk.walked == 0u) {
        over = true;    // one texel's list alone is longer than an invocation can walk
    } else {
        ivec2 same_pixel;
        MsWalk start = queue_read(pc.round, index, same_pixel, carried);
        // Again from where this invocation started, walking fewer texels: a walk that ran
        // past its budget stops before the texel that did (its next invocation starts with
        // it), the others of a group whose loops were cut walk half as many as they did.
        start.limit = walk.state == MS_WALK_PAST ? walk.walked : max(walk.walked / 2u, 1u);
        over = !queue_append(pixel, start, carried);
    }
    if (over) atomicAdd(Counter(pc.over_budget).count, 1u);
}
