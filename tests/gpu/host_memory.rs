//! Memory as a host engine manages it: objects the GPU may still use are retired until the
//! host says their frame completed (`Context::begin_frame` / `collect`), and a host's own
//! gpu-allocator holds, and counts, every buffer the library makes.

use crate::support::host::Host;
use motion_shadows::ash::vk;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{Buffer, BufferUsage, Context, OneShot};
use motion_shadows::gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use motion_shadows::technique::{
    CollectionPass, Draw, DrawList, GenerationPass, Indices, LightView, PositionStream,
    TemporalShadowMap,
};
use std::sync::{Arc, Mutex};

fn new_host() -> Host {
    Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"))
}

/// The host's own allocator on its device (buffer device addresses on, as the library needs).
fn host_allocator(host: &Host) -> Arc<Mutex<Allocator>> {
    let allocator = Allocator::new(&AllocatorCreateDesc {
        instance: host.instance.clone(),
        device: host.device.clone(),
        physical_device: host.physical,
        debug_settings: Default::default(),
        buffer_device_address: true,
        allocation_sizes: Default::default(),
    })
    .expect("the host's allocator");
    Arc::new(Mutex::new(allocator))
}

/// `Context::from_raw_with_allocator` on the host's handles.
fn wrap(host: &Host, allocator: Arc<Mutex<Allocator>>) -> Context {
    // SAFETY: Host made `device` from `physical` of `instance` (Vulkan 1.3) with a
    // graphics+compute queue of `queue_family` and the features in `host.enabled`; the
    // allocator is on that device with buffer device addresses; `host` outlives the context
    // (dropped before it), and every submission is waited for before the objects go.
    unsafe {
        Context::from_raw_with_allocator(
            &host.instance,
            host.physical,
            host.device.clone(),
            host.queue_family,
            host.queue,
            &host.enabled,
            allocator,
        )
    }
    .expect("context")
}

/// The allocations the host's allocator holds, as (name, bytes), sorted.
fn allocations(allocator: &Mutex<Allocator>) -> Vec<(String, u64)> {
    let report = allocator.lock().unwrap().generate_report();
    let mut out: Vec<_> = report
        .allocations
        .into_iter()
        .map(|a| (a.name, a.size))
        .collect();
    out.sort();
    out
}

