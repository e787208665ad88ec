//! The deferred host engine (`examples/deferred_host/src/deferred.rs`, the engine of the
//! `deferred_host` example): its own device, buffers, G-buffer, two frames in flight and
//! two lights, with the library's shadow and mask passes recorded into its command buffers.
//! Checked against the lighting pass's own per-sample decisions and against closed forms;
//! the comparisons with the standalone renderer and the ray tracer (the app, used there as a
//! reference only) are in `app/tests/gpu/deferred_host.rs`, which shares
//! `test-support/src/deferred_host.rs`.

use crate::support::host::Host;
use deferred::{
    Camera, Engine, FrameOutput, Light, Mesh, MeshIndices, Motion, Settings, ShadowLookup, Vertex,
    World,
};
use glam::{DMat4, DVec3, Vec3};

use motion_shadows_deferred_host::deferred;

// The helpers this file shares with the app's deferred-host tests.
use crate::support::deferred_host::*;

mod moving;

mod union;

/// A square of side `SIDE` at height 1 translating by `TRAVEL` in +x over the shutter, under
/// a directional light straight down: a ground point (x, z) with z under the square is in
/// shadow while a + TRAVEL t <= x <= a + SIDE + TRAVEL t, so its lit fraction is 1 minus the
/// length of [(x - a - SIDE) / TRAVEL, (x - a) / TRAVEL] within [0, 1].
fn square_world() -> (World, f64, f64) {
    const START: f64 = -4.0;
    const Z0: f32 = -1.0;
    let square = [[0.0, 0.0], [0.0, SIDE], [SIDE, SIDE], [SIDE, 0.0]].map(|[x, z]| Vertex {
        position: [x, 0.0, z],
        normal: [0.0, 1.0, 0.0],
    });
    let world = World {
        camera: Camera {
            eye: Vec3::new(0.0, 9.0, 7.0),
            target: Vec3::new(-1.0, 0.0, 0.0),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 50.0,
        },
        lights: vec![Light::Directional {
            direction: Vec3::NEG_Y,
            irradiance: 2.0,
            center: Vec3::ZERO,
            half_extent: 6.0,
            distance: 10.0,
            near: 0.5,
            far: 20.0,
        }],
        ambient: 0.05,
        meshes: vec![
            deferred::ground_mesh(),
            Mesh {
                name: "square".into(),
                vertices: square.to_vec(),
                indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
                albedo: Vec3::splat(0.5),
                closed: false,
                motion: Motion::Rigid(Box::new(|f| {
                    DMat4::from_translation(DVec3::new(
                        START + f64::from(TRAVEL) * f,
                        1.0,
                        f64::from(Z0),
                    ))
                })),
            },
        ],
    };
    (world, START, f64::from(Z0))
}

const SIDE: f32 = 2.0;
const TRAVEL: f32 = 4.0;

