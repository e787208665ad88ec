#version 450
// Lighting pass, visibility: for each sample of this pixel in the current chunk, intersect the
// camera ray with the triangle at the sample's time, and keep the nearest hit per sample with
// a 64-bit atomicMin of (distance bits << 32 | triangle id). Shading happens once per sample
// afterwards (resolve.comp), so the hardware depth test is not needed and any spp works.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 1) readonly buffer Vertices { SceneVertex vertices[]; };
layout(std430, set = 0, binding = 3) buffer Visibility { uint64_t visibility[]; };
layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) flat in uint in_id;

void main() {
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * frame.sizes.z + pixel.x;
    SceneVertex a = vertices[3u * in_id], b = vertices[3u * in_id + 1u],
                c = vertices[3u * in_id + 2u];
    uint spp = frame.sampling.x;
    uint key = pixel_key(pixel, frame.sampling.y);
    uint rotation = stratum_rotation(key, spp);
    vec3 origin = frame.camera_position.xyz;
    float near = frame.camera_position.w, far = frame.camera_forward.w;
    for (uint j = 0u; j < pc.sample_count; ++j) {
        float t;
        vec2 offset;
        pixel_sample(key, rotation, pc.first_sample + j, spp, t, offset);
        if ((pc.flags & FIXED_TIME) != 0u) t = pc.time;
        vec3 dir = camera_ray(frame, vec2(pixel) + offset);
        float depth = intersect_triangle(origin, dir, mix(a.p0.xyz, a.p1.xyz, t),
                                         mix(b.p0.xyz, b.p1.xyz, t), mix(c.p0.xyz, c.p1.xyz, t));
        if (depth < near || depth > far) continue;
        uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(in_id);
        atomicMin(visibility[p * pc.sample_count + j], packed);
    }
}
