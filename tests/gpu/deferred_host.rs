//! The deferred host engine (`examples/deferred_host/src/deferred.rs`, the engine of the
//! `deferred_host` example): its own device, buffers, G-buffer, three frames in flight and
//! two lights, with the library's shadow and mask passes recorded into its command buffers.
//! Checked against the lighting pass's own per-sample decisions and against closed forms;
//! the comparisons with the standalone renderer and the ray tracer (the app, used there as a
//! reference only) are in `app/tests/gpu/deferred_host.rs`, which shares
//! `test-support/src/deferred_host.rs`.

use crate::support::host::Host;
use deferred::{Camera, Engine, FrameOutput, Mesh, MeshIndices, Settings, Vertex, World};
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
        lights: vec![
            HostLight::Directional {
                direction: Vec3::NEG_Y,
                irradiance: 2.0,
                center: Vec3::ZERO,
                half_extent: 6.0,
                distance: 10.0,
                near: 0.5,
                far: 20.0,
            }
            .engine_light(),
        ],
        ambient: 0.05,
        meshes: vec![
            deferred::ground_mesh(),
            Mesh {
                name: "square".into(),
                vertices: square.to_vec(),
                indices: MeshIndices::U16(vec![0, 1, 2, 0, 2, 3]),
                albedo: Vec3::splat(0.5),
                closed: false,
                transform: Box::new(|f| {
                    DMat4::from_translation(DVec3::new(
                        START + f64::from(TRAVEL) * f,
                        1.0,
                        f64::from(Z0),
                    ))
                }),
            },
        ],
    };
    (world, START, f64::from(Z0))
}

const SIDE: f32 = 2.0;
const TRAVEL: f32 = 4.0;

/// `ms_lit_fraction` (through the mask pass, moving and still variants, and through the host's
/// probe shader at the same points) against the closed form of `square_world`, at the centres
/// of ground pixels that the square does not cover at t = 1 and that lie more than 1.5 shadow
/// texels from the shadow's sides (z edges); the engine's shading of those pixels against
/// albedo / pi * E * mask + ambient, and `ms_visibility` at t = 0.5 against the square's
/// position then.
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
    let mut engine = Engine::new(&host, &world, settings()).expect("engine");
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
            ..settings()
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

    // The engine's shading of those pixels: irradiance 2 straight down on the ground
    // (cos(theta) = 1), so radiance = albedo / pi * 2 * mask + ambient * albedo.
    let direct = GROUND_ALBEDO / std::f64::consts::PI * 2.0;
    let ambient = 0.05 * GROUND_ALBEDO;
    let mut worst_shading = 0.0f64;
    for &(x, y, ..) in &points {
        let i = (y * SIZE.0 + x) as usize;
        let expected = direct * f64::from(frame.masks[0][i]) + ambient;
        worst_shading = worst_shading.max((f64::from(frame.radiance[i][0]) - expected).abs());
    }
    eprintln!("shading vs albedo / pi * E * mask + ambient: max difference {worst_shading:.2e}");
    assert!(worst_shading < 1e-4 * direct);

    // The library's GLSL include in a shader of the host's own (the probe), at the same ground
    // points: ms_lit_fraction against the closed form within the mask's tolerance, and
    // ms_visibility at one instant, t = 0.5: in shadow exactly under the square then (away
    // from its edges by 1.5 texels).
    let map = engine.shadow_map(frame.slot, 0);
    let query = |p: DVec3, time: f32| Query {
        position: p.as_vec3().to_array(),
        time,
        normal: [0.0, 1.0, 0.0],
        own: u32::MAX,
    };
    let queries: Vec<Query> = points.iter().map(|&(.., p, _)| query(p, -1.0)).collect();
    let lit = probe(&host, map, &queries);
    let mut worst_include = 0.0f64;
    for (&(x, y, p, expected), &got) in points.iter().zip(&lit) {
        let error = (f64::from(got) - expected).abs();
        assert!(
            error <= tolerance,
            "pixel ({x},{y}) at ({:.3}, {:.3}): ms_lit_fraction {got}, closed form {expected}",
            p.x,
            p.z
        );
        worst_include = worst_include.max(error);
    }
    eprintln!("ms_lit_fraction in the host's probe vs the closed form: max {worst_include:.5}");
    let x_at = start + 0.5 * travel;
    let away: Vec<_> = (points.iter())
        .map(|&(.., p, _)| (p, (p.x - x_at).min(x_at + side - p.x)))
        .filter(|(_, dx)| dx.abs() >= 1.5 * texel)
        .collect();
    let queries: Vec<Query> = away.iter().map(|&(p, _)| query(p, 0.5)).collect();
    let visible = probe(&host, map, &queries);
    for (&(p, dx), &got) in away.iter().zip(&visible) {
        let under = p.z > z0 && p.z < z0 + side && dx > 0.0;
        assert_eq!(
            got,
            if under { 0.0 } else { 1.0 },
            "({:.3}, {:.3}), t = 0.5: ms_visibility {got}, under the square: {under}",
            p.x,
            p.z
        );
    }
    eprintln!("ms_visibility at t = 0.5: {} points match", away.len());

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
        transform: Box::new(move |f| {
            DMat4::from_translation(DVec3::new(start + travel * f, 1.0, 0.0))
        }),
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
        let mut engine = Engine::new(&host, &world, settings()).expect("engine");
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
    moved.lights = (demo_lights().into_iter())
        .map(|mut light| {
            match &mut light {
                HostLight::Spot { position, .. } => *position += Vec3::new(0.3, 0.0, -0.2),
                HostLight::Directional { direction, .. } => *direction += Vec3::new(0.05, 0.0, 0.0),
            }
            light.engine_light()
        })
        .collect();
    let engine = |keep: bool| {
        let mut s = settings();
        s.keep_static_layer = keep;
        Engine::new(&host, &world, s).expect("engine")
    };
    let (mut kept, mut redrawn) = (engine(true), engine(false));
    let lights = world.lights.len();
    // Per light: the frames that drew its map's static layer.
    let drawn = |frames: &[deferred::FrameOutput]| -> Vec<Vec<u32>> {
        (0..lights)
            .map(|light| {
                (frames.iter())
                    .filter(|f| f.static_layer_drawn[light])
                    .map(|f| f.frame)
                    .collect()
            })
            .collect()
    };
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
        // Frames in flight: each slot's map drew its layer once per light setup, in the
        // slot's first frame (a light that moved gets a new shadow, whose maps draw theirs
        // again); redrawn, every frame drew it.
        let slots = deferred::FRAMES_IN_FLIGHT as u32;
        let first_of_each_slot: Vec<u32> = (range.start..range.start + slots).collect();
        assert_eq!(drawn(&a), vec![first_of_each_slot; lights], "part {part}");
        let every_frame: Vec<u32> = range.clone().collect();
        assert_eq!(drawn(&b), vec![every_frame; lights], "part {part}");
        eprintln!(
            "frames {range:?}: identical; layers drawn in {:?}",
            drawn(&a)
        );
    }
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
            transform: Box::new(move |f| {
                DMat4::from_translation(DVec3::new(x0 + travel * f, h0 + (h1 - h0) * f, Z0))
            }),
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
    let mut engine = Engine::new(host, world, settings()).expect("engine");
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

mod lit_fraction;
mod own_triangle;
mod texel_samples;
