#version 450
// Collection sub-pass, exact construction: each covered run appended as its start and end
// nodes (for the generation pass, and the coverage map's passes).
#include "collection_exact.glsl"
