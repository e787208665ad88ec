//! Host geometry read in place: the draws of an engine (indexed, strided, offset, with object
//! transforms at t0 and t1) render exactly like the same triangles handed over de-indexed in
//! world space; bad indices and bad draw descriptions are errors, never silent.

use crate::support::frame::{Frame, render_draws};
use crate::support::gpu::{assert_no_validation_messages, context};
use glam::{DMat4, DVec3, Mat4, Vec3, Vec4};
use motion_shadows::Error;
use motion_shadows::gpu::{Buffer, BufferUsage, Context, OneShot};
use motion_shadows::technique::{
    Draw, DrawList, IndexStream, Indices, LightView, LightingView, PositionStream,
};
use motion_shadows_app::render::upload::{SceneGeometry, camera_view, light_view};
use motion_shadows_app::scene::{BuiltinOptions, Scene, builtin};
use std::collections::HashMap;

const SIZE: (u32, u32) = (96, 72);
const SPP: u32 = 4;

fn views(scene: &Scene) -> (LightView, LightingView) {
    let light = light_view(scene, SIZE);
    let view = LightingView {
        camera: camera_view(scene, SIZE),
        seed: 11,
        ambient: scene.ambient,
        estimator: Default::default(),
        filter: Default::default(),
    };
    (light, view)
}

/// A mesh as an engine keeps it: each distinct (t0, t1) vertex once, and indices.
struct Indexed {
    vertices: Vec<(Vec3, Vec3)>,
    indices: Vec<u32>,
}

fn index(t0: &[Vec3], t1: &[Vec3]) -> Indexed {
    let mut seen = HashMap::new();
    let mut out = Indexed {
        vertices: Vec::new(),
        indices: Vec::new(),
    };
    for (a, b) in t0.iter().zip(t1) {
        let key = (
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits),
        );
        let next = out.vertices.len() as u32;
        let i = *seen.entry(key).or_insert_with(|| {
            out.vertices.push((*a, *b));
            next
        });
        out.indices.push(i);
    }
    out
}

/// Bytes of the engine's vertex buffer: `VERTEX_OFFSET` bytes of something else, then per
/// vertex its t0 position (12 bytes), its t1 position (12 bytes) and 8 bytes of padding:
/// the t0 stream starts at the offset, the t1 stream 12 bytes later, both of stride 32.
const VERTEX_OFFSET: u64 = 64;
const STRIDE: u32 = 32;

fn vertex_bytes(meshes: &[Indexed]) -> Vec<f32> {
    let mut floats = vec![-7.0f32; VERTEX_OFFSET as usize / 4];
    for m in meshes {
        for (a, b) in &m.vertices {
            floats.extend(a.to_array());
            floats.extend(b.to_array());
            floats.extend([f32::NAN, f32::NAN]);
        }
    }
    floats
}

