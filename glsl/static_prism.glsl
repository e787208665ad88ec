// A static triangle's two nodes at a texel it covers (collection_static.vert rasterized it):
// the triangle at t = 0 and at t = 1, at the same depth. A closed draw's triangles facing
// away from the light are skipped, as the moving ones are when they face away all frame.
// (A triangle wound counter-clockwise toward the light is front-facing for the pipeline's
// counter-clockwise front face: Vulkan's y-down framebuffer and the projection's y flip
// cancel; tests/gpu/exact_prisms.rs checks which face of a box is kept.)

layout(location = 0) in float in_depth;
layout(location = 1) flat in uint in_id;
layout(location = 2) flat in uint in_closed;

bool static_prism_culled() {
    return in_closed != 0u && !gl_FrontFacing;
}
