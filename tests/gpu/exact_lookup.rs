//! The exact lookup (`Lookup::Exact`, `glsl/exact_lookup.glsl`) on maps the library's passes
//! build, run by `tests/glsl/exact_lookup_probe.comp` for receivers listed here, against
//! closed forms: a plate's edge translating over the ground (still and moving receivers,
//! within 0.01 texel of the shadow's edges, on a coarse 64 x 64 map), a still edge moved by
//! 1/64 texel, closed boxes whose shared edges let no light through, the receiver's own
//! triangle, which never shadows it (and, in `planes`, a wall that shadows the ground from its
//! very foot and a coplanar neighbour that does not shadow a receiver beside their shared
//! edge). The same for
//! one time (`ms_visible_exact`, the lighting pass's samples): a moving edge where it is at
//! that time, a still edge moved by 1/64 texel, casters smaller than a texel, and the own
//! triangle at grazing light.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::scene::{
    DirectionalLight, Light, Scene, box_mesh, light_view, mesh, overhead_directional,
    overhead_spot, scene, square, temporal_map_built, translated,
};
use crate::support::test_shader::compile_compute;
use glam::{Vec3, Vec4};
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, OneShot, Spirv, compute_pipeline, memory_barrier,
};
use motion_shadows::technique::{LightView, Lookup, NO_TRIANGLE, Pruning, RangeStorage};

mod planes;

const SIZE: (u32, u32) = (64, 64);
const TOLERANCE: f32 = 1e-4;
/// The spot light's height above the ground (overhead_spot) and its cone's half angle.
const SPOT_HEIGHT: f32 = 6.0;
const SPOT_CONE_DEG: f32 = 40.0;
/// The directional light's half-width (overhead_directional).
const HALF_EXTENT: f32 = 4.0;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    map: u64,
    receivers: u64,
    results: u64,
    count: u32,
    pad: u32,
}

/// A receiver moving from `p0` to `p1` over the shutter, on triangle `own`; with `at`, the
/// receiver at `p0` asked whether it sees the light at that one time (`ms_visible_exact`).
#[derive(Debug, Clone, Copy)]
struct Receiver {
    p0: Vec3,
    p1: Vec3,
    own: u32,
    at: Option<f32>,
}

fn still(p: Vec3) -> Receiver {
    Receiver {
        p0: p,
        p1: p,
        own: NO_TRIANGLE,
        at: None,
    }
}

/// The receiver at `p` at time `t` alone.
fn at_time(p: Vec3, t: f32) -> Receiver {
    Receiver {
        at: Some(t),
        ..still(p)
    }
}

/// The exact lit fraction of each receiver (with `at`: 1 where it sees the light at that
/// time, 0 where not), from the map of `s` built for the exact lookup.
fn lit_fractions(s: &Scene, receivers: &[Receiver]) -> Vec<f32> {
    let ctx = context();
    let device = ctx.device();
    let light = LightView {
        lookup: Lookup::Exact,
        ..light_view(s, SIZE)
    };
    let (map, _) = temporal_map_built(
        &ctx,
        s,
        SIZE,
        &light,
        RangeStorage::default(),
        Pruning::default(),
        1024,
    );
    let packed: Vec<[Vec4; 2]> = receivers
        .iter()
        .map(|r| {
            [
                r.p0.extend(f32::from_bits(r.own)),
                r.p1.extend(r.at.unwrap_or(-1.0)),
            ]
        })
        .collect();
    let input = Buffer::with_data(&ctx, "receivers", BufferUsage::HostToDevice, &packed)
        .expect("receivers");
    let results = Buffer::new(
        &ctx,
        "lit fractions",
        (receivers.len() * 4) as u64,
        BufferUsage::DeviceToHost,
    )
    .expect("results");
    let spirv = compile_compute(
        "exact_lookup_probe.comp",
        include_str!("../glsl/exact_lookup_probe.comp"),
    );
    let pipeline = compute_pipeline(
        &ctx,
        std::mem::size_of::<Push>() as u32,
        "exact_lookup_probe.comp",
        // SAFETY: shaderc's SPIR-V of tests/glsl/exact_lookup_probe.comp for Vulkan 1.2,
        // using what the library's shaders use, push constants of Push's size, no sets.
        unsafe { Spirv::new(&spirv) },
    )
    .expect("probe pipeline");
    let push = Push {
        map: map.header_address(),
        receivers: input.device_address(),
        results: results.device_address(),
        count: receivers.len() as u32,
        pad: 0,
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
            // past `count` and writes one float per receiver, the results' size, so the probe's
            // writes stay within the result buffer, which lives until the OneShot has waited.
            unsafe { device.cmd_dispatch(cmd, receivers.len().div_ceil(16) as u32, 1, 1) };
            // SAFETY: outside rendering, on the context's compute queue; host reads are a valid
            // destination once the OneShot's fence signals.
            unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ) };
            Ok(())
        })
        .expect("dispatch");
    let out = results.read::<f32>(receivers.len()).expect("read");
    drop((pipeline, map));
    assert_no_validation_messages(&ctx);
    out
}