/// `ms_lit_fraction` (through the mask pass, and through the host's own shader) against the
/// closed form of `square_world`, at the centres of ground pixels that the square does not
/// cover at t = 1 and that lie more than 1.5 shadow texels from the shadow's sides (z edges).
///
/// Tolerance: 2e-3 (the prism's rasterization snaps vertices to 1/256 texel, plus f32
/// rounding), plus what a shadow-map texel of motion implies: the map holds the interval
/// during which the square covers the texel's centre, which lies up to half a texel from the
/// point along the motion, so both ends of the interval move by up to 0.5 texel / TRAVEL;
/// its length changes only where one end is clipped to the shutter, by at most that much.
#[test]
fn lit_fraction_matches_the_closed_form_for_a_translating_square() {
    let host = new_host();
    let (world, start, z0) = square_world();
    let mut engine = Engine::new(&host, &world, settings((300_000, 200_000))).expect("engine");
    let frame = engine
        .render(&world, 0..2, &|f| f == 1)
        .expect("frames")
        .pop()
        .expect("frame 1 kept");
    // The same frame with the mask's variant for receivers standing still (the ground does).
    let still = Engine::new(
        &host,
        &world,
        Settings {
            receivers_move: false,
            ..settings((300_000, 200_000))
        },
    )
    .expect("engine")
    .render(&world, 0..2, &|f| f == 1)
    .expect("frames")
    .pop()
    .expect("frame 1 kept");
    let texel = 2.0 * 6.0 / f64::from(SHADOW.1);
    let tolerance = 2e-3 + 0.5 * texel / f64::from(TRAVEL);
    let (side, travel) = (f64::from(SIDE), f64::from(TRAVEL));
    let closed_form = |p: DVec3| -> f64 {
        if p.z < z0 || p.z > z0 + side {
            return 1.0;
        }
        let enter = ((p.x - start - side) / travel).clamp(0.0, 1.0);
        let leave = ((p.x - start) / travel).clamp(0.0, 1.0);
        1.0 - (leave - enter).max(0.0)
    };

    // Frame 1's shutter: the square from x = start to start + travel. Pixels showing the
    // square itself at t = 1 (the G-buffer's time) are not ground.
    let rays = camera_rays(&world);
    let covered = caster_boxes(&world, 1, 2.0);
    let covered_at_1 = {
        let view_proj = world.camera.view_proj(SIZE.0 as f32 / SIZE.1 as f32);
        let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
        for p in world.meshes[1].world_positions(1.0) {
            let clip = view_proj * p.extend(1.0);
            let x = (clip.x / clip.w * 0.5 + 0.5) * SIZE.0 as f32;
            let y = (clip.y / clip.w * 0.5 + 0.5) * SIZE.1 as f32;
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
        [b[0] - 2.0, b[1] - 2.0, b[2] + 2.0, b[3] + 2.0]
    };
    let (mut compared, mut partial, mut worst) = (0, 0, 0.0f64);
    let mut points = Vec::new();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            if in_any_box(&[covered_at_1], x, y) {
                continue;
            }
            let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                continue;
            };
            if (p.z - z0).abs() < 1.5 * texel || (p.z - z0 - side).abs() < 1.5 * texel {
                continue;
            }
            let expected = closed_form(p);
            let i = (y * SIZE.0 + x) as usize;
            let got = f64::from(frame.masks[0][i]);
            let error = (got - expected).abs();
            for (variant, value) in [("moving", got), ("still", f64::from(still.masks[0][i]))] {
                assert!(
                    (value - expected).abs() <= tolerance,
                    "pixel ({x},{y}) at ({:.3}, {:.3}): {variant} mask {value}, closed form \
                     {expected} (tolerance {tolerance:.4})",
                    p.x,
                    p.z
                );
            }
            compared += 1;
            partial += usize::from(expected > 0.0 && expected < 1.0);
            worst = worst.max(error);
            points.push((x, y, p, expected));
        }
    }
    eprintln!(
        "mask vs closed form: {compared} ground pixels ({partial} partly lit, {} under the \
         square's path), max error {worst:.5}, tolerance {tolerance:.5}",
        points
            .iter()
            .filter(|(x, y, ..)| in_any_box(&covered, *x, *y))
            .count()
    );
    assert!(
        compared > 5000 && partial > 500,
        "{compared} pixels, {partial} partial"
    );

    // The host's own shader calling ms_lit_fraction gives the masks' values (the R16 masks
    // round to 1/65535).
    // Irradiance 2 straight down on the ground: cos(theta) = 1 everywhere.
    let direct = |_: DVec3| GROUND_ALBEDO / std::f64::consts::PI * 2.0;
    let ambient = 0.05 * GROUND_ALBEDO;
    engine.set_lookup(ShadowLookup::LitFractionInShader);
    let in_shader = engine
        .render(&world, 1..2, &|_| true)
        .expect("frame")
        .pop()
        .expect("kept");
    let mut worst_shader = 0.0f64;
    for &(x, y, p, _) in &points {
        let i = (y * SIZE.0 + x) as usize;
        let lit = (f64::from(in_shader.radiance[i][0]) - ambient) / direct(p);
        worst_shader = worst_shader.max((lit - f64::from(frame.masks[0][i])).abs());
    }
    eprintln!(
        "ms_lit_fraction in the host's shader vs the mask: max difference {worst_shader:.2e}"
    );
    assert!(worst_shader < 1e-4);

    // And ms_visibility at one instant, t = 0.5: in shadow exactly under the square then (away
    // from its edges by 1.5 texels).
    engine.set_lookup(ShadowLookup::VisibilityAt(0.5));
    let instant = engine
        .render(&world, 1..2, &|_| true)
        .expect("frame")
        .pop()
        .expect("kept");
    let x_at = start + 0.5 * travel;
    let mut checked = 0;
    for &(x, y, p, _) in &points {
        let dx = (p.x - x_at).min(x_at + side - p.x);
        if dx.abs() < 1.5 * texel {
            continue;
        }
        let under = p.z > z0 && p.z < z0 + side && dx > 0.0;
        let i = (y * SIZE.0 + x) as usize;
        let lit = (f64::from(instant.radiance[i][0]) - ambient) / direct(p);
        assert!(
            (lit - if under { 0.0 } else { 1.0 }).abs() < 1e-3,
            "pixel ({x},{y}) at ({:.3}, {:.3}), t = 0.5: lit {lit}, under the square: {under}",
            p.x,
            p.z
        );
        checked += 1;
    }
    eprintln!("ms_visibility at t = 0.5: {checked} pixels match");

    // At texel centres the map holds exactly the intervals of the point itself (no half
    // texel of motion): there ms_lit_fraction equals the closed form to 1e-3, along a row of
    // texels across the square's whole path, through the host's own probe shader.
    // The texel row through the middle of the square's z extent.
    let queries = lit_fraction_queries_along_texel_row(&world, z0 + 0.5 * side);
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    let (mut worst_centre, mut partly) = (0.0f64, 0);
    for (q, &got) in queries.iter().zip(&lit) {
        let p = DVec3::new(f64::from(q.position[0]), 0.0, f64::from(q.position[2]));
        let expected = closed_form(p);
        partly += usize::from(expected > 0.0 && expected < 1.0);
        worst_centre = worst_centre.max((f64::from(got) - expected).abs());
    }
    eprintln!(
        "ms_lit_fraction at {} texel centres ({partly} partly lit): max error {worst_centre:.2e}",
        queries.len()
    );
    assert!(partly > 50, "{partly} partly lit texels");
    assert!(
        worst_centre < 1e-3,
        "max error {worst_centre} at texel centres"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// A comb of `slats` slats of width `COMB_WIDTH`, one every `COMB_PERIOD` in x, at height 1
/// over z in [-COMB_HALF_Z, COMB_HALF_Z], travelling twice its length in +x over frame 1's
/// shutter under a directional light straight down. Every ground point of the middle stretch
/// (from the comb's end at t = 0 to its start at t = 1) is passed by every slat, in disjoint
/// intervals of width / travel each, so it is lit for 1 - width / (2 period) of the shutter.
fn comb_world(slats: usize) -> World {
    let (mut world, _, _) = square_world();
    let travel = 2.0 * slats as f64 * f64::from(COMB_PERIOD);
    let start = -0.5 * travel - 0.5 * slats as f64 * f64::from(COMB_PERIOD);
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for k in 0..slats {
        let x0 = k as f32 * COMB_PERIOD;
        let first = vertices.len() as u16;
        for [x, z] in [
            [x0, -COMB_HALF_Z],
            [x0, COMB_HALF_Z],
            [x0 + COMB_WIDTH, COMB_HALF_Z],
            [x0 + COMB_WIDTH, -COMB_HALF_Z],
        ] {
            vertices.push(Vertex {
                position: [x, 0.0, z],
                normal: [0.0, 1.0, 0.0],
            });
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|i| first + i));
    }
    world.meshes[1] = Mesh {
        name: "comb".into(),
        vertices,
        indices: MeshIndices::U16(indices),
        albedo: Vec3::splat(0.5),
        closed: false,
        motion: Motion::Rigid(Box::new(move |f| {
            DMat4::from_translation(DVec3::new(start + travel * f, 1.0, 0.0))
        })),
    };
    world
}

