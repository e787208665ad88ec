//! The footprint hull (`glsl/convex_hull.glsl`) that the exact construction's collection and
//! the lighting pass rasterize: on point sets like a moving triangle's six projected corners
//! (static corners handed over twice, corners an ulp apart, edge-on triangles), computed the
//! way a compiler that fuses multiply-adds computes it (`tests/glsl/hull_probe.comp`).
//!
//! Why: on an NVIDIA H200 the collection dropped every triangle whose footprint did not move
//! (a square sinking straight down left no range at all) and 116 texels of a tessellated lid
//! whose outline stood still, because a fused turn test kept a duplicated corner, whose
//! zero-length edge grew the footprint by NaN. lavapipe never fuses, so its suite passed.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::rng::Rng;
use crate::support::test_shader::compile_compute;
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, OneShot, Spirv, compute_pipeline, memory_barrier,
};

/// The collection's growth past what the merge takes (collection_exact.geom).
const DILATION_TEXELS: f32 = 1.0 / 16.0;
const SETS: usize = 4096;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    points: u64,
    results: u64,
    count: u32,
    grow: f32,
}

/// The point sets' coordinates.
trait Texels {
    fn texel(&mut self) -> f32;
    fn point(&mut self) -> [f32; 2];
    fn ulps(&mut self, x: f32) -> f32;
}

impl Texels for Rng {
    fn texel(&mut self) -> f32 {
        self.unit() * 1024.0
    }
    fn point(&mut self) -> [f32; 2] {
        [self.texel(), self.texel()]
    }
    /// `x` moved by 1 to 3 ulps, up or down.
    fn ulps(&mut self, x: f32) -> f32 {
        let k = 1 + (self.next() % 3) as i32;
        let bits = x.to_bits() as i32 + if self.next() % 2 == 0 { k } else { -k };
        f32::from_bits(bits as u32)
    }
}

/// Kind of point set `i`: its corners at t = 0 and t = 1.
fn point_set(rng: &mut Rng, i: usize) -> [[f32; 2]; 6] {
    let c = [rng.point(), rng.point(), rng.point()];
    let mut at1 = c;
    match i % 4 {
        // Moves only along the light's view direction: every corner handed over twice.
        0 => {}
        // Some corners static, the others moving.
        1 => {
            for p in &mut at1 {
                if rng.next() % 2 == 0 {
                    *p = [
                        p[0] + rng.unit() * 40.0 - 20.0,
                        p[1] + rng.unit() * 40.0 - 20.0,
                    ];
                }
            }
        }
        // Static corners an ulp or three off (a transform rounded differently at t = 1).
        2 => {
            for p in &mut at1 {
                *p = [rng.ulps(p[0]), rng.ulps(p[1])];
            }
        }
        // Edge-on all frame long: on one row, sliding along it.
        _ => {
            let y = c[0][1];
            let slide = rng.unit() * 30.0;
            let row = c.map(|p| [p[0], y]);
            let moved = row.map(|p| [p[0] + slide, y]);
            return [row[0], row[1], row[2], moved[0], moved[1], moved[2]];
        }
    }
    [c[0], c[1], c[2], at1[0], at1[1], at1[2]]
}

