#version 450
// Lighting pass, shading: per pixel, for each sample of the chunk, rebuild the hit point from
// the visibility buffer, shade it (Lambert, point light with a hard cone or directional
// light), test its shadow at exactly the sample's time, and add the chunk's share of the box
// filter average to the accumulated radiance (alpha: the share of samples that see a moving
// triangle). The temporal shadow map is tested through motion_shadows.glsl, the include a
// host's own shaders call: per sample (ms_visibility and the filtered lookups), or for the
// papers' test, per texel for all the samples of a pixel in it (temporal_samples.glsl).
#extension GL_EXT_shader_atomic_int64 : require
#extension GL_EXT_control_flow_attributes : require
#include "shared.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(push_constant) uniform Push { ShadePush pc; };

// The variant, fixed when the pipeline is made (one pipeline per shadow test, estimator and
// filter): the compiler drops every other path. A CPU device such as lavapipe runs both sides
// of a branch that its lanes may take differently, masked, so a variant chosen at run time
// paid for every lookup in the shader on every sample.
layout(constant_id = 0) const uint SHADE_SHADOW = SHADOW_TEMPORAL;  // SHADOW_*
layout(constant_id = 1) const bool SHADE_ANALYTIC = false;  // temporal: the analytic estimator
layout(constant_id = 2) const uint SHADE_FILTER = 0u;       // SHADE_FILTER_*
// The most loop iterations a pixel's lookups may report before it is counted as possibly
// cut short by the device's loop limit; 0: the device has no such limit (nothing counted).
layout(constant_id = 3) const uint SHADE_LOOP_BUDGET = 0u;
// Samples per pixel in the chunk (the chunk's samples): the loops over a pixel's
// samples unroll, and their arrays stay in registers.
layout(constant_id = 4) const uint SHADE_SAMPLES = 1u;
// Temporal: the map was built for the exact lookup (Lookup::Exact, triangle records in its
// header): each sample's shadow ray against the triangles its texel names
// (exact_lookup.glsl). A specialization of its own, so that the exact test's code is not
// compiled into the depth-line variants.
layout(constant_id = 5) const bool SHADE_EXACT = false;
// The shadow source was recorded for a moving light (LightView::end): samples are shaded and
// read with the light at their times. A still light's pipelines hold none of that code: a CPU
// device runs both sides of a branch on data (the light's flag in the header), which made
// the still frame's shading 1.7x (TSM: 2.5x) slower.
layout(constant_id = 6) const bool SHADE_LIGHT_MOVES = false;
// The camera moves during the shutter (LightingView's CameraView::end): the visibility
// buffer's hits are points of the t = 0 camera's frame, carried back to the world triangle at
// the sample's time (camera_motion.glsl). Specialized for the same reason as the light's.
layout(constant_id = 7) const bool SHADE_CAMERA_MOVES = false;

#include "temporal_samples.glsl"
#include "exact_lookup.glsl"
#include "camera_motion.glsl"

const uint SHADE_FILTER_NONE = 0u;        // the receiver's texel
const uint SHADE_FILTER_BILINEAR = 1u;    // 2x2 texels, bilinear weights
const uint SHADE_FILTER_FOOTPRINT = 2u;   // those over the pixel's footprint

const float PI = 3.14159265358979323846;

// Loaded once per invocation (per pixel), not per sample: reading a header costs a few
// hundred bytes of loads, which a CPU device makes lane by lane.
CameraParams camera;
MsLight light;          // the light of either kind of map (both headers start with it)
MsMap temporal;         // SHADOW_TEMPORAL
uvec4 plain_size;       // ordinary maps: x, y = texels, z = layers
uint64_t plain_depths;   // FloatArray
uint64_t plain_ids;      // UintArray (plain maps with ids)

// What shading needs of a triangle a sample hit: its corners, albedo and whether it moves.
struct HitTriangle {
    Triangle tri;
    vec3 albedo;
    bool moving;
};

