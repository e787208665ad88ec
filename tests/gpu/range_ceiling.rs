//! An engine sizes its map from its own host-side positions before the frame
//! (`TemporalShadowMap::reserve_for`, bounded by `RangeCeiling`), so no frame runs out of
//! room and none is grown a frame late. The expectation is the device's own count of the
//! ranges it stored, which shares nothing with the CPU bound: the frame must not overflow,
//! and the bound must not be so loose that it wastes the memory it is for.
//!
//! The draws are what an engine hands over: indexed meshes whose transforms differ at
//! t = 0 and t = 1 (rigid motion), a mesh deformed in object space (skinning), and a static
//! ground named with one stream twice, under a spot light.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::rng::Rng;
use glam::{Mat4, Quat, Vec3};
use motion_shadows::gpu::{Buffer, BufferUsage, Context, OneShot};
use motion_shadows::technique::{
    CollectionPass, Counters, Draw, DrawList, GenerationPass, HostDraw, IndexStream, Indices,
    LightView, Lookup, PositionStream, PrismConstruction, RangeCeiling, TemporalShadowMap,
};

const SIZE: (u32, u32) = (160, 128);

/// One draw's host data: positions at t = 0 and t = 1 (the same vector for a static draw),
/// indices, transforms.
struct Mesh {
    t0: Vec<Vec3>,
    t1: Option<Vec<Vec3>>,
    indices: Vec<u32>,
    transform_t0: Mat4,
    transform_t1: Mat4,
    closed: bool,
}

impl Mesh {
    fn host(&self) -> HostDraw<'_> {
        HostDraw {
            transform_t0: self.transform_t0,
            transform_t1: self.transform_t1,
            closed: self.closed,
            ..HostDraw::new(
                &self.t0,
                self.t1.as_deref().unwrap_or(&self.t0),
                Some(&self.indices),
            )
        }
    }
}

/// A random scene: the ground, `cubes` cubes turning and sliding, a waving grid.
fn meshes(rng: &mut Rng, cubes: usize) -> Vec<Mesh> {
    let mut signed = || 2.0 * rng.unit() - 1.0;
    let ground = vec![
        Vec3::new(-6.0, 0.0, -6.0),
        Vec3::new(6.0, 0.0, -6.0),
        Vec3::new(6.0, 0.0, 6.0),
        Vec3::new(-6.0, 0.0, 6.0),
    ];
    let mut out = vec![Mesh {
        t0: ground,
        t1: None,
        indices: vec![0, 2, 1, 0, 3, 2],
        transform_t0: Mat4::IDENTITY,
        transform_t1: Mat4::IDENTITY,
        closed: false,
    }];
    for _ in 0..cubes {
        let (t0, indices) = crate::support::scene::indexed_unit_cube();
        let at = |position: Vec3, axis: Vec3, angle: f32, size: f32| {
            Mat4::from_scale_rotation_translation(
                Vec3::splat(size),
                Quat::from_axis_angle(axis.normalize(), angle),
                position,
            )
        };
        let p = Vec3::new(3.0 * signed(), 1.0 + signed().abs(), 3.0 * signed());
        let axis = Vec3::new(signed(), signed(), signed()) + Vec3::Y * 0.1;
        let (angle, turn, size) = (3.0 * signed(), 1.5 * signed(), 0.6 + 0.5 * signed().abs());
        let slide = Vec3::new(signed(), 0.3 * signed(), signed());
        out.push(Mesh {
            t0,
            t1: None,
            indices,
            transform_t0: at(p, axis, angle, size),
            transform_t1: at(p + slide, axis, angle + turn, size),
            closed: true,
        });
    }
    // A 6 x 6 grid waving in object space: the t1 positions differ, the transform does not.
    let n = 7u32;
    let grid = |phase: f32| -> Vec<Vec3> {
        (0..n * n)
            .map(|i| {
                let (x, z) = ((i % n) as f32 * 0.5 - 1.5, (i / n) as f32 * 0.5 - 1.5);
                Vec3::new(x, 2.5 + 0.4 * (x * 2.0 + phase).sin() * z.cos(), z)
            })
            .collect()
    };
    let phase = 3.0 * signed();
    let indices = (0..n - 1)
        .flat_map(|z| (0..n - 1).map(move |x| z * n + x))
        .flat_map(|i| [i, i + n, i + 1, i + 1, i + n, i + n + 1])
        .collect();
    out.push(Mesh {
        t0: grid(phase),
        t1: Some(grid(phase + 1.2)),
        indices,
        transform_t0: Mat4::from_translation(Vec3::new(signed(), 0.0, signed())),
        transform_t1: Mat4::from_translation(Vec3::new(signed(), 0.0, signed())),
        closed: false,
    });
    out
}

