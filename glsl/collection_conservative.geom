#version 450
// Collection sub-pass for the exact lookup: the exact construction's geometry stage with the
// footprint grown by a texel's half-diagonal and the triangle records written
// (collection_exact_geom.glsl).
#define CONSERVATIVE_COLLECTION
#include "collection_exact_geom.glsl"
