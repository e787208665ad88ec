//! Time-dependent shadow maps as an engine builds them (`EngineTsmPass`): N depth maps over
//! the shutter, the static draws' map drawn once and kept, and a mask over the host's
//! G-buffer (drawn here by the library's `GBufferPass` from the receivers alone). Checked
//! against closed forms: a caster translating over a still plane, a plane translating under a
//! still caster, a still square's shadow; and the kept static map against a redrawn one. Each
//! runs with both ways a map starts from the static one (`TsmStart`), one map per dispatch
//! and in batches (`EngineTsmMap::layers`).

use crate::support::gpu::{assert_no_validation_messages, context};
use ash::vk;
use glam::{Mat4, Vec3, Vec4};
use motion_shadows::Error;
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, Context, Image, OneShot, image_barrier, memory_barrier,
};
use motion_shadows::technique::{
    CameraView, Draw, DrawList, EngineTsmBindings, EngineTsmMap, EngineTsmPass, GBuffer,
    GBufferCamera, GBufferPass, Indices, LightView, MAX_TSM_LAYERS, MAX_TSM_MAPS, PositionStream,
    TsmStart,
};

/// The mask's pixels.
const SIZE: (u32, u32) = (96, 96);
/// The maps' texels on a side.
const SHADOW: u32 = 512;
/// Half the side of the directional light's box around the origin.
const HALF: f32 = 3.0;
/// A texel of the maps, in world units.
const TEXEL: f32 = 2.0 * HALF / SHADOW as f32;
/// How the maps start from the static map, and how many are drawn per dispatch (5: batches
/// of 5, 5, 5, 1 for 16 maps).
const CONFIGS: [(TsmStart, u32); 4] = [
    (TsmStart::Copy, 1),
    (TsmStart::SecondLookup, 1),
    (TsmStart::Copy, 5),
    (TsmStart::SecondLookup, 8),
];

/// Two triangles of the rectangle [x0, x1] x [z0, z1] at height y.
fn rect(x0: f32, x1: f32, z0: f32, z1: f32, y: f32) -> Vec<Vec3> {
    let a = Vec3::new(x0, y, z0);
    let b = Vec3::new(x0, y, z1);
    let c = Vec3::new(x1, y, z1);
    let d = Vec3::new(x1, y, z0);
    vec![a, b, c, a, c, d]
}

fn shifted(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|p| *p + by).collect()
}

/// Triangles in host-visible buffers: one stream (static) or two (moving).
struct Mesh {
    t0: Buffer,
    t1: Option<Buffer>,
    triangles: u32,
}

impl Mesh {
    fn new(ctx: &Context, t0: &[Vec3], t1: Option<&[Vec3]>) -> Mesh {
        let floats = |points: &[Vec3]| points.iter().map(|p| p.to_array()).collect::<Vec<_>>();
        let buffer = |points: &[Vec3]| {
            Buffer::with_data(ctx, "test mesh", BufferUsage::HostToDevice, &floats(points))
                .expect("mesh buffer")
        };
        Mesh {
            t0: buffer(t0),
            t1: t1.map(buffer),
            triangles: t0.len() as u32 / 3,
        }
    }

    /// Rewrites the (static) positions in place.
    fn rewrite(&mut self, t0: &[Vec3]) {
        let floats: Vec<[f32; 3]> = t0.iter().map(|p| p.to_array()).collect();
        self.t0.write(&floats).expect("rewrite mesh");
    }

    fn draw(&self, first_id: u32) -> Draw {
        let stream = |b: &Buffer| PositionStream::from_buffer(b, 0, 12).expect("stream");
        let t0 = stream(&self.t0);
        let t1 = self.t1.as_ref().map_or(t0, stream);
        Draw::new(
            t0,
            t1,
            3 * self.triangles,
            Indices::None,
            self.triangles,
            first_id,
        )
    }
}

/// A directional light along `direction` over the box of half-width [`HALF`] around the
/// origin, the maps [`SHADOW`] texels on a side.
fn light(direction: Vec3, keep_static: bool) -> LightView {
    let mut light = LightView::directional(
        direction,
        1.0,
        Vec3::ZERO,
        HALF,
        10.0,
        0.5,
        20.0,
        (SHADOW, SHADOW),
    );
    light.keep_static_layer = keep_static;
    light
}

