#version 450
// Test-only: writes known values through every shared struct, and copies the frame
// parameters back, so tests/gpu/layout.rs can check that the Rust mirrors have the same layout.
#include "shared.glsl"

layout(local_size_x = 1) in;

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(std430, set = 0, binding = 1) buffer Nodes { Node nodes[]; };
layout(std430, set = 0, binding = 2) buffer Ranges { Range ranges[]; };
layout(std430, set = 0, binding = 3) buffer Vertices { SceneVertex vertices[]; };
layout(std430, set = 0, binding = 4) buffer CounterBlock { Counters counters; };
layout(std430, set = 0, binding = 5) buffer FrameCopy { FrameParams frame_copy; };
layout(std430, set = 0, binding = 6) buffer PushCopy { PassConstants push_copy; };
layout(push_constant) uniform Push { PassConstants pc; };

void main() {
    nodes[1] = Node(1.5, 0.25, 7u, 9u);
    ranges[1] = Range(0.125, 0.75, 2.5, 3.5, 11u, 13u);
    vertices[1] = SceneVertex(vec4(1, 2, 3, 4), vec4(5, 6, 7, 8));
    counters = Counters(pc.first_triangle, pc.first_sample, pc.sample_count, pc.mode, 31u, 32u,
                        33u, 34u);
    frame_copy = frame;
    push_copy = pc;
}
