// motion_shadows/shutter_lookups.glsl: the share of the shutter a receiver at a depth line sees
// the light, from the union of the times its texel's ranges are nearer: ms_lit_fraction.
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

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
