// Collection sub-pass, exact construction (exact_prism.glsl), the geometry stage (compiled as
// collection_exact.geom, and as collection_conservative.geom with CONSERVATIVE_COLLECTION
// for the exact lookup): instead of the prism's caps and
// triangulated sides, one footprint per triangle (the convex hull of its six projected
// corners, dilated by a sliver of a texel so that every texel centre the exact test may
// count is visited), with the corners handed flat to the fragment shader, which solves each
// texel's covered times in closed form.
//
// Every emitted vertex has z = w / 2: the footprint is never clipped by the light's near or
// far plane, so a caster between the light and its near plane keeps its shadow (the
// fragment shader keeps only what lies in front of the light itself).
#include "shared.glsl"
#include "exact_prism.glsl"
#include "light_crossing.glsl"
#define HULL_MAX_POINTS 6
#include "convex_hull.glsl"

layout(triangles) in;
// The grown hull: at most the hull's 6 corners plus one more at each of at most two sharp
// ones (convex_hull.glsl's bevel: a sharp corner turns by more than 151 degrees, and the
// turns of a convex polygon add up to 360). NVIDIA's geometry shaders slow down with the
// declared output size: 12 here cost random-cubes' collection 3.7 ms more than 8 on an H200.
#define MAX_GROWN_POINTS 8
layout(triangle_strip, max_vertices = MAX_GROWN_POINTS) out;

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) in vec3 in_p0[];
layout(location = 1) in vec3 in_p1[];
layout(location = 2) in float in_valid[];

layout(location = 0) flat out vec4 out_at0[3];
layout(location = 3) flat out vec4 out_at1[3];
layout(location = 6) flat out uint out_id;
// The times the triangle's plane passes through the light (light_crossing.glsl): cuts of
// the fragment shader's pieces besides the edge roots, the same for every texel.
#ifndef CONSERVATIVE_COLLECTION
layout(location = 7) flat out vec3 out_cuts;
#endif

// How far the footprint is pushed out, in texels: far more than the rasterizer's snapping
// (1/256 texel) and float rounding, far less than a texel.
const float DILATION_TEXELS = 1.0 / 16.0;
// The conservative collection (CONSERVATIVE_COLLECTION, the exact lookup) grows it by a texel's
// half-diagonal more: every point of a texel is within that of its centre, so a texel whose
// area the swept footprint touches has its centre in the grown footprint, and is drawn.
const float HALF_DIAGONAL_TEXELS = 0.70710678;

// Footprints reaching beyond this many map widths (a corner nearly level with a perspective
// light) are drawn as the whole map instead: the fragment shader's test is exact either way.
const float FOOTPRINT_LIMIT_NDC = 64.0;

vec4 corner_at0[3], corner_at1[3];
uint triangle_id;
vec3 light_cuts;

void emit_ndc(vec2 ndc) {
    gl_Position = vec4(ndc, 0.5, 1.0);
    for (int k = 0; k < 3; ++k) {
        out_at0[k] = corner_at0[k];
        out_at1[k] = corner_at1[k];
    }
    out_id = triangle_id;
#ifndef CONSERVATIVE_COLLECTION
    out_cuts = light_cuts;
#endif
    EmitVertex();
}

void emit_whole_map() {
    emit_ndc(vec2(-1.0, -1.0));
    emit_ndc(vec2(1.0, -1.0));
    emit_ndc(vec2(-1.0, 1.0));
    emit_ndc(vec2(1.0, 1.0));
    EndPrimitive();
}

// Every point on the line through the first two distinct ones (precise turns: exact for
// repeated points). Corners on one line at t = 0 and t = 1 stay on it in between: the
// triangle is edge-on all frame long.
bool exactly_collinear(vec2 p[6]) {
    int j = 1;
    while (j < 5 && p[j] == p[0]) ++j;
    for (int k = 1; k < 6; ++k) {
        if (hull_turn(p[0], p[j], p[k]) != 0.0) return false;
    }
    return true;
}

// A quad `by` around the segment a-b (a square where a == b), in texels.
void emit_around_segment(vec2 a, vec2 b, float by, vec2 size) {
    vec2 along = a != b ? normalize(b - a) * by : vec2(by, 0.0);
    vec2 across = vec2(-along.y, along.x);
    emit_ndc((a - along - across) / size * 2.0 - 1.0);
    emit_ndc((b + along - across) / size * 2.0 - 1.0);
    emit_ndc((a - along + across) / size * 2.0 - 1.0);
    emit_ndc((b + along + across) / size * 2.0 - 1.0);
    EndPrimitive();
}

