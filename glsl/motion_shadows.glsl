// motion_shadows.glsl: the temporal shadow map as a host's own shaders see it.
//
// Include this file in any GLSL shader (it is also `motion_shadows::technique::GLSL_INCLUDE`
// in Rust) and pass the map's header address (`TemporalShadowMap::header_address()`, 8 bytes)
// in your push constants or uniform buffer. Then
//
//     MsMap map = ms_load(MsShadowMap(header_address));  // once per invocation
//     float lit = ms_visibility(map, world_position, world_normal, t, MS_NO_TRIANGLE);
//
// gives 1 where the point sees the light at shutter time t in [0, 1] and 0 where a triangle
// of the map's casters blocks it then. Pass the receiver's own triangle id instead of
// MS_NO_TRIANGLE when you know it (the library's own lighting pass does): its ranges are
// then skipped, which is the papers' fix for self-shadowing. Needs the device features
// bufferDeviceAddress and shaderInt64 (both required by the library anyway).
//
// Everything here is read-only, and every name starts with ms_ / Ms / MS_ so that it cannot
// clash with the host's own. The layouts mirror `motion_shadows::technique::gpu_types`
// (a test checks that they agree).

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

// Where a world point falls in the light's image, in texels from the map's corner
// (continuous: texel (i, j) spans [i, i + 1) x [j, j + 1)), and its linear light depth;
// false outside the light's view.
bool ms_light_texel_coords(MsLight light, uvec2 size, vec3 p, out vec2 coords,
                           out float depth) {
    vec4 view = light.view * vec4(p, 1.0);
    vec4 clip = light.proj * view;
    depth = -view.z;
    coords = vec2(0.0);
    if (clip.w <= 0.0) return false;
    vec2 ndc = clip.xy / clip.w;
    if (any(lessThan(ndc, vec2(-1.0))) || any(greaterThanEqual(ndc, vec2(1.0)))) return false;
    coords = (ndc * 0.5 + 0.5) * vec2(size);
    return true;
}

// The texel (x, y) of the map and the linear light depth of a world point; false outside
// the light's view.
bool ms_project_texel(MsLight light, uvec2 size, vec3 p, out uvec2 texel, out float depth) {
    vec2 coords;
    texel = uvec2(0u);
    if (!ms_light_texel_coords(light, size, p, coords, depth)) return false;
    texel = min(uvec2(coords), size - 1u);
    return true;
}

// The texel of the map and the linear light depth of a world point; false outside the
// light's view (then nothing in the map can shadow the point).
bool ms_project(MsLight light, uvec2 size, vec3 p, out uint texel_index, out float depth) {
    uvec2 texel;
    bool seen = ms_project_texel(light, size, p, texel, depth);
    texel_index = texel.y * size.x + texel.x;
    return seen;
}

// The receiver point actually tested: moved by the light's normal offset (a fraction of a
// shadow texel) along the normal n (unit, on the side the light is tested from), so that
// neighbouring triangles of the same surface do not shadow it where the map is coarser
// than the image.
vec3 ms_offset_receiver(MsLight light, vec3 p, vec3 n) {
    bool spot = light.position.w > 0.5;
    float light_depth = -(light.view * vec4(p, 1.0)).z;
    float texel = light.bias.z * (spot ? light_depth : 1.0);
    return p + n * (light.bias.x * texel);
}

