#version 450
// Lighting pass, shading: per pixel, for each sample of the chunk, rebuild the hit point from
// the visibility buffer, shade it (Lambert, point light with a hard cone or directional
// light), test its shadow at exactly the sample's time, and add the chunk's share of the box
// filter average to the accumulated radiance (alpha: the share of samples that see a moving
// triangle).
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 1) readonly buffer Vertices { SceneVertex vertices[]; };
layout(std430, set = 0, binding = 2) readonly buffer Triangles { TriangleInfo triangles[]; };
layout(std430, set = 0, binding = 3) readonly buffer Visibility { uint64_t visibility[]; };
layout(std430, set = 0, binding = 4) buffer Accumulation { vec4 radiance[]; };
layout(std430, set = 0, binding = 5) readonly buffer RangeHeads { uint range_heads[]; };
layout(std430, set = 0, binding = 7) readonly buffer PlainDepths { uint64_t plain_depths[]; };
layout(std430, set = 0, binding = 8) readonly buffer TsmDepths { uint tsm_depths[]; };
layout(std430, set = 0, binding = 9) readonly buffer Coverage { uint coverage[]; };
layout(std430, set = 0, binding = 10) readonly buffer CoverDepth { vec2 cover_depth[]; };
layout(push_constant) uniform Push { PassConstants pc; };

const float PI = 3.14159265358979323846;

// Shadow-map pixel and linear light depth of a world point; false outside the light's view.
bool to_shadow_map(vec3 p, out uint index, out float depth) {
    vec4 view = frame.light_view * vec4(p, 1.0);
    vec4 clip = frame.light_proj * view;
    depth = -view.z;
    if (clip.w <= 0.0) return false;
    vec2 ndc = clip.xy / clip.w;
    if (any(lessThan(ndc, vec2(-1.0))) || any(greaterThanEqual(ndc, vec2(1.0)))) return false;
    uvec2 size = frame.sizes.xy;
    uvec2 texel = min(uvec2((ndc * 0.5 + 0.5) * vec2(size)), size - 1u);
    index = texel.y * size.x + texel.x;
    return true;
}

// Is a receiver at light depth `depth`, on triangle `own`, in shadow at time t? Ranges of the
// receiver's own triangle are skipped (the self-shadow fix of the paper, 3.3).
bool shadowed_temporal(uint index, float depth, float t, uint own) {
    RangeArray range_array = RangeArray(pc.range_address);
    for (uint r = range_heads[index]; r != END_OF_LIST; r = range_array.ranges[r - 1u].next) {
        Range range = range_array.ranges[r - 1u];
        if (range.id == own || t < range.t_s || t > range.t_e) continue;
        float span = range.t_e - range.t_s;
        float occluder = span > 0.0 ? mix(range.d_s, range.d_e, (t - range.t_s) / span)
                                    : range.d_s;
        if (occluder < depth) return true;
    }
    return false;
}

bool shadowed_plain(uint index, float depth, uint own) {
    uint64_t nearest = plain_depths[index];
    uint id = uint(nearest & 0xffffffffUL);
    if (id == NO_TRIANGLE || id == own) return false;
    return uintBitsToFloat(uint(nearest >> 32)) < depth;
}

// Time-dependent shadow maps: the map of the sample's time stratum, depth only, no id (the
// time mismatch between that map and the sample is the method's self-shadow artifact).
bool shadowed_tsm(uint index, float depth, uint stratum) {
    uint layer_size = frame.sizes.x * frame.sizes.y;
    return uintBitsToFloat(tsm_depths[stratum * layer_size + index]) < depth;
}

