// The exact construction's collection fragment shader (collection_exact.frag stores nodes,
// collection_ranges.frag ranges): the texel's covered runs of this triangle, solved in
// closed form (exact_prism.glsl). A run is what the generation pass pairs from its start and
// end nodes, so where the lists are not needed for anything else (no coverage map: the
// collection with the static layer) it goes straight to the texel's range list and the
// generation pass has nothing left to do.
#include "shared.glsl"
#include "collection_append.glsl"
#include "exact_prism.glsl"

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) flat in vec4 in_at0[3];
layout(location = 3) flat in vec4 in_at1[3];
layout(location = 6) flat in uint in_id;
#ifndef CONSERVATIVE_COLLECTION
// (The conservative collection's ranges span the whole shutter: it needs no cuts.)
layout(location = 7) flat in vec3 in_cuts;
#else
// How far beyond a texel's square the conservative collection looks, in texels: more than the
// difference between where this shader and the lookups project a point (float rounding), far
// less than a texel.
const float SQUARE_MARGIN_TEXELS = 1.0 / 16.0;

// The hull of the times in [0, 1] at which some corner k has a_k + t b_k <= 0 (each corner's
// are a prefix or a suffix of [0, 1]), widened by a few ulps of t for the roots' rounding;
// empty (x > y) where none ever has.
vec2 sublevel_hull(vec3 a, vec3 b) {
    vec2 hull = vec2(2.0, -1.0);
    for (int k = 0; k < 3; ++k) {
        float f0 = a[k], f1 = a[k] + b[k];
        if (f0 <= 0.0 && f1 <= 0.0) {
            hull = vec2(0.0, 1.0);
        } else if (f0 <= 0.0 || f1 <= 0.0) {
            float root = f0 / (f0 - f1);
            hull.x = min(hull.x, f0 <= 0.0 ? 0.0 : max(root - 1e-6, 0.0));
            hull.y = max(hull.y, f0 <= 0.0 ? min(root + 1e-6, 1.0) : 1.0);
        }
    }
    return hull;
}

// A sound bound of the times at which the triangle's shadow touches the square of texel
// `ndc` (its centre; `half_size` its half width in NDC, margin included): while the triangle
// covers a point of the square its projection's bounding box overlaps the square, so some
// corner is right of the square's left side, some left of its right side, and so on. Each of
// the four is a union of the corners' prefixes or suffixes of the shutter (a corner's
// x - side w is linear in t); the hull of their intersection is within the intersection of
// their hulls. Empty (x > y) where the box never meets the square. The whole shutter where a
// corner is ever at or behind the light (its projection is not a linear motion's then).
vec2 square_times(vec4 at0[3], vec4 at1[3], vec2 ndc, vec2 half_size) {
    vec3 x0 = vec3(at0[0].x, at0[1].x, at0[2].x), x1 = vec3(at1[0].x, at1[1].x, at1[2].x);
    vec3 y0 = vec3(at0[0].y, at0[1].y, at0[2].y), y1 = vec3(at1[0].y, at1[1].y, at1[2].y);
    vec3 w0 = vec3(at0[0].z, at0[1].z, at0[2].z), w1 = vec3(at1[0].z, at1[1].z, at1[2].z);
    if (any(lessThanEqual(w0, vec3(0.0))) || any(lessThanEqual(w1, vec3(0.0)))) {
        return vec2(0.0, 1.0);
    }
    vec2 hi = ndc + half_size, lo = ndc - half_size;
    // x - side w <= 0 (left of the right side), side w - x <= 0 (right of the left side).
    vec2 t = sublevel_hull(x0 - hi.x * w0, (x1 - hi.x * w1) - (x0 - hi.x * w0));
    vec2 u = sublevel_hull(lo.x * w0 - x0, (lo.x * w1 - x1) - (lo.x * w0 - x0));
    t = vec2(max(t.x, u.x), min(t.y, u.y));
    u = sublevel_hull(y0 - hi.y * w0, (y1 - hi.y * w1) - (y0 - hi.y * w0));
    t = vec2(max(t.x, u.x), min(t.y, u.y));
    u = sublevel_hull(lo.y * w0 - y0, (lo.y * w1 - y1) - (lo.y * w0 - y0));
    return vec2(max(t.x, u.x), min(t.y, u.y));
}
#endif

void main() {
    MsShadowMap map = MsShadowMap(pc.map);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    vec2 ndc = gl_FragCoord.xy / vec2(map.size.xy) * 2.0 - 1.0;
    ExactCorner corners[3];
    for (int k = 0; k < 3; ++k) corners[k] = ExactCorner(in_at0[k], in_at1[k]);
    uint p = pixel.y * map.size.x + pixel.x;
#ifdef CONSERVATIVE_COLLECTION
    // The exact lookup reads a range's triangle and window only: a bound of the times the
    // triangle may cover some point of the texel (none: the footprint, the hull of the
    // triangle's corners over the shutter, holds more than the triangle ever covers), and
    // the triangle's depths over the shutter.
    vec2 half_size = (0.5 + SQUARE_MARGIN_TEXELS) * 2.0 / vec2(map.size.xy);
    vec2 times = square_times(in_at0, in_at1, ndc, half_size);
    if (times.x <= times.y) {
        float near = in_at0[0].w, far = in_at0[0].w;
        for (int k = 0; k < 3; ++k) {
            near = min(near, min(in_at0[k].w, in_at1[k].w));
            far = max(far, max(in_at0[k].w, in_at1[k].w));
        }
        if ((pc.flags & STATIC_NAMES) != 0u) {
            append_static_name(map, p, in_id);
        } else {
            append_named_range(map, p, times, vec2(near, far), in_id);
        }
    }
#else
    vec2 a[3], d[3];
    ExactRuns runs = exact_prism_runs(corners, ndc, in_cuts, a, d);
    for (int i = 0; i < runs.count; ++i) {
        vec2 times, depths;
        exact_run_nodes(a, d, corners, runs, i, times, depths);
#ifdef COLLECT_RANGES
        append_range(map, p, times, depths, in_id);
#else
        append_fragment(map, p, depths.x, times.x, in_id, exact_surface(times.x));
        append_fragment(map, p, depths.y, times.y, in_id, exact_surface(times.y));
#endif
    }
#endif
}
