#version 450
// Lighting pass, visibility: for each sample of this pixel in the current chunk, intersect the
// camera ray with the triangle at the sample's time, and keep the nearest hit per sample with
// a 64-bit atomicMin of (distance bits << 32 | triangle id). Shading happens once per sample
// afterwards (resolve.comp), so the hardware depth test is not needed and any spp works.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"

layout(push_constant) uniform Push { PassConstants pc; };

layout(location = 0) flat in uint in_prim;

void main() {
    // Only the members used here are loaded (each load from an address is made lane by lane
    // on a CPU device, and this runs for every fragment).
    TargetHeader header = TargetHeader(pc.target);
    uvec4 image = header.camera.image;
    vec4 position = header.camera.position;
    float far = header.camera.forward.w;
    vec3 ray00 = header.camera.ray00.xyz, ray_dx = header.camera.ray_dx.xyz;
    vec3 ray_dy = header.camera.ray_dy.xyz;
    DrawRecord d = DrawTable(pc.draws).draws[pc.draw_index];
    Triangle tri = fetch_triangle(d, in_prim);
    // A static triangle is intersected at t = 0 exactly, whatever the sample's time (see
    // resolve.comp).
    bool moving = false;
    for (int i = 0; i < 3; ++i) moving = moving || tri.p0[i] != tri.p1[i];
    uint id = d.first_id + in_prim;
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
        float depth = intersect_triangle(origin, dir, mix(tri.p0[0], tri.p1[0], t),
                                         mix(tri.p0[1], tri.p1[1], t),
                                         mix(tri.p0[2], tri.p1[2], t));
        if (depth < near || depth > far) continue;
        uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id);
        atomicMin(visibility.v[p * pc.sample_count + j], packed);
    }
}
