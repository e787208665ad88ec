//! The exact shadow test of `glsl/exact_shadow.glsl` (issue 35's building block), run on the
//! device by `tests/glsl/exact_shadow_probe.comp` for many configurations (a receiver, a
//! light, moving triangles, a window of the shutter), against two expectations that share
//! nothing with it: the ray tracer's f64 shadowed intervals (`raytrace::shutter`), and dense
//! time sampling with the tracer's watertight ray/triangle test (`raytrace::intersect`),
//! which has no polynomials. The adversarial classes have closed forms too.

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::rng::Rng;
use glam::{DVec3, Vec3};
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, OneShot, Spirv, compute_pipeline, memory_barrier,
};
use motion_shadows_app::raytrace::bvh::Bvh;
use motion_shadows_app::raytrace::intersect::Ray;
use motion_shadows_app::raytrace::shade::ShadingLight;
use motion_shadows_app::raytrace::shutter;
use motion_shadows_app::raytrace::triangles::Triangle;

mod configs;
use configs::*;

/// The probe's limits (tests/glsl/exact_shadow_probe.comp, glsl/exact_shadow.glsl).
const TRIANGLES: usize = 12;
const MAX_INTERVALS: usize = 8;
const UNION_CAPACITY: usize = 8;
/// glsl/exact_shadow.glsl's MS_EXACT_EMPTY: an empty slot of the union.
const EMPTY: f64 = -1.0;
const CONFIG_VEC4S: usize = 4 + 6 * TRIANGLES;
const RESULT_FLOATS: usize = 3 + 2 * UNION_CAPACITY + TRIANGLES * (1 + 2 * MAX_INTERVALS);
/// glsl/exact_shadow.glsl's MS_EXACT_SELF_EPSILON.
const SELF_EPSILON: f64 = 1e-4;
/// The scene size handed to the directional lights' epsilon.
const SCENE_SIZE: f32 = 10.0;
/// Samples of the dense time sampling per window.
const SAMPLES: usize = 2048;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    configs: u64,
    results: u64,
    count: u32,
    pad: u32,
}

/// One query: a receiver from `p0` to `p1`, a spot light at `light` or a directional one
/// travelling along it, triangles (corners at t = 0 and t = 1) and the window.
#[derive(Debug, Clone)]
struct Config {
    class: &'static str,
    p0: Vec3,
    p1: Vec3,
    spot: bool,
    light: Vec3,
    triangles: Vec<[[Vec3; 3]; 2]>,
    window: (f32, f32),
    /// The shadowed intervals in closed form, where the class has one.
    closed_form: Option<Vec<(f64, f64)>>,
}

/// What the probe returns for one config.
struct Answer {
    shadowed: f64,
    joined_gaps: bool,
    union: Vec<(f64, f64)>,
    per_triangle: Vec<usize>,
}

impl Config {
    /// The start of the free range of s, as the include's epsilon defines it.
    fn s_min(&self) -> f64 {
        if self.spot {
            SELF_EPSILON
        } else {
            SELF_EPSILON * f64::from(SCENE_SIZE)
        }
    }

    fn pack(&self, out: &mut Vec<[f32; 4]>) {
        let v = |p: Vec3, w: f32| [p.x, p.y, p.z, w];
        out.push(v(self.p0, 0.0));
        out.push(v(self.p1, 0.0));
        out.push(v(self.light, if self.spot { 1.0 } else { 0.0 }));
        out.push([
            SCENE_SIZE,
            self.window.0,
            self.window.1,
            self.triangles.len() as f32,
        ]);
        for k in 0..TRIANGLES {
            for corner in 0..6 {
                out.push(match self.triangles.get(k) {
                    Some(t) => v(t[corner / 3][corner % 3], 0.0),
                    None => [0.0; 4],
                });
            }
        }
    }

    fn tracer_triangles(&self) -> Vec<Triangle> {
        (self.triangles.iter().enumerate())
            .map(|(i, t)| Triangle::new(t[0], t[1], i as u32, 0))
            .collect()
    }

    fn tracer_light(&self) -> ShadingLight {
        let position = self.spot.then(|| self.light.as_dvec3());
        ShadingLight::for_shadows(position, self.light.as_dvec3(), f64::from(SCENE_SIZE))
    }

    /// (a) The ray tracer's shadowed time in the window (its f64 intervals, clipped).
    fn tracer_shadowed(&self) -> f64 {
        let bvh = Bvh::new(&self.tracer_triangles());
        let (p0, p1) = (self.p0.as_dvec3(), self.p1.as_dvec3());
        let intervals = shutter::shadowed_intervals(&bvh, &self.tracer_light(), p0, p1, u32::MAX);
        let (w0, w1) = (f64::from(self.window.0), f64::from(self.window.1));
        intervals
            .iter()
            .map(|&(a, b)| (b.min(w1) - a.max(w0)).max(0.0))
            .sum()
    }

