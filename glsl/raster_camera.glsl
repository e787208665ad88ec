// The lighting raster's push constants: its LightingRasterPush, then the camera of its
// fragment shader (RasterCamera, shared.glsl).
layout(push_constant) uniform Push {
    LightingRasterPush pc;
    RasterCamera cam;
};