const COMB_WIDTH: f32 = 0.025;
const COMB_PERIOD: f32 = 0.05;
const COMB_HALF_Z: f32 = 1.5;

/// On a device that leaves long loops (lavapipe), the mask pass says which pixels' lookups
/// may have been cut short instead of writing wrong values silently: a comb of 28 slats
/// (28 disjoint shadow intervals per point, kept in private memory) renders and matches its
/// closed form; one of 72 slats (more than 32 intervals: the long path, about 2 x 72^2 loop
/// iterations per pixel) is refused there with the count, and matches the closed form on
/// devices without the limit.
#[test]
fn the_mask_reports_pixels_past_the_device_loop_limit() {
    let host = new_host();
    for slats in [28usize, 72] {
        let world = comb_world(slats);
        let mut engine =
            Engine::new(&host, &world, settings((1_000_000, 1_000_000))).expect("engine");
        let limited = engine.context().info().shader_loop_limit.is_some();
        let result = engine.render(&world, 0..2, &|f| f == 1);
        if limited && slats == 72 {
            let error = result
                .expect_err("refused on a loop-limited device")
                .to_string();
            eprintln!("{slats} slats: {error}");
            assert!(
                error.contains("mask pixel(s) need more loop iterations"),
                "{error}"
            );
            continue;
        }
        let frame = result.expect("frames").pop().expect("frame 1 kept");
        let rays = camera_rays(&world);
        let half_stretch = 0.5 * slats as f64 * f64::from(COMB_PERIOD);
        let expected = 1.0 - f64::from(COMB_WIDTH) / (2.0 * f64::from(COMB_PERIOD));
        let (mut compared, mut worst) = (0, 0.0f64);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let Some(p) = ground_point(&rays, x as f32 + 0.5, y as f32 + 0.5, 6.0) else {
                    continue;
                };
                if p.x.abs() > half_stretch - 0.2 || p.z.abs() > f64::from(COMB_HALF_Z) - 0.2 {
                    continue;
                }
                let got = f64::from(frame.masks[0][(y * SIZE.0 + x) as usize]);
                worst = worst.max((got - expected).abs());
                compared += 1;
            }
        }
        eprintln!(
            "{slats} slats: {compared} ground pixels, lit fraction {expected}, max error \
             {worst:.2e}"
        );
        assert!(compared > 200, "{compared} pixels compared");
        assert!(worst < 2e-3, "max error {worst}");
        drop(engine);
    }
    host.assert_clean_teardown();
}