fn light(static_layer: bool) -> LightView {
    LightView {
        static_layer,
        ..LightView::spot(
            Vec3::new(1.0, 12.0, 2.0),
            Vec3::new(-0.05, -1.0, -0.1),
            40.0,
            100.0,
            0.5,
            30.0,
            SIZE,
        )
    }
}

/// One frame of `meshes` into `map`, as an engine records it: the map's counters after it.
fn frame(ctx: &Context, meshes: &[Mesh], light: &LightView, map: &TemporalShadowMap) -> Counters {
    let device = ctx.device();
    let stride = std::mem::size_of::<Vec3>() as u32;
    let mut buffers = Vec::new();
    let mut draws = Vec::new();
    let mut first_id = 0;
    for (k, mesh) in meshes.iter().enumerate() {
        let t1 = mesh.t1.as_ref().unwrap_or(&mesh.t0);
        let positions: Vec<Vec3> = mesh.t0.iter().chain(t1).copied().collect();
        let buffer = Buffer::with_data(
            ctx,
            &format!("mesh {k}"),
            BufferUsage::HostToDevice,
            &positions,
        )
        .expect("positions");
        let indices = Buffer::with_data(
            ctx,
            &format!("indices {k}"),
            BufferUsage::HostToDevice,
            &mesh.indices,
        )
        .expect("indices");
        let count = mesh.t0.len() as u32;
        let t1_offset = if mesh.t1.is_some() {
            u64::from(count * stride)
        } else {
            0
        };
        let triangles = mesh.indices.len() as u32 / 3;
        let mut draw = Draw::new(
            PositionStream::from_buffer(&buffer, 0, stride).expect("t0 stream"),
            PositionStream::from_buffer(&buffer, t1_offset, stride).expect("t1 stream"),
            count,
            Indices::U32(IndexStream::from_buffer(&indices, 0).expect("index stream")),
            triangles,
            first_id,
        );
        draw.transform_t0 = mesh.transform_t0;
        draw.transform_t1 = mesh.transform_t1;
        draw.closed = mesh.closed;
        assert_eq!(draw.is_static(), mesh.host().is_static(), "mesh {k}");
        first_id += triangles;
        draws.push(draw);
        buffers.push((buffer, indices));
    }
    let collection = CollectionPass::new(ctx).expect("collection pass");
    let generation = GenerationPass::new(ctx).expect("generation pass");
    let mut list = DrawList::new(ctx, draws.len() as u32).expect("draw list");
    OneShot::new(ctx)
        .expect("command buffer")
        .run(|cmd| {
            // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering; every
            // object outlives the submission, which `run` waits for.
            unsafe {
                list.record_update(device, cmd, &draws)?;
                collection.record(device, cmd, &list, light, map, None)?;
                generation.record(device, cmd, map);
                map.record_counter_readback(device, cmd);
            }
            Ok(())
        })
        .expect("shadow pass");
    map.read_counters().expect("counters")
}

/// Four random scenes, with the static layer (ranges collected directly) and without it
/// (nodes paired by the generation pass): a map made with room for one range, reserved for
/// the host draws, holds the whole frame; the bound is at most 3x what was stored.
#[test]
fn a_map_reserved_for_the_host_draws_never_overflows() {
    let ctx = context();
    let mut rng = Rng(0x5eed_0026);
    let mut worst: f64 = 1.0;
    for case in 0..4 {
        let meshes = meshes(&mut rng, 3 + case);
        let host: Vec<HostDraw> = meshes.iter().map(Mesh::host).collect();
        for static_layer in [true, false] {
            let light = light(static_layer);
            let mut map =
                TemporalShadowMap::new(&ctx, SIZE.0, SIZE.1, 1, 1).expect("temporal shadow map");
            let bound = map
                .reserve_for(&ctx, &light, None, &host)
                .expect("reserve")
                .expect("the exact construction is bounded");
            assert_eq!(map.range_capacity() as u64, bound);
            let counts = frame(&ctx, &meshes, &light, &map);
            let stored = u64::from(counts.range_count);
            eprintln!("case {case}, static layer {static_layer}: bound {bound}, stored {stored}");
            assert!(
                !map.needs_more_room(&counts),
                "case {case} (static layer {static_layer}): {counts:?} overflowed a map reserved for {bound}"
            );
            map.check_complete(&counts).expect("complete map");
            assert!(stored > 1000, "case {case}: only {stored} ranges");
            worst = worst.max(bound as f64 / stored as f64);
        }
    }
    // Rigid motion and a gentle wave: the bound's footprint is about what is swept.
    assert!(
        worst <= 3.0,
        "the bound is {worst:.2} times the ranges stored"
    );
    assert_no_validation_messages(&ctx);
}

