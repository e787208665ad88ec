// motion_shadows/map_layout.glsl: the temporal shadow map as it lies in memory (its ranges,
// light and header, mirrored by `motion_shadows::technique::gpu_types`) and its loads into
// the MsMap value the lookups take.
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require

const uint MS_END_OF_LIST = 0u;         // list links are index + 1, so 0 ends a list
const uint MS_NO_TRIANGLE = 0xffffffffu;
// The most ranges one texel can hold (the generation pass pairs at most 1,024 fragments).
const uint MS_MAX_TEXEL_RANGES = 512u;
// The header's size.z when every texel's ranges lie next to each other in the range buffer in
// order of their start time t_s (ties in an order of their other members), each linked to the
// one after it: the lists read the same either way, and a lookup at time t may stop at the
// first range that starts after t. 0: the ranges are linked in no particular order.
const uint MS_SORTED_RANGES = 1u;

// Loop iterations the ms_ functions have run in this invocation (an upper bound), so that a
// caller on a device that leaves loops after a fixed count (lavapipe: 65,535 per invocation,
// see DeviceInfo::shader_loop_limit) can tell when a result may have been cut short.
uint ms_loop_iterations = 0u;

// A depth-time range (24 bytes): triangle `id` covers the texel from t_s to t_e (t_s <= t_e),
// at a linear light depth going linearly from d_s to d_e.
struct MsRange {
    float t_s;
    float t_e;
    float d_s;
    float d_e;
    uint id;
    uint next;      // index + 1 of the texel's next range, MS_END_OF_LIST at the end
};

// The light a shadow map was rendered for (std430, 192 bytes).
struct MsLight {
    mat4 view;          // world -> light view (right-handed, looking down -z)
    mat4 proj;          // light view -> clip (Vulkan: z in [0, w], y down)
    vec4 position;      // xyz; w = 1 for a spot light, 0 for a directional light
    vec4 direction;     // xyz unit; w = cos(cone half angle) (-1 for directional)
    vec4 emission;      // x = intensity (W/sr, spot) or irradiance (W/m^2, directional)
    vec4 bias;          // x = receiver offset along its normal, in shadow texels;
                        // y = relative depth bias (depth d is tested as d * (1 - y));
                        // z = world size of a texel per unit depth (spot) or absolute;
                        // w = 1: test the receiver's plane at the texel centre
};

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer MsUints {
    uint v[];
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer MsRanges {
    MsRange v[];
};
// The same ranges as three 64-bit words each (t_s | t_e, d_s | d_e, id | next; the first
// member in the low half, as on every little-endian device): see ms_range.
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer MsRangeWords {
    uint64_t v[];
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer MsVec2s {
    vec2 v[];
};
layout(buffer_reference, std430, buffer_reference_align = 8) readonly buffer MsUint64s {
    uint64_t v[];
};

// The header of a temporal shadow map (written by the collection pass each frame).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MsShadowMap {
    MsLight light;
    uvec4 size;             // x, y = texels; z = MS_SORTED_RANGES or 0 (see there); w = 0
    uint64_t range_heads;   // MsUints: per texel, index + 1 of its first range
    uint64_t ranges;        // MsRanges
    uint64_t coverage;      // 0, or with the 2017 paper's coverage map: MsUints, per texel
                            // the triangle covering it nearest to the light all frame
    uint64_t cover_depth;   // MsVec2s: that triangle's depth at t = 0 and t = 1
    // The rest is the library's own (the lists the ranges are made from).
    uint64_t heads;
    uint64_t nodes;
    uint64_t counters;
    uint64_t long_pixels;
    uint64_t nearest;
    uint64_t static_nearest;  // 0, or MsUint64s: per texel, the nearest triangle that does not
                              // move, as ms_static_key(depth) << 32 | id (all ones: none)
    uint64_t tiles;           // the generation pass's indirect dispatches (tiles across, down)
    uint64_t list_ranges;     // where the collection links its ranges (the sorting's input)
    uint64_t triangles;       // 0, or with the exact lookup: MsTriangles, per global triangle
                              // id its world corners at t = 0 and t = 1 (exact_lookup.glsl)
    uint64_t static_names;    // 0, or with the exact lookup and the static layer: MsStaticNames,
                              // per texel the static triangles whose shadow touches it
};


// The header's contents as one value. A shader that tests many points loads it once
// (ms_load) and passes it on: reading the header for every test costs a few hundred bytes of
// loads each time, which a CPU device does lane by lane. Every function below also takes the
// header itself, for a single test.
struct MsMap {
    MsLight light;
    uvec2 size;
    uint64_t range_heads;
    uint64_t ranges;
    uint64_t coverage;
    uint64_t cover_depth;
    uint64_t static_nearest;
    bool sorted;            // size.z == MS_SORTED_RANGES
    uint64_t triangles;     // 0, or the exact lookup's triangle records
    uint64_t static_names;  // 0, or the exact lookup's static name lists
};

// The same header as 64-bit words (ms_load reads it so: half the loads of its 32-bit
// members; a CPU device makes each load lane by lane).
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MsShadowMapWords {
    uint64_t light[24];     // MsLight: view, proj (8 words each), position, direction,
                            // emission, bias (2 each)
    uint64_t size;          // size.xy
    uint64_t size_zw;
    uint64_t range_heads;
    uint64_t ranges;
    uint64_t coverage;
    uint64_t cover_depth;
    uint64_t heads;
    uint64_t nodes;
    uint64_t counters;
    uint64_t long_pixels;
    uint64_t nearest;
    uint64_t static_nearest;
    uint64_t tiles;
    uint64_t list_ranges;
    uint64_t triangles;
    uint64_t static_names;
};

// The vec4 of two words (the first word's halves are x and y).
vec4 ms_vec4_of(uint64_t xy, uint64_t zw) {
    return vec4(uintBitsToFloat(unpackUint2x32(xy)), uintBitsToFloat(unpackUint2x32(zw)));
}

// The MsLight at `address` (the start of a map header), read as 64-bit words.
MsLight ms_load_light(uint64_t address) {
    MsShadowMapWords words = MsShadowMapWords(address);
    vec4 v[12];
    for (int i = 0; i < 12; ++i) v[i] = ms_vec4_of(words.light[2 * i], words.light[2 * i + 1]);
    return MsLight(mat4(v[0], v[1], v[2], v[3]), mat4(v[4], v[5], v[6], v[7]), v[8], v[9],
                   v[10], v[11]);
}

MsMap ms_load(MsShadowMap header) {
    MsShadowMapWords words = MsShadowMapWords(uint64_t(header));
    MsLight light = ms_load_light(uint64_t(header));
    return MsMap(light, unpackUint2x32(words.size), words.range_heads, words.ranges,
                 words.coverage, words.cover_depth, words.static_nearest,
                 unpackUint2x32(words.size_zw).x == MS_SORTED_RANGES, words.triangles,
                 words.static_names);
}