/// How much farther out a point at `height` casts its shadow on the ground: 1 for the
/// directional light straight down, H / (H - height) for the spot light at height H.
fn spread(light: &Light, height: f32) -> f32 {
    match light {
        Light::Spot(_) => SPOT_HEIGHT / (SPOT_HEIGHT - height),
        Light::Directional(_) => 1.0,
    }
}

/// The ground width of one texel at the middle of the map.
fn texel(light: &Light) -> f32 {
    match light {
        Light::Spot(_) => 2.0 * SPOT_HEIGHT * SPOT_CONE_DEG.to_radians().tan() / SIZE.0 as f32,
        Light::Directional(_) => 2.0 * HALF_EXTENT / SIZE.0 as f32,
    }
}

fn lights() -> [Light; 2] {
    [
        overhead_directional(HALF_EXTENT),
        overhead_spot(SPOT_HEIGHT, SPOT_CONE_DEG),
    ]
}

fn assert_near(what: &str, got: &[f32], want: &[f32], receivers: &[Receiver]) {
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g - w).abs() <= TOLERANCE,
            "{what}: receiver {:?}: lit {g}, the closed form {w}",
            receivers[i]
        );
    }
}

/// A plate 2 wide (x from -2 to 0) and 2 deep (z from -1 to 1) at height 1 moves by 1 along
/// x. On the ground, its leading edge's shadow passes x0 at t = x0 / k (k = the light's
/// spread): a still receiver there is lit x0 / k of the shutter; one moving by v along x is
/// caught at t = x0 / (k - v). Receivers lie within 0.01 texel of texel boundaries along
/// the edge's path, and 0.01 texel inside and outside the side edge's shadow.
#[test]
fn a_plate_edge_translating_over_the_ground_matches_the_closed_form() {
    for light in lights() {
        let k = spread(&light, 1.0);
        let w = texel(&light);
        let plate = square(-2.0, -1.0, 2.0, 1.0);
        let s = scene(
            "plate",
            light,
            vec![mesh(
                "plate",
                plate.clone(),
                translated(&plate, Vec3::X),
                false,
            )],
        );
        let mut receivers = Vec::new();
        let mut want = Vec::new();
        for b in 1..(0.95 * k / w) as i32 {
            for d in [-0.01, 0.01] {
                let x0 = (b as f32 + d) * w;
                receivers.push(still(Vec3::new(x0, 0.0, 0.1)));
                want.push(x0 / k);
                // Moving along the edge (its shadow's lit time is the same) and across it.
                let along = Vec3::new(x0, 0.0, -0.3);
                receivers.push(Receiver {
                    p1: along + Vec3::Z * 0.6,
                    ..still(along)
                });
                want.push(x0 / k);
                let v = 0.25;
                let across = Vec3::new(x0, 0.0, 0.2);
                receivers.push(Receiver {
                    p1: across + Vec3::X * v,
                    ..still(across)
                });
                want.push((x0 / (k - v)).min(1.0));
            }
        }
        let x0 = 0.5 * k;
        for (d, lit) in [(-0.01, x0 / k), (0.01, 1.0)] {
            receivers.push(still(Vec3::new(x0, 0.0, k + d * w)));
            want.push(lit);
        }
        let got = lit_fractions(&s, &receivers);
        assert_near(&s.name, &got, &want, &receivers);
    }
}