// The depth of the receiver's tangent plane (through p, unit normal n) where the ray of the
// centre of `texel` meets it, or `depth` (p's own) where that ray runs along the plane.
// Why: every caster in the texel is stored as it is at the texel's centre, and a receiver
// compared at its own depth differs from its own plane there by up to half a texel times
// its slope, which at grazing light is many texels of depth: acne, or, with a normal offset
// large enough to hide it, lost contact shadows. At the centre the plane's depth is what a
// planar receiver's neighbours store, so they no longer shadow it while anything in front
// of the plane still does. Assumes a projection without shear (the library's own lights).
float ms_receiver_plane_depth(MsLight light, uvec2 size, uvec2 texel, vec3 p, vec3 n,
                              float depth) {
    vec2 c = (vec2(texel) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 pv = (light.view * vec4(p, 1.0)).xyz;
    vec3 nv = mat3(light.view) * n;
    vec3 o = vec3(0.0), d = vec3(0.0, 0.0, -1.0);
    if (light.position.w > 0.5) {
        d.xy = (c + vec2(light.proj[2][0], light.proj[2][1])) /
               vec2(light.proj[0][0], light.proj[1][1]);
    } else {
        o.xy = (c - vec2(light.proj[3][0], light.proj[3][1])) /
               vec2(light.proj[0][0], light.proj[1][1]);
    }
    float nd = dot(nv, d);
    if (abs(nd) <= 1e-6 * length(d)) return depth;
    return -(o + d * (dot(nv, pv - o) / nd)).z;
}

// The light depth an offset receiver point q (unit normal n) in `texel`, at linear light
// depth `depth`, is tested with: if the light asks for it, its plane's depth at the texel's
// centre; then the relative depth bias.
float ms_tested_depth(MsLight light, uvec2 size, uvec2 texel, vec3 q, vec3 n, float depth) {
    if (light.bias.w > 0.5) depth = ms_receiver_plane_depth(light, size, texel, q, n, depth);
    return depth * (1.0 - light.bias.y);
}

// The texel and the light depth a receiver at p (unit normal n) is tested with: p moved
// by the normal offset, then, if the light asks for it, its plane's depth at the texel.
bool ms_receiver_texel(MsLight light, uvec2 size, vec3 p, vec3 n, out uint texel_index,
                       out float depth) {
    vec3 q = ms_offset_receiver(light, p, n);
    uvec2 texel;
    bool seen = ms_project_texel(light, size, q, texel, depth);
    texel_index = texel.y * size.x + texel.x;
    if (!seen) return false;
    depth = ms_tested_depth(light, size, texel, q, n, depth);
    return true;
}

// ---- filtered lookups: the 2x2 texels around a receiver's projection ----
//
// One texel's answer is a step in space: a receiver is shadowed or lit as its texel's centre
// is. The filtered lookups weigh the four texels nearest to the receiver's projection by
// their overlap with a one-texel box centred on it (bilinear weights, as percentage-closer
// filtering does), so shadow edges ramp over one texel instead of stair-stepping. Each texel
// tests the receiver at its own depth there: with the receiver-plane test, its tangent
// plane's depth at that texel's centre (so the receiver's own surface does not shadow it in
// the neighbouring texels either); otherwise its own depth.

// Where a receiver at p (unit normal n) falls among the texels: `base` is the lower-left
// texel of its 2x2 footprint (may be -1 or `size` at the map's borders), `f` the bilinear
// weights' fractions, `q` the offset point and `depth` its light depth. False outside the
// light's view.
bool ms_receiver_footprint(MsLight light, uvec2 size, vec3 p, vec3 n, out vec3 q,
                           out float depth, out ivec2 base, out vec2 f) {
    q = ms_offset_receiver(light, p, n);
    vec2 coords;
    base = ivec2(0);
    f = vec2(0.0);
    if (!ms_light_texel_coords(light, size, q, coords, depth)) return false;
    vec2 u = coords - 0.5;    // in texel centres
    vec2 lower = floor(u);
    base = ivec2(lower);
    f = u - lower;
    return true;
}

// Texel k (0..3: x + 2 y) of a footprint: its index, the depth the receiver is tested at in
// it and its weight; false for a texel outside the map (nothing there shadows: weight lit).
bool ms_footprint_texel(MsLight light, uvec2 size, ivec2 base, vec2 f, int k, vec3 q,
                        vec3 n, float depth, out uint texel_index, out float texel_depth,
                        out float weight) {
    ivec2 offset = ivec2(k & 1, k >> 1);
    ivec2 c = base + offset;
    vec2 w = mix(1.0 - f, f, vec2(offset));
    weight = w.x * w.y;
    texel_index = 0u;
    texel_depth = depth;
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, ivec2(size)))) return false;
    texel_index = uint(c.y) * size.x + uint(c.x);
    if (light.bias.w > 0.5) {
        texel_depth = ms_receiver_plane_depth(light, size, uvec2(c), q, n, depth);
    }
    texel_depth *= 1.0 - light.bias.y;
    return true;
}

// A pixel's footprint on the receiver's tangent plane: the parallelogram centred on p with
// axes dpdx and dpdy (the world-space step of one pixel in x and y, e.g. dFdx / dFdy of the
// world position in a fragment shader). The footprint lookups average the bilinear lookup
// over a grid of points spread over it, as many per axis as the axis spans texels (1 to
// MS_FOOTPRINT_MAX_TAPS): a pixel then gets its whole area's shadow from one sample, with
// no noise from where in the pixel the sample fell.
const int MS_FOOTPRINT_MAX_TAPS = 2;

// The grid of points over a footprint: `taps` per axis.
ivec2 ms_footprint_taps(MsLight light, uvec2 size, vec3 p, vec3 dpdx, vec3 dpdy) {
    vec4 c0 = light.proj * (light.view * vec4(p, 1.0));
    vec4 cx = light.proj * (light.view * vec4(p + dpdx, 1.0));
    vec4 cy = light.proj * (light.view * vec4(p + dpdy, 1.0));
    vec2 half_size = 0.5 * vec2(size);
    float lx = length((cx.xy / cx.w - c0.xy / c0.w) * half_size);
    float ly = length((cy.xy / cy.w - c0.xy / c0.w) * half_size);
    bool seen = c0.w > 0.0 && cx.w > 0.0 && cy.w > 0.0 && lx < 1e6 && ly < 1e6;
    return seen ? clamp(ivec2(ceil(vec2(lx, ly))), ivec2(1), ivec2(MS_FOOTPRINT_MAX_TAPS))
                : ivec2(1);
}

// Point i (of taps.x * taps.y) of the grid over the footprint.
vec3 ms_footprint_point(vec3 p, vec3 dpdx, vec3 dpdy, ivec2 taps, int i) {
    vec2 s = (vec2(i % taps.x, i / taps.x) + 0.5) / vec2(taps) - 0.5;
    return p + s.x * dpdx + s.y * dpdy;
}

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

// The bits of a depth as an unsigned key in the depth's order (negative depths too: a
// directional light's map may hold points behind its origin), and back.
uint ms_static_key(float depth) {
    uint bits = floatBitsToUint(depth);
    return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
}

float ms_static_depth(uint key) {
    return uintBitsToFloat((key & 0x80000000u) != 0u ? key & 0x7fffffffu : ~key);
}

// Does the texel's nearest static triangle shadow a receiver at `depth` on triangle `own`?
// A static triangle's range would be [0, 1] at one depth, so only the nearest one per texel
// matters: if it is the receiver's own, every other static triangle there is at least as far
// as the receiver's own surface at the texel centre, which no receiver test puts behind.
bool ms_static_shadow(MsMap map, uint texel, float depth, uint own) {
    if (map.static_nearest == 0UL) return false;
    uint64_t nearest = MsUint64s(map.static_nearest).v[texel];
    uint id = uint(nearest & 0xffffffffUL);
    return id != MS_NO_TRIANGLE && id != own && ms_static_depth(uint(nearest >> 32)) < depth;
}