/// The exact lookup's conservative collection stores one range per texel a triangle's grown
/// footprint covers, and names still triangles in the static name lists: a map reserved for
/// the host draws (records, ranges and names) holds the whole frame, with and without the
/// static layer; the bound is at most 3x what was stored.
#[test]
fn a_map_reserved_for_the_exact_lookup_never_overflows() {
    let ctx = context();
    let mut rng = Rng(0x5eed_0040);
    let mut worst: f64 = 1.0;
    for case in 0..2 {
        let meshes = meshes(&mut rng, 3 + case);
        let host: Vec<HostDraw> = meshes.iter().map(Mesh::host).collect();
        let triangles: u64 = meshes.iter().map(|m| m.indices.len() as u64 / 3).sum();
        for static_layer in [true, false] {
            let light = LightView {
                lookup: Lookup::Exact,
                ..light(static_layer)
            };
            let mut map =
                TemporalShadowMap::new(&ctx, SIZE.0, SIZE.1, 1, 1).expect("temporal shadow map");
            map.reserve_triangle_records(&ctx, triangles)
                .expect("triangle records");
            let bound = map
                .reserve_for(&ctx, &light, None, &host)
                .expect("reserve")
                .expect("the exact lookup is bounded");
            let counts = frame(&ctx, &meshes, &light, &map);
            let stored = u64::from(counts.range_count);
            eprintln!(
                "exact, case {case}, static layer {static_layer}: bound {bound}, stored {stored}, \
                 static names {} of {}",
                counts.static_names,
                map.static_name_capacity()
            );
            assert!(
                !map.needs_more_room(&counts),
                "case {case} (static layer {static_layer}): {counts:?} overflowed a map reserved for {bound} ranges, {} names",
                map.static_name_capacity()
            );
            map.check_complete(&counts).expect("complete map");
            assert!(stored > 1000, "case {case}: only {stored} ranges");
            assert_eq!(counts.static_names > 0, static_layer, "{counts:?}");
            worst = worst.max(bound as f64 / stored as f64);
        }
    }
    assert!(
        worst <= 3.0,
        "the bound is {worst:.2} times the ranges stored"
    );
    assert_no_validation_messages(&ctx);
}

/// Bad host data is refused with the reason, not bounded wrongly; the papers' prisms are
/// not bounded at all (the caller grows after an overflow instead).
#[test]
fn bad_host_draws_are_refused_and_the_papers_prisms_not_bounded() {
    let ctx = context();
    let light = light(true);
    let ceiling = RangeCeiling::new(&light, SIZE.0, SIZE.1).expect("exact prisms");
    let points = [Vec3::ZERO, Vec3::X, Vec3::Z];
    let moved = [Vec3::Y, Vec3::X + Vec3::Y, Vec3::Z + Vec3::Y];
    let error = ceiling
        .draw(&HostDraw::new(&points, &moved, Some(&[0, 1, 3])))
        .expect_err("index 3 of 3 positions");
    assert!(error.to_string().contains("index 2 is 3"), "{error}");
    let error = ceiling
        .draw(&HostDraw::new(&points, &moved[..2], None))
        .expect_err("positions of unequal lengths");
    assert!(
        error.to_string().contains("3 at shutter open, 2"),
        "{error}"
    );
    let error = ceiling
        .draw(&HostDraw::new(&points, &moved, Some(&[0, 1, 2, 0])))
        .expect_err("a fourth index, no whole triangle");
    assert!(error.to_string().contains("4 corners (indices)"), "{error}");
    let mut map = TemporalShadowMap::new(&ctx, SIZE.0, SIZE.1, 1, 1).expect("map");
    let paper = LightView {
        prisms: PrismConstruction::Paper,
        ..light
    };
    let draws = [HostDraw::new(&points, &moved, None)];
    assert_eq!(
        map.reserve_for(&ctx, &paper, None, &draws)
            .expect("reserve"),
        None
    );
    assert_eq!(map.range_capacity(), 1, "nothing reserved");
    assert!(
        map.reserve_for(&ctx, &light, None, &draws)
            .expect("reserve")
            .unwrap()
            > 0
    );
    assert_no_validation_messages(&ctx);
}

