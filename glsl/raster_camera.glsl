// The camera of the lighting raster's fragment shader, pushed right after PassConstants
// (mirrors src/technique/raster_camera.rs). Push constants rather than loads from the
// target's header: a CPU device loads from an address lane by lane, and those loads were
// about half of the fragment shader's time there. 4-byte members only, so it packs at offset
// 56 and the whole block fits the 128 bytes every device offers; pc.map holds the visibility
// buffer's address.
struct RasterCamera {
    float origin[3];
    float near;
    float far;
    float ray00[3];
    float ray_dx[3];
    float ray_dy[3];
    uint width;
    uint spp;
    uint seed;
};

layout(push_constant) uniform Push {
    PassConstants pc;
    RasterCamera cam;
};
