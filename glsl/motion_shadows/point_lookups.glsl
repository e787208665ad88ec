// motion_shadows/point_lookups.glsl: is a receiver in shadow at one time t (the static layer,
// the coverage map, the texel's ranges): ms_shadowed, ms_visibility.
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

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
