// Coverage map, third pass of the 2017 paper's extension: the prisms again (shared by both
// constructions). A pixel loses its mark when another triangle may come nearer to the light
// than the covering one at some time during the frame, or when the covering triangle itself
// does not cover it all frame long.
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

// Clears texel p's mark if the fragment (depth, time, id, surface) shows that the marked
// triangle is not the nearest occluder all frame long.
void reset_coverage(MsShadowMap map, uint p, float depth, float time, uint id, uint surface) {
    UintArray coverage = UintArray(map.coverage);
    uint cover = coverage.v[p];
    if (cover == NO_TRIANGLE) return;
    vec2 cover_depths = Vec2Array(map.cover_depth).v[p];
    bool reset = id == cover ? surface == SURFACE_SIDE
                             : depth < mix(cover_depths.x, cover_depths.y, time);
    if (reset) coverage.v[p] = NO_TRIANGLE;
}