/// Signed distance of `q` inside the counter-clockwise polygon `poly` (negative: outside).
fn inside_by(poly: &[[f64; 2]], q: [f64; 2]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            (ex * (q[1] - a[1]) - ey * (q[0] - a[0])) / (ex * ex + ey * ey).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Distance from `q` to the segment a-b.
fn to_segment(a: [f64; 2], b: [f64; 2], q: [f64; 2]) -> f64 {
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let len2 = ex * ex + ey * ey;
    let s = if len2 > 0.0 {
        (((q[0] - a[0]) * ex + (q[1] - a[1]) * ey) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((q[0] - a[0] - s * ex).powi(2) + (q[1] - a[1] - s * ey).powi(2)).sqrt()
}

/// Every corner of every set lies inside the grown hull by the collection's growth (a point
/// or segment: within the merge distance of it, which the geometry shader covers with a quad around it), no grown
/// corner is NaN, and the triangles seen edge-on come out as segments.
#[test]
fn the_footprint_holds_every_corner_when_turn_tests_are_fused() {
    let ctx = context();
    let device = ctx.device();
    let mut rng = Rng(7);
    let sets: Vec<[[f32; 2]; 6]> = (0..SETS).map(|i| point_set(&mut rng, i)).collect();
    let flat: Vec<f32> = sets.iter().flatten().flatten().copied().collect();
    let points =
        Buffer::with_data(&ctx, "hull points", BufferUsage::HostToDevice, &flat).expect("points");
    let results = Buffer::new(
        &ctx,
        "hull results",
        (SETS * 32 * 4) as u64,
        BufferUsage::DeviceToHost,
    )
    .expect("results");
    let source = include_str!("../glsl/hull_probe.comp");
    let spirv = compile_compute("hull_probe.comp", source);
    let pipeline = compute_pipeline(
        &ctx,
        std::mem::size_of::<Push>() as u32,
        "hull_probe.comp",
        // SAFETY: shaderc's SPIR-V of tests/glsl/hull_probe.comp for Vulkan 1.2, using what
        // the library's shaders use, push constants of Push's size, no sets.
        unsafe { Spirv::new(&spirv) },
    )
    .expect("probe pipeline");
    let push = Push {
        points: points.device_address(),
        results: results.device_address(),
        count: SETS as u32,
        grow: DILATION_TEXELS,
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
            // past `count` (SETS) and writes 32 floats per set, the results' size, so the probe's
            // writes stay within the result buffer, which lives until the OneShot has waited.
            unsafe { device.cmd_dispatch(cmd, SETS.div_ceil(64) as u32, 1, 1) };
            // SAFETY: outside rendering, on the context's compute queue; host reads are a valid
            // destination once the OneShot's fence signals.
            unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ) };
            Ok(())
        })
        .expect("dispatch");
    let out: Vec<f32> = results.read(SETS * 32).expect("read");

    let (mut polygons, mut segments, mut worst) = (0, 0, f64::INFINITY);
    for (i, set) in sets.iter().enumerate() {
        let r = &out[i * 32..(i + 1) * 32];
        let (h, merge) = (r[0] as usize, f64::from(r[1]));
        let grown: Vec<[f64; 2]> = (0..h.min(12))
            .map(|k| [f64::from(r[2 + 2 * k]), f64::from(r[3 + 2 * k])])
            .collect();
        // At most 8 grown corners: the collection's geometry shader declares no more.
        assert!(
            (1..=8).contains(&h) && grown.iter().flatten().all(|v| v.is_finite()),
            "set {i} {set:?}: h {h}, grown hull {grown:?}"
        );
        for &p in set {
            let q = [f64::from(p[0]), f64::from(p[1])];
            if h >= 3 {
                let depth = inside_by(&grown, q);
                // The growth, less rounding (the rasterizer snaps to 1/256 texel).
                assert!(
                    depth > 0.95 * f64::from(DILATION_TEXELS),
                    "set {i} {set:?}: corner {q:?} only {depth} inside the grown hull {grown:?}"
                );
                worst = worst.min(depth);
            } else {
                let off = to_segment(grown[0], grown[h - 1], q);
                assert!(
                    off <= 1.5 * merge,
                    "set {i} {set:?}: corner {q:?} {off} from the merged segment {grown:?}"
                );
            }
        }
        if h >= 3 {
            polygons += 1;
        } else {
            segments += 1;
            assert_eq!(i % 4, 3, "set {i} {set:?} is no segment");
        }
    }
    eprintln!(
        "{polygons} grown hulls (every corner inside, the least by {worst:.2e} texels), \
         {segments} segments"
    );
    assert!(
        segments >= SETS / 4 - 8 && polygons >= SETS * 3 / 4,
        "{segments} {polygons}"
    );
    assert_no_validation_messages(&ctx);
}