/// An engine that keeps its shadow maps' static layers across frames
/// (`LightView::keep_static_layer`) renders what one that redraws them every frame renders,
/// bit for bit, while drawing each map's static layer once; when a light moves, the layers
/// are drawn again and the frames still match.
#[test]
fn a_kept_static_layer_renders_what_a_redrawn_one_renders() {
    let host = new_host();
    let world = World::demo();
    let mut moved = World::demo();
    for light in &mut moved.lights {
        match light {
            Light::Spot { position, .. } => *position += Vec3::new(0.3, 0.0, -0.2),
            Light::Directional { direction, .. } => *direction += Vec3::new(0.05, 0.0, 0.0),
        }
    }
    let engine = |keep: bool| {
        let mut s = settings((300_000, 200_000));
        s.keep_static_layer = keep;
        Engine::new(&host, &world, s).expect("engine")
    };
    let (mut kept, mut redrawn) = (engine(true), engine(false));
    let builds = |e: &Engine, slot: usize| -> Vec<u32> {
        (0..world.lights.len())
            .map(|light| e.shadow_map(slot, light).static_layer_builds())
            .collect()
    };
    let frames = 0..6;
    for (part, (w, range)) in [(&world, 0..6u32), (&moved, 6..10)].into_iter().enumerate() {
        let a = kept.render(w, range.clone(), &|_| true).expect("kept");
        let b = redrawn
            .render(w, range.clone(), &|_| true)
            .expect("redrawn");
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.frame, y.frame);
            assert!(
                x.radiance == y.radiance,
                "frame {}: radiance differs",
                x.frame
            );
            assert!(x.masks == y.masks, "frame {}: masks differ", x.frame);
        }
        // Two frames in flight: each slot's maps drew their layers once per light setup.
        for slot in 0..2 {
            assert_eq!(
                builds(&kept, slot),
                vec![part as u32 + 1; world.lights.len()]
            );
        }
        eprintln!(
            "frames {range:?}: identical; static layer builds per map, kept {:?} / redrawn {:?}",
            builds(&kept, 0),
            builds(&redrawn, 0)
        );
    }
    assert!(builds(&redrawn, 0)[0] as usize >= frames.len() / 2);
    drop((kept, redrawn));
    host.assert_clean_teardown();
}

/// A caster of `interval_world`: a square of `width` (x) by `SIDE` (z), its corner moving
/// from (`x0`, `h0`) at t = 0 to (`x0 + travel`, `h1`) at t = 1 (x, height), at z = `Z0`.
struct Caster {
    x0: f64,
    travel: f64,
    h0: f64,
    h1: f64,
    width: f64,
}

