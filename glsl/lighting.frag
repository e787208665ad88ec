#version 450
// Lighting pass, visibility: for each sample of this pixel in the current chunk, intersect the
// camera ray with the triangle at the sample's time, and keep the nearest hit per sample with
// a 64-bit atomicMin of (distance bits << 32 | triangle id). Shading happens once per sample
// afterwards (resolve.comp), so the hardware depth test is not needed and any spp works.
#extension GL_EXT_shader_atomic_int64 : require
#include "shared.glsl"
#include "raster_camera.glsl"
#include "time_bounds.glsl"

// The triangle, from the geometry shader: corners at t = 0 and t = 1, id in p0[0].w's bits.
layout(location = 0) flat in vec4 in_p0[3];
layout(location = 3) flat in vec3 in_p1[3];

vec3 origin, ray00, ray_dx, ray_dy;
float near, far;
vec3 p0[3];
uint id;
Uint64Array visibility;

// Tests sample k (the chunk's j-th) at time t and keeps the nearest hit.
void test_sample(uint p, uint j, vec2 at, float t) {
    vec3 dir = ray00 + at.x * ray_dx + at.y * ray_dy;
    // p0 + t (p1 - p0), not mix(): a corner that does not move is then exactly p0 at
    // every time, as it is for the static triangles that share it (no crack between).
    float depth = intersect_triangle(origin, dir, p0[0] + t * (in_p1[0] - p0[0]),
                                     p0[1] + t * (in_p1[1] - p0[1]),
                                     p0[2] + t * (in_p1[2] - p0[2]));
    if (depth < near || depth > far) return;
    uint64_t packed = (uint64_t(floatBitsToUint(depth)) << 32) | uint64_t(id);
    atomicMin(visibility.v[p * pc.sample_count + j], packed);
}

void main() {
    origin = vec3(cam.origin[0], cam.origin[1], cam.origin[2]);
    near = cam.near;
    far = cam.far;
    ray00 = vec3(cam.ray00[0], cam.ray00[1], cam.ray00[2]);
    ray_dx = vec3(cam.ray_dx[0], cam.ray_dx[1], cam.ray_dx[2]);
    ray_dy = vec3(cam.ray_dy[0], cam.ray_dy[1], cam.ray_dy[2]);
    p0 = vec3[3](in_p0[0].xyz, in_p0[1].xyz, in_p0[2].xyz);
    id = floatBitsToUint(in_p0[0].w);
    // A static triangle is intersected at t = 0 exactly, whatever the sample's time (see
    // resolve.comp).
    bool moving = false;
    for (int i = 0; i < 3; ++i) moving = moving || p0[i] != in_p1[i];
    visibility = Uint64Array(pc.visibility);
    uvec2 pixel = uvec2(gl_FragCoord.xy);
    uint p = pixel.y * cam.width + pixel.x;
    uint spp = cam.spp;
    uint key = pixel_key(pixel, cam.seed);
    uint rotation = stratum_rotation(key, spp);
    bool fixed_time = (pc.flags & FIXED_TIME) != 0u;
    if (!moving || fixed_time) {
        for (uint j = 0u; j < pc.sample_count; ++j) {
            float t;
            vec2 offset;
            pixel_sample(key, rotation, pc.first_sample + j, spp, t, offset);
            t = moving ? pc.time : 0.0;
            test_sample(p, j, vec2(pixel) + offset, t);
        }
        return;
    }
    // A moving triangle: only the time strata that overlap the pixel's time bound. Sample k
    // lies in stratum (k + rotation) mod spp, within [s, s + 1] / spp (rounding may reach
    // the upper end).
    vec3 q[3], m[3];
    for (int i = 0; i < 3; ++i) {
        q[i] = p0[i] - origin;
        m[i] = in_p1[i] - p0[i];
    }
    vec2 bound = pixel_time_bounds(pixel_planes(ray00, ray_dx, ray_dy, vec2(pixel)), q, m);
    if (bound.x > bound.y) return;
    float strata = float(spp);
    const float SLACK = 1.0 / 65536.0;  // the bound's and the sample times' rounding
    // In ints, clamped after the conversion: the loop runs at most spp times whatever the
    // bound holds.
    int first = clamp(int(floor((bound.x - SLACK) * strata)), 0, int(spp) - 1);
    int last = clamp(int(floor((bound.y + SLACK) * strata)), 0, int(spp) - 1);
    for (int n = first; n <= last; ++n) {
        uint s = uint(n);
        uint k = s >= rotation ? s - rotation : s + spp - rotation;
        uint j = k - pc.first_sample;  // wraps past the chunk's samples when k is before them
        if (j >= pc.sample_count) continue;
        float t;
        vec2 offset;
        pixel_sample(key, rotation, k, spp, t, offset);
        test_sample(p, j, vec2(pixel) + offset, t);
    }
}