/// A draw that does not move stores no range where the frame keeps it in the static layer
/// (the device counts none), and one per covered texel where it goes to the lists: the
/// reservation follows, nothing for the first, room for the second.
#[test]
fn a_static_draw_needs_room_only_outside_the_static_layer() {
    let ctx = context();
    let ground = meshes(&mut Rng(7), 0).remove(0);
    assert!(ground.host().is_static());
    for static_layer in [true, false] {
        let light = light(static_layer);
        let mut map = TemporalShadowMap::new(&ctx, SIZE.0, SIZE.1, 1, 1).expect("map");
        let bound = map
            .reserve_for(&ctx, &light, None, &[ground.host()])
            .expect("reserve")
            .expect("bounded");
        let counts = frame(&ctx, std::slice::from_ref(&ground), &light, &map);
        let stored = u64::from(counts.range_count);
        eprintln!("static layer {static_layer}: bound {bound}, stored {stored}");
        assert!(!map.needs_more_room(&counts), "{counts:?}");
        if static_layer {
            assert_eq!((bound, stored), (0, 0));
        } else {
            assert!(stored > 1000 && bound >= stored, "{bound} for {stored}");
        }
    }
    assert_no_validation_messages(&ctx);
}

/// A spot light among the moving triangles (a flashlight in a scene: the waving grid passes
/// through the light's plane, corners in front and behind): the device's count never passes
/// the reservation, and that reservation is not every texel of the map for each triangle
/// that reaches behind the light.
#[test]
fn a_light_among_moving_triangles_is_bounded_too() {
    let ctx = context();
    let mut rng = Rng(0x0f1a_5411);
    let meshes = meshes(&mut rng, 4);
    let host: Vec<HostDraw> = meshes.iter().map(Mesh::host).collect();
    let light = LightView {
        static_layer: true,
        ..LightView::spot(
            Vec3::new(0.3, 2.5, -0.2),
            Vec3::new(0.1, -1.0, 0.05),
            50.0,
            100.0,
            0.05,
            30.0,
            SIZE,
        )
    };
    // Moving triangles with corners on both sides of the light's plane.
    let plane = |p: Vec3| (light.view * p.extend(1.0)).z;
    let crossing: u64 = host
        .iter()
        .filter(|d| !d.is_static())
        .map(|d| {
            d.triangles()
                .expect("triangles")
                .filter(|(t0, t1)| {
                    let z: Vec<f32> = t0.iter().chain(t1).map(|&p| plane(p)).collect();
                    z.iter().any(|&z| z < 0.0) && z.iter().any(|&z| z > 0.0)
                })
                .count() as u64
        })
        .sum();
    let mut map = TemporalShadowMap::new(&ctx, SIZE.0, SIZE.1, 1, 1).expect("map");
    let bound = map
        .reserve_for(&ctx, &light, None, &host)
        .expect("reserve")
        .expect("bounded");
    let counts = frame(&ctx, &meshes, &light, &map);
    let stored = u64::from(counts.range_count);
    let cap = 5 * u64::from(SIZE.0 * SIZE.1);
    eprintln!(
        "{crossing} triangles cross the light's plane: bound {bound}, stored {stored}, {crossing} x cap {}",
        crossing * cap
    );
    assert!(
        crossing >= 10,
        "only {crossing} triangles cross the light's plane"
    );
    assert!(
        !map.needs_more_room(&counts),
        "{counts:?} overflowed {bound}"
    );
    map.check_complete(&counts).expect("complete map");
    assert!(stored > 1000, "only {stored} ranges");
    assert!(
        bound < crossing * cap / 4,
        "the bound {bound} is near every texel for each of the {crossing} crossing triangles"
    );
    assert_no_validation_messages(&ctx);
}