/// A still plate whose edge sits at 0.3 + j/64 texel (j = 0..4): the receivers 1/256 texel
/// on either side of each edge's shadow are in shadow and lit, whatever texel the edge
/// falls in (no snapping to texels).
#[test]
fn a_still_edge_moved_by_a_64th_of_a_texel_moves_the_shadow_with_it() {
    for light_index in 0..2 {
        for j in 0..4 {
            let [directional, spot] = lights();
            let light = if light_index == 0 { directional } else { spot };
            let (k, w) = (spread(&light, 1.0), texel(&light));
            let edge = 0.3 + j as f32 * w / 64.0;
            let plate = square(edge - 2.0, -1.0, 2.0, 1.0);
            let s = scene(
                "still edge",
                light,
                vec![mesh("plate", plate.clone(), plate, false)],
            );
            let shadow = edge * k;
            let receivers = [
                still(Vec3::new(shadow - w / 256.0, 0.0, 0.0)),
                still(Vec3::new(shadow + w / 256.0, 0.0, 0.0)),
            ];
            let got = lit_fractions(&s, &receivers);
            assert_near(&format!("edge {j}/64 texel"), &got, &[0.0, 1.0], &receivers);
        }
    }
}

/// Closed boxes (3 x 3 quads a face), still and moving by 0.3 along x: ground receivers
/// under the box all shutter long, densely along the projections of the top face's shared
/// edges (grid lines and diagonals), are never lit.
#[test]
fn a_closed_box_lets_no_light_through_its_shared_edges() {
    for light in lights() {
        let k = spread(&light, 2.0);
        let centre = Vec3::new(0.013, 1.5, 0.007);
        let cube = translated(&box_mesh(Vec3::ONE, 3), centre);
        let moved = translated(&cube, Vec3::X * 0.3);
        let s = scene("box", light, vec![mesh("box", cube, moved, true)]);
        let mut receivers = Vec::new();
        for i in 0..120 {
            let u = -0.3 + 0.6 * (i as f32 + 0.5) / 120.0;
            for line in [-1.0 / 6.0, 1.0 / 6.0] {
                // Grid lines of the top face along z and along x, and its diagonals, at the
                // box's position at t = 0 and t = 1, seen from the light.
                for shift in [0.0, 0.3] {
                    let top = |x: f32, z: f32| {
                        Vec3::new((centre.x + shift + x) * k, 0.0, (centre.z + z) * k)
                    };
                    receivers.push(still(top(line, u)));
                    receivers.push(still(top(u, line)));
                    receivers.push(still(top(u, u)));
                    receivers.push(still(top(u, -u)));
                }
            }
        }
        // Only those under the box at both ends (so all shutter long): x within the
        // overlap of the box's spans at t = 0 and t = 1 (seen from the light: its bottom,
        // the narrower shadow, bounds the region).
        let kb = spread(&s.light, 1.0);
        receivers.retain(|r| {
            let x = r.p0.x;
            x > (centre.x + 0.3 - 0.5) * kb && x < (centre.x + 0.5) * kb
        });
        assert!(receivers.len() > 300, "{} receivers", receivers.len());
        let got = lit_fractions(&s, &receivers);
        let want = vec![0.0; receivers.len()];
        assert_near(&format!("box under {}", k), &got, &want, &receivers);
    }
}

/// A receiver rebuilt 0.01 below its own ground triangle (a depth buffer's rounding): the
/// triangle blocks its ray (lit 0 when the receiver is on no triangle), but never shadows
/// the receiver that names it as its own (lit 1). Both for a still ground (its triangles in
/// the static name lists) and for one sliding by 0.5 with the receiver on it (in the
/// frame's ranges).
#[test]
fn the_receivers_own_triangle_never_shadows_it() {
    let ground = square(-1.0, -1.0, 2.0, 0.0);
    let slide = Vec3::new(0.5, 0.0, 0.0);
    for by in [Vec3::ZERO, slide] {
        let moved = ground.iter().map(|&q| q + by).collect();
        let s = scene(
            "own",
            overhead_directional(HALF_EXTENT),
            vec![mesh("ground", ground.clone(), moved, false)],
        );
        // Triangle 0 is (-1, -1), (-1, 1), (1, 1) in xz: where x <= z.
        let p = Vec3::new(-0.5, -0.01, 0.5);
        let on_ground = Receiver {
            p0: p,
            p1: p + by,
            own: NO_TRIANGLE,
            at: None,
        };
        // And at one time (the lighting pass's lookup), where the ground is then.
        let at_half = Receiver {
            own: NO_TRIANGLE,
            ..at_time(p + 0.5 * by, 0.5)
        };
        let receivers = [
            on_ground,
            Receiver {
                own: 0,
                ..on_ground
            },
            at_half,
            Receiver { own: 0, ..at_half },
        ];
        let got = lit_fractions(&s, &receivers);
        assert_near(
            &format!("own triangle, moved by {by}"),
            &got,
            &[0.0, 1.0, 0.0, 1.0],
            &receivers,
        );
    }
}

