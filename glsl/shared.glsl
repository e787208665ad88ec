// Shared by every shader: the structs that mirror src/technique/gpu_types.rs, the frame
// parameters, sampling, and geometry helpers. Changing a struct here means changing it there;
// tests/gpu_layout.rs checks that both agree.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require

const uint END_OF_LIST = 0u;        // list links are index + 1, so 0 ends a list
const uint NO_TRIANGLE = 0xffffffffu;

// One fragment of a prism, as stored by the collection sub-pass (16 bytes).
struct Node {
    float depth;   // linear distance along the light's view axis
    float time;    // shutter time in [0, 1]
    uint id;       // global triangle id
    uint next;     // index + 1 of the next node of this pixel, END_OF_LIST at the end
};

// A depth-time range, as stored by the generation sub-pass (24 bytes). t_s <= t_e.
struct Range {
    float t_s;
    float t_e;
    float d_s;     // depth at t_s
    float d_e;     // depth at t_e
    uint id;
    uint next;
};

struct SceneVertex {
    vec4 p0;       // world position at t = 0 (w = 1)
    vec4 p1;       // world position at t = 1 (w = 1)
};

struct TriangleInfo {
    vec4 albedo_flags;   // rgb albedo, w = TRIANGLE_* flags (as a float)
};

const uint TRIANGLE_CLOSED = 1u;   // its mesh is closed: faces away all frame -> may be culled
const uint TRIANGLE_MOVING = 2u;   // some vertex moves during the frame

bool has_flag(TriangleInfo info, uint flag) {
    return (uint(info.albedo_flags.w) & flag) != 0u;
}

// Capacities are written by the host when recording; counts by the shaders. A count past its
// capacity means the pass overflowed and nothing past the capacity was linked in.
// `overlong_pixels` counts shadow-map pixels whose list exceeded MAX_LIST_NODES (their ranges
// are not generated: the frame is an error), `longest_list` is the longest list seen.
struct Counters {
    uint node_count;
    uint node_capacity;
    uint range_count;
    uint range_capacity;
    uint overlong_pixels;
    uint longest_list;
    uint ranges_without_coverage;   // what range_count would be without the coverage map
    uint reserved;
};

// The most fragments one shadow-map pixel may hold. The generation pass sorts a pixel's list
// in private memory; this bound also keeps every shader loop far below lavapipe's limit of
// 65535 loop iterations per invocation, past which it silently leaves loops.
const uint MAX_LIST_NODES = 512u;

struct FrameParams {
    mat4 light_view;            // world -> light view (right-handed, looking down -z)
    mat4 light_proj;            // light view -> clip (Vulkan: z in [0, w], y down)
    mat4 camera_view_proj;      // world -> camera clip
    mat4 camera_inv_view_proj;
    vec4 camera_position;       // xyz; w = near plane distance
    vec4 camera_forward;        // xyz unit; w = far plane distance
    vec4 light_position;        // xyz; w = 1 for a spot light, 0 for a directional light
    vec4 light_direction;       // xyz unit; w = cos(cone half angle)
    vec4 light_params;          // x = intensity (W/sr) or irradiance (W/m^2), y = ambient,
                                // z = normal offset in shadow texels, w = relative depth bias
    vec4 light_texel;           // x = world size of a shadow texel per unit depth (spot) or
                                // absolute (directional)
    vec4 camera_ray00;          // ray direction through the image's top-left corner
    vec4 camera_ray_dx;         // change of the ray direction per pixel to the right
    vec4 camera_ray_dy;         // change of the ray direction per pixel down
    uvec4 sizes;                // xy = shadow map size, zw = image size
    uvec4 sampling;             // x = samples per pixel, y = seed
};

// What every pass pushes (48 bytes).
struct PassConstants {
    uint first_triangle;        // global id of the draw's first triangle
    uint first_sample;          // first sample index of this chunk (shadow maps: the layer)
    uint sample_count;          // samples in this chunk
    uint mode;                  // lighting: SHADOW_*; shadow maps: DEPTH_*
    float time;                 // shadow maps: the scene's time; lighting: see FIXED_TIME
    uint flags;
    uint reserved0;
    uint reserved1;
    uint64_t node_address;      // the fragment (node) buffer, reached by address: it may be
    uint64_t range_address;     // larger than one storage-buffer descriptor can cover
};

layout(buffer_reference, std430, buffer_reference_align = 16) buffer NodeArray { Node nodes[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer RangeArray { Range ranges[]; };

// Lighting pass shadow tests.
const uint SHADOW_TEMPORAL = 0u;    // depth-time ranges
const uint SHADOW_PLAIN = 1u;       // one ordinary map (depth and id) for every sample
const uint SHADOW_NONE = 2u;
const uint SHADOW_TSM = 3u;         // time-dependent shadow maps: sample in stratum s uses map s

// Lighting pass flag: every sample at time pc.time (brute-force reference slices).
const uint FIXED_TIME = 1u;
// Collection and generation flag: build / use the coverage map (2017 paper's extension).
const uint USE_COVERAGE = 2u;

const uint SHADOW_COVERAGE = 4u;    // coverage map, then depth-time ranges

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

// Ordinary shadow map contents.
const uint DEPTH_AND_ID = 0u;       // 64 bits: depth bits << 32 | triangle id
const uint DEPTH_ONLY = 1u;         // 32 bits: depth bits (as the papers' TSM stores)

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
    return key % spp;
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

// Ray-triangle intersection (Moller-Trumbore), both faces. Returns the ray parameter, or -1.
float intersect_triangle(vec3 origin, vec3 dir, vec3 a, vec3 b, vec3 c) {
    vec3 e1 = b - a;
    vec3 e2 = c - a;
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-12) return -1.0;
    float inv = 1.0 / det;
    vec3 s = origin - a;
    float u = dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return -1.0;
    vec3 q = cross(s, e1);
    float v = dot(dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    float d = dot(e2, q) * inv;
    return d > 0.0 ? d : -1.0;
}

// The camera ray through a point of the image, in pixels from the top-left corner. `dir` is
// scaled so that its component along the view axis is 1: the ray parameter of a hit is its
// view depth, comparable across triangles and directly testable against near and far.
vec3 camera_ray(FrameParams frame, vec2 pixel_pos) {
    return frame.camera_ray00.xyz + pixel_pos.x * frame.camera_ray_dx.xyz
           + pixel_pos.y * frame.camera_ray_dy.xyz;
}