HitTriangle fetch_hit(uint id) {
    DrawRecord d = load_draw(pc.draws, find_draw(DrawTable(pc.draws), pc.draw_count, id));
    HitTriangle hit;
    hit.tri = fetch_triangle(d, id - d.first_id);
    hit.albedo = d.albedo_flags.rgb;
    hit.moving = false;
    for (int i = 0; i < 3; ++i) hit.moving = hit.moving || hit.tri.p0[i] != hit.tri.p1[i];
    return hit;
}

// The light-view depth of an ordinary map's texel from the z/w its depth attachment kept
// (+inf where nothing was drawn: the attachment's clear value 1 is never written, the test
// being LESS). Inverts z/w = (P22 z + P32) / (P23 z + P33) for the view-space z.
float ordinary_depth(float stored) {
    if (stored >= 1.0) return 1.0 / 0.0;
    float z = (light.proj[3][2] - stored * light.proj[3][3])
            / (stored * light.proj[2][3] - light.proj[2][2]);
    return -z;
}

bool shadowed_plain(uint index, float depth, uint own) {
    uint id = UintArray(plain_ids).v[index];
    if (id == NO_TRIANGLE || id == own) return false;
    return ordinary_depth(FloatArray(plain_depths).v[index]) < depth;
}

// Time-dependent shadow maps: the map of the sample's time stratum, depth only, no id (the
// time mismatch between that map and the sample is the method's self-shadow artifact).
bool shadowed_tsm(uint index, float depth, uint stratum) {
    uint layer_size = plain_size.x * plain_size.y;
    return ordinary_depth(FloatArray(plain_depths).v[stratum * layer_size + index]) < depth;
}

// Shadow test of the ordinary maps (plain, TSM) in texel `index` at `depth`.
bool shadowed_ordinary_texel(uint index, float depth, uint id, uint stratum) {
    return SHADE_SHADOW == SHADOW_TSM ? shadowed_tsm(index, depth, stratum)
                                 : shadowed_plain(index, depth, id);
}

// Visibility from the ordinary maps (plain, TSM), with the same receiver test as
// ms_visibility applies to the temporal map; `filtered`: percentage-closer filtering over the
// same 2x2 footprint as ms_visibility_filtered.
float visibility_ordinary(vec3 p, vec3 n, uint id, uint stratum, bool filtered) {
    if (!filtered) {
        uint index;
        float depth;
        if (!ms_receiver_texel(light, plain_size.xy, p, n, index, depth)) return 1.0;
        return shadowed_ordinary_texel(index, depth, id, stratum) ? 0.0 : 1.0;
    }
    vec3 q;
    float depth;
    ivec2 base;
    vec2 f;
    if (!ms_receiver_footprint(light, plain_size.xy, p, n, q, depth, base, f)) return 1.0;
    float lit = 0.0;
    for (int k = 0; k < 4; ++k) {
        uint index;
        float texel_depth, weight;
        bool inside = ms_footprint_texel(light, plain_size.xy, base, f, k, q, n, depth, index,
                                         texel_depth, weight);
        if (weight == 0.0) continue;
        if (!inside || !shadowed_ordinary_texel(index, texel_depth, id, stratum)) lit += weight;
    }
    return lit;
}

// visibility_ordinary (filtered) averaged over a pixel's footprint, as
// ms_visibility_footprint does for the temporal map.
float visibility_ordinary_footprint(vec3 p, vec3 n, uint id, uint stratum, vec3 dpdx,
                                    vec3 dpdy) {
    ivec2 taps = ms_footprint_taps(light, plain_size.xy, p, dpdx, dpdy);
    float sum = 0.0;
    for (int i = 0; i < taps.x * taps.y; ++i) {
        sum += visibility_ordinary(ms_footprint_point(p, dpdx, dpdy, taps, i), n, id, stratum,
                                   true);
    }
    return sum / float(taps.x * taps.y);
}

