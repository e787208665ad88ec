#version 460
// The viewer's deferred shading: Lambert with the library's lit share of the shutter, the
// same terms as the offline deferred frame's host-side shading (render/deferred.rs: shade,
// direct_factor), then 2^exposure, clamp and the sRGB curve (output/png.rs), so that the
// window shows what `render --frame deferred` writes. The stochastic frame's radiance
// (the lighting pass's) takes only the exposure and the curve.
#extension GL_EXT_buffer_reference : require

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D depth_image;
layout(set = 0, binding = 1) uniform sampler2D normal_image;
layout(set = 0, binding = 2) uniform usampler2D id_image;
layout(set = 0, binding = 3, r32f) uniform readonly image2D lit_image;
layout(set = 0, binding = 4, rgba8) uniform writeonly image2D output_image;
// The stochastic frame's radiance (the lighting pass's, written into this image).
layout(set = 0, binding = 5, rgba32f) uniform readonly image2D radiance_image;
// The split view's right-hand method's lit shares, read from column width / 2 on.
layout(set = 0, binding = 6, r32f) uniform readonly image2D split_lit_image;

// The number of triangles, then per triangle (its global id) the albedo of its mesh.
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Albedos {
    uint count;
    vec4 albedo[];
};

// The overlay's codes, OVERLAY_WIDTH a row: 0 leaves the pixel, 1 darkens it, 2 is text.
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer Overlay {
    uint code[];
};

layout(push_constant) uniform Push {
    mat4 inv_view_proj;
    // xyz, w > 0.5 for a spot light.
    vec4 light_position;
    // xyz the light's direction, w the cosine of a spot's half cone.
    vec4 light_direction;
    Albedos albedos;
    Overlay overlay;
    // Intensity (spot) or irradiance (directional).
    float emission;
    float ambient;
    float exposure_scale;
    // Width | height << 15 (0: no overlay); bit 31: show the stochastic frame's radiance;
    // bit 30: the split view.
    uint overlay_size;
} pc;

const float PI = 3.14159265358979;

vec3 srgb(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    vec3 curve = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(12.92 * c, curve, greaterThan(c, vec3(0.0031308)));
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(output_image);
    if (any(greaterThanEqual(p, size))) {
        return;
    }
    float depth = texelFetch(depth_image, p, 0).r;
    vec3 radiance = vec3(0.0);
    bool stochastic = (pc.overlay_size >> 31) != 0u;
    bool split = ((pc.overlay_size >> 30) & 1u) != 0u;
    if (stochastic) {
        radiance = imageLoad(radiance_image, p).rgb;
    } else if (depth < 1.0) {
        vec2 ndc = (vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0;
        vec4 h = pc.inv_view_proj * vec4(ndc, depth, 1.0);
        vec3 position = h.xyz / h.w;
        vec3 n = texelFetch(normal_image, p, 0).xyz;
        uint id = texelFetch(id_image, p, 0).r;
        // An id past the table (not the viewer's own scenes: the table is made again
        // whenever the posed scene's triangles change) reads nothing: magenta shows it.
        vec3 albedo = id < pc.albedos.count ? pc.albedos.albedo[id].rgb : vec3(1.0, 0.0, 1.0);
        bool spot = pc.light_position.w > 0.5;
        vec3 to_light = spot ? pc.light_position.xyz - position : -pc.light_direction.xyz;
        float dist2 = spot ? dot(to_light, to_light) : 1.0;
        vec3 l = normalize(to_light);
        float cos_theta = dot(n, l);
        bool in_cone = !spot || dot(-l, pc.light_direction.xyz) >= pc.light_direction.w;
        float direct = 0.0;
        if (cos_theta > 0.0 && in_cone) {
            direct = pc.emission * cos_theta / (PI * dist2);
        }
        float lit = split && p.x >= size.x / 2 ? imageLoad(split_lit_image, p).r
                                               : imageLoad(lit_image, p).r;
        radiance = albedo * (pc.ambient + direct * lit);
    }
    // Rounded here to one of 256 levels: the store's own float-to-unorm rounding is not
    // pinned down by Vulkan.
    vec3 encoded = round(srgb(radiance * pc.exposure_scale) * 255.0) / 255.0;
    uvec2 overlay = uvec2(pc.overlay_size & 0x7fffu, (pc.overlay_size >> 15) & 0x7fffu);
    if (split && overlay.x > 0u && p.x == size.x / 2) {
        // The seam, with the overlay (off, each half is its method's frame exactly).
        encoded = vec3(1.0);
    }
    if (all(lessThan(uvec2(p), overlay))) {
        uint code = pc.overlay.code[uint(p.y) * overlay.x + uint(p.x)];
        if (code == 1u) {
            encoded = round(encoded * 0.35 * 255.0) / 255.0;
        } else if (code == 2u) {
            encoded = vec3(1.0);
        }
    }
    imageStore(output_image, p, vec4(encoded, 1.0));
}
