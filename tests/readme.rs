//! Every Rust snippet of the README is compiled: each appears, line for line (indentation
//! aside), in one of the functions below, which the compiler checks against the library's
//! API (they are never called: they need a host's device). A snippet edited in the README
//! and not here, or an API change that breaks one, fails this test or the build.

// The snippets are the README's, line for line: their unsafe calls are explained by the README's
// prose, and a SAFETY comment here would have to be one there too.
#![allow(
    dead_code,
    unused_variables,
    clippy::too_many_arguments,
    clippy::undocumented_unsafe_blocks
)]

use motion_shadows::ash::{self, vk};
use motion_shadows::glam::{Mat4, Vec3};
use motion_shadows::technique::{MaskBindings, NormalImage, TemporalShadowMap, VisibilityMaskPass};

type AnyResult = Result<(), Box<dyn std::error::Error>>;

/// "Integrating into your engine", the frame.
#[rustfmt::skip]
fn one_frame(
    instance: ash::Instance, physical: vk::PhysicalDevice, queues: Vec<vk::DeviceQueueCreateInfo>,
    queue_family: u32, queue: vk::Queue, cmd: vk::CommandBuffer, position: Vec3, direction: Vec3,
    previous_positions: u64, current_positions: u64, indices: u64, vertex_count: u32,
    triangle_count: u32, first_triangle_id: u32, n: u64, cpu_t0: Vec<Vec3>, cpu_t1: Vec<Vec3>,
    cpu_indices: Vec<u32>,
) -> AnyResult {
use motion_shadows::gpu::{Context, DeviceRequirements};
use motion_shadows::technique::{
    CollectionPass, Draw, DrawList, GenerationPass, HostDraw, IndexStream, Indices, LightView,
    PositionStream, TemporalShadowMap,
};

// Once: create your device with what the library needs chained in, wrap it, make the passes.
let mut requirements = unsafe { DeviceRequirements::for_device(&instance, physical) }?;
let extensions = requirements.extension_names();
let device_info = requirements.chain(vk::DeviceCreateInfo::default()
    .queue_create_infos(&queues).enabled_extension_names(&extensions));
let device = unsafe { instance.create_device(physical, &device_info, None) }?;
let ctx = unsafe {
    Context::from_raw(&instance, physical, device.clone(), queue_family, queue,
                      &requirements.features) // what you enabled; refused if one is off
}?;
let (collection, generation) = (CollectionPass::new(&ctx)?, GenerationPass::new(&ctx)?);

// Per frame in flight: a draw list, and per light a shadow map (grown on demand, below).
let mut draws = DrawList::new(&ctx, 64)?;
let mut map = TemporalShadowMap::new(&ctx, 1024, 1024, 1 << 16, 1 << 20)?;
let light = LightView::spot(position, direction, 30.0, 100.0, 0.1, 50.0, (1024, 1024));

// Each frame, into your command buffer, outside any render pass: last frame's and this
// frame's positions (e.g. straight from your compute skinning), read in place.
let draw = unsafe {
    Draw::new(
        PositionStream::from_device_address(previous_positions, 12),
        PositionStream::from_device_address(current_positions, 12),
        vertex_count,
        Indices::U32(IndexStream::from_device_address(indices)),
        triangle_count,
        first_triangle_id,
    )
};
// Where the host holds those positions too: room for all the frame can store, so it never
// overflows (RangeCeiling; a draw that does not move names one slice twice).
map.reserve_for(&ctx, &light, None, &[HostDraw::new(&cpu_t0, &cpu_t1, Some(&cpu_indices))])?;
unsafe {
    draws.record_update(&device, cmd, &[draw])?;
    collection.record(&device, cmd, &draws, &light, &map, None)?;
    generation.record(&device, cmd, &map);
    map.record_counter_readback(&device, cmd);
}
// Your shaders: #include "motion_shadows.glsl", push map.header_address(), call
// ms_visibility(MsShadowMap(addr), pos, normal, t, own_id); or the papers' LightingPass.

// After frame n's fence (with ctx.begin_frame(n) before recording it): free what was
// dropped meanwhile; a map that ran out of room (not reserved) had incomplete shadows: grow it.
unsafe { ctx.collect(n) };
let counts = map.read_counters()?;
if map.needs_more_room(&counts) { map.grow_to_fit(&ctx, &counts)?; }
Ok(())
}

/// "Integrating into your engine", the deferred mask.
#[rustfmt::skip]
fn deferred_mask(
    device: ash::Device, cmd: vk::CommandBuffer, mask: &VisibilityMaskPass,
    mut mask_bindings: MaskBindings, map: TemporalShadowMap, depth: vk::ImageView,
    depth_layout: vk::ImageLayout, mask_view: vk::ImageView, size: (u32, u32),
    inv_view_proj: Mat4, normals: NormalImage, motion_view: vk::ImageView, id_view: vk::ImageView,
) -> AnyResult {
use motion_shadows::technique::{MaskInputs, MotionImage, TriangleIdImage};
const SHADER_READ_ONLY_OPTIMAL: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
// Depth and output views, size, the camera; background depth 1 by default. Your triangle-id
// image is required with moving receivers (refused without: a turning surface would shadow
// itself).
let inputs = MaskInputs::new(depth, depth_layout, mask_view, size, inv_view_proj)
    .with_normals(normals) // or none: rebuilt from the depth; either facing
    .with_motion(MotionImage { view: motion_view, layout: SHADER_READ_ONLY_OPTIMAL }, 1.0)
    .with_ids(TriangleIdImage { view: id_view, layout: SHADER_READ_ONLY_OPTIMAL });
// .with_background_depth(0.0) for reversed Z
// .with_positions(..) your world positions: receivers exact at grazing light
unsafe { mask.record(&device, cmd, &mut mask_bindings, &inputs, &map) }?;
Ok(())
}

/// The README's ```rust blocks.
fn readme_snippets() -> Vec<Vec<String>> {
    let readme = include_str!("../README.md");
    let mut blocks = Vec::new();
    let mut current: Option<Vec<String>> = None;
    for line in readme.lines() {
        match (&mut current, line.trim_start()) {
            (None, l) if l.starts_with("```rust") => current = Some(Vec::new()),
            (Some(_), l) if l.starts_with("```") => blocks.push(current.take().unwrap()),
            (Some(block), _) => block.push(line.trim().to_owned()),
            _ => {}
        }
    }
    blocks
}

#[test]
fn every_readme_rust_snippet_is_compiled_here() {
    let source: Vec<String> = include_str!("readme.rs")
        .lines()
        .map(|l| l.trim().to_owned())
        .collect();
    let blocks = readme_snippets();
    assert!(
        blocks.len() >= 2,
        "the README's integration snippets: {}",
        blocks.len()
    );
    for block in blocks {
        let block: Vec<&String> = block.iter().filter(|l| !l.is_empty()).collect();
        let lines: Vec<&String> = source.iter().filter(|l| !l.is_empty()).collect();
        let found = lines.windows(block.len()).any(|w| w == block.as_slice());
        assert!(
            found,
            "a README snippet is not in tests/readme.rs (compiled):\n{}",
            block
                .iter()
                .map(|l| l.as_str())
                .collect::<Vec<_>>()
                .join("\n")
        );
    }
}