// The world-space step of one pixel along x (`axis` (1, 0)) or y ((0, 1)) on the plane
// through p with normal n, seen from the camera: where the ray one pixel over meets the
// plane. Zero where that ray runs along the plane (or meets it behind the camera).
vec3 pixel_step(vec2 pixel_pos, vec2 axis, vec3 p, vec3 n) {
    vec3 dir = camera_ray(camera, pixel_pos + axis);
    float along = dot(dir, n);
    float s = abs(along) < 1e-8 ? 0.0 : dot(p - camera.position.xyz, n) / along;
    return s > 0.0 ? camera.position.xyz + s * dir - p : vec3(0.0);
}

// The normal of `hit`'s triangle at time t (a static triangle at t = 0 exactly: mix(a, a, t)
// may round differently for another t, and its shading must not depend on the sample's
// time), on the side seen along `dir` (two-sided).
vec3 surface_normal(HitTriangle hit, float t, vec3 dir) {
    Triangle tri = hit.tri;
    float s = hit.moving ? t : 0.0;
    vec3 pa = mix(tri.p0[0], tri.p1[0], s), pb = mix(tri.p0[1], tri.p1[1], s);
    vec3 pc_ = mix(tri.p0[2], tri.p1[2], s);
    vec3 n = normalize(cross(pb - pa, pc_ - pa));
    return dot(n, -dir) < 0.0 ? -n : n;
}

// The share of the light a sample at p (normal n, time t, on triangle id; sample k of the
// pixel, at `offset` in it) receives, by the per-sample lookups of the pipeline's variant.
float sample_lit(uvec2 pixel, uint rotation, uint k, vec2 offset, vec3 p, vec3 n, float t,
                 uint id, bool moving) {
    // The footprint is centred on the pixel's centre, not the sample, so that where the
    // sample fell does not matter.
    const bool filtered = SHADE_FILTER != SHADE_FILTER_NONE;
    const bool footprint = SHADE_FILTER == SHADE_FILTER_FOOTPRINT;
    vec3 dpdx = vec3(0.0), dpdy = vec3(0.0), centre = p;
    if (footprint) {
        vec2 pos = vec2(pixel) + offset;
        dpdx = pixel_step(pos, vec2(1.0, 0.0), p, n);
        dpdy = pixel_step(pos, vec2(0.0, 1.0), p, n);
        centre = p + (0.5 - offset.x) * dpdx + (0.5 - offset.y) * dpdy;
    }
    // One return for every path: llvmpipe (Mesa 22.3) lost the value of an early return
    // taken by some lanes only, ahead of the footprint loops, and shaded those samples with
    // the per-sample path's answer instead.
    float lit = 1.0;
    uint stratum = time_stratum(rotation, k, camera.image.z);
    if (SHADE_SHADOW == SHADOW_TEMPORAL && SHADE_EXACT) {
        // The exact lookup has no texels to filter (the host refuses a filter with it); the
        // analytic estimator's standing receivers take their exact lit share of the shutter.
        // A moving (translating) light: projected and tested with the light where it is at t
        // (ms_map_at; the analytic estimator is refused with a moving light).
        MsMap at = SHADE_LIGHT_MOVES ? ms_map_at(temporal, pc.shadow, t) : temporal;
        lit = SHADE_ANALYTIC && !moving ? ms_lit_fraction_exact(temporal, p, id)
                                        : (ms_visible_exact(at, p, t, id) ? 1.0 : 0.0);
    } else if (SHADE_SHADOW == SHADOW_TEMPORAL && SHADE_ANALYTIC && !moving) {
        // The analytic estimator: a receiver that stays put all frame is lit for exactly
        // ms_lit_fraction of the shutter, whatever the sample's time.
        lit = footprint ? ms_lit_fraction_footprint(temporal, centre, n, id, dpdx, dpdy)
              : filtered ? ms_lit_fraction_filtered(temporal, p, n, id)
                         : ms_lit_fraction(temporal, p, n, id);
    } else if (SHADE_SHADOW == SHADOW_TEMPORAL) {
        // With the light where it is at t (a moving light, light_motion.glsl).
        MsMap at = SHADE_LIGHT_MOVES ? ms_map_at(temporal, pc.shadow, t) : temporal;
        lit = footprint ? ms_visibility_footprint(at, centre, n, t, id, dpdx, dpdy)
              : filtered ? ms_visibility_filtered(at, p, n, t, id)
                         : ms_visibility(at, p, n, t, id);
    } else if (SHADE_SHADOW != SHADOW_NONE) {
        // Read with the light the layer was drawn with (a moving light's, at the layer's time).
        MsLight kept = light;
        if (SHADE_LIGHT_MOVES) {
            light = plain_layer_light(pc.shadow, SHADE_SHADOW == SHADOW_TSM ? stratum : 0u);
        }
        lit = footprint ? visibility_ordinary_footprint(centre, n, id, stratum, dpdx, dpdy)
                        : visibility_ordinary(p, n, id, stratum, filtered);
        light = kept;
    }
    return lit;
}

