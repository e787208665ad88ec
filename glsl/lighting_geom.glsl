// Lighting pass, stochastic rasterization (McGuire et al. 2010): cover every pixel that the
// moving triangle can touch during the frame with the screen-space convex hull of its six
// vertices. The hull of the part in front of the near plane is the hull of the vertices in
// front plus the near-plane crossings of every segment to a vertex behind. It is then grown by
// the pixel square (Minkowski sum), so a pixel is rasterized iff any point of it may be hit:
// sample positions are jittered over the whole pixel, not at its centre.
//
// The body of two geometry shaders: lighting.geom (a still camera) and
// lighting_camera_moves.geom (LIGHTING_CAMERA_MOVES: the corners at t = 1 are first carried
// into the t = 0 camera's frame, camera_motion.glsl), so a still camera's pipeline holds none
// of a moving camera's code.
#include "shared.glsl"
#ifdef LIGHTING_CAMERA_MOVES
#include "camera_motion.glsl"
#endif

layout(triangles) in;
layout(triangle_strip, max_vertices = 32) out;

layout(push_constant) uniform Push { LightingRasterPush pc; };

layout(location = 0) in vec3 in_p0[];
layout(location = 1) in vec3 in_p1[];
layout(location = 2) in float in_valid[];
// The triangle itself, for the fragment shader's per-sample ray tests: its corners at t = 0
// (xyz) and t = 1, and its global id (the bits of p0[0].w). Passed along rather than fetched
// again per fragment: a fetch (draw record, indices, positions) costs many loads per
// fragment, made lane by lane on a CPU device. 7 locations, 28 components per vertex: 32
// vertices stay within the 1024 output components every device has.
layout(location = 0) flat out vec4 out_p0[3];
layout(location = 3) flat out vec3 out_p1[3];

CameraParams camera;

// Corners in front of the near plane and crossings of it.
#define HULL_MAX_POINTS 12
#include "convex_hull.glsl"
const int MAX_CLIPPED = HULL_MAX_POINTS;
// Grown hull points: one per hull vertex plus the pixel-square corners where the outward
// normal crosses a quadrant boundary, 4 in all around a convex polygon: at most
// MAX_CLIPPED + 4 = 16. Floating-point wobble on near-collinear edges could add a few;
// past the room left, the hull's grown bounding box is drawn instead (conservative).
const int MAX_POINTS = 32;

vec2 to_pixels(vec4 clip) {
    return (clip.xy / clip.w * 0.5 + 0.5) * vec2(camera.image.xy);
}

// Quadrant of a direction, counter-clockwise from +x+y; the pixel-square corner with those
// signs supports every outward normal in it.
int quadrant(vec2 n) {
    return n.x >= 0.0 ? (n.y >= 0.0 ? 0 : 3) : (n.y >= 0.0 ? 1 : 2);
}

