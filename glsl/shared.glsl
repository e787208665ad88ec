// Shared by the library's own shaders: the public structs (motion_shadows.glsl), the
// internal ones (fragments, counters, draws, cameras, push constants), vertex fetching,
// sampling and geometry helpers. The structs mirror src/technique/gpu_types.rs;
// tests/gpu/layout.rs checks that both agree.
//
// Nothing is bound through descriptor sets: every buffer is reached by its device address,
// found in the push constants or in a header buffer the push constants point at. That keeps
// the passes immutable after creation (no descriptor to rewrite per frame), so one set of
// pass objects serves any number of frames in flight and lights.

#include "motion_shadows.glsl"

const uint END_OF_LIST = MS_END_OF_LIST;
const uint NO_TRIANGLE = MS_NO_TRIANGLE;

// One fragment of a prism, as stored by the collection sub-pass (16 bytes).
struct Node {
    float depth;   // linear distance along the light's view axis
    float time;    // shutter time in [0, 1]
    uint id;       // global triangle id
    uint next;     // index + 1 of the next node of this pixel, END_OF_LIST at the end
};

// Capacities are written by the host when recording; counts by the shaders. A count past its
// capacity means the pass overflowed and nothing past the capacity was linked in.
// `overlong_pixels` counts shadow-map pixels whose list exceeded MAX_LIST_NODES (their ranges
// are not generated: the frame is an error), `longest_list` is the longest list seen.
// `invalid_triangles` counts triangles whose indices point past their draw's vertex count
// (they are not drawn; the frame is an error).
struct Counters {
    uint node_count;
    uint node_capacity;
    uint range_count;
    uint range_capacity;
    uint overlong_pixels;
    uint longest_list;
    uint ranges_without_coverage;   // what range_count would be without the coverage map
    uint invalid_triangles;
    uint wrapped;                   // 1 if node_count passed 2^32 - 1 (the frame is an error)
    uint ranges_direct;             // 1: the collection stored ranges, no nodes (host-written)
    uint reserved1, reserved2;
};

// The most fragments one shadow-map pixel may hold. The generation pass sorts a pixel's list
// in private memory; this bound also keeps every shader loop far below lavapipe's limit of
// 65535 loop iterations per invocation, past which it silently leaves loops.
const uint MAX_LIST_NODES = 512u;

layout(buffer_reference, std430, buffer_reference_align = 8) buffer Words { uint64_t v[]; };

// Nodes (2 words: depth | time, id | next) and ranges (3 words, see ms_range) are read and
// written as 64-bit words, the first member in the low half: a CPU device makes every load
// and store lane by lane, so a word costs what one 32-bit member would.
Node load_node(uint64_t nodes, uint index) {
    Words words = Words(nodes);
    uvec2 depth_time = unpackUint2x32(words.v[2u * index]);
    uvec2 id_next = unpackUint2x32(words.v[2u * index + 1u]);
    return Node(uintBitsToFloat(depth_time.x), uintBitsToFloat(depth_time.y), id_next.x,
                id_next.y);
}

void store_node(uint64_t nodes, uint index, Node node) {
    Words words = Words(nodes);
    words.v[2u * index] = packUint2x32(floatBitsToUint(vec2(node.depth, node.time)));
    words.v[2u * index + 1u] = packUint2x32(uvec2(node.id, node.next));
}