/// Two squares sliding over the ground at different heights and speeds (one fast and narrow,
/// one slow and wide: over some points their shadow intervals overlap, over others one nests
/// in the other) and one that sinks straight down through the ground (its depth crosses the
/// ground's a quarter into the shutter).
const INTERVAL_CASTERS: [Caster; 3] = [
    Caster {
        x0: -5.5,
        travel: 6.0,
        h0: 1.0,
        h1: 1.0,
        width: 2.5,
    },
    Caster {
        x0: -4.5,
        travel: 2.5,
        h0: 2.0,
        h1: 2.0,
        width: 2.5,
    },
    Caster {
        x0: 3.5,
        travel: 0.0,
        h0: 1.0,
        h1: -3.0,
        width: 2.0,
    },
];
const Z0: f64 = -1.0;

fn interval_world() -> World {
    caster_world(&INTERVAL_CASTERS)
}

/// The ground and `casters` (`Caster`), under `square_world`'s light.
fn caster_world(casters: &[Caster]) -> World {
    let (world, _, _) = square_world();
    let mut meshes = vec![deferred::ground_mesh()];
    for (i, c) in casters.iter().enumerate() {
        let w = c.width as f32;
        let square = [[0.0, 0.0], [0.0, SIDE], [w, SIDE], [w, 0.0]].map(|[x, z]| Vertex {
            position: [x, 0.0, z],
            normal: [0.0, 1.0, 0.0],
        });
        let (x0, travel, h0, h1) = (c.x0, c.travel, c.h0, c.h1);
        meshes.push(Mesh {
            name: format!("caster-{i}"),
            vertices: square.to_vec(),
            indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
            albedo: Vec3::splat(0.5),
            closed: false,
            motion: Motion::Rigid(Box::new(move |f| {
                DMat4::from_translation(DVec3::new(x0 + travel * f, h0 + (h1 - h0) * f, Z0))
            })),
        });
    }
    World { meshes, ..world }
}

/// `interval_world`'s engine after frame 1 (whose shutter the casters' motions span), and
/// that frame.
fn interval_frame(host: &Host) -> (Engine<'_>, FrameOutput) {
    caster_frame(host, &interval_world())
}

/// `world`'s engine after frame 1, and that frame.
fn caster_frame<'h>(host: &'h Host, world: &World) -> (Engine<'h>, FrameOutput) {
    let mut engine = Engine::new(host, world, settings((300_000, 200_000))).expect("engine");
    let frame = engine
        .render(world, 0..2, &|f| f == 1)
        .expect("frames")
        .pop()
        .expect("frame 1 kept");
    (engine, frame)
}

/// The times in frame 1's shutter during which caster `c` covers ground point (x, z) and is
/// nearer to the overhead light than the ground there (its height above `depth_margin`).
fn caster_interval(c: &Caster, x: f64, z: f64, depth_margin: f64) -> Option<(f64, f64)> {
    if z <= Z0 || z >= Z0 + f64::from(SIDE) {
        return None;
    }
    let (mut from, mut to) = if c.travel == 0.0 {
        if x <= c.x0 || x >= c.x0 + c.width {
            return None;
        }
        (0.0, 1.0)
    } else {
        ((x - c.x0 - c.width) / c.travel, (x - c.x0) / c.travel)
    };
    // Above the ground: h0 + (h1 - h0) t > margin.
    if c.h1 < c.h0 {
        to = to.min((c.h0 - depth_margin) / (c.h0 - c.h1));
    } else if c.h1 > c.h0 {
        from = from.max((depth_margin - c.h0) / (c.h1 - c.h0));
    }
    from = from.max(0.0);
    to = to.min(1.0);
    (to > from).then_some((from, to))
}

/// The length of the union of intervals.
fn union_length(mut intervals: Vec<(f64, f64)>) -> f64 {
    intervals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut length, mut covered_to) = (0.0, f64::NEG_INFINITY);
    for (from, to) in intervals {
        length += (to - from.max(covered_to)).max(0.0);
        covered_to = covered_to.max(to);
    }
    length
}