/// A triangle moving across the light's view: one draw of three vertices (t0 and t1
/// positions interleaved, stride 32).
fn moving_triangle(ctx: &Context) -> (Buffer, Draw) {
    let t0 = [
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(1.0, 1.0, -1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ];
    let mut data = Vec::new();
    for p in t0 {
        let q = p + Vec3::new(1.0, 0.0, 0.0);
        data.extend_from_slice(&[p.x, p.y, p.z, 1.0, q.x, q.y, q.z, 1.0]);
    }
    let buffer = Buffer::with_data(ctx, "triangle", BufferUsage::HostToDevice, &data)
        .expect("vertex buffer");
    let draw = Draw::new(
        PositionStream::from_buffer(&buffer, 0, 32).expect("t0 stream"),
        PositionStream::from_buffer(&buffer, 16, 32).expect("t1 stream"),
        3,
        Indices::None,
        1,
        0,
    );
    (buffer, draw)
}

/// How much more than an object's own bytes the host's allocator may count for it: its
/// alignment padding. 256 bytes on lavapipe; on an NVIDIA H200 a 512-byte 1x1 image took
/// 1,120 (its 1 KiB alignment).
const PADDING: u64 = 4096;

/// Grows a map while the frame that uses it is in flight: the old buffers are retired with
/// the frame and destroyed only when the host collects it after the fence. Without the
/// retirement (`reserve` freeing at once, as before), the validation layer reports
/// vkDestroyBuffer on buffers that a pending command buffer uses.
#[test]
fn a_map_replaced_while_its_frame_is_in_flight_waits_for_the_frame() {
    let host = new_host();
    let allocator = host_allocator(&host);
    let ctx = wrap(&host, allocator.clone());
    let collection = CollectionPass::new(&ctx).expect("collection pass");
    let generation = GenerationPass::new(&ctx).expect("generation pass");
    let (vertices, draw) = moving_triangle(&ctx);
    let mut draws = DrawList::new(&ctx, 1).expect("draw list");
    let mut map = TemporalShadowMap::new(&ctx, 64, 64, 1 << 12, 1 << 12).expect("map");
    let light = LightView::spot(
        Vec3::new(0.0, 8.0, 0.0),
        Vec3::NEG_Y,
        40.0,
        50.0,
        0.5,
        50.0,
        (64, 64),
    );
    let device = &host.device;
    let before = allocations(&allocator);

    ctx.begin_frame(1);
    host.record_and_submit(|cmd| unsafe {
        // SAFETY: the host's command buffer, recording, outside rendering, on a graphics and
        // compute queue; the objects outlive the frame (retired until it is collected).
        draws.record_update(device, cmd, &[draw]).expect("draws");
        collection
            .record(device, cmd, &draws, &light, &map, None)
            .expect("collection");
        generation.record(device, cmd, &map);
        map.record_counter_readback(device, cmd);
    })
    .expect("submission");

    // Frame 1 is in flight: the map grows (new buffers) and the draw list goes.
    map.reserve(&ctx, 1 << 13, 1 << 13).expect("reserve");
    drop(draws);
    let retired = ctx.retired_objects();
    assert_eq!(
        retired,
        map.allocations().len() + 1,
        "each of the old map's buffers and the draw list wait for frame 1"
    );
    // Still allocated in the host's budget: nothing was freed under the pending frame.
    let during = allocations(&allocator);
    assert_eq!(during.len(), before.len() + map.allocations().len());

    host.wait().expect("fence");
    assert_eq!(
        // SAFETY: frame 1's fence has signalled (host.wait above), so frame 0, recorded
        // before it on the same queue, has completed too.
        unsafe { ctx.collect(0) },
        0,
        "frame 1 is not collected with frame 0"
    );
    // SAFETY: frame 1's fence has signalled (host.wait above).
    assert_eq!(unsafe { ctx.collect(1) }, retired);
    assert_eq!(ctx.retired_objects(), 0);
    let after = allocations(&allocator);
    assert_eq!(
        after.len(),
        before.len() - 1,
        "the old map's buffers and the draw list are back in the host's allocator"
    );

    drop((map, vertices, collection, generation, ctx));
    assert!(
        allocations(&allocator).is_empty(),
        "the library left nothing allocated"
    );
    drop(allocator);
    host.assert_clean_teardown();
}

/// Whether the host's allocator still holds an allocation named `name`.
fn holds(allocator: &Mutex<Allocator>, name: &str) -> bool {
    allocations(allocator).iter().any(|(n, _)| n == name)
}

/// A one-shot (the host's own upload through `OneShot`, or the library's download) waits for
/// its own work only: on a host's context the host's frame may be recording or in flight on
/// the same queue, so a one-shot's end must free nothing retired with that frame. A buffer
/// dropped while frame 1 records (its handle in the host's command buffer, not yet submitted)
/// and one dropped while frame 1 is in flight both stay allocated in the host's allocator
/// through an upload and a download, and go only when the host collects frame 1 after its
/// fence; the validation layer (which would report the submission of a destroyed buffer)
/// stays silent. Fails when a one-shot's end frees everything retired.
#[test]
fn a_one_shot_during_a_hosts_frame_frees_nothing_the_frame_uses() {
    let host = new_host();
    let allocator = host_allocator(&host);
    let ctx = wrap(&host, allocator.clone());
    let device = &host.device;
    let map = TemporalShadowMap::new(&ctx, 8, 8, 16, 16).expect("map");
    let uploaded = Buffer::new(&ctx, "uploaded", 256, BufferUsage::Storage).expect("buffer");
    let source = Buffer::with_data(&ctx, "source", BufferUsage::HostToDevice, &[7u32; 64])
        .expect("upload source");
    let upload = || {
        OneShot::new(&ctx)
            .and_then(|one_shot| {
                one_shot.run(|cmd| {
                    let region = vk::BufferCopy::default().size(256);
                    // SAFETY: both buffers are the context's and alive; the one-shot waits.
                    unsafe { device.cmd_copy_buffer(cmd, source.raw(), uploaded.raw(), &[region]) };
                    Ok(())
                })
            })
            .expect("one-shot upload")
    };
    let recorded =
        Buffer::new(&ctx, "used while recording", 256, BufferUsage::Storage).expect("buffer");
    let in_flight = Buffer::new(&ctx, "used in flight", 256, BufferUsage::Storage).expect("buffer");

    ctx.begin_frame(1);
    host.record_and_submit(|cmd| {
        // SAFETY: the host's command buffer, recording, outside rendering; each buffer is
        // retired with frame 1 when dropped.
        unsafe {
            device.cmd_fill_buffer(cmd, recorded.raw(), 0, vk::WHOLE_SIZE, 1);
            device.cmd_fill_buffer(cmd, in_flight.raw(), 0, vk::WHOLE_SIZE, 2);
        }
        drop(recorded);
        upload();
        map.download_static_layer(&ctx).expect("download");
        assert!(
            holds(&allocator, "used while recording"),
            "a one-shot freed a buffer that frame 1, still recording, uses"
        );
    })
    .expect("submission");
    drop(in_flight);
    upload();
    map.download_static_layer(&ctx).expect("download");
    for name in ["used while recording", "used in flight"] {
        assert!(
            holds(&allocator, name),
            "a one-shot freed {name:?} while frame 1 is in flight"
        );
    }
    assert_eq!(host.validation_messages(), Vec::<String>::new());

    host.wait().expect("fence");
    // SAFETY: frame 1's fence has signalled; the one-shots waited for theirs.
    unsafe { ctx.collect(1) };
    for name in ["used while recording", "used in flight"] {
        assert!(!holds(&allocator, name), "{name:?} is freed with frame 1");
    }
    drop((map, uploaded, source, ctx));
    drop(allocator);
    host.assert_clean_teardown();
}

/// The host's allocator counts the library's allocations: a map's buffers appear in the
/// host's report under the names and sizes the map reports (`allocations`), and leave it once
/// collected.
#[test]
fn the_hosts_allocator_counts_the_librarys_allocations() {
    let host = new_host();
    let allocator = host_allocator(&host);
    let ctx = wrap(&host, allocator.clone());
    let before = allocations(&allocator);
    let map = TemporalShadowMap::new(&ctx, 128, 96, 5000, 3000).expect("map");
    let mut added = allocations(&allocator);
    for a in &before {
        let i = added
            .iter()
            .position(|b| b == a)
            .expect("earlier allocations stay");
        added.remove(i);
    }
    let mut reported: Vec<(String, u64)> = map
        .allocations()
        .into_iter()
        .map(|(name, bytes)| (name.to_owned(), bytes))
        .collect();
    reported.sort();
    // The host's report counts each allocation with its alignment padding (the allocator's
    // chunk), at most the largest alignment the buffers ask for ahead of it: PADDING.
    let names = |v: &[(String, u64)]| v.iter().map(|a| a.0.clone()).collect::<Vec<_>>();
    assert_eq!(
        names(&added),
        names(&reported),
        "the host's allocator holds the map's buffers"
    );
    for (host_view, map_view) in added.iter().zip(&reported) {
        assert!(
            map_view.1 > 0 && (map_view.1..map_view.1 + PADDING).contains(&host_view.1),
            "{}: the host counts {} bytes, the map reports {}",
            map_view.0,
            host_view.1,
            map_view.1
        );
    }
    let nodes = reported
        .iter()
        .find(|(n, _)| n == "nodes")
        .expect("the fragment buffer");
    // The default path stores no fragment: one node, not the 5000 asked for
    // (docs/src/integration.md#bytes-per-map).
    assert!(nodes.1 < 5000 * 16, "{nodes:?}");
    let heads = reported
        .iter()
        .find(|(n, _)| n == "node heads")
        .expect("the list heads");
    assert!(heads.1 >= 128 * 96 * 4, "{heads:?}");
    assert!(
        reported.iter().map(|r| r.1).sum::<u64>() >= map.allocated_bytes(),
        "allocations hold at least the buffers' bytes"
    );

    // The draw list and the mask's bindings report theirs the same way.
    let draws = motion_shadows::technique::DrawList::new(&ctx, 8).expect("draw list");
    let mask = motion_shadows::technique::VisibilityMaskPass::new(&ctx).expect("mask pass");
    let bindings = mask.bindings(&ctx, (64, 48)).expect("bindings");
    let host_view = allocations(&allocator);
    for (name, bytes) in draws
        .allocations()
        .into_iter()
        .chain(bindings.allocations())
    {
        assert!(
            host_view
                .iter()
                .any(|(n, b)| n == name && bytes > 0 && (bytes..bytes + PADDING).contains(b)),
            "{name} ({bytes} bytes) in the host's allocator: {host_view:?}"
        );
    }
    drop((draws, bindings, mask));

    drop(map);
    // No frame was submitted: nothing pending uses the map.
    // SAFETY: no submission at all.
    unsafe { ctx.collect(0) };
    assert_eq!(allocations(&allocator), before);
    drop(ctx);
    drop(allocator);
    host.assert_clean_teardown();
}

/// A headless-style check that a host's context never destroys at once: dropped objects wait
/// even without `begin_frame` (frame 0), and `collect(0)` frees them.
#[test]
fn a_hosts_context_retires_even_before_its_first_frame() {
    let host = new_host();
    let allocator = host_allocator(&host);
    let ctx = wrap(&host, allocator.clone());
    let buffer = Buffer::new(&ctx, "scratch", 256, BufferUsage::Storage).expect("buffer");
    host.record_and_submit(|cmd| unsafe {
        // SAFETY: the host's command buffer, recording, outside rendering.
        host.device
            .cmd_fill_buffer(cmd, buffer.raw(), 0, vk::WHOLE_SIZE, 7);
    })
    .expect("submission");
    drop(buffer);
    assert_eq!(ctx.retired_objects(), 1);
    host.wait().expect("fence");
    // SAFETY: the only submission has completed.
    assert_eq!(unsafe { ctx.collect(0) }, 1);
    drop(ctx);
    drop(allocator);
    host.assert_clean_teardown();
}

/// A safe function never records one context's buffer into another's command buffer (a
/// foreign handle is undefined behaviour): downloading a map with another context than its
/// own is refused by name.
#[test]
fn a_map_is_not_copied_with_another_context() {
    let (ctx, other) = (
        crate::support::gpu::context(),
        crate::support::gpu::context(),
    );
    let map = TemporalShadowMap::new(&ctx, 8, 8, 16, 16).expect("map");
    let err = map
        .download_static_layer(&other)
        .expect_err("a foreign context is refused");
    assert!(err.to_string().contains("another context"), "{err}");
    assert!(map.download_static_layer(&ctx).is_ok());
    drop(map);
    crate::support::gpu::assert_no_validation_messages(&ctx);
    crate::support::gpu::assert_no_validation_messages(&other);
}