// Range r of the map's list (r = index + 1), read as three 64-bit words: a CPU device makes
// every load lane by lane, so three loads cost half of the struct's six.
MsRange ms_range(uint64_t ranges, uint r) {
    MsRangeWords words = MsRangeWords(ranges);
    uint at = 3u * (r - 1u);
    uvec2 times = unpackUint2x32(words.v[at]);
    uvec2 depths = unpackUint2x32(words.v[at + 1u]);
    uvec2 links = unpackUint2x32(words.v[at + 2u]);
    return MsRange(uintBitsToFloat(times.x), uintBitsToFloat(times.y),
                   uintBitsToFloat(depths.x), uintBitsToFloat(depths.y), links.x, links.y);
}

// The covering triangle's depths at t = 0 and 1 in `texel` (one 64-bit load, see ms_range).
vec2 ms_cover_depth(MsMap map, uint texel) {
    return uintBitsToFloat(unpackUint2x32(MsUint64s(map.cover_depth).v[texel]));
}

// Is a receiver at light depth `depth`, on triangle `own`, in shadow at time t, given the
// ranges of its texel? Ranges of the receiver's own triangle are skipped. Sorted ranges
// (MS_SORTED_RANGES) are read only up to the first that starts after t.
bool ms_ranges_shadow(MsMap map, uint texel, float depth, float t, uint own) {
    for (uint r = MsUints(map.range_heads).v[texel]; r != MS_END_OF_LIST;) {
        ++ms_loop_iterations;
        MsRange range = ms_range(map.ranges, r);
        r = range.next;
        if (map.sorted && t < range.t_s) break;
        if (range.id == own || t < range.t_s || t > range.t_e) continue;
        float span = range.t_e - range.t_s;
        float occluder = span > 0.0 ? mix(range.d_s, range.d_e, (t - range.t_s) / span)
                                    : range.d_s;
        if (occluder < depth) return true;
    }
    return false;
}

// The same test where a coverage map marks the texel as covered by triangle `cover` all
// frame (the 2017 paper's final test; the texel holds no ranges): the covering triangle does
// not shadow itself and shadows what is behind it. The paper says "shadows everything else";
// "what is behind it" (its depth at time t, linear in t, from the coverage map) is what its
// range would say, so that neighbouring triangles of one surface do not shadow each other
// where a texel straddles their shared edge.
bool ms_covered_shadow(MsMap map, uint texel, uint cover, float depth, float t, uint own) {
    vec2 d = ms_cover_depth(map, texel);
    return cover != own && mix(d.x, d.y, t) < depth;
}

// Is a receiver at light depth `depth` on triangle `own` in shadow at time t in `texel`
// (whose coverage mark, if the map has a coverage map, decides first)?
bool ms_texel_shadowed(MsMap map, uint texel, float depth, float t, uint own) {
    if (ms_static_shadow(map, texel, depth, own)) return true;
    if (map.coverage != 0UL) {
        uint cover = MsUints(map.coverage).v[texel];
        if (cover != MS_NO_TRIANGLE) return ms_covered_shadow(map, texel, cover, depth, t, own);
    }
    return ms_ranges_shadow(map, texel, depth, t, own);
}

// The texel and the biased light depth of a receiver at `p` with unit normal `n` (on the
// side facing the light); false outside the light's view.
bool ms_receiver(MsMap map, vec3 p, vec3 n, out uint texel, out float depth) {
    return ms_receiver_texel(map.light, map.size, p, n, texel, depth);
}

// Shadowed at time t? `p` is the receiver's world position, `n` its unit normal on the side
// facing the light (used for the receiver offset), `own` its triangle id or MS_NO_TRIANGLE.
bool ms_shadowed(MsMap map, vec3 p, vec3 n, float t, uint own) {
    uint texel;
    float depth;
    if (!ms_receiver(map, p, n, texel, depth)) return false;
    return ms_texel_shadowed(map, texel, depth, t, own);
}

bool ms_shadowed(MsShadowMap header, vec3 p, vec3 n, float t, uint own) {
    return ms_shadowed(ms_load(header), p, n, t, own);
}

// 1 where the point sees the light at time t, 0 where it is in shadow (the light's cone and
// the surface's orientation are the host's shading: this is visibility alone).
float ms_visibility(MsMap map, vec3 p, vec3 n, float t, uint own) {
    return ms_shadowed(map, p, n, t, own) ? 0.0 : 1.0;
}

float ms_visibility(MsShadowMap header, vec3 p, vec3 n, float t, uint own) {
    return ms_visibility(ms_load(header), p, n, t, own);
}

// ---- visibility integrated over the shutter ----

// The part of the window [w.x, w.y] (within [t_s, t_e]) during which an occluder whose depth
// runs linearly from d_s at t_s to d_e at t_e is nearer to the light than a receiver whose
// depth runs linearly from r.x at w.x to r.y at w.y. Both are linear in time there, so their
// difference changes sign at most once: one interval (empty when x > y). A zero-length range
// shadows a single instant: measure zero.
vec2 ms_nearer_span(float t_s, float t_e, float d_s, float d_e, vec2 w, vec2 r) {
    const vec2 EMPTY = vec2(1.0, 0.0);
    float a = max(t_s, w.x), b = min(t_e, w.y);
    if (!(t_e > t_s) || !(b > a)) return EMPTY;
    // Ends that are the lines' own ends are taken as stored (no rounding: a receiver that
    // stands still over the whole shutter gets exactly the static answer).
    float ta = (a - t_s) / (t_e - t_s), tb = (b - t_s) / (t_e - t_s);
    float wa = (a - w.x) / (w.y - w.x), wb = (b - w.x) / (w.y - w.x);
    float fa = (a > t_s ? mix(d_s, d_e, ta) : d_s) - (a > w.x ? mix(r.x, r.y, wa) : r.x);
    float fb = (b < t_e ? mix(d_s, d_e, tb) : d_e) - (b < w.y ? mix(r.x, r.y, wb) : r.y);
    bool start_nearer = fa < 0.0, end_nearer = fb < 0.0;
    if (start_nearer && end_nearer) return vec2(a, b);
    if (!start_nearer && !end_nearer) return EMPTY;
    float crossing = clamp(a + fa / (fa - fb) * (b - a), a, b);
    return start_nearer ? vec2(a, crossing) : vec2(crossing, b);
}

