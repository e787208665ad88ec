// The temporal map's shadow test for all the samples of one pixel at once (the lighting
// pass's shading, sampled estimator, unfiltered). The includer defines SHADE_SAMPLES, the
// samples per pixel of a chunk (a specialization constant: the loops over samples unroll and
// their arrays stay in registers).
//
// Why: the samples of a pixel that land in the same texel on the same triangle differ only
// in their time (and their depth's rounding). Their texel's static-layer key, coverage mark
// and depth-time ranges are read once for all of them, each range tested at every sample's
// time: the reads are what the test costs (a CPU device makes every load lane by lane), and
// a pixel's 8 samples mostly share one texel. Each sample gets exactly what ms_shadowed
// answers for it alone (the same comparisons in the same order of precedence: the static
// layer, then the coverage map, then the ranges).

// The bits of the samples in `candidates` whose receiver (texel[j], light depth depth[j],
// triangle own[j]) is in shadow at time t[j].
uint ms_samples_shadowed(MsMap map, uint candidates, uint texel[SHADE_SAMPLES],
                         float depth[SHADE_SAMPLES], float t[SHADE_SAMPLES],
                         uint own[SHADE_SAMPLES]) {
    uint shadowed = 0u;
    uint pending = candidates;
    // One group per distinct texel among the samples: usually one, two where the pixel
    // straddles a texel edge. (Samples of a group may lie on different triangles: the own
    // triangle test is each sample's.)
    while (pending != 0u) {
        uint first = uint(findLSB(pending));
        uint group_texel = 0u;
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if (j == first) group_texel = texel[j];
        }
        uint group = 0u;
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if ((pending & (1u << j)) != 0u && texel[j] == group_texel) group |= 1u << j;
        }
        pending &= ~group;

        // The static layer's nearest triangle (ms_static_shadow).
        if (map.static_nearest != 0UL) {
            uint64_t nearest = MsUint64s(map.static_nearest).v[group_texel];
            uint id = uint(nearest & 0xffffffffUL);
            float static_depth = ms_static_depth(uint(nearest >> 32));
            [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
                bool blocks = id != MS_NO_TRIANGLE && id != own[j] && static_depth < depth[j];
                if ((group & (1u << j)) != 0u && blocks) shadowed |= 1u << j;
            }
        }
        uint open = group & ~shadowed;  // not decided yet

        // A texel the coverage map marks decides by its covering triangle alone
        // (ms_covered_shadow).
        if (map.coverage != 0UL) {
            uint cover = MsUints(map.coverage).v[group_texel];
            if (cover != MS_NO_TRIANGLE) {
                vec2 d = ms_cover_depth(map, group_texel);
                [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
                    bool behind = cover != own[j] && mix(d.x, d.y, t[j]) < depth[j];
                    if ((open & (1u << j)) != 0u && behind) shadowed |= 1u << j;
                }
                open = 0u;
            }
        }

        // The ranges (ms_ranges_shadow), until every open sample is shadowed; sorted ranges
        // only up to the first that starts after every open sample's time.
        float latest = -1.0;
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if ((open & (1u << j)) != 0u) latest = max(latest, t[j]);
        }
        for (uint r = MsUints(map.range_heads).v[group_texel];
             r != MS_END_OF_LIST && open != 0u;) {
            ++ms_loop_iterations;
            MsRange range = ms_range(map.ranges, r);
            r = range.next;
            if (map.sorted && latest < range.t_s) break;
            float span = range.t_e - range.t_s;
            [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
                bool outside = t[j] < range.t_s || t[j] > range.t_e;
                if ((open & (1u << j)) == 0u || range.id == own[j] || outside) continue;
                float occluder = span > 0.0 ? mix(range.d_s, range.d_e, (t[j] - range.t_s) / span)
                                            : range.d_s;
                if (occluder < depth[j]) {
                    shadowed |= 1u << j;
                    open &= ~(1u << j);
                }
            }
        }
    }
    return shadowed;
}
