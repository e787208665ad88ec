// A camera that moves during the shutter (src/technique/camera_motion.rs): its pose at t = 1,
// right after the lighting target's CameraParams (whose camera_end holds its address). The
// lighting pass works in the t = 0 camera's frame: a vertex's t = 1 position is carried by
// `frame` to where the t = 0 camera must see it to see it as the t = 1 camera does, so each
// vertex's clip position moves linearly from the t = 0 camera's to the t = 1 camera's
// (McGuire et al. 2010), and the raster, its time bounds and its ray tests run unchanged.
// Only the pipelines made for a moving camera include this file (LIGHTING_CAMERA_MOVES,
// SHADE_CAMERA_MOVES): a still camera's keep today's arithmetic and cost.
#ifndef CAMERA_MOTION_GLSL
#define CAMERA_MOTION_GLSL

struct CameraEnd {
    mat4 frame;         // inverse(view at t = 0) * view at t = 1
    vec4 position;      // xyz: the eye at t = 1; w = 1
};

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CameraEndRef {
    CameraEnd end;
};

// A t = 1 position as the t = 0 camera must see it.
vec3 camera_end_frame(CameraEnd end, vec3 p1) {
    return (end.frame * vec4(p1, 1.0)).xyz;
}

// The world point of a sample that hit `tri` at `q`, a point of the triangle as the t = 0
// camera's frame holds it at time t (corners p0 + t (frame p1 - p0), as the ray test made
// them): the point with the same barycentric coordinates on the world triangle at t (at
// t = 0 for a still one, as shading takes it). On the surface by construction, so shading and
// the shadow test see the triangle itself, not a point beside it.
vec3 camera_end_world_point(CameraEnd end, Triangle tri, bool moving, float t, vec3 q) {
    vec3 a[3], w[3];
    float s = moving ? t : 0.0;
    for (int i = 0; i < 3; ++i) {
        a[i] = tri.p0[i] + t * (camera_end_frame(end, tri.p1[i]) - tri.p0[i]);
        w[i] = tri.p0[i] + s * (tri.p1[i] - tri.p0[i]);
    }
    vec3 e1 = a[1] - a[0], e2 = a[2] - a[0], d = q - a[0];
    vec3 n = cross(e1, e2);
    float inv = 1.0 / dot(n, n);
    float b1 = dot(cross(d, e2), n) * inv, b2 = dot(cross(e1, d), n) * inv;
    return w[0] + b1 * (w[1] - w[0]) + b2 * (w[2] - w[0]);
}

#endif