// The papers' test on the temporal map, unfiltered: every sample of the pixel tested in one
// pass over each texel's data (temporal_samples.glsl).
const bool SHADE_PER_TEXEL = SHADE_SHADOW == SHADOW_TEMPORAL && !SHADE_ANALYTIC
                             && SHADE_FILTER == SHADE_FILTER_NONE && !SHADE_EXACT;

void main() {
    camera = load_camera(pc.target);
    if (SHADE_SHADOW == SHADOW_TEMPORAL) {
        temporal = ms_load(MsShadowMap(pc.shadow));
        light = temporal.light;
    } else {
        PlainHeader header = PlainHeader(pc.shadow);
        light = ms_load_light(pc.shadow);
        plain_size = header.size;
        plain_depths = header.depths;
        plain_ids = header.ids;
    }
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= camera.image.x || pixel.y >= camera.image.y) return;
    uint p = pixel.y * camera.image.x + pixel.x;
    uint key = pixel_key(pixel, camera.image.w);
    uint rotation = stratum_rotation(key, camera.image.z);

    // Each sample's hit: its triangle, time, position in the pixel and point.
    Uint64Array visibility = Uint64Array(camera.visibility);
    uint id[SHADE_SAMPLES];
    float t[SHADE_SAMPLES];
    vec2 offset[SHADE_SAMPLES];
    vec3 dir[SHADE_SAMPLES], point[SHADE_SAMPLES];
    uint pending = 0u;  // samples on a triangle not fetched yet
    [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        uint64_t hit = visibility.v[p * SHADE_SAMPLES + j];
        id[j] = uint(hit & 0xffffffffUL);
        pixel_sample(key, rotation, pc.first_sample + j, camera.image.z, t[j], offset[j]);
        if ((pc.flags & FIXED_TIME) != 0u) t[j] = pc.time;
        dir[j] = camera_ray(camera, vec2(pixel) + offset[j]);
        point[j] = camera.position.xyz + uintBitsToFloat(uint(hit >> 32)) * dir[j];
        if (id[j] != NO_TRIANGLE) pending |= 1u << j;
    }

    // The distinct triangles the samples hit (most pixels: one), each fetched once: fetching
    // a triangle through its draw is many loads, and a CPU device makes each load lane by
    // lane for every lane of a branch, taken or not; this loop runs as often as the lanes'
    // most distinct triangles.
    vec3 normal[SHADE_SAMPLES], albedo[SHADE_SAMPLES];
    uint moving = 0u;   // samples on a moving triangle
    CameraEnd camera_end;
    if (SHADE_CAMERA_MOVES) camera_end = CameraEndRef(camera.camera_end).end;
    [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        normal[j] = vec3(0.0);
        albedo[j] = vec3(0.0);
    }
    while (pending != 0u) {
        uint first = uint(findLSB(pending));
        uint hit_id = NO_TRIANGLE;
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if (j == first) hit_id = id[j];
        }
        HitTriangle hit = fetch_hit(hit_id);
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if ((pending & (1u << j)) == 0u || id[j] != hit_id) continue;
            if (SHADE_CAMERA_MOVES) {
                // The hit in the world, seen from the eye where it is at the sample's time.
                point[j] = camera_end_world_point(camera_end, hit.tri, hit.moving, t[j],
                                                  point[j]);
                vec3 eye = camera.position.xyz
                           + t[j] * (camera_end.position.xyz - camera.position.xyz);
                dir[j] = point[j] - eye;
            }
            normal[j] = surface_normal(hit, t[j], dir[j]);
            albedo[j] = hit.albedo;
            if (hit.moving) moving |= 1u << j;
            pending &= ~(1u << j);
        }
    }

    // Lambert shading; `facing`: the samples the light reaches but for shadows.
    vec3 ambient[SHADE_SAMPLES], direct[SHADE_SAMPLES];
    uint facing = 0u;
    bool spot = light.position.w > 0.5;
    [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        // A moving light shades each sample from where it is at the sample's time.
        MsLight at = light;
        if (SHADE_LIGHT_MOVES && SHADE_SHADOW == SHADOW_TEMPORAL) {
            at = ms_map_at(temporal, pc.shadow, t[j]).light;
        } else if (SHADE_LIGHT_MOVES) {
            at = ms_light_at(light, pc.shadow + PLAIN_LIGHT_END_OFFSET, t[j]);
        }
        vec3 to_light = spot ? at.position.xyz - point[j] : -at.direction.xyz;
        float dist2 = spot ? dot(to_light, to_light) : 1.0;
        vec3 l = normalize(to_light);
        float cos_theta = dot(normal[j], l);
        ambient[j] = camera.shading.x * albedo[j];
        direct[j] = albedo[j] / PI * at.emission.x * cos_theta / dist2;
        bool away = cos_theta <= 0.0 || (spot && dot(-l, at.direction.xyz) < at.direction.w);
        if (id[j] != NO_TRIANGLE && !away) facing |= 1u << j;
    }

    // The shadow term of each facing sample.
    float lit[SHADE_SAMPLES];
    [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) lit[j] = 1.0;
    if (SHADE_PER_TEXEL) {
        uint texel[SHADE_SAMPLES];
        float depth[SHADE_SAMPLES];
        uint seen = 0u;
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            MsMap at = SHADE_LIGHT_MOVES ? ms_map_at(temporal, pc.shadow, t[j]) : temporal;
            bool tested = ms_receiver(at, point[j], normal[j], texel[j], depth[j]);
            if ((facing & (1u << j)) != 0u && tested) seen |= 1u << j;
        }
        uint shadowed = ms_samples_shadowed(temporal, seen, texel, depth, t, id);
        [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if ((shadowed & (1u << j)) != 0u) lit[j] = 0.0;
        }
    } else {
        [[dont_unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
            if ((facing & (1u << j)) == 0u) continue;
            lit[j] = sample_lit(pixel, rotation, pc.first_sample + j, offset[j], point[j],
                                normal[j], t[j], id[j], (moving & (1u << j)) != 0u);
        }
    }

    vec3 sum = vec3(0.0);
    [[unroll]] for (uint j = 0u; j < SHADE_SAMPLES; ++j) {
        if (id[j] == NO_TRIANGLE) continue;
        bool lit_side = (facing & (1u << j)) != 0u;
        sum += lit_side ? ambient[j] + direct[j] * lit[j] : ambient[j];
    }
    Vec4Array radiance = Vec4Array(camera.radiance);
    radiance.v[p] += vec4(sum, float(bitCount(moving))) / float(camera.image.z);
    // The device leaves loops past a fixed count: say so when this pixel's lookups may have
    // come near it (the host re-runs with fewer samples per invocation, or fails).
    if (SHADE_LOOP_BUDGET > 0u && ms_loop_iterations > SHADE_LOOP_BUDGET) {
        atomicAdd(UintArray(camera.counters).v[1], 1u);
    }
}