    /// (b) The shadowed time in the window from the watertight ray/triangle test at `SAMPLES`
    /// times (midpoints of equal steps), with the include's range of s.
    fn sampled_shadowed(&self) -> f64 {
        let tris = self.tracer_triangles();
        let (p0, p1) = (self.p0.as_dvec3(), self.p1.as_dvec3());
        let (w0, w1) = (f64::from(self.window.0), f64::from(self.window.1));
        let step = (w1 - w0) / SAMPLES as f64;
        let shadowed = (0..SAMPLES)
            .filter(|&k| {
                let t = w0 + (k as f64 + 0.5) * step;
                let p = p0 + t * (p1 - p0);
                let (ray, s_max) = if self.spot {
                    (Ray::new(p, self.light.as_dvec3() - p), 1.0)
                } else {
                    (
                        Ray::new(p, -self.light.as_dvec3().normalize()),
                        f64::INFINITY,
                    )
                };
                tris.iter()
                    .any(|tri| ray.intersect(&tri.at(t), self.s_min(), s_max).is_some())
            })
            .count();
        shadowed as f64 * step
    }
}

fn compile_probe() -> Vec<u8> {
    let glsl = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../glsl");
    let compiler = shaderc::Compiler::new().expect("shaderc");
    let mut options = shaderc::CompileOptions::new().expect("shaderc options");
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_include_callback(move |name, _kind, _from, _depth| {
        let content =
            std::fs::read_to_string(glsl.join(name)).map_err(|e| format!("{name}: {e}"))?;
        Ok(shaderc::ResolvedInclude {
            resolved_name: name.to_owned(),
            content,
        })
    });
    let source = include_str!("../../../tests/glsl/exact_shadow_probe.comp");
    compiler
        .compile_into_spirv(
            source,
            shaderc::ShaderKind::Compute,
            "exact_shadow_probe.comp",
            "main",
            Some(&options),
        )
        .unwrap_or_else(|e| panic!("{e}"))
        .as_binary_u8()
        .to_vec()
}

/// Runs the probe on every config.
fn probe(configs: &[Config]) -> Vec<Answer> {
    let ctx = context();
    let device = ctx.device();
    let mut packed = Vec::new();
    for c in configs {
        assert!(
            c.triangles.len() <= TRIANGLES,
            "{}: too many triangles",
            c.class
        );
        c.pack(&mut packed);
    }
    assert_eq!(packed.len(), configs.len() * CONFIG_VEC4S);
    let input = Buffer::with_data(&ctx, "exact configs", BufferUsage::HostToDevice, &packed)
        .expect("configs");
    let results = Buffer::new(
        &ctx,
        "exact results",
        (configs.len() * RESULT_FLOATS * 4) as u64,
        BufferUsage::DeviceToHost,
    )
    .expect("results");
    let spirv = compile_probe();
    let pipeline = compute_pipeline(
        &ctx,
        std::mem::size_of::<Push>() as u32,
        "exact_shadow_probe.comp",
        // SAFETY: shaderc's SPIR-V of tests/glsl/exact_shadow_probe.comp for Vulkan 1.2,
        // using what the library's shaders use, push constants of Push's size, no sets.
        unsafe { Spirv::new(&spirv) },
    )
    .expect("probe pipeline");
    let push = Push {
        configs: input.device_address(),
        results: results.device_address(),
        count: configs.len() as u32,
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
            // past `count` and writes RESULT_FLOATS per configuration, the results' size, so the
            // probe's writes stay within the result buffer, which lives until the OneShot has
            // waited.
            unsafe { device.cmd_dispatch(cmd, configs.len().div_ceil(16) as u32, 1, 1) };
            // SAFETY: outside rendering, on the context's compute queue; host reads are a valid
            // destination once the OneShot's fence signals.
            unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ) };
            Ok(())
        })
        .expect("dispatch");
    let out: Vec<f32> = results.read(configs.len() * RESULT_FLOATS).expect("read");
    assert_no_validation_messages(&ctx);
    out.chunks_exact(RESULT_FLOATS)
        .map(|r| {
            let spans = r[2] as usize;
            let f = |i: usize| f64::from(r[i]);
            Answer {
                shadowed: f(0),
                joined_gaps: r[1] != 0.0,
                union: sorted_spans((0..spans).map(|i| (f(3 + 2 * i), f(4 + 2 * i)))),
                per_triangle: (0..TRIANGLES)
                    .map(|k| r[3 + 2 * UNION_CAPACITY + k * (1 + 2 * MAX_INTERVALS)] as usize)
                    .collect(),
            }
        })
        .collect()
}

