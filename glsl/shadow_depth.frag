#version 450
// The plain map's and the reference's triangle ids (DEPTH_AND_ID), beside the depth
// attachment: the id of the nearest triangle, so that the receiver's own triangle can be
// skipped. Depth-only maps (TSM) are drawn without a fragment shader.
layout(early_fragment_tests) in;

layout(location = 0) flat in uint in_id;
layout(location = 0) out uint out_id;

void main() {
    out_id = in_id;
}