// The part of a range's interval during which its triangle is nearer to the light than a
// receiver standing still at `depth` (see ms_nearer_span).
vec2 ms_nearer_interval(float t_s, float t_e, float d_s, float d_e, float depth) {
    const vec2 EMPTY = vec2(1.0, 0.0);
    if (!(t_e > t_s)) return EMPTY;
    bool start_nearer = d_s < depth, end_nearer = d_e < depth;
    if (start_nearer && end_nearer) return vec2(t_s, t_e);
    if (!start_nearer && !end_nearer) return EMPTY;
    float crossing = t_s + (depth - d_s) / (d_e - d_s) * (t_e - t_s);
    crossing = clamp(crossing, t_s, t_e);
    return start_nearer ? vec2(t_s, crossing) : vec2(crossing, t_e);
}

// The interval of a range that shadows a receiver on triangle `own` whose depth runs from
// r.x to r.y over the window w.
vec2 ms_range_nearer(MsRange range, vec2 w, vec2 r, uint own) {
    if (range.id == own) return vec2(1.0, 0.0);
    return ms_nearer_span(range.t_s, range.t_e, range.d_s, range.d_e, w, r);
}

// The interval of a range that shadows a receiver standing still at `depth` on `own`.
vec2 ms_range_nearer(MsRange range, float depth, uint own) {
    if (range.id == own) return vec2(1.0, 0.0);
    return ms_nearer_interval(range.t_s, range.t_e, range.d_s, range.d_e, depth);
}

// The length of the union of two intervals (empty where x >= y).
float ms_union_length(vec2 a, vec2 b) {
    float la = max(a.y - a.x, 0.0), lb = max(b.y - b.x, 0.0);
    if (la == 0.0 || lb == 0.0) return la + lb;
    return la + lb - max(min(a.y, b.y) - max(a.x, b.x), 0.0);
}

// How many disjoint intervals ms_texel_lit_span keeps in private memory. Loop iterations
// are the budget here: lavapipe leaves every loop of an invocation once they have run 65,535
// iterations in all (silently). The union is built as a sorted set of disjoint intervals,
// each new interval merged into it (n ranges cost about n times the set's size; the ranges
// of a moving mesh overlap and merge, so the set stays small); only a texel whose shadow
// comes and goes more often than this is measured by repeated scans (n per interval).
const uint MS_DISJOINT_INTERVALS = 32u;

// In the repeated scans of ms_texel_lit_span: is interval `iv` (number `index`) the next
// one to take, after (last_start, last_index) in order of start, and before the best so far?
void ms_consider_next(vec2 iv, uint index, float covered_to, float last_start,
                      uint last_index, inout float next_start, inout float next_end,
                      inout uint next_index) {
    if (!(iv.y > iv.x) || iv.y <= covered_to) return;
    bool after_last = iv.x > last_start || (iv.x == last_start && index > last_index);
    bool before_next = iv.x < next_start || (iv.x == next_start && index < next_index);
    if (after_last && before_next) {
        next_start = iv.x;
        next_end = iv.y;
        next_index = index;
    }
}

