#version 450
// Collection sub-pass (4.2): append this fragment to its pixel's linked list. A fragment past
// the node capacity is counted but not linked, so the count tells the caller the size needed.
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 3) buffer Heads { uint heads[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Nodes { Node nodes[]; };
layout(std430, set = 0, binding = 5) buffer CounterBlock { Counters counters; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint index = atomicAdd(counters.node_count, 1u);
    if (index >= counters.node_capacity) return;
    uint head = pixel.y * frame.sizes.x + pixel.x;
    uint next = atomicExchange(heads[head], index + 1u);
    nodes[index] = Node(in_depth, clamp(in_time, 0.0, 1.0), in_id, next);
}
