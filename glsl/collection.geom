#version 450
// Collection sub-pass (Hong & Oh 2018, 4.1): the prism swept by a moving triangle, seen from
// the light. Two caps (t = 0 and t = 1) and, per moving edge, either four triangles around
// the centre vertex (t = 0.5) or, when the edge at t = 0 crosses the edge at t = 1 on the
// screen, two triangles through the crossing point. At most 14 triangles.
#include "shared.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 42) out;

layout(push_constant) uniform Push { MapDrawPush pc; };

layout(location = 0) in vec3 in_p0[];
layout(location = 1) in vec3 in_p1[];
layout(location = 2) in float in_valid[];

layout(location = 0) out float out_depth;
layout(location = 1) out float out_time;
layout(location = 2) flat out uint out_id;
layout(location = 3) flat out uint out_surface;  // SURFACE_*

struct PrismVertex { vec4 clip; float depth; float time; };

uint triangle_id;
uint surface = SURFACE_SIDE;

void emit_vertex(PrismVertex v) {
    gl_Position = v.clip;
    out_depth = v.depth;
    out_time = v.time;
    out_id = triangle_id;
    out_surface = surface;
    EmitVertex();
}

void emit_triangle(PrismVertex a, PrismVertex b, PrismVertex c) {
    emit_vertex(a);
    emit_vertex(b);
    emit_vertex(c);
    EndPrimitive();
}

PrismVertex average(PrismVertex a, PrismVertex b) {
    return PrismVertex(0.5 * (a.clip + b.clip), 0.5 * (a.depth + b.depth), 0.5);
}

// The point of segment a-b (clip space) that projects to screen parameter s along a-b.
PrismVertex at_screen_parameter(PrismVertex a, PrismVertex b, float s) {
    float sigma = s * a.clip.w / (s * a.clip.w + (1.0 - s) * b.clip.w);
    return PrismVertex(mix(a.clip, b.clip, sigma), mix(a.depth, b.depth, sigma), 0.0);
}

float cross2(vec2 x, vec2 y) { return x.x * y.y - x.y * y.x; }

// Side surface of edge (P, Q) moving to (P', Q').
void emit_side(PrismVertex p, PrismVertex q, PrismVertex p1, PrismVertex q1) {
    bool in_front = p.clip.w > 1e-6 && q.clip.w > 1e-6 && p1.clip.w > 1e-6 && q1.clip.w > 1e-6;
    if (in_front) {
        vec2 a = p.clip.xy / p.clip.w, b = q.clip.xy / q.clip.w;
        vec2 c = p1.clip.xy / p1.clip.w, d = q1.clip.xy / q1.clip.w;
        // Equation (1) of the paper, written with cross2 (the paper's PDP has the opposite
        // sign convention for its first argument): A + s AB = C + u CD.
        float denom = cross2(b - a, d - c);
        if (abs(denom) > 1e-12) {
            float s = cross2(c - a, d - c) / denom;
            float u = cross2(c - a, b - a) / denom;
            if (s > 0.0 && s < 1.0 && u > 0.0 && u < 1.0) {
                PrismVertex x = average(at_screen_parameter(p, q, s),
                                        at_screen_parameter(p1, q1, u));
                emit_triangle(p, p1, x);
                emit_triangle(q, q1, x);
                return;
            }
        }
    }
    PrismVertex h = PrismVertex(0.25 * (p.clip + q.clip + q1.clip + p1.clip),
                                0.25 * (p.depth + q.depth + q1.depth + p1.depth), 0.5);
    emit_triangle(p, q, h);
    emit_triangle(q, q1, h);
    emit_triangle(q1, p1, h);
    emit_triangle(p1, p, h);
}

void main() {
    DrawRecord d = load_draw(pc.draw.draws, pc.draw.draw_index);
    MsShadowMap map = MsShadowMap(pc.map);
    if (in_valid[0] == 0.0 || in_valid[1] == 0.0 || in_valid[2] == 0.0) {
        // Coverage's reset pass draws the same prisms: count each bad triangle once.
        if ((pc.flags & COUNT_INVALID) != 0u)
            atomicAdd(CounterRef(map.counters).c.invalid_triangles, 1u);
        return;
    }
    triangle_id = d.first_id + uint(gl_PrimitiveIDIn);
    MsLight light = map.light;
    // A moving light: each vertex's t = 1 position is seen from the light at t = 1, its
    // light-clip position blended between the two (the light's moving frame,
    // light_motion.glsl).
    mat4 view1 = light.view;
    if (ms_light_moves(light)) view1 = ms_light_end(pc.map).view;
    bool orthographic = light.position.w == 0.0;

    vec3 v0[3], v1[3];
    PrismVertex s0[3], s1[3];
    vec4 clip[6];
    for (int i = 0; i < 3; ++i) {
        v0[i] = (light.view * vec4(in_p0[i], 1.0)).xyz;
        v1[i] = (view1 * vec4(in_p1[i], 1.0)).xyz;
        s0[i] = PrismVertex(light.proj * vec4(v0[i], 1.0), -v0[i].z, 0.0);
        s1[i] = PrismVertex(light.proj * vec4(v1[i], 1.0), -v1[i].z, 1.0);
        clip[i] = s0[i].clip;
        clip[i + 3] = s1[i].clip;
    }
    if (outside_one_plane(clip)) return;
    bool closed = has_flag(d, DRAW_CLOSED);
    if (closed && faces_away_whole_frame(v0[0], v0[1], v0[2], v1[0], v1[1], v1[2], orthographic))
        return;

    surface = SURFACE_CAP0;
    emit_triangle(s0[0], s0[1], s0[2]);
    surface = SURFACE_CAP1;
    emit_triangle(s1[0], s1[1], s1[2]);
    surface = SURFACE_SIDE;
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        emit_side(s0[a], s0[b], s1[a], s1[b]);
    }
}
