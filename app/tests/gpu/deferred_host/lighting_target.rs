//! The lighting pass writing into an image the host made.

use super::*;
use crate::support::host_memory;

/// The papers' lighting pass written into a host's own storage image
/// (`LightingImageOutput`) holds exactly the radiance the lighting target reads back, on the
/// host's device and in the host's command buffer.
#[test]
fn lighting_pass_writes_into_a_host_image() {
    use motion_shadows::gpu::Context;
    use motion_shadows::technique::{
        CollectionPass, DrawList, GenerationPass, LightingImageOutput, LightingPass,
        LightingTarget, ShadowSource,
    };
    use motion_shadows_app::render::upload::{SceneGeometry, light_view};
    let host = Host::new(true).unwrap_or_else(|e| panic!("needs a Vulkan device: {e}"));
    assert!(
        host.enabled.storage_image_write_without_format(),
        "lavapipe and desktop GPUs support shaderStorageImageWriteWithoutFormat"
    );
    let size = (64u32, 48u32);
    let rgb_host;
    let rgb_target;
    {
        // SAFETY: Host::new enables every feature from_raw lists (and the optional one it
        // reports); the host outlives the context (dropped at the end of this block).
        let ctx = unsafe {
            Context::from_raw(
                &host.instance,
                host.physical,
                host.device.clone(),
                host.queue_family,
                host.queue,
                &host.enabled,
            )
        }
        .expect("from_raw");
        let scene = app::builtin("cubes-toward-light", &app::BuiltinOptions::default()).unwrap();
        let geometry = SceneGeometry::upload(&ctx, &scene).unwrap();
        let mut draws = DrawList::new(&ctx, geometry.draws.len() as u32).unwrap();
        let light = light_view(&scene, size);
        let view = LightingView {
            camera: camera_view(&scene, size),
            seed: 3,
            ambient: scene.ambient,
            estimator: Default::default(),
            filter: Default::default(),
        };
        let collection = CollectionPass::new(&ctx).unwrap();
        let generation = GenerationPass::new(&ctx).unwrap();
        let lighting = LightingPass::new(&ctx).unwrap();
        let output = LightingImageOutput::new(&ctx).unwrap();
        let mut bindings = output.bindings().unwrap();
        let target = LightingTarget::new(&ctx, size.0, size.1, 4, 16).unwrap();
        let map = TemporalShadowMap::new(&ctx, size.0, size.1, 1 << 16, 1 << 15).unwrap();
        // The allocator goes with the image's and the buffer's last handle on it.
        let memory = host_memory::Memory::new(&host).unwrap();
        let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC;
        let features = vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::TRANSFER_SRC;
        let format = vk::Format::R32G32B32A32_SFLOAT;
        let image = host_memory::Image::new(&memory, format, (usage, features), size).unwrap();
        let pixels = (size.0 * size.1) as u64;
        let usage = vk::BufferUsageFlags::TRANSFER_DST;
        let mut readback = host_memory::HostBuffer::new(&memory, pixels * 16, usage).unwrap();
        let device = &host.device;
        host.record_and_wait(|cmd| {
            use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
            // SAFETY: the host's command buffer, recording, outside rendering; every object
            // outlives the wait.
            unsafe {
                draws.record_update(device, cmd, &geometry.draws).unwrap();
                collection
                    .record(device, cmd, &draws, &light, &map, None)
                    .unwrap();
                generation.record(device, cmd, &map);
                lighting
                    .record(
                        device,
                        cmd,
                        &draws,
                        &view,
                        ShadowSource::Temporal(&map),
                        &target,
                        None,
                    )
                    .unwrap();
                target.record_readback(device, cmd);
                host_memory::pipeline_barrier(
                    device,
                    cmd,
                    &[image.barrier(
                        (L::UNDEFINED, S::NONE, A::NONE),
                        (L::GENERAL, S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                    )],
                    &[],
                );
                output.record(device, cmd, &mut bindings, &target, image.view);
                host_memory::pipeline_barrier(
                    device,
                    cmd,
                    &[image.barrier(
                        (L::GENERAL, S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                        (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ),
                    )],
                    &[],
                );
                let region = vk::BufferImageCopy::default()
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: 0,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width: size.0,
                        height: size.1,
                        depth: 1,
                    });
                device.cmd_copy_image_to_buffer(
                    cmd,
                    image.image,
                    L::TRANSFER_SRC_OPTIMAL,
                    readback.buffer,
                    &[region],
                );
                let to_host = [vk::MemoryBarrier2::default()
                    .src_stage_mask(S::COPY)
                    .src_access_mask(A::TRANSFER_WRITE)
                    .dst_stage_mask(S::HOST)
                    .dst_access_mask(A::HOST_READ)];
                host_memory::pipeline_barrier(device, cmd, &[], &to_host);
            }
        })
        .unwrap();
        let rgba: Vec<f32> = readback.read(pixels as usize * 4).unwrap();
        rgb_host = rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect::<Vec<f32>>();
        rgb_target = target.read_rgb().unwrap();
    }
    assert_eq!(rgb_host.len(), rgb_target.len());
    let differing = rgb_host
        .iter()
        .zip(&rgb_target)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{differing} channels differ");
    assert!(rgb_host.iter().any(|&v| v > 0.0), "not a black image");
    assert_eq!(host.validation_messages(), Vec::<String>::new());
}
