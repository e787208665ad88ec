//! The footprint hull (`glsl/convex_hull.glsl`) on point sets with exact coordinate ties:
//! a triangle of axis-aligned geometry under an orthographic light, moving by a whole number
//! of texels, hands over corners that share x (or y) exactly, which random float points
//! never do. The chain needs its points sorted by x and then by y: among points of equal x
//! the first must be the lowest and the last the highest, or the chain starts or ends in the
//! middle of a vertical side and cuts a corner off the footprint (a right triangle moving by
//! (0, 5) lost 8 of its 28 square texels in half of its corner orders). Checked against a
//! hull computed here in exact integers.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::rng::Rng;
use crate::support::test_shader::compile_compute;
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, OneShot, Spirv, compute_pipeline, memory_barrier,
};

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    points: u64,
    results: u64,
    count: u32,
    reserved: u32,
}

type Point = [i64; 2];

/// The convex hull of `points`, counter-clockwise from the lowest of the leftmost points,
/// without repeated or collinear vertices (one point: it; all on a line: its two ends).
/// Andrew's monotone chain in exact integer arithmetic.
fn hull_oracle(points: &[Point]) -> Vec<Point> {
    let mut p = points.to_vec();
    p.sort();
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let turn = |o: Point, a: Point, b: Point| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<Point> = Vec::new();
    for pass in [p.clone(), p.iter().rev().copied().collect()] {
        let floor = hull.len();
        for q in pass {
            while hull.len() >= floor + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    if hull.len() < 3 {
        // All on one line: the chain went out and back.
        hull.truncate(2);
    }
    hull
}

/// Twice the area of a counter-clockwise polygon.
fn double_area(poly: &[Point]) -> i64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum()
}

/// A triangle of small whole-number corners and its copy moved by a whole-number step (at
/// times along one axis only), as the six corners the collection hands over.
fn moving_triangle(rng: &mut Rng) -> [Point; 6] {
    let mut coord = |n: usize| rng.below(n) as i64;
    let c = [
        [coord(7), coord(7)],
        [coord(7), coord(7)],
        [coord(7), coord(7)],
    ];
    let mut step = [coord(11) - 5, coord(11) - 5];
    match coord(3) {
        0 => step[0] = 0,
        1 => step[1] = 0,
        _ => {}
    }
    let m = c.map(|p| [p[0] + step[0], p[1] + step[1]]);
    [c[0], c[1], c[2], m[0], m[1], m[2]]
}

/// The hull of each set (its six points in the order given) through `hull_chain_probe.comp`:
/// per set, the hull's vertices as the shader returns them.
fn gpu_hulls(sets: &[[Point; 6]]) -> Vec<Vec<[f32; 2]>> {
    let ctx = context();
    let device = ctx.device();
    let flat: Vec<f32> = sets.iter().flatten().flatten().map(|&v| v as f32).collect();
    let points =
        Buffer::with_data(&ctx, "hull points", BufferUsage::HostToDevice, &flat).expect("points");
    let results = Buffer::new(
        &ctx,
        "hull results",
        (sets.len() * 32 * 4) as u64,
        BufferUsage::DeviceToHost,
    )
    .expect("results");
    let source = include_str!("../glsl/hull_chain_probe.comp");
    let spirv = compile_compute("hull_chain_probe.comp", source);
    let pipeline = compute_pipeline(
        &ctx,
        std::mem::size_of::<Push>() as u32,
        "hull_chain_probe.comp",
        // SAFETY: shaderc's SPIR-V of tests/glsl/hull_chain_probe.comp for Vulkan 1.2, using
        // what the library's shaders use, push constants of Push's size, no sets.
        unsafe { Spirv::new(&spirv) },
    )
    .expect("probe pipeline");
    let push = Push {
        points: points.device_address(),
        results: results.device_address(),
        count: sets.len() as u32,
        reserved: 0,
    };
    OneShot::new(&ctx)
        .expect("one shot")
        .run(|cmd| {
            // SAFETY: `cmd` is the OneShot's command buffer, recording outside rendering; the probe
            // pipeline is a compute pipeline of this context, alive through the run.
            unsafe { pipeline.bind(device, cmd) };
            // SAFETY: the probe's layout was made with Push's size as its push range
            // (compute_pipeline above).
            unsafe { pipeline.push(device, cmd, &push) };
            // SAFETY: the pipeline is bound and pushed; the shader returns for invocations at or
            // past `count` (the sets) and writes 32 floats per set, the results' size, so the
            // probe's writes stay within the result buffer, which lives until the OneShot has
            // waited.
            unsafe { device.cmd_dispatch(cmd, sets.len().div_ceil(64) as u32, 1, 1) };
            // SAFETY: outside rendering, on the context's compute queue; host reads are a valid
            // destination once the OneShot's fence signals.
            unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ) };
            Ok(())
        })
        .expect("dispatch");
    let out: Vec<f32> = results.read(sets.len() * 32).expect("read");
    drop(pipeline);
    assert_no_validation_messages(&ctx);
    out.chunks(32)
        .map(|r| {
            let h = (r[0] as usize).min(12);
            (0..h).map(|k| [r[1 + 2 * k], r[2 + 2 * k]]).collect()
        })
        .collect()
}