/// The camera: above the ground at an angle, the light's box in view.
fn camera() -> (Mat4, Vec3) {
    let c = CameraView::perspective(
        Vec3::new(0.4, 7.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        SIZE.0 as f32 / SIZE.1 as f32,
        0.1,
        50.0,
    );
    (c.proj * c.view, c.position)
}

/// What a test frame draws: the G-buffer's receivers (drawn at `gbuffer_time`, their motion
/// read when `moving_receivers`) and the shadow maps' draws.
struct Frame<'a> {
    receivers: &'a [Draw],
    casters: &'a [Draw],
    light: &'a LightView,
    maps: u32,
    gbuffer_time: f32,
    moving_receivers: bool,
    /// Draw the G-buffer (else the last frame's is read again).
    draw_gbuffer: bool,
}

/// The passes, the G-buffer, the output image and its readback.
struct Rig<'c> {
    ctx: &'c Context,
    gbuffer_pass: GBufferPass,
    pass: EngineTsmPass,
    bindings: EngineTsmBindings,
    gbuffer: GBuffer,
    output: Image,
    readback: Buffer,
    receivers: DrawList,
    casters: DrawList,
    /// The G-buffer's world points (None: background), from its last readback.
    points: Vec<Option<Vec3>>,
}

impl<'c> Rig<'c> {
    fn new(ctx: &'c Context) -> Rig<'c> {
        let pass = EngineTsmPass::new(ctx).expect("engine TSM pass");
        Rig {
            ctx,
            gbuffer_pass: GBufferPass::new(ctx).expect("G-buffer pass"),
            bindings: pass.bindings().expect("bindings"),
            pass,
            gbuffer: GBuffer::new(ctx, SIZE.0, SIZE.1).expect("G-buffer"),
            output: Image::new(
                ctx,
                "TSM mask",
                (SIZE.0, SIZE.1, 1),
                vk::Format::R32_SFLOAT,
                vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            )
            .expect("mask image"),
            readback: Buffer::new(
                ctx,
                "TSM mask readback",
                SIZE.0 as u64 * SIZE.1 as u64 * 4,
                BufferUsage::Readback,
            )
            .expect("readback"),
            receivers: DrawList::new(ctx, 4).expect("draw list"),
            casters: DrawList::new(ctx, 4).expect("draw list"),
            points: Vec::new(),
        }
    }

    /// Records and runs one frame into `map`; the mask, row after row.
    fn run(&mut self, frame: &Frame, map: &EngineTsmMap) -> Result<Vec<f32>, Error> {
        let (view_proj, eye) = camera();
        let inputs = self.gbuffer.mask_inputs(
            self.output.layer_view(0),
            view_proj.inverse(),
            frame.gbuffer_time,
            frame.moving_receivers,
        );
        let device = self.ctx.device();
        let one_shot = OneShot::new(self.ctx)?;
        let output = self.output.raw();
        let range = self.output.layers_range(0, 1);
        // SAFETY: `cmd` is the OneShot's command buffer of this context, recording outside
        // rendering on its graphics and compute queue: each draw list's update precedes the pass
        // that reads it, the output image is moved to GENERAL before the pass writes it and to
        // TRANSFER_SRC_OPTIMAL before its copy, and every object used outlives the run, which
        // waits.
        one_shot.run(|cmd| unsafe {
            if frame.draw_gbuffer {
                self.receivers.record_update(device, cmd, frame.receivers)?;
                let camera = GBufferCamera { view_proj, eye };
                self.gbuffer_pass.record(
                    device,
                    cmd,
                    &self.receivers,
                    &camera,
                    frame.gbuffer_time,
                    &self.gbuffer,
                );
            }
            self.casters.record_update(device, cmd, frame.casters)?;
            image_barrier(
                device,
                cmd,
                output,
                range,
                (vk::ImageLayout::UNDEFINED, vk::ImageLayout::GENERAL),
                Access::TRANSFER_READ,
                Access::COMPUTE_RW,
            );
            self.pass.record(
                device,
                cmd,
                &mut self.bindings,
                &inputs,
                &self.casters,
                frame.light,
                map,
                frame.maps,
            )?;
            image_barrier(
                device,
                cmd,
                output,
                range,
                (
                    vk::ImageLayout::GENERAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                ),
                Access::COMPUTE_RW,
                Access::TRANSFER_READ,
            );
            self.output
                .record_copy_to_buffer(device, cmd, self.readback.raw(), 0);
            memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
            if frame.draw_gbuffer {
                self.gbuffer.record_readback(device, cmd);
            }
            Ok(())
        })?;
        // Submitted and waited for: a static map it drew may be kept.
        map.static_map_submitted();
        if frame.draw_gbuffer {
            let contents = self.gbuffer.read()?;
            let inverse = view_proj.inverse();
            self.points = (0..SIZE.0 * SIZE.1)
                .map(|i| {
                    let depth = contents.depth[i as usize];
                    (depth != 1.0).then(|| {
                        let (x, y) = (i % SIZE.0, i / SIZE.0);
                        let ndc = (glam::Vec2::new(x as f32, y as f32) + 0.5)
                            / glam::Vec2::new(SIZE.0 as f32, SIZE.1 as f32)
                            * 2.0
                            - 1.0;
                        let p = inverse * Vec4::new(ndc.x, ndc.y, depth, 1.0);
                        p.truncate() / p.w
                    })
                })
                .collect();
        }
        self.readback.read::<f32>((SIZE.0 * SIZE.1) as usize)
    }
}

/// The pixel whose G-buffer point is nearest to the ground point (x, 0, 0.3).
fn nearest_pixel(rig: &Rig, x: f32) -> usize {
    let target = Vec3::new(x, 0.0, 0.3);
    (rig.points.iter().enumerate())
        .filter_map(|(i, p)| p.map(|p| (i, (p - target).length())))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("ground pixels")
        .0
}

/// The length of [a, b] within the shutter [0, 1].
fn within_shutter(a: f32, b: f32) -> f32 {
    (b.min(1.0) - a.max(0.0)).max(0.0)
}

/// Per pixel whose point `closed_form` answers (None: skipped), the mask's error.
fn errors(
    rig: &Rig,
    mask: &[f32],
    closed_form: impl Fn(Vec3) -> Option<f32>,
) -> Vec<(usize, f32, f32)> {
    rig.points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let expected = closed_form((*p)?)?;
            Some((i, mask[i], expected))
        })
        .collect()
}

