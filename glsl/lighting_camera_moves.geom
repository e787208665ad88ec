#version 450
// The lighting raster's geometry shader for a camera that moves during the shutter
// (lighting_geom.glsl, camera_motion.glsl).
#define LIGHTING_CAMERA_MOVES
#include "lighting_geom.glsl"
