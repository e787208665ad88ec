// motion_shadows.glsl: the temporal shadow map as a host's own shaders see it.
//
// Include this file in any GLSL shader (it is also `motion_shadows::technique::GLSL_INCLUDE`
// in Rust) and pass the map's header address (`TemporalShadowMap::header_address()`, 8 bytes)
// in your push constants or uniform buffer. Then
//
//     MsMap map = ms_load(MsShadowMap(header_address));  // once per invocation
//     float lit = ms_visibility(map, world_position, world_normal, t, MS_NO_TRIANGLE);
//
// gives 1 where the point sees the light at shutter time t in [0, 1] and 0 where a triangle
// of the map's casters blocks it then. Pass the receiver's own triangle id instead of
// MS_NO_TRIANGLE when you know it (the library's own lighting pass does): its ranges are
// then skipped, which is the papers' fix for self-shadowing. Needs the device features
// bufferDeviceAddress and shaderInt64 (both required by the library anyway).
//
// Everything here is read-only, and every name starts with ms_ / Ms / MS_ so that it cannot
// clash with the host's own. The layouts mirror `motion_shadows::technique::gpu_types`
// (a test checks that they agree).
//
// The code is in glsl/motion_shadows/, one concept a file, included below in order (each part
// uses the ones before it): include this file, not a part. GLSL_INCLUDE in Rust is the same
// parts concatenated, self-contained, for hosts that serve it from their own include callback.

#include "motion_shadows/map_layout.glsl"
#include "motion_shadows/receiver_projection.glsl"
#include "motion_shadows/point_lookups.glsl"
#include "motion_shadows/shutter_lookups.glsl"
#include "motion_shadows/receiver_path.glsl"
#include "motion_shadows/filtered_lookups.glsl"