vec3 shade(uvec2 pixel, uint key, uint rotation, uint k, uint64_t hit) {
    uint id = uint(hit & 0xffffffffUL);
    if (id == NO_TRIANGLE) return vec3(0.0);
    float view_depth = uintBitsToFloat(uint(hit >> 32));
    float t;
    vec2 offset;
    pixel_sample(key, rotation, k, frame.sampling.x, t, offset);
    if ((pc.flags & FIXED_TIME) != 0u) t = pc.time;
    vec3 dir = camera_ray(frame, vec2(pixel) + offset);
    vec3 p = frame.camera_position.xyz + view_depth * dir;

    SceneVertex a = vertices[3u * id], b = vertices[3u * id + 1u], c = vertices[3u * id + 2u];
    vec3 pa = mix(a.p0.xyz, a.p1.xyz, t), pb = mix(b.p0.xyz, b.p1.xyz, t);
    vec3 pc_ = mix(c.p0.xyz, c.p1.xyz, t);
    vec3 n = normalize(cross(pb - pa, pc_ - pa));
    if (dot(n, -dir) < 0.0) n = -n;  // two-sided: the face the camera sees
    vec3 albedo = triangles[id].albedo_flags.rgb;

    bool spot = frame.light_position.w > 0.5;
    vec3 to_light = spot ? frame.light_position.xyz - p : -frame.light_direction.xyz;
    float dist2 = spot ? dot(to_light, to_light) : 1.0;
    vec3 l = normalize(to_light);
    float cos_theta = dot(n, l);
    vec3 ambient = frame.light_params.y * albedo;
    if (cos_theta <= 0.0) return ambient;
    if (spot && dot(-l, frame.light_direction.xyz) < frame.light_direction.w) return ambient;
    vec3 direct = albedo / PI * frame.light_params.x * cos_theta / dist2;

    if (pc.mode != SHADOW_NONE) {
        // Normal offset of a fraction of a shadow texel keeps neighbouring triangles of the
        // same surface from shadowing the receiver where the map is coarser than the image.
        float light_depth = -(frame.light_view * vec4(p, 1.0)).z;
        float texel = frame.light_texel.x * (spot ? light_depth : 1.0);
        vec3 q = p + n * (frame.light_params.z * texel);
        uint index;
        float depth;
        if (to_shadow_map(q, index, depth)) {
            depth *= 1.0 - frame.light_params.w;
            bool dark;
            if (pc.mode == SHADOW_TEMPORAL) {
                dark = shadowed_temporal(index, depth, t, id);
            } else if (pc.mode == SHADOW_COVERAGE) {
                // The 2017 paper's final test: the covering triangle does not shadow itself,
                // it shadows everything else at a covered texel, and elsewhere the ranges
                // decide. "Shadows everything else" is made "shadows what is behind it" (its
                // depth at the sample's time, from the coverage map), as its range would:
                // neighbouring triangles of one surface must not shadow each other where a
                // texel straddles their shared edge.
                uint cover = coverage[index];
                if (cover == NO_TRIANGLE) {
                    dark = shadowed_temporal(index, depth, t, id);
                } else {
                    vec2 d = cover_depth[index];
                    dark = cover != id && mix(d.x, d.y, t) < depth;
                }
            } else if (pc.mode == SHADOW_TSM) {
                dark = shadowed_tsm(index, depth,
                                    time_stratum(rotation, k, frame.sampling.x));
            } else {
                dark = shadowed_plain(index, depth, id);
            }
            if (dark) return ambient;
        }
    }
    return direct + ambient;
}

void main() {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= frame.sizes.z || pixel.y >= frame.sizes.w) return;
    uint p = pixel.y * frame.sizes.z + pixel.x;
    uint key = pixel_key(pixel, frame.sampling.y);
    uint rotation = stratum_rotation(key, frame.sampling.x);
    vec3 sum = vec3(0.0);
    float moving = 0.0;  // samples that see a moving triangle: the moving-object mask
    for (uint j = 0u; j < pc.sample_count; ++j) {
        uint64_t hit = visibility[p * pc.sample_count + j];
        sum += shade(pixel, key, rotation, pc.first_sample + j, hit);
        uint id = uint(hit & 0xffffffffUL);
        if (id != NO_TRIANGLE && has_flag(triangles[id], TRIANGLE_MOVING)) moving += 1.0;
    }
    radiance[p] += vec4(sum, moving) / float(frame.sampling.x);
}