// How long, within the window [w.x, w.y] of the shutter, a receiver in `texel` on triangle
// `own` whose light depth runs linearly from r.x at w.x to r.y at w.y sees the light: the
// window's length minus the length of the union of the intervals during which the texel's
// nearest static triangle, its covering triangle or one of its ranges is nearer than it.
float ms_texel_lit_span(MsMap map, uint texel, vec2 w, vec2 r, uint own) {
    const vec2 EMPTY = vec2(1.0, 0.0);
    float span = max(w.y - w.x, 0.0);
    // The static layer's nearest triangle: one occluder at one depth all shutter long (if it
    // is the receiver's own, every other static triangle there is at least as far as the
    // receiver's own surface at the texel centre, which no receiver test puts behind).
    vec2 fixed_iv = EMPTY;
    if (map.static_nearest != 0UL) {
        uint64_t nearest = MsUint64s(map.static_nearest).v[texel];
        uint id = uint(nearest & 0xffffffffUL);
        if (id != MS_NO_TRIANGLE && id != own) {
            float d = ms_static_depth(uint(nearest >> 32));
            fixed_iv = ms_nearer_span(0.0, 1.0, d, d, w, r);
        }
    }
    float fixed_length = max(fixed_iv.y - fixed_iv.x, 0.0);
    if (fixed_length >= span) return 0.0;
    if (map.coverage != 0UL) {
        uint cover = MsUints(map.coverage).v[texel];
        if (cover != MS_NO_TRIANGLE) {
            if (cover == own) return span - fixed_length;
            vec2 d = ms_cover_depth(map, texel);
            vec2 iv = ms_nearer_span(0.0, 1.0, d.x, d.y, w, r);
            return span - min(ms_union_length(fixed_iv, iv), span);
        }
    }
    uint head = MsUints(map.range_heads).v[texel];
    // The union so far: m disjoint intervals in order, starting with the static one. A
    // zero-length interval shadows an instant (measure zero) and is left out.
    vec2 set[MS_DISJOINT_INTERVALS];
    set[0] = fixed_iv;
    uint m = fixed_length > 0.0 ? 1u : 0u;
    bool fits = true;
    for (uint r_ = head; r_ != MS_END_OF_LIST && fits;) {
        MsRange range = ms_range(map.ranges, r_);
        r_ = range.next;
        // Sorted ranges that start after the window (and every one after them) miss it.
        if (map.sorted && range.t_s >= w.y) break;
        vec2 iv = ms_range_nearer(range, w, r, own);
        // Every loop iteration is counted where it runs: a moving receiver walks one list per
        // texel it crosses, and most ranges there miss its window (no scan at all).
        ++ms_loop_iterations;
        if (!(iv.y > iv.x)) continue;
        // set[first .. last] are the intervals iv overlaps or touches (none: first > last,
        // and iv goes in at first).
        uint first = 0u;
        while (first < m && set[first].y < iv.x) {
            ++first;
            ++ms_loop_iterations;
        }
        uint last = first;
        while (last < m && set[last].x <= iv.y) {
            ++last;
            ++ms_loop_iterations;
        }
        if (last == first) {
            fits = m < MS_DISJOINT_INTERVALS;
            ms_loop_iterations += m - first;
            for (uint j = m; fits && j > first; --j) set[j] = set[j - 1u];
            if (fits) {
                set[first] = iv;
                ++m;
            }
        } else {
            set[first] = vec2(min(iv.x, set[first].x), max(iv.y, set[last - 1u].y));
            uint removed = last - first - 1u;
            ms_loop_iterations += m - first;
            for (uint j = first + 1u; j + removed < m; ++j) set[j] = set[j + removed];
            m -= removed;
        }
    }
    float shadowed = 0.0;
    float covered_to = w.x;     // the union so far ends here
    if (fits) {
        ms_loop_iterations += m;
        for (uint j = 0u; j < m; ++j) shadowed += set[j].y - set[j].x;
        return span - min(shadowed, span);
    }
    // Many intervals: take them in order of their start, the next found by a scan (the last
    // taken as (start, number): the static interval is number 0, the list's ranges 1, 2, ...;
    // the next is the smallest after it).
    float last_start = w.x - 1.0;
    uint last_index = 0u;
    for (uint taken = 0u; taken <= MS_MAX_TEXEL_RANGES + 1u && covered_to < w.y; ++taken) {
        float next_start = w.y + 1.0, next_end = 0.0;
        uint next_index = 0xffffffffu;
        ms_consider_next(fixed_iv, 0u, covered_to, last_start, last_index, next_start,
                         next_end, next_index);
        uint index = 1u;
        for (uint r_ = head; r_ != MS_END_OF_LIST; ++index) {
            ++ms_loop_iterations;
            MsRange range = ms_range(map.ranges, r_);
            r_ = range.next;
            if (map.sorted && range.t_s >= w.y) break;
            ms_consider_next(ms_range_nearer(range, w, r, own), index, covered_to, last_start,
                             last_index, next_start, next_end, next_index);
        }
        if (next_index == 0xffffffffu) break;
        shadowed += max(next_end - max(next_start, covered_to), 0.0);
        covered_to = max(covered_to, next_end);
        last_start = next_start;
        last_index = next_index;
    }
    return span - min(shadowed, span);
}

// The lit fraction of the shutter for a receiver standing still at light depth `depth` on
// triangle `own` in `texel` (see ms_lit_fraction).
// (The standing receiver's own copy of ms_texel_lit_span's union, as it was before receivers
// could move: the general form, with its window clipping and exact loop counting, made the
// analytic estimator's shading 1.17x slower on lavapipe, measured by ab-frame. Answers are
// the same, asserted bit for bit by a_receiver_standing_still_gets_the_static_lit_fraction.)
float ms_texel_lit_fraction(MsMap map, uint texel, float depth, uint own) {
    if (ms_static_shadow(map, texel, depth, own)) return 0.0;
    if (map.coverage != 0UL) {
        uint cover = MsUints(map.coverage).v[texel];
        if (cover != MS_NO_TRIANGLE) {
            if (cover == own) return 1.0;
            vec2 d = ms_cover_depth(map, texel);
            vec2 iv = ms_nearer_interval(0.0, 1.0, d.x, d.y, depth);
            return 1.0 - max(iv.y - iv.x, 0.0);
        }
    }
    uint head = MsUints(map.range_heads).v[texel];
    // The union so far: m disjoint intervals in order. A zero-length interval shadows an
    // instant (measure zero) and is left out.
    vec2 set[MS_DISJOINT_INTERVALS];
    uint m = 0u;
    bool fits = true;
    for (uint r = head; r != MS_END_OF_LIST && fits;) {
        MsRange range = ms_range(map.ranges, r);
        r = range.next;
        vec2 iv = ms_range_nearer(range, depth, own);
        ms_loop_iterations += 1u + 2u * m;   // the scans and shifts below, at most
        if (!(iv.y > iv.x)) continue;
        // set[first .. last] are the intervals iv overlaps or touches (none: first > last,
        // and iv goes in at first).
        uint first = 0u;
        while (first < m && set[first].y < iv.x) ++first;
        uint last = first;
        while (last < m && set[last].x <= iv.y) ++last;
        if (last == first) {
            fits = m < MS_DISJOINT_INTERVALS;
            for (uint j = m; fits && j > first; --j) set[j] = set[j - 1u];
            if (fits) {
                set[first] = iv;
                ++m;
            }
        } else {
            set[first] = vec2(min(iv.x, set[first].x), max(iv.y, set[last - 1u].y));
            uint removed = last - first - 1u;
            for (uint j = first + 1u; j + removed < m; ++j) set[j] = set[j + removed];
            m -= removed;
        }
    }
    float shadowed = 0.0;
    float covered_to = 0.0;     // the union so far ends here
    if (fits) {
        for (uint j = 0u; j < m; ++j) shadowed += set[j].y - set[j].x;
        return 1.0 - min(shadowed, 1.0);
    }
    // Many intervals: take them in order of their start, the next found by a scan (the last
    // taken as (start, position in the list); the next is the smallest after it).
    float last_start = -1.0;
    uint last_index = 0u;
    for (uint taken = 0u; taken <= MS_MAX_TEXEL_RANGES && covered_to < 1.0; ++taken) {
        float next_start = 2.0, next_end = 0.0;
        uint next_index = 0xffffffffu;
        uint index = 0u;
        for (uint r = head; r != MS_END_OF_LIST; ++index) {
            ++ms_loop_iterations;
            MsRange range = ms_range(map.ranges, r);
            r = range.next;
            vec2 iv = ms_range_nearer(range, depth, own);
            if (!(iv.y > iv.x) || iv.y <= covered_to) continue;
            bool after_last = iv.x > last_start || (iv.x == last_start && index > last_index);
            bool before_next = iv.x < next_start || (iv.x == next_start && index < next_index);
            if (after_last && before_next) {
                next_start = iv.x;
                next_end = iv.y;
                next_index = index;
            }
        }
        if (next_index == 0xffffffffu) break;
        shadowed += max(next_end - max(next_start, covered_to), 0.0);
        covered_to = max(covered_to, next_end);
        last_start = next_start;
        last_index = next_index;
    }
    return 1.0 - min(shadowed, 1.0);
}