#[test]
fn indexed_strided_offset_draws_render_like_deindexed_triangles() {
    let ctx = context();
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let (light, view) = views(&scene);

    // The app's own upload: de-indexed triangles, one position pair per corner.
    let soup = SceneGeometry::upload(&ctx, &scene).unwrap();
    let reference = render_draws(&ctx, &soup.draws, &light, &view, SIZE, SIZE, SPP).unwrap();

    // The engine's layout: one vertex buffer at an offset with interleaved t0/t1 positions;
    // 32-bit indices for the first mesh, 16-bit ones for the others, the 16-bit streams
    // starting at a 2-byte (not 4-byte) aligned offset.
    let meshes: Vec<Indexed> = scene.meshes.iter().map(|m| index(&m.t0, &m.t1)).collect();
    let vertex_buffer = Buffer::with_data(
        &ctx,
        "engine vertices",
        BufferUsage::HostToDevice,
        &vertex_bytes(&meshes),
    )
    .unwrap();
    let mut index_bytes: Vec<u8> = vec![0xab; 6];
    let mut draws = Vec::new();
    let (mut first_vertex, mut first_id) = (0u64, 0u32);
    for (i, (m, original)) in meshes.iter().zip(&scene.meshes).enumerate() {
        assert!(m.vertices.len() < 65536);
        let start = index_bytes.len() as u64;
        let indices = if i == 0 {
            index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
            let start = index_bytes.len() as u64;
            m.indices
                .iter()
                .for_each(|v| index_bytes.extend(v.to_le_bytes()));
            (start, true)
        } else {
            if start % 4 == 0 {
                index_bytes.extend([0xcd, 0xcd]);
            }
            let start = index_bytes.len() as u64;
            m.indices
                .iter()
                .for_each(|&v| index_bytes.extend((v as u16).to_le_bytes()));
            (start, false)
        };
        draws.push((first_vertex, m.vertices.len() as u32, indices, first_id));
        first_vertex += m.vertices.len() as u64;
        first_id += original.t0.len() as u32 / 3;
    }
    index_bytes.resize(index_bytes.len().next_multiple_of(4) + 4, 0);
    let index_buffer = Buffer::with_data(
        &ctx,
        "engine indices",
        BufferUsage::HostToDevice,
        &index_bytes,
    )
    .unwrap();
    let draws: Vec<Draw> = draws
        .into_iter()
        .zip(&scene.meshes)
        .map(|((first, count, (offset, wide), id), original)| {
            let base = VERTEX_OFFSET + first * STRIDE as u64;
            let stream = IndexStream::from_buffer(&index_buffer, offset).unwrap();
            // A static mesh names its t0 positions twice, as the renderer's upload does (the
            // documented way to make a draw static, which the exact construction rasterizes
            // directly).
            let t1 = if original.t0 == original.t1 {
                base
            } else {
                base + 12
            };
            let mut draw = Draw::new(
                PositionStream::from_buffer(&vertex_buffer, base, STRIDE).unwrap(),
                PositionStream::from_buffer(&vertex_buffer, t1, STRIDE).unwrap(),
                count,
                if wide {
                    Indices::U32(stream)
                } else {
                    Indices::U16(stream)
                },
                original.t0.len() as u32 / 3,
                id,
            );
            draw.closed = original.closed;
            draw.albedo = original.albedo;
            draw
        })
        .collect();
    let engine = render_draws(&ctx, &draws, &light, &view, SIZE, SIZE, SPP).unwrap();

    assert!(reference.counters.node_count > 1000);
    assert_eq!(engine.counters, reference.counters);
    assert_same_ranges(&engine, &reference);
    let differing = engine
        .rgb
        .iter()
        .zip(&reference.rgb)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{differing} channels differ");
    assert!(engine.rgb.iter().any(|&v| v > 0.0));
    assert_no_validation_messages(&ctx);
}

/// Per texel, the same ranges (as sets: the list order follows atomics).
fn assert_same_ranges(a: &Frame, b: &Frame) {
    let key = |r: &motion_shadows::technique::Range| {
        (
            r.id,
            r.t_s.to_bits(),
            r.t_e.to_bits(),
            r.d_s.to_bits(),
            r.d_e.to_bits(),
        )
    };
    for y in 0..a.map.height {
        for x in 0..a.map.width {
            let mut ra: Vec<_> = a.map.ranges_at(x, y).iter().map(key).collect();
            let mut rb: Vec<_> = b.map.ranges_at(x, y).iter().map(key).collect();
            ra.sort_unstable();
            rb.sort_unstable();
            assert_eq!(ra, rb, "ranges at texel ({x}, {y})");
        }
    }
}

