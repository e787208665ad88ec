#version 450
// Collection sub-pass, exact construction: the geometry stage (collection_exact_geom.glsl).
#include "collection_exact_geom.glsl"
