#version 450
// Coverage map, third pass of the 2017 paper's extension: the prisms again. A pixel loses its
// mark when another triangle may come nearer to the light than the covering one at some time
// during the frame, or when the covering triangle itself does not cover it all frame long.
//
// Where the paper leaves it open (it tests against the depth buffer, i.e. the last cap depth
// written, which misses a blocker that is nearer only while the covering triangle is far):
// every fragment is compared at its own time. The covering triangle T covers the pixel all
// frame, so its depth there goes linearly from its t = 0 to its t = 1 cap depth (exactly as
// its range says). Another triangle's fragments are the end points (time, depth) of its ranges,
// and its depth is linear in time between them; if it is behind T at both end points, it is
// behind T all through the range. So a pixel stays marked iff every other triangle is behind T
// whenever it covers the pixel: T is the nearest occluder for the whole frame. And a
// side-surface fragment of T itself means one of T's edges sweeps over the pixel: T does not
// cover it all frame, even if it does at t = 0 and t = 1 (possible with rotation-like vertex
// motion), so that resets too.
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) in float in_depth;
layout(location = 1) in float in_time;
layout(location = 2) flat in uint in_id;
layout(location = 3) flat in uint in_surface;

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * map.size.x + pixel.x;
    UintArray coverage = UintArray(map.coverage);
    uint cover = coverage.v[p];
    // (Reading the time also keeps the prism pipeline's interface whole for validation.)
    if (cover == NO_TRIANGLE || isnan(in_time)) return;
    vec2 cover_depths = Vec2Array(map.cover_depth).v[p];
    bool reset = in_id == cover ? in_surface == SURFACE_SIDE
                                : in_depth < mix(cover_depths.x, cover_depths.y, in_time);
    if (reset) coverage.v[p] = NO_TRIANGLE;
}