/// `ms_lit_fraction` where the ranges over a receiver overlap, nest, and cross its depth:
/// at the texel centres of a row across every caster's path, through the host's probe shader,
/// against 1 minus the length of the union of the closed-form intervals during which a
/// caster is nearer to the light than the ground point (the sinking square's interval ends
/// where its depth passes the receiver's, near a quarter into the shutter: the receiver is
/// the ground point moved up by the light's normal offset of one texel, its depth less the
/// relative bias of 1e-4).
/// Tolerance 1e-3 (f32 rounding; at texel centres the map holds the point's own intervals).
/// The row is chosen, and checked, to hold texels where intervals overlap partly, where one
/// nests in another, and where the crossing decides: summing instead of uniting, or taking
/// the wrong side of the crossing, moves those by more than 0.1.
#[test]
fn lit_fraction_unites_overlapping_ranges_and_cuts_at_the_depth_crossing() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let queries =
        lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.5 * f64::from(SIDE));
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    // The receiver tested: the ground point moved up by the light's normal offset (one
    // texel: the box is 12 units across the map), its depth less the relative bias 1e-4.
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let margin = 10.0 - (10.0 - texel) * (1.0 - 1e-4);
    let (mut overlapping, mut nested, mut crossing, mut worst) = (0, 0, 0, 0.0f64);
    let mut wrong = Vec::new();
    for (q, &got) in queries.iter().zip(&lit) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let intervals: Vec<(f64, f64)> = INTERVAL_CASTERS
            .iter()
            .filter_map(|c| caster_interval(c, x, z, margin))
            .collect();
        let expected = 1.0 - union_length(intervals.clone()).min(1.0);
        let error = (f64::from(got) - expected).abs();
        if error > 1e-3 {
            wrong.push(format!(
                "texel centre x = {x:.3}: ms_lit_fraction {got}, closed form {expected} \
                 (intervals {intervals:?})"
            ));
        }
        worst = worst.max(error);
        let summed: f64 = intervals.iter().map(|(a, b)| b - a).sum();
        if summed - union_length(intervals.clone()) > 0.1 {
            let (a, b) = (intervals[0], intervals[1]);
            let nests = (a.0 <= b.0 && b.1 <= a.1) || (b.0 <= a.0 && a.1 <= b.1);
            if nests {
                nested += 1;
            } else {
                overlapping += 1;
            }
        }
        let sinking = &INTERVAL_CASTERS[2];
        if caster_interval(sinking, x, z, margin).is_some()
            && intervals.len() == 1
            && (expected - 0.76).abs() < 0.01
        {
            crossing += 1;
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} texel centres off by more than 1e-3:\n{}",
        wrong.len(),
        queries.len(),
        wrong.join("\n")
    );
    eprintln!(
        "ms_lit_fraction at {} texel centres: {overlapping} with overlapping intervals, \
         {nested} nested, {crossing} decided by a depth crossing; max error {worst:.2e}",
        queries.len()
    );
    assert!(
        overlapping >= 15 && nested >= 15 && crossing >= 15,
        "{overlapping} overlapping, {nested} nested, {crossing} crossing"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The self-shadow rule: a receiver's own triangle never shadows it. Points just below a
/// moving caster's surface (at a time it covers them, away from its diagonal and from the
/// other casters) and just below the ground (where no caster covers them then) are in the
/// shadow of their own surface by depth: `ms_visibility` must say 1 with their own triangle's
/// id, and 0 without one (`MS_NO_TRIANGLE`). The ground's own test is the static layer's, the
/// caster's its ranges'.
#[test]
fn a_receivers_own_triangle_never_shadows_it() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let z = Z0 + 0.37 * f64::from(SIDE);
    let (mut queries, mut owns) = (Vec::new(), Vec::new());
    for t in [0.2, 0.5, 0.8] {
        for i in 0..240 {
            let x = -5.8 + 11.6 * f64::from(i) / 240.0;
            let covering: Vec<usize> = INTERVAL_CASTERS
                .iter()
                .enumerate()
                .filter(|(_, c)| {
                    let left = c.x0 + c.travel * t;
                    x > left - 2.0 * texel && x < left + c.width + 2.0 * texel
                })
                .map(|(k, _)| k)
                .collect();
            let (position, own) = match covering[..] {
                // Below the ground, its own triangle's id (away from the grid's diagonals and
                // its cells' edges, every 3 units, where a texel may be a neighbour's).
                [] => match ground_triangle(DVec3::new(x, 0.0, z), 2.0 * texel) {
                    Some(id) if ((x + 6.0).rem_euclid(3.0) - 1.5).abs() < 1.5 - 2.0 * texel => {
                        ([x as f32, -0.2, z as f32], id)
                    }
                    _ => continue,
                },
                // Just below a flat caster that alone covers the point, inside it by two
                // texels (the ranges of its texel are its own).
                [k] if INTERVAL_CASTERS[k].h0 == INTERVAL_CASTERS[k].h1 => {
                    let c = &INTERVAL_CASTERS[k];
                    let (u, w) = (
                        (x - c.x0 - c.travel * t) / c.width,
                        (z - Z0) / f64::from(SIDE),
                    );
                    if !(2.0 * texel / c.width..1.0 - 2.0 * texel / c.width).contains(&u)
                        || (u - w).abs() < 2.0 * texel
                    {
                        continue;
                    }
                    // (0, 1, 2) is the half with w > u.
                    let id = ground_triangles + 2 * k as u32 + u32::from(w < u);
                    ([x as f32, (c.h0 - 0.2) as f32, z as f32], id)
                }
                _ => continue,
            };
            for own in [own, u32::MAX] {
                queries.push(Query {
                    position,
                    time: t as f32,
                    normal: [0.0, 1.0, 0.0],
                    own,
                });
                owns.push(own != u32::MAX);
            }
        }
    }
    let lit = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    let (mut under_ground, mut under_caster) = (0, 0);
    for ((q, &own), &got) in queries.iter().zip(&owns).zip(&lit) {
        let expected = if own { 1.0 } else { 0.0 };
        assert_eq!(
            got, expected,
            "point {:?} at t = {}, own id {}: ms_visibility {got}",
            q.position, q.time, q.own
        );
        if own {
            if q.position[1] < 0.0 {
                under_ground += 1;
            } else {
                under_caster += 1;
            }
        }
    }
    eprintln!(
        "own triangle skipped: {under_ground} points under the ground, {under_caster} under a caster"
    );
    assert!(
        under_ground >= 50 && under_caster >= 50,
        "{under_ground} / {under_caster}"
    );
    drop(engine);
    host.assert_clean_teardown();
}

