#version 450
// Collection sub-pass, exact construction, static draws: with a static layer (the header
// has its address), the nearest static triangle per texel; without (the coverage map needs
// every fragment), both nodes of the texel.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"
#include "collection_append.glsl"
#include "static_prism.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

void main() {
    if (static_prism_culled()) return;
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    if (map.static_nearest != 0UL) {
        uint64_t key = (uint64_t(ms_static_key(in_depth)) << 32) | uint64_t(in_id);
        atomicMin(Uint64Array(map.static_nearest).v[p], key);
        return;
    }
    append_fragment(map, p, in_depth, 0.0, in_id, SURFACE_CAP0);
    append_fragment(map, p, in_depth, 1.0, in_id, SURFACE_CAP1);
}
