//! Receivers that move during the shutter (`ms_lit_fraction_moving`, the mask's MOVING
//! variant), through the host's probe shader against maps the host engine built: closed
//! forms for a receiver translating under a still caster (both light kinds), for one moving
//! with or behind a moving caster, and the static answer where the receiver stands still.

use super::deferred::{self, Light, Mesh, MeshIndices, Vertex, World};
use super::{
    MOVING_PROBE_COMP, Query, SHADOW, SIDE, Shape, interval_frame, interval_world,
    lit_fraction_queries_along_texel_row, new_host, probe, run_probe, settings, square_world,
};
use crate::support::deferred_host::HostLight;
use crate::support::host::Host;
use glam::{DMat4, DVec3, Vec3};
use motion_shadows::technique::TemporalShadowMap;

/// The z range the receivers' paths keep to: well inside the square's [-1, 1] (its z edges
/// are not what these tests measure).
const Z_INSIDE: f64 = 0.6;

/// Ground, and a square of side 2 (x and z in [-1, 1] when `at(f)` is 0) at height 1,
/// translated by `at(f)` at frame f, under `light`.
fn square_over_ground(light: Light, at: impl Fn(f64) -> DVec3 + 'static) -> World {
    let (world, _, _) = square_world();
    let square = [[-1.0, -1.0], [-1.0, 1.0], [1.0, 1.0], [1.0, -1.0]].map(|[x, z]| Vertex {
        position: [x, 0.0, z],
        normal: [0.0, 1.0, 0.0],
    });
    World {
        lights: vec![light],
        meshes: vec![
            deferred::ground_mesh(),
            Mesh {
                name: "square".into(),
                vertices: square.to_vec(),
                indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
                albedo: Vec3::splat(0.5),
                closed: false,
                transform: Box::new(move |f| DMat4::from_translation(DVec3::Y + at(f))),
            },
        ],
        ..world
    }
}

fn spot_over_ground() -> Light {
    HostLight::Spot {
        position: Vec3::new(0.0, 6.0, 0.0),
        direction: Vec3::NEG_Y,
        cone_half_angle_deg: 60.0,
        intensity: 50.0,
        near: 0.5,
        far: 20.0,
    }
    .engine_light()
}

/// The world's map of frame 1, whose shutter runs from frame 0 (t = 0) to frame 1.
fn frame_map<'h>(host: &'h Host, world: &World) -> (deferred::Engine<'h>, usize) {
    let mut engine = deferred::Engine::new(host, world, settings()).expect("engine");
    let frame = engine
        .render(world, 0..2, &|f| f == 1)
        .expect("frames")
        .pop()
        .expect("frame 1 kept");
    (engine, frame.slot)
}

/// Ground receivers moving from `from[i]` to `to[i]` (normal up, no own triangle): their lit
/// fractions through the probe.
pub(super) fn moving_lit(
    host: &Host,
    map: &TemporalShadowMap,
    paths: &[(DVec3, DVec3)],
) -> Vec<f64> {
    let query = |p: DVec3| Query {
        position: p.as_vec3().to_array(),
        time: 0.0,
        normal: [0.0, 1.0, 0.0],
        own: u32::MAX,
    };
    let queries: Vec<Query> = paths
        .iter()
        .flat_map(|&(a, b)| [query(a), query(b)])
        .collect();
    let shape = Shape {
        per_invocation: 2,
        workgroup: 64,
        results_per_query: 1,
    };
    let out = run_probe(host, map, &queries, MOVING_PROBE_COMP, shape);
    out[..paths.len()].iter().map(|&v| f64::from(v)).collect()
}

/// The measure of the times in [0, 1] at which a + t (b - a) lies strictly inside (lo, hi).
fn time_inside(a: f64, b: f64, lo: f64, hi: f64) -> f64 {
    if a == b {
        return if lo < a && a < hi { 1.0 } else { 0.0 };
    }
    let (t_lo, t_hi) = ((lo - a) / (b - a), (hi - a) / (b - a));
    (t_lo.max(t_hi).min(1.0) - t_lo.min(t_hi).max(0.0)).max(0.0)
}

