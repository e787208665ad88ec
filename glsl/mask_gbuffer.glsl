// mask_gbuffer.glsl: a host's G-buffer point as the mask passes rebuild it (the temporal
// map's visibility_mask.comp and time-dependent shadow maps' tsm_mask.comp), so that both
// test exactly the same receivers.
//
// The includer declares, before including this file:
//   uniform sampler2D depth_image;     the host's depth image
//   uniform sampler2D normal_image;    its normal image (read when pc.flags has
//                                      MASK_HAS_NORMALS)
//   uniform sampler2D position_image;  its world-position image (read when pc.flags has
//                                      MASK_HAS_POSITIONS)
//   push constants `pc` with members   mat4 inv_view_proj (camera clip -> world, Vulkan
//                                      NDC), uvec2 size (pixels), float background_depth
//                                      (the depth image's clear value), uint flags (MASK_*)

// MASK_HAS_NORMALS (read the normal image, else rebuild from depth) and MASK_NORMALS_UNORM
// (stored as n * 0.5 + 0.5): generated from src/technique/gpu_constants.rs.
#include "gpu_constants.glsl"

// The world point of `pixel`, whose depth image holds `depth`: the host's position image
// where it has one, else rebuilt from the depth. Why a position image: a 32-bit float depth
// of a standard (not reversed) depth buffer carries an error along the view ray of about
// z^2 / near * 6e-8, which moves a receiver off its own plane; at grazing light its coplanar
// neighbours then stand in front of it and streak it with shadow (with near 0.1, measured on
// hard-grazing: RMSE 0.37 against the truth with depth alone, 0.06 with positions).
vec3 world_at(ivec2 pixel, float depth) {
    if ((pc.flags & MASK_HAS_POSITIONS) != 0u) return texelFetch(position_image, pixel, 0).xyz;
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

// The unit world normal of the G-buffer point p of `pixel` (the normal image's, or rebuilt
// from the depth neighbours; 0 where neither gives one), turned to the side the light is
// tested from (the receiver offset goes there).
vec3 gbuffer_normal(ivec2 pixel, vec3 p, MsLight light) {
    vec3 n;
    if ((pc.flags & MASK_HAS_NORMALS) != 0u) {
        n = texelFetch(normal_image, pixel, 0).xyz;
        if ((pc.flags & MASK_NORMALS_UNORM) != 0u) n = n * 2.0 - 1.0;
        n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
    } else {
        n = normal_from_depth(pixel, p);
    }
    vec3 to_light = light.position.w > 0.5 ? light.position.xyz - p : -light.direction.xyz;
    if (dot(n, to_light) < 0.0) n = -n;
    return n;
}