// The fraction of the shutter [0, 1] during which a receiver that stays at `p` all frame
// sees the light: 1 minus the length of the union of the intervals during which some range
// of its texel is nearer to the light than it. Exact (no time samples, no noise), with the
// same receiver offset, bias and own-triangle rule as ms_shadowed. The union is measured by
// taking the intervals in order of their start, found by a scan per interval: no arrays,
// O(n^2) in the texel's ranges (a handful in practice; at most 512).
float ms_lit_fraction(MsMap map, vec3 p, vec3 n, uint own) {
    uint texel;
    float depth;
    if (!ms_receiver(map, p, n, texel, depth)) return 1.0;
    return ms_texel_lit_fraction(map, texel, depth, own);
}

float ms_lit_fraction(MsShadowMap header, vec3 p, vec3 n, uint own) {
    return ms_lit_fraction(ms_load(header), p, n, own);
}

// ---- receivers that move during the shutter ----

// Narrows [lo, hi] to the times t at which g0 + t * dg >= 0.
void ms_clip_times(float g0, float dg, inout float lo, inout float hi) {
    if (dg > 0.0) {
        lo = max(lo, -g0 / dg);
    } else if (dg < 0.0) {
        hi = min(hi, -g0 / dg);
    } else if (g0 < 0.0) {
        hi = lo;
    }
}

// The time at which the linear clip-space path c0 + t * dc crosses the texel boundary at
// normalized coordinate `edge` on axis `axis` (x/w = edge: linear in t even for a spot
// light's projection); 2 where it never does.
float ms_boundary_time(vec4 c0, vec4 dc, int axis, float edge) {
    float den = dc[axis] - edge * dc.w;
    return den != 0.0 ? -(c0[axis] - edge * c0.w) / den : 2.0;
}

// A point's linear path as the light's map sees it: its clip position c0 + t dc, the times
// [lo, hi] it spends inside the light's view (x/w and y/w in [-1, 1], w > 0), and the texel it
// is in from `t` on, walked texel by texel (ms_path_advance) in the one direction of travel
// per axis (the sign of d(x/w)/dt is that of dx w0 - x0 dw, fixed for the whole shutter).
// Each boundary crossing solves a linear equation, for both light kinds. Shared by the
// depth-line and the exact moving lookups.
struct MsLightPath {
    vec4 c0;
    vec4 dc;
    float lo;
    float hi;
    ivec2 dir;
    ivec2 texel;
    float t;
};

// False where the path never enters the light's view.
bool ms_path_start(MsLight light, uvec2 size, vec3 p0, vec3 p1, out MsLightPath path) {
    mat4 to_clip = light.proj * light.view;
    path.c0 = to_clip * vec4(p0, 1.0);
    path.dc = to_clip * vec4(p1, 1.0) - path.c0;
    vec4 c0 = path.c0, dc = path.dc;
    path.lo = 0.0;
    path.hi = 1.0;
    ms_clip_times(c0.w, dc.w, path.lo, path.hi);
    ms_clip_times(c0.w + c0.x, dc.w + dc.x, path.lo, path.hi);
    ms_clip_times(c0.w - c0.x, dc.w - dc.x, path.lo, path.hi);
    ms_clip_times(c0.w + c0.y, dc.w + dc.y, path.lo, path.hi);
    ms_clip_times(c0.w - c0.y, dc.w - dc.y, path.lo, path.hi);
    path.dir = ivec2(sign(vec2(dc.x * c0.w - c0.x * dc.w, dc.y * c0.w - c0.y * dc.w)));
    vec4 start = c0 + path.lo * dc;
    path.texel = clamp(ivec2(floor((start.xy / start.w * 0.5 + 0.5) * vec2(size))), ivec2(0),
                       ivec2(size) - 1);
    path.t = path.lo;
    return path.hi > path.lo;
}

// The time the path leaves its current texel (at most hi), then steps it into the next one;
// false once it has stepped past the map's border (by rounding only: hi is where it leaves
// the view).
bool ms_path_advance(inout MsLightPath path, uvec2 size, out float exit) {
    vec2 fsize = vec2(size);
    float tx = 2.0, ty = 2.0;
    if (path.dir.x != 0) {
        float edge = float(path.texel.x + max(path.dir.x, 0)) / fsize.x * 2.0 - 1.0;
        tx = ms_boundary_time(path.c0, path.dc, 0, edge);
    }
    if (path.dir.y != 0) {
        float edge = float(path.texel.y + max(path.dir.y, 0)) / fsize.y * 2.0 - 1.0;
        ty = ms_boundary_time(path.c0, path.dc, 1, edge);
    }
    exit = clamp(min(min(tx, ty), path.hi), path.t, path.hi);
    if (tx <= ty) {
        path.texel.x += path.dir.x;
    } else {
        path.texel.y += path.dir.y;
    }
    return all(greaterThanEqual(path.texel, ivec2(0))) && all(lessThan(path.texel, ivec2(size)));
}

