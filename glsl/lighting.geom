#version 450
// The lighting raster's geometry shader for a still camera (lighting_geom.glsl).
#include "lighting_geom.glsl"