/// Deterministic paths on the ground: x from and to anywhere in [-4, 4] (at least one unit
/// of travel), z inside the square's band, diagonal as often as not.
fn crossing_paths(count: usize) -> Vec<(DVec3, DVec3)> {
    let mut state = 0x2545_f491u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        f64::from(state) / f64::from(u32::MAX)
    };
    let mut paths = Vec::new();
    while paths.len() < count {
        let (xa, xb) = (next() * 8.0 - 4.0, next() * 8.0 - 4.0);
        let (za, zb) = (
            (next() * 2.0 - 1.0) * Z_INSIDE,
            (next() * 2.0 - 1.0) * Z_INSIDE,
        );
        if (xb - xa).abs() >= 1.0 {
            paths.push((DVec3::new(xa, 0.0, za), DVec3::new(xb, 0.0, zb)));
        }
    }
    paths
}

/// Checks `lit` against 1 minus the time each path spends with x inside (-edge, edge), the
/// still square's shadow; `texel` is the shadow map's texel on the ground. Tolerance: the
/// map's shadow edges lie up to half a texel from the square's, so each of the two edge
/// times may be off by half a texel over the path's x speed; plus 2e-3 of f32 rounding.
fn assert_still_square_shadow(paths: &[(DVec3, DVec3)], lit: &[f64], edge: f64, texel: f64) {
    let mut partly = 0;
    for (&(a, b), &got) in paths.iter().zip(lit) {
        let expected = 1.0 - time_inside(a.x, b.x, -edge, edge);
        let tolerance = texel / (b.x - a.x).abs() + 2e-3;
        assert!(
            (got - expected).abs() <= tolerance,
            "receiver from {a} to {b}: lit {got}, closed form {expected} (tolerance {tolerance})"
        );
        partly += usize::from(expected > 0.05 && expected < 0.95);
    }
    assert!(partly >= paths.len() / 3, "only {partly} paths partly lit");
}