void store_range(uint64_t ranges, uint index, MsRange range) {
    Words words = Words(ranges);
    words.v[3u * index] = packUint2x32(floatBitsToUint(vec2(range.t_s, range.t_e)));
    words.v[3u * index + 1u] = packUint2x32(floatBitsToUint(vec2(range.d_s, range.d_e)));
    words.v[3u * index + 2u] = packUint2x32(uvec2(range.id, range.next));
}
layout(buffer_reference, std430, buffer_reference_align = 4) buffer UintArray { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer FloatArray { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Uint64Array { uint64_t v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer Vec2Array { vec2 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vec4Array { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer CounterRef { Counters c; };

// The generation pass runs one 8x8-texel workgroup per tile of the map, through an indirect
// dispatch the collection sets (the map header's `tiles`, 3 group counts and a pad): every
// tile where the lists hold fragments, none where the collection stored the ranges itself.
const uint TILE_TEXELS = 8u;

// ---- host geometry ----

const uint INDEX_NONE = 0u;
const uint INDEX_U16 = 1u;
const uint INDEX_U32 = 2u;

const uint DRAW_CLOSED = 1u;   // the mesh is closed: faces away all frame -> may be culled
const uint DRAW_UNTRANSFORMED = 2u;  // both transforms are the identity: positions are world
const uint DRAW_STATIC = 4u;  // same positions and transform at t = 0 and 1: nothing moves

// One draw of the host's geometry (std430, 160 bytes): positions at shutter open and close
// (3 floats each, at any stride; the addresses include the offset), optional indices, object
// transforms at t = 0 and t = 1 (rows of a 3x4 affine matrix), its triangles' global ids
// first_id .. first_id + triangle_count - 1.
struct DrawRecord {
    uint64_t positions0;
    uint64_t positions1;
    uint64_t indices;
    uint stride0;
    uint stride1;
    uint index_kind;        // INDEX_*
    uint vertex_count;      // valid vertices in each position stream
    uint first_id;
    uint triangle_count;
    vec4 albedo_flags;      // rgb albedo (the library's own lighting pass), w = DRAW_* flags
    vec4 model0[3];
    vec4 model1[3];
};

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer DrawTable {
    DrawRecord draws[];
};
// The same table as 64-bit words, 20 per record (load_draw).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer DrawWords {
    uint64_t v[];
};
const uint DRAW_RECORD_WORDS = 20u;

// Draw `index` of the table at `table`, read as 64-bit words: a CPU device makes every load
// lane by lane, and a record's 40 scalars are 20 words.
DrawRecord load_draw(uint64_t table, uint index) {
    DrawWords words = DrawWords(table);
    uint w = DRAW_RECORD_WORDS * index;
    DrawRecord d;
    d.positions0 = words.v[w];
    d.positions1 = words.v[w + 1u];
    d.indices = words.v[w + 2u];
    uvec2 strides = unpackUint2x32(words.v[w + 3u]);
    uvec2 kind_count = unpackUint2x32(words.v[w + 4u]);
    uvec2 ids = unpackUint2x32(words.v[w + 5u]);
    d.stride0 = strides.x;
    d.stride1 = strides.y;
    d.index_kind = kind_count.x;
    d.vertex_count = kind_count.y;
    d.first_id = ids.x;
    d.triangle_count = ids.y;
    d.albedo_flags = ms_vec4_of(words.v[w + 6u], words.v[w + 7u]);
    for (uint k = 0u; k < 3u; ++k) {
        d.model0[k] = ms_vec4_of(words.v[w + 8u + 2u * k], words.v[w + 9u + 2u * k]);
        d.model1[k] = ms_vec4_of(words.v[w + 14u + 2u * k], words.v[w + 15u + 2u * k]);
    }
    return d;
}

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Float3Ref {
    float v[3];
};

bool has_flag(DrawRecord d, uint flag) {
    return (uint(d.albedo_flags.w) & flag) != 0u;
}

// Index `i` of the draw's index stream (or i itself without one); 16-bit indices are read as
// the half of an aligned 32-bit word, so no 16-bit storage feature is needed.
uint draw_index(DrawRecord d, uint i) {
    if (d.index_kind == INDEX_NONE) return i;
    // One load for either width (a CPU device makes every load it meets, taken or not).
    bool wide = d.index_kind == INDEX_U32;
    uint64_t address = d.indices + (wide ? 4UL : 2UL) * uint64_t(i);
    uint word = MsUints(address & ~3UL).v[0];
    return wide ? word : ((address & 2UL) != 0UL ? word >> 16 : word & 0xffffu);
}

vec3 transform(vec4 rows[3], vec3 p) {
    vec4 h = vec4(p, 1.0);
    return vec3(dot(rows[0], h), dot(rows[1], h), dot(rows[2], h));
}

// Whether every index of the draw's triangle `prim` is below the draw's vertex count. A
// triangle that fails is not drawn by any pass (and the collection and lighting passes count
// it), so a bad index buffer can never make a shader read outside the position streams.
bool triangle_valid(DrawRecord d, uint prim) {
    for (uint i = 0u; i < 3u; ++i) {
        if (draw_index(d, 3u * prim + i) >= d.vertex_count) return false;
    }
    return true;
}

// World positions of corner `corner` of the draw's (valid) triangle `prim` at t = 0 and 1.
void fetch_corner(DrawRecord d, uint prim, uint corner, out vec3 p0, out vec3 p1) {
    uint v = min(draw_index(d, 3u * prim + corner), d.vertex_count - 1u);
    Float3Ref a = Float3Ref(d.positions0 + uint64_t(d.stride0) * uint64_t(v));
    Float3Ref b = Float3Ref(d.positions1 + uint64_t(d.stride1) * uint64_t(v));
    p0 = vec3(a.v[0], a.v[1], a.v[2]);
    p1 = vec3(b.v[0], b.v[1], b.v[2]);
    // Most draws have no transform (world-space positions): skip its loads and arithmetic
    // (every fragment of the lighting pass fetches its triangle).
    if (!has_flag(d, DRAW_UNTRANSFORMED)) {
        p0 = transform(d.model0, p0);
        p1 = transform(d.model1, p1);
    }
}

// A triangle's three corners at t = 0 and t = 1.
struct Triangle {
    vec3 p0[3];
    vec3 p1[3];
};

Triangle fetch_triangle(DrawRecord d, uint prim) {
    Triangle tri;
    for (uint i = 0u; i < 3u; ++i) fetch_corner(d, prim, i, tri.p0[i], tri.p1[i]);
    return tri;
}

// The draw a global triangle id belongs to: draws are sorted by first id, ranges disjoint.
uint find_draw(DrawTable table, uint draw_count, uint id) {
    uint lo = 0u, hi = draw_count;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (table.draws[mid].first_id <= id) lo = mid; else hi = mid;
    }
    return lo;
}

// ---- the camera of the lighting pass ----

// The most samples of a pixel one lighting chunk renders (lighting.rs,
// MAX_SAMPLES_PER_CHUNK): the shading keeps a chunk's hits in private arrays of this size.
const uint MAX_SAMPLES_PER_CHUNK = 16u;

struct CameraParams {
    mat4 view_proj;         // world -> camera clip
    vec4 position;          // xyz; w = near plane distance
    vec4 forward;           // xyz unit; w = far plane distance
    vec4 ray00;             // ray direction through the image's top-left corner, unit along
    vec4 ray_dx;            // the view axis; its change per pixel right
    vec4 ray_dy;            // and down
    uvec4 image;            // xy = image size, z = samples per pixel, w = seed
    vec4 shading;           // x = ambient radiance factor; y, z, w = 0 (the estimator, the
                            // filter and the loop budget are the shading pipeline's
                            // specialization constants)
    uint64_t visibility;    // Uint64Array: per pixel and sample of a chunk, depth bits | id
    uint64_t radiance;      // Vec4Array: per pixel, accumulated radiance and moving share
    uint64_t counters;      // UintArray: [0] = triangles dropped for an invalid index,
                            // [1] = pixels whose lookups ran past the loop budget
    uint64_t reserved;
};

// The camera header at `address`, read as 64-bit words (26; see load_draw).
CameraParams load_camera(uint64_t address) {
    Words words = Words(address);
    vec4 v[9];
    for (uint i = 0u; i < 9u; ++i) v[i] = ms_vec4_of(words.v[2u * i], words.v[2u * i + 1u]);
    return CameraParams(mat4(v[0], v[1], v[2], v[3]), v[4], v[5], v[6], v[7], v[8],
                        uvec4(unpackUint2x32(words.v[18]), unpackUint2x32(words.v[19])),
                        ms_vec4_of(words.v[20], words.v[21]), words.v[22], words.v[23],
                        words.v[24], words.v[25]);
}

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer TargetHeader {
    CameraParams camera;
};

// ---- ordinary shadow maps ----

// Drawn with a depth attachment (LESS) and copied out for the lookups, layer after layer.
const uint DEPTH_AND_ID = 0u;       // depth + triangle id (R32_UINT colour attachment)
const uint DEPTH_ONLY = 1u;         // depth alone (as the papers' TSM stores it)

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer PlainHeader {
    MsLight light;
    uvec4 size;             // x, y = texels; z = layers; w = DEPTH_*
    uint64_t depths;        // floats: the attachment's z/w in [0, 1]; 1 = nothing drawn
    uint64_t ids;           // DEPTH_AND_ID: uints, NO_TRIANGLE = nothing drawn
};

// ---- push constants ----

// What every pass pushes (56 bytes).
struct PassConstants {
    uint64_t map;           // MsShadowMap or PlainHeader of the map built or read
    uint64_t draws;         // DrawTable
    uint64_t target;        // TargetHeader (lighting pass); TileList (collection)
    uint draw_index;        // the draw being drawn
    uint draw_count;        // draws in the table
    uint first_sample;      // first sample index of this chunk (shadow maps: the layer)
    uint sample_count;      // samples in this chunk
    uint mode;              // lighting: SHADOW_*; shadow maps: DEPTH_*
    float time;             // shadow maps: the scene's time; lighting: see FIXED_TIME
    uint flags;
    uint reserved;
};

// Lighting pass shadow tests.
const uint SHADOW_TEMPORAL = 0u;    // depth-time ranges (and the coverage map, if the map has one)
const uint SHADOW_PLAIN = 1u;       // one ordinary map (depth and id) for every sample
const uint SHADOW_NONE = 2u;
const uint SHADOW_TSM = 3u;         // time-dependent shadow maps: sample in stratum s uses map s

// Lighting pass flag: every sample at time pc.time (brute-force reference slices).
const uint FIXED_TIME = 1u;
// Prism pipelines: count triangles dropped for an invalid index (once per frame: collection).
const uint COUNT_INVALID = 4u;

// Which surface of a prism a fragment lies on (nearest map, coverage passes).
const uint SURFACE_CAP0 = 0u;       // the triangle at t = 0
const uint SURFACE_CAP1 = 1u;       // the triangle at t = 1
const uint SURFACE_SIDE = 2u;       // a side surface: an edge sweeping over the pixel

// The nearest map packs (depth bits << 32 | surface << 30 | triangle id): ids below 2^30.
const uint NEAREST_ID_MASK = 0x3fffffffu;
const uint64_t NEAREST_EMPTY = 0xffffffffffffffffUL;

uint64_t pack_nearest(float depth, uint surface, uint id) {
    return (uint64_t(floatBitsToUint(max(depth, 0.0))) << 32) | uint64_t((surface << 30) | id);
}

// ---- sampling: stratified times, deterministic for (pixel, sample, seed) ----

uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Computed once per pixel; every sample of the pixel derives from it.
uint pixel_key(uvec2 pixel, uint seed) {
    return pcg_hash(pixel.x + pcg_hash(pixel.y + pcg_hash(seed)));
}

// Sample k of spp lies in time stratum (k + r) mod spp, r = key mod spp a per-pixel
// rotation, so that strata are decorrelated from sample positions across pixels. The rotation
// is computed once per pixel: a CPU device divides integers lane by lane, and two divisions
// per sample were a large share of the lighting pass on lavapipe.
uint stratum_rotation(uint key, uint spp) {
    // A power of two (the usual spp) takes a mask: the same value, no division per lane.
    return (spp & (spp - 1u)) == 0u ? key & (spp - 1u) : key % spp;
}

uint time_stratum(uint rotation, uint k, uint spp) {
    uint s = k + rotation;  // k < spp and rotation < spp: one subtraction is the modulo
    return s >= spp ? s - spp : s;
}

// The time in [0, 1) and the position in the pixel ([0, 1)^2) of sample k.
void pixel_sample(uint key, uint rotation, uint k, uint spp, out float t, out vec2 offset) {
    uint h = pcg_hash(key ^ pcg_hash(k));
    t = (float(time_stratum(rotation, k, spp)) + float(h >> 8) * (1.0 / 16777216.0))
        / float(spp);
    uint g = pcg_hash(h);
    offset = (vec2(float(g & 0xffffu), float(g >> 16)) + 0.5) * (1.0 / 65536.0);
}

// ---- geometry ----

// The orientation of a moving triangle, as a cubic in t, is checked through its Bernstein
// coefficients: if all are negative, the triangle faces away during the whole frame.
// `f` holds the orientation at t = 0, 1/3, 2/3, 1.
bool negative_whole_frame(vec4 f) {
    float b1 = (-5.0 * f.x + 18.0 * f.y - 9.0 * f.z + 2.0 * f.w) / 6.0;
    float b2 = (2.0 * f.x - 9.0 * f.y + 18.0 * f.z - 5.0 * f.w) / 6.0;
    return f.x < 0.0 && b1 < 0.0 && b2 < 0.0 && f.w < 0.0;
}

// How much a triangle (view-space vertices) faces the eye: positive when front-facing with
// counter-clockwise outward winding. Perspective: eye at the origin; orthographic: along +z.
float facing(vec3 a, vec3 b, vec3 c, bool orthographic) {
    vec3 n = cross(b - a, c - a);
    return orthographic ? n.z : -dot(n, a);
}

bool faces_away_whole_frame(vec3 a0, vec3 b0, vec3 c0, vec3 a1, vec3 b1, vec3 c1,
                            bool orthographic) {
    vec4 f;
    for (int i = 0; i < 4; ++i) {
        float t = float(i) / 3.0;
        f[i] = facing(mix(a0, a1, t), mix(b0, b1, t), mix(c0, c1, t), orthographic);
    }
    return negative_whole_frame(f);
}

// True when all points lie outside one clip plane (so the convex hull of them is invisible).
bool outside_one_plane(vec4 c[6]) {
    bool all_l = true, all_r = true, all_b = true, all_t = true, all_n = true, all_f = true;
    for (int i = 0; i < 6; ++i) {
        all_l = all_l && c[i].x < -c[i].w;
        all_r = all_r && c[i].x > c[i].w;
        all_b = all_b && c[i].y < -c[i].w;
        all_t = all_t && c[i].y > c[i].w;
        all_n = all_n && c[i].z < 0.0;
        all_f = all_f && c[i].z > c[i].w;
    }
    return all_l || all_r || all_b || all_t || all_n || all_f;
}

// (v[kx], v[ky], v[kz]) for the permutation of intersect_triangle: kz the axis of the ray's
// largest component, kx and ky swapped when the ray points down it (keeps the winding).
vec3 permute_axes(vec3 v, int kz, bool swap_xy) {
    vec3 p = kz == 0 ? v.yzx : (kz == 1 ? v.zxy : v.xyz);
    return swap_xy ? p.yxz : p;
}

// Watertight ray-triangle intersection (Woop, Benthin and Wald 2013, "Watertight
// Ray/Triangle Intersection"), both faces. Returns the ray parameter, or -1. The ray is
// sheared to run along +z from the origin, and each edge function is a 2D cross product of
// two sheared corners: triangles sharing an edge compute its function from the same products
// with the subtraction reversed (`precise`: no fused multiply-add on one side only), so a ray
// through the edge, or a shared corner, hits at least one of them. (Moller-Trumbore rounds
// each triangle's barycentrics on its own and lets rare samples through such cracks.)
float intersect_triangle(vec3 origin, vec3 dir, vec3 a, vec3 b, vec3 c) {
    vec3 m = abs(dir);
    int kz = m.x >= m.y && m.x >= m.z ? 0 : (m.y >= m.z ? 1 : 2);
    vec3 d = permute_axes(dir, kz, false);
    bool swap_xy = d.z < 0.0;
    d = swap_xy ? d.yxz : d;
    float sz = 1.0 / d.z;
    vec2 s = d.xy * sz;
    vec3 pa = permute_axes(a - origin, kz, swap_xy);
    vec3 pb = permute_axes(b - origin, kz, swap_xy);
    vec3 pc = permute_axes(c - origin, kz, swap_xy);
    precise vec2 sa = pa.xy - s * pa.z;
    precise vec2 sb = pb.xy - s * pb.z;
    precise vec2 sc = pc.xy - s * pc.z;
    precise float u = sc.x * sb.y - sc.y * sb.x;
    precise float v = sa.x * sc.y - sa.y * sc.x;
    precise float w = sb.x * sa.y - sb.y * sa.x;
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0)) return -1.0;
    float det = u + v + w;
    if (det == 0.0) return -1.0;
    float hit = (u * pa.z + v * pb.z + w * pc.z) * sz / det;
    return hit > 0.0 ? hit : -1.0;
}

// The camera ray through a point of the image, in pixels from the top-left corner. `dir` is
// scaled so that its component along the view axis is 1: the ray parameter of a hit is its
// view depth, comparable across triangles and directly testable against near and far.
vec3 camera_ray(CameraParams camera, vec2 pixel_pos) {
    return camera.ray00.xyz + pixel_pos.x * camera.ray_dx.xyz + pixel_pos.y * camera.ray_dy.xyz;
}

// ---- the ordinary maps' vertices ----

// Corner vertex % 3 of triangle vertex / 3 of the draw, at time pc.time, seen
// from `light`: its clip position, its light-view depth and its triangle's global id. An
// invalid triangle (an index out of range) lands every corner on one point outside the view,
// so nothing is rasterized (the lighting pass counts such triangles).
void ordinary_map_vertex(PassConstants pc, MsLight light, uint vertex, out vec4 position,
                         out float depth, out uint id) {
    DrawRecord d = load_draw(pc.draws, pc.draw_index);
    uint prim = vertex / 3u;
    id = d.first_id + prim;
    if (!triangle_valid(d, prim)) {
        position = vec4(2.0, 2.0, 2.0, 1.0);
        depth = 0.0;
        return;
    }
    vec3 p0, p1;
    fetch_corner(d, prim, vertex % 3u, p0, p1);
    vec3 view = (light.view * vec4(mix(p0, p1, pc.time), 1.0)).xyz;
    position = light.proj * vec4(view, 1.0);
    depth = -view.z;
}