/// Rigid motion by object transforms (a turn and a translation between t0 and t1) renders
/// like the same motion applied to the vertices on the CPU (in f64). Rounding differs
/// (the shader transforms in f32), so a few pixels on edges may differ.
#[test]
fn object_transforms_at_t0_and_t1_move_the_mesh() {
    let ctx = context();
    let mut scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    // Keep the ground and one cube; the cube is static in object space.
    let cube = scene
        .meshes
        .iter()
        .position(|m| m.closed && m.t0 != m.t1)
        .expect("a moving closed mesh");
    let object: Vec<Vec3> = scene.meshes[cube].t0.clone();
    let centre = object.iter().fold(Vec3::ZERO, |a, p| a + *p) / object.len() as f32;
    let local: Vec<Vec3> = object.iter().map(|p| *p - centre).collect();
    let at = |turn_deg: f64, shift: DVec3| {
        DMat4::from_translation(centre.as_dvec3() + shift)
            * DMat4::from_rotation_y(turn_deg.to_radians())
    };
    let (m0, m1) = (at(0.0, DVec3::ZERO), at(35.0, DVec3::new(0.6, 0.2, -0.9)));
    let world = |m: DMat4| -> Vec<Vec3> {
        local
            .iter()
            .map(|p| m.transform_point3(p.as_dvec3()).as_vec3())
            .collect()
    };
    scene.meshes[cube].t0 = world(m0);
    scene.meshes[cube].t1 = world(m1);
    let kept: Vec<_> = (scene.meshes.drain(..).enumerate())
        .filter(|(i, m)| !m.closed || *i == cube)
        .map(|(_, m)| m)
        .collect();
    scene.meshes = kept;
    let (light, view) = views(&scene);
    let soup = SceneGeometry::upload(&ctx, &scene).unwrap();
    let reference = render_draws(&ctx, &soup.draws, &light, &view, SIZE, SIZE, SPP).unwrap();

    // The same cube as object-space vertices (static) and two transforms.
    let floats: Vec<f32> = local.iter().flat_map(|p| p.to_array()).collect();
    let buffer = Buffer::with_data(&ctx, "cube", BufferUsage::HostToDevice, &floats).unwrap();
    let mut draws = soup.draws.clone();
    let cube_draw = draws.iter().position(|d| d.closed).unwrap();
    let stream = PositionStream::from_buffer(&buffer, 0, 12).unwrap();
    let d = &mut draws[cube_draw];
    d.positions_t0 = stream;
    d.positions_t1 = stream;
    d.transform_t0 = m0.as_mat4();
    d.transform_t1 = m1.as_mat4();
    let moved = render_draws(&ctx, &draws, &light, &view, SIZE, SIZE, SPP).unwrap();

    let pixels = (SIZE.0 * SIZE.1) as usize;
    let differing = (0..pixels)
        .filter(|&i| (0..3).any(|c| (moved.rgb[3 * i + c] - reference.rgb[3 * i + c]).abs() > 1e-4))
        .count();
    eprintln!("transforms vs CPU-moved vertices: {differing} of {pixels} pixels differ");
    assert!(
        differing * 200 <= pixels,
        "{differing} of {pixels} pixels differ"
    );
    let ranges = |f: &Frame| f.counters.range_count as f64;
    assert!((ranges(&moved) / ranges(&reference) - 1.0).abs() < 0.01);
    // And the motion is really there: the cube frozen at t0 renders otherwise.
    let mut frozen = draws.clone();
    frozen[cube_draw].transform_t1 = frozen[cube_draw].transform_t0;
    let still = render_draws(&ctx, &frozen, &light, &view, SIZE, SIZE, SPP).unwrap();
    let moved_pixels = (0..pixels)
        .filter(|&i| (0..3).any(|c| (still.rgb[3 * i + c] - moved.rgb[3 * i + c]).abs() > 1e-4))
        .count();
    assert!(moved_pixels > 20 * differing.max(1), "{moved_pixels}");
    assert_no_validation_messages(&ctx);
}

fn engine_square(ctx: &Context) -> (Buffer, Buffer) {
    // Two triangles of a unit square at height 1, and indices with one past the end.
    let corners: [f32; 12] = [0., 1., 0., 0., 1., 1., 1., 1., 1., 1., 1., 0.];
    let indices: [u32; 6] = [0, 1, 2, 0, 2, 4];
    (
        Buffer::with_data(ctx, "square", BufferUsage::HostToDevice, &corners).unwrap(),
        Buffer::with_data(ctx, "square indices", BufferUsage::HostToDevice, &indices).unwrap(),
    )
}

