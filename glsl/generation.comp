#version 450
// Generation sub-pass (4.3): per shadow-map pixel, group the fragments by triangle id, order
// each group by depth, and pair consecutive fragments (1st-2nd, 3rd-4th, ...) into depth-time
// ranges. An odd group leaves its farthest fragment alone; it becomes a zero-length range
// [t, t] (it happens where the prism is cut by the light's near or far plane, or at a
// pixel centre exactly on a prism edge), kept so that nothing is dropped and counted by tests.
// Quadratic in the list length, but needs no per-pixel storage, so no list is ever too long.
#include "shared.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 3) readonly buffer Heads { uint heads[]; };
layout(std430, set = 0, binding = 4) readonly buffer Nodes { Node nodes[]; };
layout(std430, set = 0, binding = 5) buffer CounterBlock { Counters counters; };
layout(std430, set = 0, binding = 6) writeonly buffer RangeHeads { uint range_heads[]; };
layout(std430, set = 0, binding = 7) writeonly buffer Ranges { Range ranges[]; };

bool before(Node x, uint xi, Node y, uint yi) {
    return x.depth < y.depth || (x.depth == y.depth && xi < yi);
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.sizes.x || pixel.y >= frame.sizes.y) return;
    uint p = pixel.y * frame.sizes.x + pixel.x;
    uint first = heads[p];
    uint out_head = END_OF_LIST;

    for (uint a = first; a != END_OF_LIST; a = nodes[a - 1u].next) {
        Node na = nodes[a - 1u];
        uint rank = 0u;          // fragments of the same triangle before this one
        uint partner = END_OF_LIST;
        Node np;
        for (uint b = first; b != END_OF_LIST; b = nodes[b - 1u].next) {
            Node nb = nodes[b - 1u];
            if (b == a || nb.id != na.id) continue;
            if (before(nb, b, na, a)) {
                rank++;
            } else if (partner == END_OF_LIST || before(nb, b, np, partner)) {
                partner = b;
                np = nb;
            }
        }
        if ((rank & 1u) == 1u) continue;  // an exit fragment: its entry emits the range
        if (partner == END_OF_LIST) np = na;

        Range r;
        bool entry_first = na.time <= np.time;
        r.t_s = entry_first ? na.time : np.time;
        r.t_e = entry_first ? np.time : na.time;
        r.d_s = entry_first ? na.depth : np.depth;
        r.d_e = entry_first ? np.depth : na.depth;
        r.id = na.id;
        uint index = atomicAdd(counters.range_count, 1u);
        if (index >= counters.range_capacity) continue;
        r.next = out_head;
        ranges[index] = r;
        out_head = index + 1u;
    }
    range_heads[p] = out_head;
}
