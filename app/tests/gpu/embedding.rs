//! Embedding: the library on a host engine's own instance, device, queue, command buffer and
//! fence (`Context::from_raw`) renders exactly what the standalone renderer renders on a
//! context of its own, leaves the host's device alive and clean, and makes the validation
//! layer (on the host's instance) report nothing.

use crate::support::gpu::{assert_no_validation_messages, context, render};
use crate::support::host::Host;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    CollectionPass, Counters, DrawList, GenerationPass, LightingPass, LightingTarget, LightingView,
    MAX_SAMPLES_PER_CHUNK, ShadowSource, TemporalShadowMap,
};
use motion_shadows_app::render::upload::{self, SceneGeometry};
use motion_shadows_app::render::{ReceiverTest, RenderSettings};
use motion_shadows_app::scene::{BuiltinOptions, Scene, builtin};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;
const SPP: u32 = 4;
const SEED: u32 = 5;

struct Embedded {
    rgb: Vec<f32>,
    counts: Counters,
    attempts: u32,
}

/// One frame recorded into the host's command buffer. Starts with tiny shadow-map capacities
/// so that the grow-and-re-record path runs. Every library object is dropped on return.
fn render_embedded(host: &Host, scene: &Scene) -> Embedded {
    // SAFETY: Host::new creates a Vulkan 1.3 device from `physical` of `instance` with a
    // graphics+compute queue family and exactly the contract's features; `host` outlives
    // the context and every object made from it (all dropped before this returns).
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
    .expect("Context::from_raw");
    assert_eq!(ctx.info().name, host.device_name);

    let size = (WIDTH, HEIGHT);
    let geometry = SceneGeometry::upload(&ctx, scene).expect("geometry");
    let mut draws = DrawList::new(&ctx, geometry.draws.len() as u32).expect("draw list");
    let light = upload::light_view(scene, size);
    let view = LightingView {
        camera: upload::camera_view(scene, size),
        seed: SEED,
        ambient: scene.ambient,
        estimator: Default::default(),
        filter: Default::default(),
    };
    let collection = CollectionPass::new(&ctx).expect("collection pass");
    let generation = GenerationPass::new(&ctx).expect("generation pass");
    let lighting = LightingPass::new(&ctx).expect("lighting pass");
    let target =
        LightingTarget::new(&ctx, WIDTH, HEIGHT, SPP, MAX_SAMPLES_PER_CHUNK).expect("target");
    let mut map = TemporalShadowMap::new(&ctx, WIDTH, HEIGHT, 16, 16).expect("map");

    let device = &host.device;
    let mut attempts = 0;
    let counts = loop {
        attempts += 1;
        assert!(
            attempts <= 3,
            "the shadow map still overflows after growing"
        );
        host.record_and_wait(|cmd| {
            // SAFETY: the host's command buffer is recording, outside rendering, on its
            // graphics+compute queue; every object outlives the wait below.
            unsafe {
                draws
                    .record_update(device, cmd, &geometry.draws)
                    .expect("draws");
                collection
                    .record(device, cmd, &draws, &light, &map, None)
                    .expect("collection");
                generation.record(device, cmd, &map);
                map.record_counter_readback(device, cmd);
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
                    .expect("lighting");
            }
            // SAFETY: the same command buffer, after the frame's passes.
            unsafe { target.record_readback(device, cmd) };
        })
        .expect("host submission");
        let counts = map.read_counters().expect("counters");
        if !map.needs_more_room(&counts) {
            break counts;
        }
        map.grow_to_fit(&ctx, &counts).expect("grow");
    };
    let rgb = target.read_rgb().expect("radiance");
    assert_eq!(
        ctx.validation_messages(),
        Vec::<String>::new(),
        "a from_raw context has no messenger of its own"
    );
    drop((
        map, target, lighting, generation, collection, draws, geometry,
    ));
    drop(ctx);
    Embedded {
        rgb,
        counts,
        attempts,
    }
}

#[test]
fn host_device_and_command_buffer_render_the_same_image_as_the_renderer() {
    let host = Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    let scene = builtin("cubes-toward-light", &BuiltinOptions::default()).expect("scene");

    let embedded = render_embedded(&host, &scene);
    assert!(
        embedded.attempts >= 2,
        "16-entry lists should have overflowed and been grown"
    );

    let ctx = context();
    assert_eq!(
        ctx.info().name,
        host.device_name,
        "the host and the library context must render on the same device to compare bits"
    );
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: SPP,
        seed: SEED,
        // The host's lights keep the library's default receiver test (the normal offset).
        receiver: ReceiverTest::Offset,
        ..RenderSettings::default()
    };
    let reference = render(&ctx, &scene, &settings);
    assert_eq!(
        u64::from(embedded.counts.node_count),
        reference.stats.fragments
    );
    assert_eq!(
        u64::from(embedded.counts.range_count),
        reference.stats.ranges
    );
    assert!(reference.stats.fragments > 0 && reference.stats.ranges > 0);
    assert_eq!(embedded.rgb.len(), reference.image.rgb.len());
    let differing: Vec<usize> = embedded
        .rgb
        .iter()
        .zip(&reference.image.rgb)
        .enumerate()
        .filter(|(_, (a, b))| a.to_bits() != b.to_bits())
        .map(|(i, _)| i)
        .collect();
    assert!(
        differing.is_empty(),
        "{} of {} channels differ; first at pixel {}: embedded {} vs renderer {}",
        differing.len(),
        embedded.rgb.len(),
        differing[0] / 3,
        embedded.rgb[differing[0]],
        reference.image.rgb[differing[0]]
    );
    assert!(
        embedded.rgb.iter().any(|&v| v > 0.0),
        "the image is not black"
    );
    drop(reference);
    assert_no_validation_messages(&ctx);
    drop(ctx);

    // The library destroyed none of the host's objects: the device and queue still work.
    // SAFETY: the library's context is gone and waited for nothing of the host's; the host's device
    // is live, and the fence, made and destroyed here, is never submitted.
    unsafe {
        let fence = host
            .device
            .create_fence(&ash::vk::FenceCreateInfo::default(), None)
            .expect("the host's device survives the library");
        host.device.destroy_fence(fence, None);
    }
    host.record_and_wait(|_| {})
        .expect("the host's queue, pool and fence still work");
    assert_eq!(host.validation_messages(), Vec::<String>::new());

    // Destroying the host's device and instance reports any object the library left on them.
    host.assert_clean_teardown();
}