/// A receiver translating under a still square, directional light straight down: lit while
/// its x is outside [-1, 1].
#[test]
fn a_receiver_translating_under_a_still_caster_is_lit_outside_its_shadow() {
    let host = new_host();
    let (world, _, _) = square_world();
    let world = square_over_ground(world.lights[0], |_| DVec3::ZERO);
    let (engine, slot) = frame_map(&host, &world);
    let paths = crossing_paths(96);
    let lit = moving_lit(&host, engine.shadow_map(slot, 0), &paths);
    assert_still_square_shadow(&paths, &lit, 1.0, 12.0 / f64::from(SHADOW.0));
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// The same under a spot light 6 units up: the square (height 1) casts its shadow on the
/// ground scaled by 6 / 5, so x in [-1.2, 1.2]; the path's texels come from a perspective
/// projection (crossing times of x/w).
#[test]
fn a_receiver_translating_under_a_still_caster_in_a_spot_light() {
    let host = new_host();
    let world = square_over_ground(spot_over_ground(), |_| DVec3::ZERO);
    let (engine, slot) = frame_map(&host, &world);
    // Only paths that stay inside the scaled square's z band and the cone.
    let paths = crossing_paths(96);
    let lit = moving_lit(&host, engine.shadow_map(slot, 0), &paths);
    // The map spans 2 * 6 * tan(60 deg) units of ground over its texels.
    let texel = 12.0 * 60f64.to_radians().tan() / f64::from(SHADOW.0);
    assert_still_square_shadow(&paths, &lit, 1.2, texel);
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// A square translating 4 units in x over the shutter and receivers starting under it: those
/// moving with it stay in its shadow all shutter long (lit 0; the cube whose face turned from
/// the light showed a lit gradient when receivers were taken as standing still), those moving
/// half as fast fall behind it and leave its shadow when its back edge passes them: a
/// receiver u0 in (0, 2) ahead of the back edge at t = 0 is passed at t = u0 / 2, so
/// lit = 1 - min(u0 / 2, 1). Tolerance: half a texel over the relative speed (2) for the receiver's
/// edge, half a texel over the caster's speed (4) for where in its texel the map holds the
/// caster's interval, and 2e-3.
#[test]
fn receivers_moving_with_and_behind_a_moving_caster() {
    let host = new_host();
    let (world, _, _) = square_world();
    let world = square_over_ground(world.lights[0], |f| DVec3::new(-3.0 + 4.0 * f, 0.0, 0.0));
    let (engine, slot) = frame_map(&host, &world);
    let texel = 12.0 / f64::from(SHADOW.0);
    let mut paths = Vec::new();
    let mut expected = Vec::new();
    for i in 0..40 {
        // u0: the receiver's distance from the square's back edge (x = -4 at t = 0).
        let u0 = 0.1 + 1.8 * f64::from(i) / 39.0;
        let z = (f64::from(i % 5) / 2.0 - 1.0) * Z_INSIDE;
        let p0 = DVec3::new(-4.0 + u0, 0.0, z);
        paths.push((p0, p0 + DVec3::new(4.0, 0.0, 0.0)));
        expected.push((0.0, 2.0 * texel / 4.0 + 2e-3));
        paths.push((p0, p0 + DVec3::new(2.0, 0.0, 0.0)));
        expected.push((
            1.0 - (u0 / 2.0).min(1.0),
            0.5 * texel / 2.0 + 0.5 * texel / 4.0 + 2e-3,
        ));
    }
    let lit = moving_lit(&host, engine.shadow_map(slot, 0), &paths);
    for ((&(a, b), &got), &(want, tolerance)) in paths.iter().zip(&lit).zip(&expected) {
        assert!(
            (got - want).abs() <= tolerance,
            "receiver from {a} to {b}: lit {got}, closed form {want} (tolerance {tolerance})"
        );
    }
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// A receiver that does not move gets exactly the static answer (`ms_lit_fraction`), on the
/// row of the interval world where ranges overlap, nest and cross the receiver's depth.
#[test]
fn a_receiver_standing_still_gets_the_static_lit_fraction() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let map = engine.shadow_map(frame.slot, 0);
    let queries =
        lit_fraction_queries_along_texel_row(&interval_world(), -1.0 + 0.5 * f64::from(SIDE));
    let still = probe(&host, map, &queries);
    let paths: Vec<(DVec3, DVec3)> = queries
        .iter()
        .map(|q| {
            let p = Vec3::from(q.position).as_dvec3();
            (p, p)
        })
        .collect();
    let moving = moving_lit(&host, map, &paths);
    let mut partly = 0;
    for ((q, &want), &got) in queries.iter().zip(&still).zip(&moving) {
        assert_eq!(got as f32, want, "receiver at {:?}", q.position);
        partly += usize::from(want > 0.0 && want < 1.0);
    }
    assert!(partly >= 20, "only {partly} texels partly lit");
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// Receivers under a still square rising from the ground to twice its height (or falling
/// back): shadowed while they are below it, lit once above, within one texel the whole
/// shutter, so this holds the receiver's depth along its path (linear in time) to the closed
/// form: the tested point is the receiver moved up by the light's normal offset (one texel)
/// with its depth less the relative bias 1e-4, shadowed while that depth exceeds the
/// square's (9, under a light 10 up). Tolerance 2e-3 (f32 rounding).
#[test]
fn a_receiver_rising_past_a_still_caster_leaves_its_shadow() {
    let host = new_host();
    let (world, _, _) = square_world();
    let world = square_over_ground(world.lights[0], |_| DVec3::ZERO);
    let (engine, slot) = frame_map(&host, &world);
    let offset = 12.0 / f64::from(SHADOW.0);
    let mut paths = Vec::new();
    for i in 0..16 {
        let x = (f64::from(i % 4) / 1.5 - 1.0) * Z_INSIDE;
        let z = (f64::from(i / 4) / 1.5 - 1.0) * Z_INSIDE;
        let (low, high) = (DVec3::new(x, 0.0, z), DVec3::new(x, 2.0, z));
        paths.push((low, high));
        paths.push((high, low));
    }
    let lit = moving_lit(&host, engine.shadow_map(slot, 0), &paths);
    for (&(a, b), &got) in paths.iter().zip(&lit) {
        // Shadowed while (10 - y - offset) (1 - 1e-4) > 9.
        let y_cross = 10.0 - offset - 9.0 / (1.0 - 1e-4);
        let shadowed = time_inside(a.y, b.y, -1e9, y_cross);
        let expected = 1.0 - shadowed;
        assert!(
            (got - expected).abs() <= 2e-3,
            "receiver from {a} to {b}: lit {got}, closed form {expected}"
        );
    }
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// Ground receivers moving under a still plate at height 1 that covers the whole view of
/// `spot_over_ground` (the map holds it at every texel), on paths that leave the light's
/// view (or enter it) part way through the shutter: in shadow while inside the view, and,
/// as `ms_lit_fraction_moving` documents, lit while outside it, so lit = the share of the
/// shutter the tested point spends outside. The tested point is the receiver moved up by
/// the light's normal offset (one texel at its light depth 6: 6 * 2 tan 60 / 256), and the
/// view is the square frustum |x|, |z| < (6 - y) tan 60 deg. Tolerance 2e-3 (f32 rounding):
/// inside the view nothing but the plate decides.
#[test]
fn a_receiver_leaving_the_spot_lights_view_is_lit_outside_it() {
    let host = new_host();
    let (world, _, _) = square_world();
    let plate = [[-1.0, -1.0], [-1.0, 1.0], [1.0, 1.0], [1.0, -1.0]].map(|[x, z]| Vertex {
        position: [20.0 * x, 0.0, 20.0 * z],
        normal: [0.0, 1.0, 0.0],
    });
    let world = World {
        lights: vec![spot_over_ground()],
        meshes: vec![Mesh {
            name: "plate".into(),
            vertices: plate.to_vec(),
            indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
            albedo: Vec3::splat(0.5),
            closed: false,
            transform: Box::new(|_| DMat4::from_translation(DVec3::Y)),
        }],
        ..world
    };
    let (engine, slot) = frame_map(&host, &world);
    let tan = 60f64.to_radians().tan();
    let lift = 6.0 * 2.0 * tan / f64::from(SHADOW.1);
    let half_view = (6.0 - lift) * tan;
    let mut paths = Vec::new();
    for z in [-3.0, 0.0, 4.5] {
        let (inside, outside) = (DVec3::new(2.0, 0.0, z), DVec3::new(18.0, 0.0, z));
        paths.extend([(inside, outside), (outside, inside)]);
        let (inside, outside) = (DVec3::new(z, 0.0, -1.0), DVec3::new(z, 0.0, -14.0));
        paths.extend([(inside, outside), (outside, inside)]);
    }
    // Across a corner: out through x, then through z, and in again.
    paths.push((DVec3::new(9.0, 0.0, 6.0), DVec3::new(14.0, 0.0, 11.0)));
    paths.push((DVec3::new(-16.0, 0.0, 7.0), DVec3::new(16.0, 0.0, 9.0)));
    let lit = moving_lit(&host, engine.shadow_map(slot, 0), &paths);
    for (&(a, b), &got) in paths.iter().zip(&lit) {
        let [from_x, to_x] = time_range_inside(a.x, b.x, half_view);
        let [from_z, to_z] = time_range_inside(a.z, b.z, half_view);
        let inside = (to_x.min(to_z) - from_x.max(from_z)).max(0.0);
        let expected = 1.0 - inside;
        assert!(
            (got - expected).abs() <= 2e-3,
            "receiver from {a} to {b}: lit {got}, closed form {expected} (in view {inside})"
        );
        assert!(
            expected > 0.05 && expected < 0.95,
            "path {a} to {b} not partly lit"
        );
    }
    drop(engine);
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}

/// The times in [0, 1] during which a + t (b - a) lies in (-half, half), as [from, to]
/// (empty: from >= to).
fn time_range_inside(a: f64, b: f64, half: f64) -> [f64; 2] {
    if a == b {
        return if a.abs() < half {
            [0.0, 1.0]
        } else {
            [1.0, 0.0]
        };
    }
    let (t_lo, t_hi) = ((-half - a) / (b - a), (half - a) / (b - a));
    [t_lo.min(t_hi).max(0.0), t_lo.max(t_hi).min(1.0)]
}