/// The own-triangle rule in the lit fraction: points 0.2 below the slow wide caster (the only
/// one above them), at texel centres along a row across its path. The square's two triangles
/// pass over such a point one after the other (its diagonal splits each pass), so with the
/// id of one of them `ms_lit_fraction` is 1 minus the time the other covers the point, and
/// with no id 1 minus the time the square does (closed forms from the caster's motion;
/// tolerance 1e-3). Fails when the lit fraction counts the receiver's own ranges.
#[test]
fn a_receivers_own_triangle_never_darkens_its_lit_fraction() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    // Global ids: the ground's 32 triangles, then two per caster ((0, 1, 2) is the half of
    // the square with w > u).
    let ground_triangles = 2 * 4 * 4;
    let k = 1;
    let c = &INTERVAL_CASTERS[k];
    let first = ground_triangles + 2 * k as u32;
    // The time during which the square's u (0 at its leading... trailing edge x0 + travel t,
    // 1 at the other) lies in [a, b] at world x.
    let covered = |x: f64, a: f64, b: f64| {
        let from = ((x - c.x0 - b * c.width) / c.travel).max(0.0);
        let to = ((x - c.x0 - a * c.width) / c.travel).min(1.0);
        (to - from).max(0.0)
    };
    let (mut queries, mut expected) = (Vec::new(), Vec::new());
    let mut decided = 0;
    for q in lit_fraction_queries_along_texel_row(&interval_world(), Z0 + 0.37 * f64::from(SIDE)) {
        let (x, z) = (f64::from(q.position[0]), f64::from(q.position[2]));
        let w = (z - Z0) / f64::from(SIDE);
        // Triangle `first` covers u < w, triangle `first + 1` u > w.
        let (upper, lower) = (covered(x, 0.0, w), covered(x, w, 1.0));
        if upper + lower == 0.0 {
            continue;
        }
        let position = [q.position[0], (c.h0 - 0.2) as f32, q.position[2]];
        for (own, lit) in [
            (u32::MAX, 1.0 - (upper + lower)),
            (first, 1.0 - lower),
            (first + 1, 1.0 - upper),
        ] {
            queries.push(Query {
                position,
                time: -1.0,
                normal: [0.0, 1.0, 0.0],
                own,
            });
            expected.push(lit);
        }
        decided += usize::from(upper > 0.05) + usize::from(lower > 0.05);
    }
    let got = probe(&host, engine.shadow_map(frame.slot, 0), &queries);
    for ((q, &want), &got) in queries.iter().zip(&expected).zip(&got) {
        assert!(
            (f64::from(got) - want).abs() <= 1e-3,
            "point {:?}, own id {}: ms_lit_fraction {got}, closed form {want}",
            q.position,
            q.own
        );
    }
    eprintln!(
        "{} queries; {decided} where the own triangle covers the point 5% of the shutter or more",
        queries.len()
    );
    assert!(decided >= 20, "{decided}");
    drop(engine);
    host.assert_clean_teardown();
}

