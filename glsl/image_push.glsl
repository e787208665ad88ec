// The push constants of the passes that read or write a host's images (the masks, the
// G-buffer, the radiance copy), one block per pass: mirrors of src/technique/push_constants.rs,
// probed by tests/gpu/layout.rs. Kept apart from shared.glsl because the mask shaders include
// only the public header. Needs 64-bit integer types.
#ifndef MS_IMAGE_PUSH_GLSL
#define MS_IMAGE_PUSH_GLSL

// The temporal map's visibility mask (visibility_mask.comp; 128 bytes).
struct MaskPush {
    mat4 inv_view_proj;     // camera clip -> world (the host's matrices, Vulkan NDC)
    uint64_t map;           // MsShadowMap header
    uvec2 size;             // pixels
    float background_depth; // the depth buffer's clear value: no surface there
    uint flags;             // MASK_*
    uint64_t over_budget;   // u32: pixels whose lookups ran past loop_budget iterations
    uint loop_budget;       // 0: the device does not limit loops
    float time;             // the shutter time the depth image shows (read when MOVING)
    uint64_t queue;         // the overflow queues (moving receivers, exact lookup)
    uint round;             // 0: every pixel; r > 0: the pixels of round r's queue
    uint rounds;            // follow-up rounds recorded after round 0
    uint capacity;          // entries per queue
    uint probe;             // 2 on a device with a loop limit, else 0 (loops_were_cut)
};

// The engine TSM's mask of one batch of maps (tsm_mask.comp; 128 bytes).
struct TsmMaskPush {
    mat4 inv_view_proj;     // camera clip -> world (the host's matrices, Vulkan NDC)
    uint64_t light;         // MsLight (the start of the maps' header)
    uvec2 size;             // pixels
    float background_depth; // the depth buffer's clear value: no surface there
    uint flags;             // MASK_* | TSM_*
    uvec2 map_size;         // texels of a map
    float time;             // the shutter time the G-buffer shows (read when MOVING)
    float maps;             // N
    float inv_maps;         // 1 / N: map i is drawn at (i + 0.5) * (1 / N)
    uint first_map;         // the batch's first map (layer 0)
    uint batch;             // maps in the batch (layers 0 .. batch - 1)
    uint reserved;
};

// The G-buffer (gbuffer.vert, gbuffer.frag; 96 bytes).
struct GBufferPush {
    mat4 view_proj;         // world -> camera clip (Vulkan)
    vec4 eye;               // xyz: the camera's position
    uint64_t draws;         // the DrawRecord table
    uint draw_index;        // the draw being drawn
    float time;             // the shutter time drawn
};

// The lighting target's radiance into a host image (radiance_to_image.comp; 16 bytes).
struct RadiancePush {
    uint64_t radiance;      // the lighting target's radiance buffer
    uvec2 size;             // pixels
};

#endif