/// The union's slots, empty ones left out, in order (the include keeps them in none).
fn sorted_spans(slots: impl Iterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut spans: Vec<_> = slots.filter(|&(a, b)| (a, b) != (EMPTY, EMPTY)).collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    spans
}

/// Per class: the largest difference of the shadowed time from the tracer's intervals, from
/// dense sampling, and of interval ends from the closed form.
#[derive(Default)]
struct Worst {
    tracer: f64,
    sampled: f64,
    closed: f64,
    configs: usize,
    /// Configs shadowed for part of the window only, and the most intervals one triangle
    /// gave (the include's bound is 8).
    partial: usize,
    most_intervals: usize,
}

#[test]
fn exact_shadow_intervals_match_the_ray_tracer_and_closed_forms() {
    let mut rng = Rng(35);
    let mut configs = random_configs(&mut rng, 400);
    configs.extend(scissor_configs(&mut rng));
    configs.extend(box_edge_configs());
    configs.extend(rotating_plate_configs());
    configs.extend(through_light_configs());
    configs.extend(shared_edge_configs());
    configs.extend(rounded_shared_edge_configs(&mut rng));
    configs.extend(edge_on_configs());
    configs.extend(own_surface_configs());
    configs.extend(past_capacity_configs());
    let answers = probe(&configs);

    let mut worst: std::collections::BTreeMap<&str, Worst> = Default::default();
    let mut failures = Vec::new();
    for (c, got) in configs.iter().zip(&answers) {
        let w = worst.entry(c.class).or_default();
        w.configs += 1;
        let length = f64::from(c.window.1 - c.window.0);
        w.partial += usize::from(got.shadowed > 1e-3 && got.shadowed < length - 1e-3);
        w.most_intervals = w
            .most_intervals
            .max(got.per_triangle.iter().copied().max().unwrap_or(0));
        let tracer = (got.shadowed - c.tracer_shadowed()).abs();
        let sampled = (got.shadowed - c.sampled_shadowed()).abs();
        w.tracer = w.tracer.max(tracer);
        w.sampled = w.sampled.max(sampled);
        // Sampling misses at most one step per interval end; a few ends per config.
        let sample_tolerance = 8.0 * length / SAMPLES as f64;
        if c.class == PAST_CAPACITY {
            // Checked against its closed form below: the joined gaps shadow more than the truth.
            let joined: f64 = (c.closed_form.iter().flatten()).map(|(a, b)| b - a).sum();
            if !got.joined_gaps || (got.shadowed - joined).abs() > 2e-5 {
                failures.push(format!(
                    "{}: shadowed {} (joined gaps: {}), expected {joined} with gaps joined: {:?}",
                    c.class, got.shadowed, got.joined_gaps, got.union
                ));
            }
        } else if tracer > 2e-5 || sampled > sample_tolerance || got.joined_gaps {
            failures.push(format!(
                "{}: shadowed {} (tracer off by {tracer:.2e}, sampling by {sampled:.2e}), \
                 per triangle {:?}, union {:?}: {c:?}",
                c.class, got.shadowed, got.per_triangle, got.union
            ));
        }
        if let Some(expected) = &c.closed_form {
            let off = if expected.len() == got.union.len() {
                (expected.iter().zip(&got.union))
                    .map(|(e, g)| (e.0 - g.0).abs().max((e.1 - g.1).abs()))
                    .fold(0.0, f64::max)
            } else {
                f64::INFINITY
            };
            w.closed = w.closed.max(off);
            if off > 1e-4 {
                failures.push(format!(
                    "{}: union {:?}, closed form {expected:?}: {c:?}",
                    c.class, got.union
                ));
            }
        }
    }
    for (class, w) in &worst {
        eprintln!(
            "{class}: {} configs ({} partly shadowed, up to {} intervals from one triangle), \
             shadowed time off the tracer's by {:.2e}, off dense sampling ({SAMPLES}) by \
             {:.2e}, interval ends off the closed form by {:.2e}",
            w.configs, w.partial, w.most_intervals, w.tracer, w.sampled, w.closed
        );
    }
    assert!(
        failures.is_empty(),
        "{} of {} configs wrong:\n{}",
        failures.len(),
        configs.len(),
        failures[..failures.len().min(6)].join("\n")
    );
}
