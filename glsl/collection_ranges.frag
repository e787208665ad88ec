#version 450
// Collection sub-pass, exact construction with the static layer (no coverage map): each
// covered run appended to the texel's range list directly.
#define COLLECT_RANGES
#include "collection_exact.glsl"
