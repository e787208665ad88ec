#version 450
// The visibility-mask pass for deferred engines: for every pixel of the host's depth image,
// rebuild the world position (and the normal, from the host's normal image or the depth
// neighbours), and write the fraction of the shutter during which that point sees the light
// into the host's single-channel image, ready for its own lighting. Background pixels get 1.
// Two variants (specialization constant MOVING): receivers standing still (ms_lit_fraction)
// or moving as the host's motion image says (ms_lit_fraction_moving: each range tested
// where the point is at that time).
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
layout(set = 0, binding = 2) writeonly uniform image2D mask;
// rgb: the point's world displacement over the shutter, p(1) - p(0) (read when MOVING).
layout(set = 0, binding = 3) uniform sampler2D motion_image;

layout(constant_id = 0) const bool MOVING = false;

const uint MASK_HAS_NORMALS = 1u;       // read the normal image (else rebuild from depth)
const uint MASK_NORMALS_UNORM = 2u;     // stored as n * 0.5 + 0.5

layout(push_constant) uniform Push {
    mat4 inv_view_proj;     // camera clip -> world (the host's matrices, Vulkan NDC)
    uint64_t map;           // MsShadowMap header
    uvec2 size;             // pixels
    float background_depth; // the depth buffer's clear value: no surface there
    uint flags;             // MASK_*
    uint64_t over_budget;   // u32: pixels whose lookups ran past loop_budget iterations
    uint loop_budget;       // 0: the device does not limit loops
    float time;             // the shutter time the depth image shows (read when MOVING)
} pc;

layout(buffer_reference, std430, buffer_reference_align = 4) buffer Counter { uint count; };

vec3 world_at(ivec2 pixel, float depth) {
    vec2 ndc = (vec2(pixel) + 0.5) / vec2(pc.size) * 2.0 - 1.0;
    vec4 p = pc.inv_view_proj * vec4(ndc, depth, 1.0);
    return p.xyz / p.w;
}

// A normal from the depth neighbours: on each axis the neighbour whose depth differs least
// (so that a depth edge next to the pixel does not bend it).
vec3 normal_from_depth(ivec2 pixel, vec3 p) {
    ivec2 last = ivec2(pc.size) - 1;
    vec3 dx = vec3(0.0), dy = vec3(0.0);
    float best_x = 1e30, best_y = 1e30;
    for (int s = -1; s <= 1; s += 2) {
        ivec2 qx = clamp(pixel + ivec2(s, 0), ivec2(0), last);
        ivec2 qy = clamp(pixel + ivec2(0, s), ivec2(0), last);
        float zx = texelFetch(depth_image, qx, 0).r, zy = texelFetch(depth_image, qy, 0).r;
        if (qx != pixel && zx != pc.background_depth) {
            vec3 d = (world_at(qx, zx) - p) * float(s);
            if (dot(d, d) < best_x) { best_x = dot(d, d); dx = d; }
        }
        if (qy != pixel && zy != pc.background_depth) {
            vec3 d = (world_at(qy, zy) - p) * float(s);
            if (dot(d, d) < best_y) { best_y = dot(d, d); dy = d; }
        }
    }
    vec3 n = cross(dx, dy);
    return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), pc.size))) return;
    float depth = texelFetch(depth_image, pixel, 0).r;
    if (depth == pc.background_depth) {
        imageStore(mask, pixel, vec4(1.0));
        return;
    }
    vec3 p = world_at(pixel, depth);
    vec3 n;
    if ((pc.flags & MASK_HAS_NORMALS) != 0u) {
        n = texelFetch(normal_image, pixel, 0).xyz;
        if ((pc.flags & MASK_NORMALS_UNORM) != 0u) n = n * 2.0 - 1.0;
        n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
    } else {
        n = normal_from_depth(pixel, p);
    }
    // The receiver offset goes to the side the light is tested from.
    MsShadowMap map = MsShadowMap(pc.map);
    MsLight light = map.light;
    vec3 to_light = light.position.w > 0.5 ? light.position.xyz - p : -light.direction.xyz;
    if (dot(n, to_light) < 0.0) n = -n;
    float lit;
    if (MOVING) {
        vec3 motion = texelFetch(motion_image, pixel, 0).xyz;
        vec3 p0 = p - pc.time * motion;
        lit = ms_lit_fraction_moving(map, p0, p0 + motion, n, MS_NO_TRIANGLE);
    } else {
        lit = ms_lit_fraction(map, p, n, MS_NO_TRIANGLE);
    }
    imageStore(mask, pixel, vec4(lit));
    // The device leaves loops past a fixed count: say so when this pixel's lookup may have
    // come near it (the value above may then be cut short).
    if (pc.loop_budget > 0u && ms_loop_iterations > pc.loop_budget) {
        atomicAdd(Counter(pc.over_budget).count, 1u);
    }
}
