// motion_shadows/receiver_projection.glsl: where a receiver falls in the light's map and the
// depth it is tested at there (normal offset, receiver-plane depth, depth bias).
//
// Part of the public include motion_shadows.glsl, which includes its parts in order (each
// uses the ones before it) and is what a shader includes; GLSL_INCLUDE is the parts
// concatenated. Every name starts with ms_ / Ms / MS_.

// Where a world point falls in the light's image, in texels from the map's corner
// (continuous: texel (i, j) spans [i, i + 1) x [j, j + 1)), and its linear light depth;
// false outside the light's view.
bool ms_light_texel_coords(MsLight light, uvec2 size, vec3 p, out vec2 coords,
                           out float depth) {
    vec4 view = light.view * vec4(p, 1.0);
    vec4 clip = light.proj * view;
    depth = -view.z;
    coords = vec2(0.0);
    if (clip.w <= 0.0) return false;
    vec2 ndc = clip.xy / clip.w;
    if (any(lessThan(ndc, vec2(-1.0))) || any(greaterThanEqual(ndc, vec2(1.0)))) return false;
    coords = (ndc * 0.5 + 0.5) * vec2(size);
    return true;
}

// The texel (x, y) of the map and the linear light depth of a world point; false outside
// the light's view.
bool ms_project_texel(MsLight light, uvec2 size, vec3 p, out uvec2 texel, out float depth) {
    vec2 coords;
    texel = uvec2(0u);
    if (!ms_light_texel_coords(light, size, p, coords, depth)) return false;
    texel = min(uvec2(coords), size - 1u);
    return true;
}

// The texel of the map and the linear light depth of a world point; false outside the
// light's view (then nothing in the map can shadow the point).
bool ms_project(MsLight light, uvec2 size, vec3 p, out uint texel_index, out float depth) {
    uvec2 texel;
    bool seen = ms_project_texel(light, size, p, texel, depth);
    texel_index = texel.y * size.x + texel.x;
    return seen;
}

// The receiver point actually tested: moved by the light's normal offset (a fraction of a
// shadow texel) along the normal n (unit, on the side the light is tested from), so that
// neighbouring triangles of the same surface do not shadow it where the map is coarser
// than the image.
vec3 ms_offset_receiver(MsLight light, vec3 p, vec3 n) {
    bool spot = light.position.w > 0.5;
    float light_depth = -(light.view * vec4(p, 1.0)).z;
    float texel = light.bias.z * (spot ? light_depth : 1.0);
    return p + n * (light.bias.x * texel);
}

// The depth of the receiver's tangent plane (through p, unit normal n) where the ray of the
// centre of `texel` meets it, or `depth` (p's own) where that ray runs along the plane.
// Why: every caster in the texel is stored as it is at the texel's centre, and a receiver
// compared at its own depth differs from its own plane there by up to half a texel times
// its slope, which at grazing light is many texels of depth: acne, or, with a normal offset
// large enough to hide it, lost contact shadows. At the centre the plane's depth is what a
// planar receiver's neighbours store, so they no longer shadow it while anything in front
// of the plane still does. Assumes a projection without shear (the library's own lights).
float ms_receiver_plane_depth(MsLight light, uvec2 size, uvec2 texel, vec3 p, vec3 n,
                              float depth) {
    vec2 c = (vec2(texel) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 pv = (light.view * vec4(p, 1.0)).xyz;
    vec3 nv = mat3(light.view) * n;
    vec3 o = vec3(0.0), d = vec3(0.0, 0.0, -1.0);
    if (light.position.w > 0.5) {
        d.xy = (c + vec2(light.proj[2][0], light.proj[2][1])) /
               vec2(light.proj[0][0], light.proj[1][1]);
    } else {
        o.xy = (c - vec2(light.proj[3][0], light.proj[3][1])) /
               vec2(light.proj[0][0], light.proj[1][1]);
    }
    float nd = dot(nv, d);
    if (abs(nd) <= 1e-6 * length(d)) return depth;
    return -(o + d * (dot(nv, pv - o) / nd)).z;
}

// The light depth an offset receiver point q (unit normal n) in `texel`, at linear light
// depth `depth`, is tested with: if the light asks for it, its plane's depth at the texel's
// centre; then the relative depth bias.
float ms_tested_depth(MsLight light, uvec2 size, uvec2 texel, vec3 q, vec3 n, float depth) {
    if (light.bias.w > 0.5) depth = ms_receiver_plane_depth(light, size, texel, q, n, depth);
    return depth * (1.0 - light.bias.y);
}

// The texel and the light depth a receiver at p (unit normal n) is tested with: p moved
// by the normal offset, then, if the light asks for it, its plane's depth at the texel.
bool ms_receiver_texel(MsLight light, uvec2 size, vec3 p, vec3 n, out uint texel_index,
                       out float depth) {
    vec3 q = ms_offset_receiver(light, p, n);
    uvec2 texel;
    bool seen = ms_project_texel(light, size, q, texel, depth);
    texel_index = texel.y * size.x + texel.x;
    if (!seen) return false;
    depth = ms_tested_depth(light, size, texel, q, n, depth);
    return true;
}
