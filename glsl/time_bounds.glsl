// Per-pixel time bounds of a moving triangle (in the spirit of Laine et al. 2011, "Clipless
// Dual-Space Bounds for Faster Stochastic Rasterization"): the times at which the triangle may
// meet the pixel's frustum. The stochastic raster covers a moving triangle's whole sweep, so
// most of a fragment's samples have times at which the triangle is elsewhere; testing only the
// samples whose time stratum overlaps the bound skips most ray tests.
//
// The test is with the four side planes of the pixel's frustum, all through the eye. A corner
// moves linearly in world space, so its signed distance to such a plane is linear in time: for
// each plane, the times at which all three corners are outside it (the triangle is separated
// from the pixel) form one interval, found in closed form. A separated interval that starts
// before the frame or ends after it cuts the bound from that side; one in the middle would
// split it in two and is ignored (still conservative).
//
// The pixel is grown by PIXEL_MARGIN on every side: the ray tests round differently from the
// plane distances, and the margin (in pixels, thousands of times their rounding error) keeps
// every time whose ray test could hit inside the bound, so the image is the same as when every
// sample is tested.

const float PIXEL_MARGIN = 1.0 / 16.0;
const float TIME_BOUND_HUGE = 1e30;

// Plane normals through the eye in the camera's ray space. With D = det(ray_dx, ray_dy, ray00),
// the plane of image column x is cross(ray00 + x ray_dx, ray_dy) = col0 + x col1, and
// dot(it, q) = depth(q) * D * (x - column(q)) for a point q (relative to the eye) whose image
// column is column(q); rows alike: cross(ray_dx, ray00 + y ray_dy) = row0 + y col1.
struct PixelPlanes {
    vec3 n[4];  // dot(n, q) > 0 outside the pixel's frustum (for q in front of the eye)
};

PixelPlanes pixel_planes(vec3 ray00, vec3 ray_dx, vec3 ray_dy, vec2 pixel) {
    vec3 col0 = cross(ray00, ray_dy), row0 = cross(ray_dx, ray00), col1 = cross(ray_dx, ray_dy);
    float d = sign(dot(col1, ray00));  // sign of D: orients every plane the same way
    vec2 lo = pixel - PIXEL_MARGIN, hi = pixel + (1.0 + PIXEL_MARGIN);
    PixelPlanes planes;
    planes.n[0] = d * (col0 + lo.x * col1);   // left: column < lo.x outside
    planes.n[1] = -d * (col0 + hi.x * col1);  // right
    planes.n[2] = d * (row0 + lo.y * col1);   // top
    planes.n[3] = -d * (row0 + hi.y * col1);  // bottom
    return planes;
}

// Narrows [lo, hi] to the times at which plane n does not separate the triangle whose corners
// (relative to the eye) are q[i] + t m[i]. A separating plane through the eye separates the
// whole frustum, points behind the eye included, so the test holds for any corner position.
void narrow_by_plane(vec3 n, vec3 q[3], vec3 m[3], inout float lo, inout float hi) {
    // Separated at t iff dot(n, q[i]) + t dot(n, m[i]) > 0 for every corner: t in (s0, s1).
    float s0 = -TIME_BOUND_HUGE, s1 = TIME_BOUND_HUGE;
    for (int i = 0; i < 3; ++i) {
        float a = dot(n, q[i]), b = dot(n, m[i]);
        if (b > 0.0) s0 = max(s0, -a / b);
        else if (b < 0.0) s1 = min(s1, -a / b);
        else if (a <= 0.0) s1 = -TIME_BOUND_HUGE;  // this corner is never outside
    }
    if (s0 < 0.0 && s1 > 1.0) hi = -1.0;  // separated all frame
    else if (s0 < 0.0) lo = max(lo, s1);
    else if (s1 > 1.0) hi = min(hi, s0);
}

// The times in [0, 1] at which the triangle may be hit by a ray through the pixel (lo > hi:
// none).
vec2 pixel_time_bounds(PixelPlanes planes, vec3 q[3], vec3 m[3]) {
    float lo = 0.0, hi = 1.0;
    for (int p = 0; p < 4; ++p) narrow_by_plane(planes.n[p], q, m, lo, hi);
    return vec2(lo, hi);
}