/// An index at the draw's vertex count drops its triangle and is reported, by the shadow
/// map's counters (an error for the frame) and by the lighting pass.
#[test]
fn an_out_of_range_index_is_counted_and_refused() {
    let ctx = context();
    let (positions, indices) = engine_square(&ctx);
    let stream = PositionStream::from_buffer(&positions, 0, 12).unwrap();
    let draw = Draw::new(
        stream,
        stream,
        4,
        Indices::U32(IndexStream::from_buffer(&indices, 0).unwrap()),
        2,
        0,
    );
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let (light, view) = views(&scene);
    let frame = render_draws(&ctx, &[draw], &light, &view, (32, 24), (32, 24), 1).unwrap();
    assert_eq!(frame.counters.invalid_triangles, 1);
    assert_eq!(frame.lighting_invalid, 1);
    let map = motion_shadows::technique::TemporalShadowMap::new(&ctx, 32, 24, 4, 4).unwrap();
    match map.check_complete(&frame.counters) {
        Err(Error::InvalidIndices { triangles: 1 }) => {}
        other => panic!("expected InvalidIndices, got {other:?}"),
    }
    assert_no_validation_messages(&ctx);
}

/// Draw descriptions the shaders could not read safely are refused before anything is
/// recorded, each with a message naming the draw and the figures.
#[test]
fn bad_draw_descriptions_are_refused() {
    let ctx = context();
    let (positions, indices) = engine_square(&ctx);
    let stream = PositionStream::from_buffer(&positions, 0, 12).unwrap();
    let good = Draw::new(stream, stream, 4, Indices::None, 1, 0);
    // A host's raw handle gives the same stream as the library's own buffer.
    // SAFETY: `positions` is a live buffer of this device with address usage, alive here.
    let raw = unsafe {
        PositionStream::from_raw_buffer(ctx.device(), positions.raw(), positions.size(), 0, 12)
    }
    .unwrap();
    assert_eq!(raw, stream);
    // SAFETY: as above.
    let raw_indices =
        unsafe { IndexStream::from_raw_buffer(ctx.device(), indices.raw(), indices.size(), 4) }
            .unwrap();
    assert_eq!(raw_indices, IndexStream::from_buffer(&indices, 4).unwrap());
    let mut list = DrawList::new(&ctx, 4).unwrap();
    let attempt = |list: &mut DrawList, draws: &[Draw]| -> Result<(), Error> {
        let mut outcome = Ok(());
        OneShot::new(&ctx)
            .unwrap()
            .run(|cmd| {
                // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering.
                outcome = unsafe { list.record_update(ctx.device(), cmd, draws) };
                Ok(())
            })
            .unwrap();
        outcome
    };
    attempt(&mut list, &[good]).expect("a good draw");
    let mut cases: Vec<(&str, Vec<Draw>)> = Vec::new();
    cases.push((
        "overlapping ids",
        vec![
            good,
            Draw {
                first_triangle_id: 0,
                ..good
            },
        ],
    ));
    cases.push((
        "more vertices than the buffer holds",
        vec![Draw {
            vertex_count: 5,
            ..good
        }],
    ));
    cases.push((
        "more triangles than vertices without indices",
        vec![Draw {
            triangle_count: 2,
            ..good
        }],
    ));
    let narrow = PositionStream::from_buffer(&positions, 0, 8).unwrap();
    cases.push((
        "stride below 12",
        vec![Draw {
            positions_t1: narrow,
            ..good
        }],
    ));
    let odd = PositionStream::from_buffer(&positions, 2, 12).unwrap();
    cases.push((
        "misaligned positions",
        vec![Draw {
            positions_t0: odd,
            ..good
        }],
    ));
    let short = IndexStream::from_buffer(&indices, 20).unwrap();
    cases.push((
        "indices past the buffer",
        vec![Draw {
            indices: Indices::U32(short),
            triangle_count: 1,
            ..good
        }],
    ));
    let mut projective = good;
    projective.transform_t0 =
        Mat4::from_cols(Vec4::X, Vec4::Y, Vec4::Z, Vec4::new(0.0, 0.0, -1.0, 0.0));
    cases.push(("a projective transform", vec![projective]));
    cases.push((
        "ids reaching u32::MAX",
        vec![Draw {
            first_triangle_id: u32::MAX - 1,
            ..good
        }],
    ));
    for (what, draws) in cases {
        match attempt(&mut list, &draws) {
            Err(Error::InvalidArgument(message)) => {
                assert!(
                    message.starts_with("draw") || message.contains("overlap"),
                    "{what}: {message}"
                )
            }
            other => panic!("{what}: expected InvalidArgument, got {other:?}"),
        }
        assert_eq!(list.records().len(), 1, "{what}: the list kept its draws");
    }
    assert_no_validation_messages(&ctx);
}