/// The lighting pass tests a pixel's samples per texel (`ms_samples_shadowed`, glsl/
/// temporal_samples.glsl, not part of the public include); each sample must get exactly what
/// `ms_texel_shadowed` answers for it alone. Groups of 8 receivers around one point (within
/// a texel or two, so some share a texel and some do not), at random times, on the ground or
/// just below a caster, with their own triangle's id, another triangle's, or none: the two
/// answers agree for every one, and the own ids decide many of them (the test fails when
/// either function drops the own-triangle skip, or the static layer, coverage or time test).
#[test]
fn per_texel_sample_tests_answer_as_ms_texel_shadowed() {
    let host = new_host();
    let (engine, frame) = interval_frame(&host);
    let texel = 2.0 * 6.0 / f64::from(SHADOW.0);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 11) as f64 / (1u64 << 53) as f64
    };
    // Global ids: the ground's 32 triangles, then two per caster.
    let ground_triangles = 2 * 4 * 4;
    let ids: Vec<u32> = (0..ground_triangles + 6).collect();
    let mut queries = Vec::new();
    for _ in 0..400 {
        let (x, z) = (-5.5 + 11.0 * uniform(), Z0 + f64::from(SIDE) * uniform());
        // Below the ground, below the low caster, or below the high one.
        let surface = (uniform() * 3.0) as usize;
        let height = [-0.2, 0.8, 1.8][surface];
        for _ in 0..8 {
            let (px, pz) = (
                x + 2.0 * texel * (uniform() - 0.5),
                z + 2.0 * texel * (uniform() - 0.5),
            );
            // A third each: the id of the surface just above (either triangle of a caster),
            // any id, none.
            let own = match (uniform() * 3.0) as usize {
                0 if surface == 0 => ground_triangle(DVec3::new(px, 0.0, pz), 0.0).unwrap_or(0),
                0 => ground_triangles + 2 * (surface as u32 - 1) + u32::from(uniform() < 0.5),
                1 => ids[(uniform() * ids.len() as f64) as usize],
                _ => u32::MAX,
            };
            queries.push(Query {
                position: [px as f32, height as f32, pz as f32],
                time: uniform() as f32,
                normal: [0.0, 1.0, 0.0],
                own,
            });
        }
    }
    let map = engine.shadow_map(frame.slot, 0);
    let answers = run_probe(
        &host,
        map,
        &queries,
        deferred::sources::SAMPLES_PROBE_COMP,
        Shape {
            per_invocation: 8,
            workgroup: 16,
            results_per_query: 2,
        },
    );
    // The same receivers without their own ids: how many answers the ids decide.
    let anonymous: Vec<Query> = queries
        .iter()
        .map(|q| Query {
            own: u32::MAX,
            ..*q
        })
        .collect();
    let without_ids = probe(&host, map, &anonymous);
    let (mut shadowed, mut decided_by_id) = (0, 0);
    for (i, (q, pair)) in queries.iter().zip(answers.chunks_exact(2)).enumerate() {
        assert_eq!(
            pair[0], pair[1],
            "query {i} {q:?}: per texel {}, alone {}",
            pair[0], pair[1]
        );
        shadowed += usize::from(pair[1] == 1.0);
        // Shadowed without an id (probe gives visibility: 0), lit with its own.
        decided_by_id += usize::from(pair[1] == 0.0 && without_ids[i] == 0.0);
    }
    eprintln!(
        "{} receivers: {shadowed} shadowed, {decided_by_id} lit only by their own id",
        queries.len()
    );
    assert!(
        shadowed >= 300 && queries.len() - shadowed >= 300 && decided_by_id >= 100,
        "{shadowed} shadowed, {decided_by_id} decided by the id"
    );
    drop(engine);
    host.assert_clean_teardown();
}