void main() {
    DrawRecord d = load_draw(pc.draw.draws, pc.draw.draw_index);
    MsShadowMap map = MsShadowMap(pc.map);
    if (in_valid[0] == 0.0 || in_valid[1] == 0.0 || in_valid[2] == 0.0) {
        if ((pc.flags & COUNT_INVALID) != 0u)
            atomicAdd(CounterRef(map.counters).c.invalid_triangles, 1u);
        return;
    }
    triangle_id = d.first_id + uint(gl_PrimitiveIDIn);
    // A compile-time choice: the conservative collection's code stays out of the default
    // pipeline (as a push flag it made the default collection 1.15x slower on lavapipe).
#ifdef CONSERVATIVE_COLLECTION
    const bool conservative = true;
#else
    const bool conservative = false;
#endif
    if (conservative && map.triangles != 0UL) {
        // Once per triangle (one draw per triangle per frame): its world corners at both ends.
        // MsTriangles in exact_lookup.glsl: six vec4 per triangle.
        Vec4Array records = Vec4Array(map.triangles);
        for (int k = 0; k < 3; ++k) {
            records.v[6u * triangle_id + uint(k)] = vec4(in_p0[k], 1.0);
            records.v[6u * triangle_id + 3u + uint(k)] = vec4(in_p1[k], 1.0);
        }
    }
    MsLight light = map.light;
    // A moving light: each vertex's t = 1 position is seen from the light at t = 1, its
    // light-clip position blended between the two (the light's moving frame,
    // light_motion.glsl).
    mat4 view1 = light.view;
    if (ms_light_moves(light)) view1 = ms_light_end(pc.map).view;
    bool orthographic = light.position.w == 0.0;

    vec3 v0[3], v1[3];
    vec4 clip[6];
    bool all_in_front = true;
    for (int i = 0; i < 3; ++i) {
        v0[i] = (light.view * vec4(in_p0[i], 1.0)).xyz;
        v1[i] = (view1 * vec4(in_p1[i], 1.0)).xyz;
        clip[i] = light.proj * vec4(v0[i], 1.0);
        clip[i + 3] = light.proj * vec4(v1[i], 1.0);
        corner_at0[i] = vec4(clip[i].xyw, -v0[i].z);
        corner_at1[i] = vec4(clip[i + 3].xyw, -v1[i].z);
    }
    bool behind = true, left = true, right = true, below = true, above = true;
    for (int i = 0; i < 6; ++i) {
        behind = behind && clip[i].w <= 0.0;
        left = left && clip[i].x < -clip[i].w;
        right = right && clip[i].x > clip[i].w;
        below = below && clip[i].y < -clip[i].w;
        above = above && clip[i].y > clip[i].w;
        all_in_front = all_in_front && clip[i].w > 0.0;
    }
    if (behind || left || right || below || above) return;
    if (has_flag(d, DRAW_CLOSED) &&
        faces_away_whole_frame(v0[0], v0[1], v0[2], v1[0], v1[1], v1[2], orthographic))
        return;

    vec2 size = vec2(map.size.xy);
    vec2 texels[6];
    bool bounded = all_in_front;
    for (int i = 0; i < 6 && bounded; ++i) {
        vec2 ndc = clip[i].xy / clip[i].w;
        bounded = all(lessThan(abs(ndc), vec2(FOOTPRINT_LIMIT_NDC)));
        texels[i] = (ndc * 0.5 + 0.5) * size;
    }
    if (!bounded) {
        // Some corner at or behind the light: the triangle may contain the light while its
        // plane passes through it.
        light_cuts = vec3(EXACT_NO_ROOT);
        if (!all_in_front) {
            vec3 p[3], q[3];
            for (int k = 0; k < 3; ++k) {
                p[k] = corner_at0[k].xyz;
                q[k] = corner_at1[k].xyz;
            }
            light_cuts = light_crossing_times(p, q);
        }
        emit_whole_map();
        return;
    }
    light_cuts = vec3(EXACT_NO_ROOT);  // all in front: never contains the light
    vec2 hull[2 * HULL_MAX_POINTS];
    vec2 corners[6] = texels;
    float merge = hull_merge_distance(texels, 6);
    int h = convex_hull(texels, 6, merge, hull);
    // The hull may miss up to `merge` of the footprint (convex_hull.glsl): grown by that too.
    float grow = DILATION_TEXELS + 1.5 * merge + (conservative ? HALF_DIAGONAL_TEXELS : 0.0);
    if (h < 3) {
        // Seen exactly edge-on all frame long (a wall under a light straight above it): no
        // texel centre is ever covered, nothing to draw. Otherwise a sliver or a speck
        // thinner than `merge`: a thin quad around it, the fragment shader finds what it
        // covers.
        if (exactly_collinear(corners)) return;
        emit_around_segment(hull[0], hull[h - 1], grow, size);
        return;
    }
    h = hull_grow(hull, h, grow);
    if (h > MAX_GROWN_POINTS) {
        // Not reached (see MAX_GROWN_POINTS); rounding aside, the grown box is as safe.
        vec2 lo_corner = hull[0], hi_corner = hull[0];
        for (int i = 1; i < h; ++i) {
            lo_corner = min(lo_corner, hull[i]);
            hi_corner = max(hi_corner, hull[i]);
        }
        hull[0] = lo_corner;
        hull[1] = vec2(hi_corner.x, lo_corner.y);
        hull[2] = hi_corner;
        hull[3] = vec2(lo_corner.x, hi_corner.y);
        h = 4;
    }
    // A convex polygon as one strip: 0, 1, h-1, 2, h-2, ...
    int lo = 0, hi = h - 1;
    emit_ndc(hull[lo++] / size * 2.0 - 1.0);
    for (bool from_low = true; lo <= hi; from_low = !from_low) {
        emit_ndc((from_low ? hull[lo++] : hull[hi--]) / size * 2.0 - 1.0);
    }
    EndPrimitive();
}