/// Asserts |error| <= 1/N + the texel term at every pixel, and returns the mean |error|
/// over the pixels whose lit fraction is strictly between 0 and 1.
fn check_convergence(what: &str, n: u32, found: &[(usize, f32, f32)], texel_term: f32) -> f32 {
    let bound = 1.0 / n as f32 + texel_term + 1e-4;
    let partial: Vec<_> = found
        .iter()
        .filter(|(_, _, e)| *e > 0.02 && *e < 0.98)
        .collect();
    assert!(
        partial.len() > 200,
        "{what}, N = {n}: only {} pixels partly lit",
        partial.len()
    );
    for &(i, got, expected) in found {
        assert!(
            (got - expected).abs() <= bound,
            "{what}, N = {n}: pixel ({}, {}) lit {got}, closed form {expected} (bound {bound})",
            i as u32 % SIZE.0,
            i as u32 / SIZE.0
        );
    }
    partial
        .iter()
        .map(|(_, got, expected)| (got - expected).abs())
        .sum::<f32>()
        / partial.len() as f32
}

/// A still ground under a square translating along x (a moving draw), light straight down:
/// a ground point at x is shadowed while the square's extent [x0 + D t, x0 + s + D t] holds
/// x. TSM-N's mask is within 1/N (stratified times) plus a texel's worth of motion of that
/// at every pixel, and its mean error falls as N grows. Both starts, one map per dispatch or
/// batches, give the same mask bit for bit. Fails when the maps' times, the moving draws' time or the counting are wrong.
#[test]
fn engine_tsm_converges_under_a_moving_caster() {
    let ctx = context();
    let (x0, s, d) = (-1.5f32, 1.0f32, 1.5f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = rect(x0, x0 + s, -1.0, 1.0, 1.0);
    let caster = Mesh::new(&ctx, &square, Some(&shifted(&square, Vec3::X * d)));
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let light = light(Vec3::NEG_Y, false);
    let closed_form = |p: Vec3| {
        let inside_box = p.x.abs() < HALF - 0.1 && p.z.abs() < HALF - 0.1;
        let near_side = (p.z.abs() - 1.0).abs() < 2.0 * TEXEL;
        if !inside_box || near_side {
            return None;
        }
        if p.z.abs() > 1.0 {
            return Some(1.0);
        }
        Some(1.0 - within_shutter((p.x - x0 - s) / d, (p.x - x0) / d))
    };
    let mut rig = Rig::new(&ctx);
    let mut by_config = Vec::new();
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut means = Vec::new();
        let mut masks = Vec::new();
        for n in [4, 16, 64] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            means.push(check_convergence(&start.clone(), n, &found, TEXEL / d));
            masks.push(mask);
        }
        assert!(
            means[0] > means[1] && means[1] > means[2],
            "{start}: mean errors {means:?} do not fall with N = 4, 16, 64"
        );
        by_config.push((start, masks));
    }
    for (config, masks) in &by_config[1..] {
        assert!(
            masks == &by_config[0].1,
            "{config} differs from {}",
            by_config[0].0
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// The lit fraction TSM-N must give exactly, counting the maps' times t_i = (i + 0.5) / N at
/// which `shadowed(t_i)` is false; None where a time's shadow edge lies within `margin` of the
/// point (`edge_distance(t)`: the distance at time t to the nearer edge), where the texel a
/// receiver reads may fall on either side.
fn stratified_lit_fraction(
    n: u32,
    margin: f32,
    shadowed: impl Fn(f32) -> bool,
    edge_distance: impl Fn(f32) -> f32,
) -> Option<f32> {
    let times = (0..n).map(|i| (i as f32 + 0.5) / n as f32);
    if times.clone().any(|t| edge_distance(t) < margin) {
        return None;
    }
    Some(times.filter(|t| !shadowed(*t)).count() as f32 / n as f32)
}

/// TSM-1 and TSM-4 exactly: away from the shadows' edges a pixel's mask is the count of the
/// maps whose time t_i = (i + 0.5) / N sees the light, over N, for a square translating over
/// a still ground and for the ground translating under a still square (light straight down,
/// pixels within two texels of an edge at some t_i left out). The convergence tests' bound
/// (1/N plus a texel's motion) cannot tell a map drawn at i/N from one at (i + 0.5)/N; this
/// can: fails when the maps' times, or the receivers' times, are off the strata's centres.
#[test]
fn engine_tsm_samples_the_strata_centres() {
    let ctx = context();
    let d = 1.5f32;
    let margin = 2.0 * TEXEL;
    let inside = |p: Vec3| p.x.abs() < HALF - 0.1 && p.z.abs() < 1.0 - margin;
    // A square [x0, x0 + s] at t = 0 moving by D over the still ground.
    let (x0, s) = (-1.5f32, 1.0f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = rect(x0, x0 + s, -1.0, 1.0, 1.0);
    let moving_square = Mesh::new(&ctx, &square, Some(&shifted(&square, Vec3::X * d)));
    // The ground moving by D (seen at t = 1) under a still square [c0, c0 + s].
    let c0 = -0.5f32;
    let plane = rect(-6.0, 6.0, -6.0, 6.0, 0.0);
    let moving_ground = Mesh::new(&ctx, &plane, Some(&shifted(&plane, Vec3::X * d)));
    let still_square = Mesh::new(&ctx, &rect(c0, c0 + s, -1.0, 1.0, 1.0), None);
    let light = light(Vec3::NEG_Y, false);
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        for n in [1, 4] {
            for moving_receiver in [false, true] {
                let (receivers, casters) = if moving_receiver {
                    (
                        [moving_ground.draw(0)],
                        [moving_ground.draw(0), still_square.draw(2)],
                    )
                } else {
                    ([ground.draw(0)], [ground.draw(0), moving_square.draw(2)])
                };
                // Where the point seen at x (at shutter close) is at time t, and the square's
                // extent then.
                let at = |x: f32, t: f32| {
                    if moving_receiver {
                        x + (t - 1.0) * d
                    } else {
                        x
                    }
                };
                let extent = |t: f32| {
                    let a = if moving_receiver { c0 } else { x0 + d * t };
                    (a, a + s)
                };
                let expected = |p: Vec3| {
                    if !inside(p) || (moving_receiver && p.x - d < -HALF + 0.1) {
                        return None;
                    }
                    stratified_lit_fraction(
                        n,
                        margin,
                        |t| (extent(t).0..=extent(t).1).contains(&at(p.x, t)),
                        |t| {
                            (at(p.x, t) - extent(t).0)
                                .abs()
                                .min((at(p.x, t) - extent(t).1).abs())
                        },
                    )
                };
                let frame = Frame {
                    receivers: &receivers,
                    casters: &casters,
                    light: &light,
                    maps: n,
                    gbuffer_time: 1.0,
                    moving_receivers: moving_receiver,
                    draw_gbuffer: true,
                };
                let mask = rig.run(&frame, &map).expect("frame");
                let found = errors(&rig, &mask, expected);
                let what =
                    format!("{start:?} x{layers}, N = {n}, moving receiver {moving_receiver}");
                assert!(
                    found.iter().filter(|f| f.2 < 1.0).count() > 100,
                    "{what}: too few shadowed pixels to check"
                );
                for &(i, got, want) in &found {
                    assert!(
                        got == want,
                        "{what}: pixel ({}, {}) lit {got}, the maps at (i + 0.5)/N give {want}",
                        i as u32 % SIZE.0,
                        i as u32 / SIZE.0
                    );
                }
            }
        }
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// The ground translating along x (a moving draw, drawn into every map at its time, and the
/// G-buffer's receivers drawn at shutter close with their motion) under a still square
/// (a static draw, in the static map): a receiver at x (at time 1) is shadowed while
/// x + (t - 1) D lies in the square's [c0, c0 + s]. Within 1/N plus the texel term at every
/// pixel, the mean error falling with N. Fails when the receiver ignores its motion, or when
/// a map lacks the static draws.
#[test]
fn engine_tsm_converges_for_a_moving_receiver() {
    let ctx = context();
    let (c0, s, d) = (-0.5f32, 0.8f32, 1.5f32);
    let plane = rect(-6.0, 6.0, -6.0, 6.0, 0.0);
    let ground = Mesh::new(&ctx, &plane, Some(&shifted(&plane, Vec3::X * d)));
    let caster = Mesh::new(&ctx, &rect(c0, c0 + s, -1.0, 1.0, 1.0), None);
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let light = light(Vec3::NEG_Y, false);
    let closed_form = |p: Vec3| {
        // The path [x - D, x] stays inside the light's box.
        let inside_box = p.x - d > -HALF + 0.1 && p.x < HALF - 0.1 && p.z.abs() < HALF - 0.1;
        let near_side = (p.z.abs() - 1.0).abs() < 2.0 * TEXEL;
        if !inside_box || near_side {
            return None;
        }
        if p.z.abs() > 1.0 {
            return Some(1.0);
        }
        Some(1.0 - within_shutter(1.0 + (c0 - p.x) / d, 1.0 + (c0 + s - p.x) / d))
    };
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut means = Vec::new();
        for n in [4, 16, 64] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: true,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            means.push(check_convergence(&start.clone(), n, &found, TEXEL / d));
        }
        assert!(
            means[0] > means[1] && means[1] > means[2],
            "{start}: mean errors {means:?} do not fall with N = 4, 16, 64"
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// With static draws only, TSM-1 is an ordinary shadow map: a still square under a slanted
/// directional light shadows the ground points whose ray toward the light meets it, exactly
/// 0 there and 1 elsewhere (pixels within three texels of the shadow's edge left out), and
/// TSM-4 gives the same mask. Bad map counts are refused before anything is recorded, bad
/// sizes and layer counts when the map is made.
#[test]
fn engine_tsm_of_static_draws_is_an_ordinary_shadow_map() {
    let ctx = context();
    let (x0, x1, z0, z1) = (-0.5f32, 0.7f32, -0.8f32, 0.6f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let caster = Mesh::new(&ctx, &rect(x0, x1, z0, z1, 1.0), None);
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let light = light(direction, false);
    let closed_form = |p: Vec3| {
        if p.x.abs() > HALF - 0.5 || p.z.abs() > HALF - 0.5 {
            return None;
        }
        // Where the ray toward the light reaches the square's height.
        let q = p - direction * (1.0 / -direction.y);
        let inside = (q.x - x0).min(x1 - q.x).min(q.z - z0).min(z1 - q.z);
        if inside.abs() < 3.0 * TEXEL {
            return None;
        }
        Some(if inside > 0.0 { 0.0 } else { 1.0 })
    };
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut masks = Vec::new();
        for n in [1, 4] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            let shadowed = found.iter().filter(|(_, _, e)| *e == 0.0).count();
            assert!(
                shadowed > 150 && found.len() - shadowed > 1000,
                "{start}: {shadowed} shadowed of {} pixels tested",
                found.len()
            );
            let wrong: Vec<_> = found.iter().filter(|(_, got, e)| got != e).collect();
            assert!(
                wrong.is_empty(),
                "{start}, N = {n}: {} pixels differ from the square's shadow, e.g. {:?}",
                wrong.len(),
                &wrong[..wrong.len().min(5)]
            );
            masks.push(mask);
        }
        assert!(masks[0] == masks[1], "{start}: TSM-4 differs from TSM-1");
        for maps in [0, MAX_TSM_MAPS + 1] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            match rig.run(&frame, &map) {
                Err(Error::InvalidArgument(message)) => {
                    assert!(
                        message.contains(&format!("{maps} time-dependent")),
                        "{message}"
                    )
                }
                other => panic!("{maps} maps: {other:?}"),
            }
        }
    }
    for (what, size, layers) in [
        ("size 0x512", (0, SHADOW), 1),
        ("0 time-dependent shadow map layers", (SHADOW, SHADOW), 0),
        (
            "65 time-dependent shadow map layers",
            (SHADOW, SHADOW),
            MAX_TSM_LAYERS + 1,
        ),
    ] {
        match EngineTsmMap::new(&ctx, size.0, size.1, layers, TsmStart::Copy) {
            Err(Error::InvalidArgument(message)) => {
                assert!(message.contains(what), "{message}")
            }
            Err(other) => panic!("{what}: {other:?}"),
            Ok(_) => panic!("{what}: made"),
        }
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// The static map is drawn once and kept: with `keep_static_layer`, a second frame does not
/// redraw it (the build count stays 1) and gives the same mask bit for bit, even though the
/// static square's buffer was moved in place meanwhile (so a redraw would show it moved);
/// after `forget_static_map` the next frame redraws it (count 2) and shows the square where
/// it now is. A moving caster is drawn in every frame as well. Fails when the static map is
/// redrawn every frame, or when a kept map loses its contents.
#[test]
fn engine_tsm_keeps_its_static_map() {
    let ctx = context();
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = |x0: f32| rect(x0, x0 + 0.8, -1.0, 1.0, 1.0);
    let mut still = Mesh::new(&ctx, &square(-1.5), None);
    let bar = rect(0.8, 1.0, -2.0, 2.0, 1.5);
    let moving = Mesh::new(&ctx, &bar, Some(&shifted(&bar, Vec3::X * 0.6)));
    let light = light(Vec3::NEG_Y, true);
    let receivers = [ground.draw(0)];
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let run = |rig: &mut Rig, still: &Mesh, draw_gbuffer: bool| -> Vec<f32> {
            let casters = [ground.draw(0), still.draw(2), moving.draw(4)];
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: 4,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer,
            };
            rig.run(&frame, &map).expect("frame")
        };
        still.rewrite(&square(-1.5));
        let first = run(&mut rig, &still, true);
        assert_eq!(map.static_map_builds(), 1);
        // The square is where it was drawn: shadowed under it, lit beside it.
        let (under, beside) = (nearest_pixel(&rig, -1.1), nearest_pixel(&rig, -0.2));
        assert_eq!((first[under], first[beside]), (0.0, 1.0), "{start}");

        still.rewrite(&square(-0.6));
        let kept = run(&mut rig, &still, false);
        assert_eq!(
            map.static_map_builds(),
            1,
            "{start}: the kept map was redrawn"
        );
        assert!(
            kept == first,
            "{start}: the kept static map changed the mask"
        );

        map.forget_static_map();
        let redrawn = run(&mut rig, &still, false);
        assert_eq!(map.static_map_builds(), 2, "{start}");
        assert_eq!(
            (redrawn[under], redrawn[beside]),
            (1.0, 0.0),
            "{start}: the redrawn map does not show the square where it now is"
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}