/// One time: the plate of the closed-form test (x from -2 to 0 at t = 0, moving by 1 along
/// x) has its leading edge at x = t, whose shadow is at k t on the ground: receivers 1/256
/// texel on either side of it are in shadow and lit at that time, and the receivers of the
/// other end of the shutter's edge are not (each ray tested against the corners where they
/// are at t).
#[test]
fn at_one_time_a_moving_edge_shadows_where_it_is_then() {
    for light in lights() {
        let (k, w) = (spread(&light, 1.0), texel(&light));
        let plate = square(-2.0, -1.0, 2.0, 1.0);
        let s = scene(
            "moving edge at one time",
            light,
            vec![mesh(
                "plate",
                plate.clone(),
                translated(&plate, Vec3::X),
                false,
            )],
        );
        let mut receivers = Vec::new();
        let mut want = Vec::new();
        for t in [0.0, 0.13, 0.5, 0.77, 1.0] {
            let shadow = t * k;
            for (dx, lit) in [(-w / 256.0, 0.0), (w / 256.0, 1.0)] {
                receivers.push(at_time(Vec3::new(shadow + dx, 0.0, 0.1), t));
                want.push(lit);
            }
            // The edge's shadow at the shutter's other end: lit at t = 0 (the edge has not
            // got there), shadowed at t = 1 (it has passed).
            let other = if t < 0.5 { 0.9 * k } else { 0.1 * k };
            receivers.push(at_time(Vec3::new(other, 0.0, -0.2), t));
            want.push(if t < 0.5 { 1.0 } else { 0.0 });
        }
        let got = lit_fractions(&s, &receivers);
        assert_near(&s.name, &got, &want, &receivers);
    }
}

/// One time: a still plate whose edge sits at 0.3 + j/64 texel (j = 0..4), as the shutter
/// test's: the receivers 1/256 texel on either side of its shadow are in shadow and lit at
/// t = 0.37 (no snapping to texels).
#[test]
fn at_one_time_a_still_edge_moved_by_a_64th_of_a_texel_moves_the_shadow_with_it() {
    for light_index in 0..2 {
        for j in 0..4 {
            let light = lights().into_iter().nth(light_index).expect("two lights");
            let (k, w) = (spread(&light, 1.0), texel(&light));
            let edge = 0.3 + j as f32 * w / 64.0;
            let plate = square(edge - 2.0, -1.0, 2.0, 1.0);
            let s = scene(
                "still edge at one time",
                light,
                vec![mesh("plate", plate.clone(), plate, false)],
            );
            let shadow = edge * k;
            let receivers = [
                at_time(Vec3::new(shadow - w / 256.0, 0.0, 0.0), 0.37),
                at_time(Vec3::new(shadow + w / 256.0, 0.0, 0.0), 0.37),
            ];
            let got = lit_fractions(&s, &receivers);
            assert_near(&format!("edge {j}/64 texel"), &got, &[0.0, 1.0], &receivers);
        }
    }
}

/// One time: still triangles a fifth of a texel wide, at height 1, whose shadows fall near
/// either side of their texels and of the map's middle: the receiver under each shadow's
/// centre is in shadow (only the texel it falls in names the triangle), one a texel beside it
/// is lit.
#[test]
fn at_one_time_casters_smaller_than_a_texel_shadow_the_texel_they_fall_in() {
    for light in lights() {
        let (k, w) = (spread(&light, 1.0), texel(&light));
        let mut meshes = Vec::new();
        let mut receivers = Vec::new();
        let mut want = Vec::new();
        for (i, (fx, fz)) in [(0.2, 0.5), (0.8, 0.5), (0.5, 0.2), (0.5, 0.8), (0.15, 0.85)]
            .into_iter()
            .enumerate()
        {
            // The shadow's centre on the ground, in texel i along x from the middle, at the
            // fractions (fx, fz) of the texel; the triangle above it at height 1.
            let ground = Vec3::new((3.0 * i as f32 + fx) * w, 0.0, (fz - 2.0) * w);
            let centre = Vec3::new(ground.x / k, 1.0, ground.z / k);
            let r = 0.1 * w / k;
            let tri = vec![
                centre + Vec3::new(-r, 0.0, -r),
                centre + Vec3::new(0.0, 0.0, r),
                centre + Vec3::new(r, 0.0, -r),
            ];
            meshes.push(mesh("speck", tri.clone(), tri, false));
            receivers.push(at_time(ground, 0.6));
            want.push(0.0);
            receivers.push(at_time(ground + Vec3::X * w, 0.6));
            want.push(1.0);
        }
        let s = scene("specks", light, meshes);
        let got = lit_fractions(&s, &receivers);
        assert_near(&s.name, &got, &want, &receivers);
    }
}

