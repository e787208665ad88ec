#version 450
// Collection sub-pass (4.2): append this fragment to its pixel's linked list. A fragment past
// the node capacity is counted but not linked, so the count tells the caller the size needed.
// With USE_COVERAGE it also keeps the nearest fragment per pixel: the nearest map, first pass
// of the 2017 paper's extension (same prisms, so it shares this rasterization).
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 3) buffer Heads { uint heads[]; };
layout(std430, set = 0, binding = 5) buffer CounterBlock { Counters counters; };
layout(std430, set = 0, binding = 6) buffer Nearest { uint64_t nearest[]; };
layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;
layout(location = 3) flat in uint in_surface;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    if ((pc.flags & USE_COVERAGE) != 0u) {
        atomicMin(nearest[pixel.y * frame.sizes.x + pixel.x],
                  pack_nearest(in_depth, in_surface, in_id));
    }
    uint index = atomicAdd(counters.node_count, 1u);
    if (index >= counters.node_capacity) return;
    uint head = pixel.y * frame.sizes.x + pixel.x;
    uint next = atomicExchange(heads[head], index + 1u);
    NodeArray(pc.node_address).nodes[index] = Node(in_depth, clamp(in_time, 0.0, 1.0), in_id, next);
}