// A moving lookup's walk along its path, resumable between two texels (issue 35): the texels'
// time windows are disjoint and their shares add up, so a walk may stop before any texel and
// go on later, in another invocation, from the time and texel it reached and its sum so far.
// On a device that leaves loops after a fixed count (lavapipe), the visibility mask cuts a
// long walk into pieces that each fit one invocation's budget.
const uint MS_WALK_START = 0u;      // in: from the path's start
const uint MS_WALK_RESUME = 1u;     // in: from t, texel and sum
const uint MS_WALK_DONE = 2u;       // out: sum is the lit fraction
const uint MS_WALK_STOPPED = 3u;    // out: stopped before `texel` at time t: resume from there
const uint MS_WALK_PAST = 4u;       // out: past the budget at texel `walked`: nothing is sure
const uint MS_WALK_NO_LIMIT = 0xffffffffu;

struct MsWalk {
    uint state;
    float t;
    ivec2 texel;
    float sum;      // so far: the lit time (depth lines), the shadowed time (exact)
    uint limit;     // texels (exact: loop iterations) it may walk (MS_WALK_NO_LIMIT: any)
    uint walked;    // texels this invocation has walked (exact: its loop iterations)
    uint cursor;    // exact walks: where in `texel`'s list it goes on (0: the list's start)
};

MsWalk ms_walk_start() {
    return MsWalk(MS_WALK_START, 0.0, ivec2(0), 0.0, MS_WALK_NO_LIMIT, 0u, 0u);
}

// The count a walk stops at, before its next texel, to go on with a fresh budget: half of
// `budget` (the other half for the texel it is in, which may be long); never with budget 0
// (no loop limit).
uint ms_walk_stop_count(uint budget) {
    return budget == 0u ? 0xffffffffu : budget / 2u;
}

// Whether the walk stops before its next texel (past its stop count or its texel limit).
// Tested at the top of the walk's loop: a caller that passes a budget of 0 known when the
// shader is compiled has it folded away (a test left there made the visibility mask 1.3x
// slower on lavapipe).
bool ms_walk_stops(MsWalk walk, uint stop_count) {
    return ms_loop_iterations > stop_count || walk.walked >= walk.limit;
}

// The walk's state once its loop is left: past `budget` (the last texel walked ran past it:
// nothing this invocation did is sure; `walked` is that texel's number), stopped before the
// texel at t (resume there with `sum`), or done (`sum` is the lit fraction).
void ms_walk_end(inout MsWalk walk, uint budget, bool stopped, float t, ivec2 texel, float sum,
                 float lit) {
    if (budget != 0u && ms_loop_iterations > budget) {
        walk.state = MS_WALK_PAST;
        walk.walked -= 1u;
    } else if (stopped) {
        walk.state = MS_WALK_STOPPED;
        walk.t = t;
        walk.texel = texel;
        walk.sum = sum;
    } else {
        walk.state = MS_WALK_DONE;
        walk.sum = lit;
    }
}

// The fraction of the shutter [0, 1] during which a receiver moving linearly from p0 (at
// t = 0) to p1 (at t = 1), unit normal n (on the side facing the light; taken as constant),
// on triangle `own`, sees the light: each range tested where the point is when it holds.
// Exact for a receiver that translates (any linear motion of the point), with the same
// receiver offset, bias and own-triangle rule as ms_lit_fraction, to which it reduces when
// p0 == p1.
//
// The point's path is cut where it crosses texel boundaries (its projection x/w is monotonic
// in t, and each crossing time solves a linear equation, for both light kinds); within one
// texel its light depth, and its tangent plane's depth at the texel centre, are linear in t,
// so every range shadows it during one interval (ms_texel_lit_span). Time spent outside the
// light's view is lit. The cost is one list walk per texel crossed. Walked from `walk` (see
// MsWalk) until done or, with a loop `budget` (0: none), stopped between two texels.
void ms_walk_moving(MsMap map, vec3 p0, vec3 p1, vec3 n, uint own, uint budget,
                    inout MsWalk walk) {
    MsLight light = map.light;
    // The normal offset is linear in the point's light depth, so the offset point moves
    // linearly too.
    vec3 q0 = ms_offset_receiver(light, p0, n), q1 = ms_offset_receiver(light, p1, n);
    MsLightPath path;
    if (!ms_path_start(light, map.size, q0, q1, path)) {
        walk.state = MS_WALK_DONE;
        walk.sum = 1.0;
        return;
    }
    float lit = 1.0 - (path.hi - path.lo);    // outside the light's view
    if (walk.state == MS_WALK_RESUME) {
        path.t = walk.t;
        path.texel = walk.texel;
        lit = walk.sum;
    }
    float depth0 = -(light.view * vec4(q0, 1.0)).z, depth1 = -(light.view * vec4(q1, 1.0)).z;
    uint stop_count = ms_walk_stop_count(budget);
    bool stopped = false;
    for (uint crossed = 0u; path.t < path.hi && crossed <= map.size.x + map.size.y; ++crossed) {
        if (ms_walk_stops(walk, stop_count)) {
            stopped = true;
            break;
        }
        ++ms_loop_iterations;
        uvec2 at = uvec2(path.texel);
        float t = path.t, exit;
        bool inside = ms_path_advance(path, map.size, exit);
        float da = ms_tested_depth(light, map.size, at, mix(q0, q1, t), n, mix(depth0, depth1, t));
        float db = ms_tested_depth(light, map.size, at, mix(q0, q1, exit), n,
                                   mix(depth0, depth1, exit));
        lit += ms_texel_lit_span(map, at.y * map.size.x + at.x, vec2(t, exit), vec2(da, db), own);
        ++walk.walked;
        path.t = exit;
        // Past the map's border by rounding only: the sliver left is counted lit, as outside.
        if (!inside) {
            lit += path.hi - path.t;
            break;
        }
    }
    ms_walk_end(walk, budget, stopped, path.t, path.texel, lit, min(lit, 1.0));
}

