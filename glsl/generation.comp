#version 450
// Generation, first tier: every pixel whose list holds at most SHORT_LIST fragments (nearly
// all of them) is paired here with small private arrays; longer lists are handed to the
// second tier (generation_long.comp) through the long-pixel list. One workgroup per 8x8-texel
// tile, dispatched indirectly as the collection set it (shared.glsl's TILE_TEXELS).
#define SHORT_LIST 16u
#define LIST_CAPACITY SHORT_LIST
#include "generation_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
    open_map();
    uvec2 pixel = gl_WorkGroupID.xy * TILE_TEXELS + gl_LocalInvocationID.xy;
    if (pixel.x >= map.size.x || pixel.y >= map.size.y) return;
    uint p = pixel.y * map.size.x + pixel.x;
    if (pair_two(p)) return;
    uint n = load_list(p);
    if (n <= SHORT_LIST) {
        pair_list(p, n);
        return;
    }
    uint index = atomicAdd(long_list.head.count, 1u);
    if (index % LONG_TIER_GROUP == 0u) atomicAdd(long_list.head.groups_x, 1u);
    long_list.long_pixels[index] = p;
}
