#version 450
// Collection sub-pass for the exact lookup: one range per triangle and texel over the whole
// shutter (collection_exact.glsl).
#define COLLECT_RANGES
#define CONSERVATIVE_COLLECTION
#include "collection_exact.glsl"