/// One time, grazing light (1 degree above a tilted ground): receivers on their own ground
/// triangle (rounded onto it in f32) and 0.01 below it are lit when they name it as their
/// own; those below it, naming no triangle, are in shadow (their rays cross it ~0.57 away):
/// the triangle is left out by its id, not by the epsilon.
#[test]
fn at_one_time_the_receivers_own_triangle_never_shadows_it_at_grazing_light() {
    let tilt = |p: Vec3| Vec3::new(p.x, 0.3 * p.x + 0.2 * p.z, p.z);
    let ground: Vec<Vec3> = square(-2.0, -2.0, 4.0, 0.0).into_iter().map(tilt).collect();
    let normal = Vec3::new(-0.3, 1.0, -0.2).normalize();
    let along = Vec3::new(1.0, 0.3, 0.0).normalize();
    let angle = 1.0f32.to_radians();
    let direction = along * angle.cos() - normal * angle.sin();
    let light = Light::Directional(DirectionalLight {
        direction,
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent: 3.0,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
    });
    let s = scene(
        "own at grazing light",
        light,
        vec![mesh("ground", ground.clone(), ground, false)],
    );
    let mut receivers = Vec::new();
    let mut want = Vec::new();
    for i in 0..10 {
        for j in 0..10 {
            let (x, z) = (-0.6 + 0.13 * i as f32, -1.2 + 0.27 * j as f32);
            // Triangle 0 is where x - z <= 0 (square's first half); its ray toward the light
            // runs to -x, staying in that half.
            let own = if x <= z { 0 } else { 1 };
            if x - 0.6 < -2.0 || (own == 1 && x - 0.6 <= z) {
                continue;
            }
            let on = tilt(Vec3::new(x, 0.0, z));
            let below = on - normal * 0.01;
            receivers.push(Receiver {
                own,
                ..at_time(on, 0.5)
            });
            want.push(1.0);
            receivers.push(Receiver {
                own,
                ..at_time(below, 0.5)
            });
            want.push(1.0);
            receivers.push(at_time(below, 0.5));
            want.push(0.0);
        }
    }
    assert!(receivers.len() > 150, "{} receivers", receivers.len());
    let got = lit_fractions(&s, &receivers);
    assert_near(&s.name, &got, &want, &receivers);
}

/// One time: the closed box of the shutter test, moving by 0.3 along x, asked at t = 0.37
/// where it then is: ground receivers densely along the projections of its top face's
/// shared edges (grid lines and diagonals) are never lit (each shared edge computed in one
/// canonical order by both of its triangles).
#[test]
fn at_one_time_a_closed_box_lets_no_light_through_its_shared_edges() {
    let t = 0.37;
    for light in lights() {
        let k = spread(&light, 2.0);
        let centre = Vec3::new(0.013, 1.5, 0.007);
        let cube = translated(&box_mesh(Vec3::ONE, 3), centre);
        let moved = translated(&cube, Vec3::X * 0.3);
        let s = scene(
            "box at one time",
            light,
            vec![mesh("box", cube, moved, true)],
        );
        let shift = 0.3 * t;
        let mut receivers = Vec::new();
        for i in 0..160 {
            let u = -0.4 + 0.8 * (i as f32 + 0.5) / 160.0;
            let top =
                |x: f32, z: f32| Vec3::new((centre.x + shift + x) * k, 0.0, (centre.z + z) * k);
            for line in [-1.0 / 6.0, 1.0 / 6.0] {
                receivers.push(at_time(top(line, u), t));
                receivers.push(at_time(top(u, line), t));
            }
            receivers.push(at_time(top(u, u), t));
            receivers.push(at_time(top(u, -u), t));
        }
        let want = vec![0.0; receivers.len()];
        let got = lit_fractions(&s, &receivers);
        assert_near(&s.name, &got, &want, &receivers);
    }
}
