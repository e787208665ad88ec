#version 450
// Collection sub-pass, exact construction, for static draws (DRAW_STATIC): nothing moves, so
// a triangle covers a texel all frame long or never, and the rasterizer says which (its
// top-left rule is watertight) without a geometry shader. z = w / 2, as in
// collection_exact.geom: the light's near and far planes clip nothing.
#include "shared.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) out float out_depth;
layout(location = 1) flat out uint out_id;
layout(location = 2) flat out uint out_closed;

void main() {
    DrawRecord d = load_draw(pc.draw.draws, pc.draw.draw_index);
    MsShadowMap map = MsShadowMap(pc.map);
    uint prim = uint(gl_VertexIndex) / 3u;
    uint corner = uint(gl_VertexIndex) % 3u;
    out_id = d.first_id + prim;
    out_closed = has_flag(d, DRAW_CLOSED) ? 1u : 0u;
    out_depth = 0.0;
    if (!triangle_valid(d, prim)) {
        // Counted once, by its first corner; w < 0 at every corner clips it away.
        if (corner == 0u && (pc.flags & COUNT_INVALID) != 0u)
            atomicAdd(CounterRef(map.counters).c.invalid_triangles, 1u);
        gl_Position = vec4(0.0, 0.0, 0.0, -1.0);
        return;
    }
    vec3 p0, p1;
    fetch_corner(d, prim, corner, p0, p1);
    vec3 v = (map.light.view * vec4(p0, 1.0)).xyz;
    vec4 clip = map.light.proj * vec4(v, 1.0);
    gl_Position = vec4(clip.xy, 0.5 * clip.w, clip.w);
    out_depth = -v.z;
}