void main() {
    camera = load_camera(pc.target);
    if (in_valid[0] == 0.0 || in_valid[1] == 0.0 || in_valid[2] == 0.0) {
        // Counted once per frame: by the first chunk's geometry pass (flag set by the host).
        if ((pc.flags & COUNT_INVALID) != 0u) atomicAdd(UintArray(camera.counters).v[0], 1u);
        return;
    }
    DrawRecord d = load_draw(pc.draw.draws, pc.draw.draw_index);
    uint prim = uint(gl_PrimitiveIDIn);
#ifdef LIGHTING_CAMERA_MOVES
    // Each corner at t = 1 where the t = 0 camera must see it to see it as the t = 1 camera
    // does: everything below, and the fragment shader's ray tests, then run in the t = 0
    // camera's frame, where the corners' clip positions blend linearly between the two ends.
    CameraEnd end = CameraEndRef(camera.camera_end).end;
    vec3 moved_p1[3];
    for (int i = 0; i < 3; ++i) moved_p1[i] = camera_end_frame(end, in_p1[i]);
#define CORNER_T1 moved_p1
#else
#define CORNER_T1 in_p1
#endif
    vec4 c[6];
    vec3 w[6];
    // With one time for every sample (reference slices) the triangle is where it is at that
    // time: its hull is the triangle itself, half the points to sort.
    bool fixed_time = (pc.flags & FIXED_TIME) != 0u;
    int corners = fixed_time ? 3 : 6;
    for (int i = 0; i < 3; ++i) {
        w[i] = fixed_time ? mix(in_p0[i], CORNER_T1[i], pc.time) : in_p0[i];
        w[i + 3] = fixed_time ? w[i] : CORNER_T1[i];
    }
    for (int i = 0; i < 6; ++i) c[i] = camera.view_proj * vec4(w[i], 1.0);
    if (outside_one_plane(c)) return;

    bool closed = has_flag(d, DRAW_CLOSED);
    if (closed) {
        vec3 e = camera.position.xyz;
        if (faces_away_whole_frame(w[0] - e, w[1] - e, w[2] - e, w[3] - e, w[4] - e, w[5] - e,
                                   false))
            return;
    }

    // Points of the hull, in pixels. Clip w is the view depth for a perspective camera.
    float near = camera.position.w;
    vec2 pts[MAX_CLIPPED];
    int n = 0;
    for (int i = 0; i < corners; ++i) {
        if (c[i].w < near) continue;
        pts[n++] = to_pixels(c[i]);
        for (int j = 0; j < corners; ++j) {
            if (c[j].w >= near) continue;
            float s = (c[i].w - near) / (c[i].w - c[j].w);
            pts[n++] = to_pixels(mix(c[i], c[j], s));
        }
    }
    if (n == 0) return;

    // Convex hull of the points, counter-clockwise (convex_hull.glsl: equal and nearly equal
    // points merged, which the growth below makes up for).
    float merge = hull_merge_distance(pts, n);
    vec2 hull[2 * HULL_MAX_POINTS];
    int h = convex_hull(pts, n, merge, hull);

    // Grown by the pixel square (half a pixel, plus a margin for rounding), so that a pixel is
    // rasterized iff any point of it may be hit. Each edge moves out by the square's support
    // along its normal and a vertex becomes the meeting point of its two moved edges (few
    // vertices: the rasterizer's cost grows with the triangles of the strip); where the edges
    // meet at a sharp angle, that point lies far out, and the exact sum is used instead: the
    // square corners supporting the outward normals between the two edges.
    float r = 0.5 + 1.0 / 64.0 + 1.5 * merge;
    const float MITER_LIMIT = 2.0;  // pixels from the hull vertex
    vec2 corner[4] = vec2[4](vec2(r, r), vec2(-r, r), vec2(-r, -r), vec2(r, -r));
    vec2 poly[MAX_POINTS];
    int count = 0;
    bool overflow = false;
    for (int i = 0; i < h && !overflow; ++i) {
        if (count > MAX_POINTS - 4) {
            overflow = true;
            break;
        }
        vec2 v = hull[i];
        if (h == 1) {
            for (int q = 0; q < 4; ++q) poly[count++] = v + corner[q];
            break;
        }
        vec2 e_in = v - hull[(i + h - 1) % h], e_out = hull[(i + 1) % h] - v;
        vec2 n_in = normalize(vec2(e_in.y, -e_in.x)), n_out = normalize(vec2(e_out.y, -e_out.x));
        // The moved edges: n . x = n . v + support(n), for both normals; solve for x - v.
        float o_in = r * (abs(n_in.x) + abs(n_in.y)), o_out = r * (abs(n_out.x) + abs(n_out.y));
        float det = n_in.x * n_out.y - n_in.y * n_out.x;
        vec2 miter = vec2(o_in * n_out.y - o_out * n_in.y, n_in.x * o_out - n_out.x * o_in) / det;
        if (det > 1e-4 && dot(miter, miter) <= MITER_LIMIT * MITER_LIMIT) {
            poly[count++] = v + miter;
            continue;
        }
        int q = quadrant(n_in), q_out = quadrant(n_out);
        poly[count++] = v + corner[q];
        for (int steps = 0; q != q_out && steps < 3; ++steps) {
            q = (q + 1) & 3;
            poly[count++] = v + corner[q];
        }
    }

    if (overflow) {
        vec2 lo_corner = hull[0], hi_corner = hull[0];
        for (int i = 1; i < h; ++i) {
            lo_corner = min(lo_corner, hull[i]);
            hi_corner = max(hi_corner, hull[i]);
        }
        lo_corner -= vec2(r);
        hi_corner += vec2(r);
        poly[0] = lo_corner;
        poly[1] = vec2(hi_corner.x, lo_corner.y);
        poly[2] = hi_corner;
        poly[3] = vec2(lo_corner.x, hi_corner.y);
        count = 4;
    }

    // A convex polygon as one strip: start, start + 1, start - 1, start + 2, ... Started at
    // the point farthest along the polygon's longer extent, most of the strip's triangles are
    // rungs across a long streak (a moving triangle's hull) rather than slivers along it. A
    // rasterizer shades blocks of pixels per triangle, and a sliver touches blocks along the
    // whole streak (on lavapipe: about 9% less raster time on cubes-toward-light).
    vec2 lo_pt = poly[0], hi_pt = poly[0];
    for (int i = 1; i < count; ++i) {
        lo_pt = min(lo_pt, poly[i]);
        hi_pt = max(hi_pt, poly[i]);
    }
    int axis = hi_pt.x - lo_pt.x >= hi_pt.y - lo_pt.y ? 0 : 1;
    int start = 0;
    for (int i = 1; i < count; ++i) {
        if (poly[i][axis] < poly[start][axis]) start = i;
    }
    int lo = 1, hi = count - 1;
    vec2 size = vec2(camera.image.xy);
    for (int i = 0; i < count; ++i) {
        int idx;
        if (i == 0) idx = 0;
        else if ((i & 1) == 1) idx = lo++;
        else idx = hi--;
        idx = (idx + start) % count;
        gl_Position = vec4(poly[idx] / size * 2.0 - 1.0, 0.5, 1.0);
        for (int c = 0; c < 3; ++c) {
            out_p0[c] = vec4(in_p0[c], c == 0 ? uintBitsToFloat(d.first_id + prim) : 0.0);
            out_p1[c] = CORNER_T1[c];
        }
        EmitVertex();
    }
    EndPrimitive();
}