/// Every set, in the order the collection hands it over and reversed, gives the oracle's
/// hull, vertex for vertex (counter-clockwise, from its lowest leftmost vertex): on 2,048
/// moving triangles of small whole-number corners and steps, and on a right triangle moving
/// by (0, 5) (its corners in every order), whose footprint is the trapezoid (0, 0), (4, 0),
/// (4, 5), (0, 9) (area 28).
#[test]
fn the_footprint_of_points_with_tied_coordinates_is_their_hull() {
    let mut rng = Rng(36);
    // The right triangle with its corners in each of their six orders.
    let corners: [Point; 3] = [[0, 0], [4, 0], [0, 4]];
    let mut sets: Vec<[Point; 6]> = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ]
    .iter()
    .map(|order| {
        let c = order.map(|k| corners[k]);
        let m = c.map(|p| [p[0], p[1] + 5]);
        [c[0], c[1], c[2], m[0], m[1], m[2]]
    })
    .collect();
    let right_triangle = sets[0];
    sets.extend((0..2048).map(|_| moving_triangle(&mut rng)));
    let reversed: Vec<[Point; 6]> = sets
        .iter()
        .map(|s| {
            let mut r = *s;
            r.reverse();
            r
        })
        .collect();
    sets.extend(reversed);
    let gpu = gpu_hulls(&sets);
    assert_eq!(
        hull_oracle(&right_triangle),
        [[0, 0], [4, 0], [4, 5], [0, 9]]
    );
    let (mut tied, mut polygons, mut wrong) = (0, 0, Vec::new());
    for (set, got) in sets.iter().zip(&gpu) {
        let want = hull_oracle(set);
        // Whole numbers in and out: the chain only drops and reorders points.
        assert!(got.iter().flatten().all(|v| v.fract() == 0.0), "{got:?}");
        let mut got_exact: Vec<Point> = got.iter().map(|p| [p[0] as i64, p[1] as i64]).collect();
        // The same polygon from the same first vertex (the chain promises no first vertex).
        if let Some(first) = (0..got_exact.len()).min_by_key(|&i| got_exact[i]) {
            got_exact.rotate_left(first);
        }
        if got_exact != want {
            let lost = if got.len() >= 3 && want.len() >= 3 {
                (double_area(&want) - double_area(&got_exact)) as f64 / 2.0
            } else {
                f64::NAN
            };
            wrong.push(format!(
                "points {set:?}: hull {got:?}, the oracle's {want:?} (area lost: {lost})"
            ));
        }
        let mut xs: Vec<i64> = want.iter().map(|p| p[0]).collect();
        xs.sort();
        xs.dedup();
        tied += usize::from(xs.len() < want.len());
        polygons += usize::from(want.len() >= 3);
    }
    assert!(
        wrong.is_empty(),
        "{} of {} point sets have another hull than the oracle's:\n{}",
        wrong.len(),
        sets.len(),
        wrong[..wrong.len().min(8)].join("\n")
    );
    eprintln!(
        "{} point sets: {polygons} polygons, {tied} with hull corners of equal x",
        sets.len()
    );
    assert!(
        tied * 4 >= sets.len() && polygons * 2 >= sets.len(),
        "{tied} tied, {polygons} polygons"
    );
}
