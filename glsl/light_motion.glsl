// A light that moves during the shutter (issue 38; LightView::moving_to): its pose at t = 1,
// at the end of a temporal map's header, and the lookups' view of it. Include after
// motion_shadows.glsl.
//
// The map is built in the light's moving frame: each vertex's light-clip position at t = 0
// with the t = 0 view, at t = 1 with the t = 1 view, blended between (exact for a
// translating light). A receiver is read the same way: a sample at time t through the map
// of ms_map_at(map, header, t) (the blend of the two views, the light's position and
// direction at t), and a moving receiver's path with its t = 1 end moved into the t = 0
// view's world by ms_light_frame_end (the t = 0 view then sees it where the t = 1 view does)
// and, under a turning light, its normal carried through the same frame (ms_light_turns).
// For a still light (light.emission.y = 0) both leave everything as it is.
#ifndef MS_LIGHT_MOTION_GLSL
#define MS_LIGHT_MOTION_GLSL

// The pose at t = 1 (std430, 160 bytes); zeros for a still light.
struct MsLightEnd {
    mat4 view;          // world -> light view at t = 1
    mat4 frame;         // inverse(view at t = 0) * view at t = 1: a world point at t = 1 as
                        // the t = 0 view must see it to see it as the t = 1 view does
    vec4 position;      // xyz at t = 1; w = 1
    vec4 direction;     // xyz unit at t = 1; w = cos(cone half angle), as MsLight's
};

// Where MsLightEnd sits in a temporal map's header: after MsShadowMap's members.
const uint64_t MS_LIGHT_END_OFFSET = 320UL;

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer MsLightEndRef {
    MsLightEnd end;
};

bool ms_light_moves(MsLight light) {
    return light.emission.y != 0.0;
}

MsLightEnd ms_light_end(uint64_t header) {
    return MsLightEndRef(header + MS_LIGHT_END_OFFSET).end;
}

// The light at time t, from its pose at t = 0 (`light`) and its MsLightEnd at `end_address`:
// the view blended between the two ends, the position linear, the direction the normalised
// blend. A still light as it is.
MsLight ms_light_at(MsLight light, uint64_t end_address, float t) {
    if (!ms_light_moves(light)) return light;
    MsLightEnd end = MsLightEndRef(end_address).end;
    // a + t (b - a): exactly a where b = a (a light that does not move at all).
    light.view = light.view + t * (end.view - light.view);
    light.position.xyz += t * (end.position.xyz - light.position.xyz);
    vec3 d0 = light.direction.xyz, d1 = end.direction.xyz;
    if (d1 != d0) light.direction.xyz = normalize(d0 + t * (d1 - d0));
    return light;
}

// `map` (loaded from `header`) as a receiver at time t reads it (ms_light_at).
MsMap ms_map_at(MsMap map, uint64_t header, float t) {
    map.light = ms_light_at(map.light, header + MS_LIGHT_END_OFFSET, t);
    return map;
}

// A moving receiver's point at t = 1 moved into the t = 0 view's world (a still light's: as
// it is), for ms_lit_fraction_moving and the mask's walk: its path then runs, in the map's
// texels, from the t = 0 view's image of its t = 0 point to the t = 1 view's of its t = 1
// point.
vec3 ms_light_frame_end(MsLight light, uint64_t header, vec3 p1) {
    if (!ms_light_moves(light)) return p1;
    return (ms_light_end(header).frame * vec4(p1, 1.0)).xyz;
}

// Whether the light turns during the shutter (its direction at t = 1 is not t = 0's: a
// translating light's is the same, bit for bit), and the rotation that takes a receiver's t = 1
// point into the t = 0 view's world (`frame`'s), for ms_walk_moving_turned.
bool ms_light_turns(MsLight light, uint64_t header, out mat3 turn) {
    turn = mat3(1.0);
    if (!ms_light_moves(light)) return false;
    MsLightEnd end = ms_light_end(header);
    turn = mat3(end.frame);
    return end.direction.xyz != light.direction.xyz;
}

// The lit share of the shutter of a receiver moving from p0 (t = 0) to p1 (t = 1), unit
// normal n, under the map's light, moving or not: its path and its normal in the light's
// moving frame (ms_light_frame_end, ms_walk_moving_turned).
float ms_lit_fraction_moving_light(MsMap map, uint64_t header, vec3 p0, vec3 p1, vec3 n,
                                   uint own) {
    mat3 turn;
    bool turns = ms_light_turns(map.light, header, turn);
    MsWalk walk = ms_walk_start();
    ms_walk_moving_turned(map, p0, ms_light_frame_end(map.light, header, p1), n, turns, turn,
                          own, 0u, walk);
    return walk.sum;
}

#endif
