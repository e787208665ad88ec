#version 450
// Lighting pass, visibility: for each sample of this pixel in the current chunk, intersect the
// camera ray with the triangle at the sample's time, and keep the nearest hit per sample with
// a 64-bit atomicMin of (distance bits << 32 | triangle id). Shading happens once per sample
// afterwards (resolve.comp), so the hardware depth test is not needed and any spp works.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

// The triangle, from the geometry shader: corners at t = 0 and t = 1, id in p0[0].w's bits.
layout(location = 0) flat in vec4 in_p0[3];
layout(location = 3) flat in vec3 in_p1[3];

void main() {
    // Only the members used here are loaded (each load from an address is made lane by lane
    // on a CPU device, and this runs for every fragment).
    TargetHeader header = TargetHeader(pc.target);
    uvec4 image = header.camera.image;
    vec4 position = header.camera.position;
    float far = header.camera.forward.w;
    vec3 ray00 = header.camera.ray00.xyz, ray_dx = header.camera.ray_dx.xyz;
    vec3 ray_dy = header.camera.ray_dy.xyz;
    vec3 p0[3] = vec3[3](in_p0[0].xyz, in_p0[1].xyz, in_p0[2].xyz);
    uint id = floatBitsToUint(in_p0[0].w);
    // A static triangle is intersected at t = 0 exactly, whatever the sample's time (see
    // resolve.comp).
    bool moving = false;
    for (int i = 0; i < 3; ++i) moving = moving || p0[i] != in_p1[i];
    Uint64Array visibility = Uint64Array(header.camera.visibility);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * image.x + pixel.x;
    uint spp = image.z;
    uint key = pixel_key(pixel, image.w);
    uint rotation = stratum_rotation(key, spp);
    vec3 origin = position.xyz;
    float near = position.w;
    for (uint j = 0u; j < pc.sample_count; ++j) {
        float t;
        vec2 offset;
        pixel_sample(key, rotation, pc.first_sample + j, spp, t, offset);
        if ((pc.flags & FIXED_TIME) != 0u) t = pc.time;
        if (!moving) t = 0.0;
        vec2 at = vec2(pixel) + offset;
        vec3 dir = ray00 + at.x * ray_dx + at.y * ray_dy;
        // p0 + t (p1 - p0), not mix(): a corner that does not move is then exactly p0 at
        // every time, as it is for the static triangles that share it (no crack between).
        float depth = intersect_triangle(origin, dir, p0[0] + t * (in_p1[0] - p0[0]),
                                         p0[1] + t * (in_p1[1] - p0[1]),
                                         p0[2] + t * (in_p1[2] - p0[2]));
        if (depth < near || depth > far) continue;
        uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id);
        atomicMin(visibility.v[p * pc.sample_count + j], packed);
    }
}