float ms_lit_fraction_moving(MsMap map, vec3 p0, vec3 p1, vec3 n, uint own) {
    MsWalk walk = ms_walk_start();
    ms_walk_moving(map, p0, p1, n, own, 0u, walk);
    return walk.sum;
}

float ms_lit_fraction_moving(MsShadowMap header, vec3 p0, vec3 p1, vec3 n, uint own) {
    return ms_lit_fraction_moving(ms_load(header), p0, p1, n, own);
}

// The footprint lookups' common part: the taps' bilinear weights summed per texel first, so
// that a texel several taps share is evaluated once (its depth there is the receiver
// plane's, the same for every tap; without the plane test, the first tap's own depth), then
// each texel answered at time t, or over the shutter where t < 0.
//
// (Written as two flat loops on purpose: llvmpipe in Mesa 22.3 lost whole lanes' results
// when the texel loop with its range scans sat inside the tap loop.)
const int MS_FOOTPRINT_MAX_TEXELS = 4 * MS_FOOTPRINT_MAX_TAPS * MS_FOOTPRINT_MAX_TAPS;

float ms_footprint_lookup(MsMap map, vec3 p, vec3 n, float t, uint own, vec3 dpdx, vec3 dpdy) {
    ivec2 taps = ms_footprint_taps(map.light, map.size, p, dpdx, dpdy);
    int tap_count = taps.x * taps.y;
    uint texels[MS_FOOTPRINT_MAX_TEXELS];
    float weights[MS_FOOTPRINT_MAX_TEXELS];
    float depths[MS_FOOTPRINT_MAX_TEXELS];
    int count = 0;
    float lit = 0.0;    // weight of taps outside the map (lit) so far
    for (int i = 0; i < tap_count; ++i) {
        vec3 q;
        float depth;
        ivec2 base;
        vec2 f;
        vec3 point = ms_footprint_point(p, dpdx, dpdy, taps, i);
        bool seen = ms_receiver_footprint(map.light, map.size, point, n, q, depth, base, f);
        if (!seen) lit += 1.0;
        for (int k = 0; k < 4 && seen; ++k) {
            uint texel;
            float texel_depth, weight;
            bool inside = ms_footprint_texel(map.light, map.size, base, f, k, q, n, depth, texel,
                                             texel_depth, weight);
            if (!inside) lit += weight;
            int found = count;
            ms_loop_iterations += uint(MS_FOOTPRINT_MAX_TEXELS);
            for (int j = 0; j < MS_FOOTPRINT_MAX_TEXELS; ++j) {
                if (j < count && texels[j] == texel) found = j;
            }
            if (inside && found == count) {
                texels[count] = texel;
                weights[count] = 0.0;
                depths[count] = texel_depth;
                ++count;
            }
            if (inside) weights[found] += weight;
        }
    }
    for (int j = 0; j < count; ++j) {
        float v = t < 0.0 ? ms_texel_lit_fraction(map, texels[j], depths[j], own)
                          : (ms_texel_shadowed(map, texels[j], depths[j], t, own) ? 0.0 : 1.0);
        lit += weights[j] * v;
    }
    return lit / float(tap_count);
}

// ---- filtered (see ms_receiver_footprint): smooth in space as well ----
// (Both are the footprint lookups below with a footprint of one point.)

// The share of the 2x2 footprint around p that sees the light at time t: 1 lit, 0 shadowed,
// in between on a shadow edge (percentage-closer filtering of the ranges at time t).
float ms_visibility_filtered(MsMap map, vec3 p, vec3 n, float t, uint own) {
    return ms_footprint_lookup(map, p, n, max(t, 0.0), own, vec3(0.0), vec3(0.0));
}

float ms_visibility_filtered(MsShadowMap header, vec3 p, vec3 n, float t, uint own) {
    return ms_visibility_filtered(ms_load(header), p, n, t, own);
}

// ms_lit_fraction over the 2x2 footprint around p: the weighted mean of the four texels'
// exact lit fractions of the shutter. For a receiver that does not move during the shutter:
// no time noise, and shadow edges ramp over a texel.
float ms_lit_fraction_filtered(MsMap map, vec3 p, vec3 n, uint own) {
    return ms_footprint_lookup(map, p, n, -1.0, own, vec3(0.0), vec3(0.0));
}

float ms_lit_fraction_filtered(MsShadowMap header, vec3 p, vec3 n, uint own) {
    return ms_lit_fraction_filtered(ms_load(header), p, n, own);
}

// ms_visibility_filtered averaged over a pixel's footprint (see ms_footprint_taps).
float ms_visibility_footprint(MsMap map, vec3 p, vec3 n, float t, uint own, vec3 dpdx,
                              vec3 dpdy) {
    return ms_footprint_lookup(map, p, n, max(t, 0.0), own, dpdx, dpdy);
}

// ms_lit_fraction_filtered averaged over a pixel's footprint: for a receiver that does not
// move during the shutter, the pixel's lit share of its area and of the shutter at once.
float ms_lit_fraction_footprint(MsMap map, vec3 p, vec3 n, uint own, vec3 dpdx, vec3 dpdy) {
    return ms_footprint_lookup(map, p, n, -1.0, own, dpdx, dpdy);
}
