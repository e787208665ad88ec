// motion_shadows/filtered_lookups.glsl: lookups smooth in space, the bilinear 2x2 texels around
// a receiver's projection and the grid over a pixel's footprint: ms_visibility_filtered,
// ms_lit_fraction_filtered, ms_lit_fraction_footprint.
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

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
