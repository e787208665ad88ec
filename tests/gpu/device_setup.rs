//! Device setup as a host does it: the host creates its device with what
//! `DeviceRequirements::for_device` lists, and `Context::from_raw` is told what was enabled.
//! A device created without a required feature is refused by that feature's name (before,
//! `from_raw` only checked what the device supports and ran on such a device, with only the
//! validation layer complaining); without the optional hostQueryReset the context works and
//! timestamps are off and say so.

use crate::support::host::Host;
use motion_shadows::Error;
use motion_shadows::ash::vk;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{
    Context, ContextOptions, DeviceFeatures, DeviceRequirements, TimestampQueries,
};

/// `Context::from_raw` on the host's handles, told what the host enabled.
fn wrap(host: &Host) -> motion_shadows::Result<Context> {
    // SAFETY: Host made `device` from `physical` of `instance` (Vulkan 1.3) with a
    // graphics+compute queue of `queue_family` and exactly the features in `host.enabled`;
    // `host` outlives the context (dropped before the host in each test).
    unsafe {
        Context::from_raw(
            &host.instance,
            host.physical,
            host.device.clone(),
            host.queue_family,
            host.queue,
            &host.enabled,
        )
    }
}

/// Turns one feature off.
type TurnOff = fn(&mut DeviceFeatures);

/// Each required feature, by its Vulkan name, and how to turn it off.
const REQUIRED: &[(&str, TurnOff)] = &[
    ("geometryShader", |f| f.core.geometry_shader = vk::FALSE),
    ("fragmentStoresAndAtomics", |f| {
        f.core.fragment_stores_and_atomics = vk::FALSE
    }),
    ("shaderInt64", |f| f.core.shader_int64 = vk::FALSE),
    ("shaderBufferInt64Atomics", |f| {
        f.vulkan12.shader_buffer_int64_atomics = vk::FALSE
    }),
    ("bufferDeviceAddress", |f| {
        f.vulkan12.buffer_device_address = vk::FALSE
    }),
    ("dynamicRendering", |f| {
        f.vulkan13.dynamic_rendering = vk::FALSE
    }),
    ("synchronization2", |f| {
        f.vulkan13.synchronization2 = vk::FALSE
    }),
];

#[test]
fn a_device_created_without_a_required_feature_is_refused_by_name() {
    for (name, turn_off) in REQUIRED {
        let host = Host::with_features(true, turn_off).unwrap_or_else(|e| {
            panic!("GPU tests need a Vulkan device and the validation layer: {e}")
        });
        match wrap(&host) {
            Ok(_) => panic!("a device created without {name} was accepted"),
            Err(Error::FeaturesNotEnabled { missing, detail }) => {
                assert_eq!(missing, [*name], "{detail}");
                let text = Error::FeaturesNotEnabled { missing, detail }.to_string();
                assert!(
                    text.contains(&format!("without {name} (")),
                    "the message names the feature and its use: {text}"
                );
            }
            Err(e) => panic!("refused for another reason than {name}: {e}"),
        }
        host.assert_clean_teardown();
    }
}

#[test]
fn the_required_features_alone_make_a_working_context() {
    let host = Host::with_features(true, |f| *f = DeviceFeatures::required())
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    let ctx = wrap(&host).expect("the required features are enough");
    assert!(!ctx.info().host_query_reset);
    assert!(!ctx.info().storage_image_write_without_format);
    // The mask pass needs the optional shaderStorageImageWriteWithoutFormat, and says so.
    let err = motion_shadows::technique::VisibilityMaskPass::new(&ctx)
        .err()
        .expect("no mask pass without shaderStorageImageWriteWithoutFormat");
    assert!(
        err.to_string()
            .contains("shaderStorageImageWriteWithoutFormat"),
        "{err}"
    );
    drop(ctx);
    host.assert_clean_teardown();
}

#[test]
fn without_host_query_reset_timestamps_are_off_and_say_so() {
    let host = Host::with_features(true, |f| f.vulkan12.host_query_reset = vk::FALSE)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    assert!(!host.enabled.host_query_reset());
    let ctx = wrap(&host).expect("hostQueryReset is optional");
    assert!(!ctx.info().host_query_reset);
    let mut timestamps = TimestampQueries::new(&ctx, 4).expect("timestamps");
    assert!(!timestamps.supported());
    let why = timestamps.unsupported_reason().expect("a reason");
    assert!(why.contains("hostQueryReset"), "{why}");
    host.record_and_wait(|cmd| {
        // SAFETY: `cmd` is the host's command buffer of the context's device, recording
        // (record_and_wait began it), and `timestamps` lives past the wait; unsupported here, mark
        // records nothing.
        unsafe { timestamps.mark(cmd, "start") };
        // SAFETY: as the mark before: the same recording command buffer, `timestamps` outliving its
        // execution.
        unsafe { timestamps.mark(cmd, "end") };
    })
    .expect("submission");
    assert_eq!(timestamps.spans_ms().expect("spans"), Vec::new());
    // SAFETY: record_and_wait waited for the host's fence, so no command buffer with these marks is
    // pending.
    unsafe { timestamps.clear() };
    drop((timestamps, ctx));
    // The validation layer would report vkResetQueryPool on a device without hostQueryReset.
    host.assert_clean_teardown();
}

#[test]
fn with_host_query_reset_timestamps_time() {
    let host = Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    assert!(
        host.enabled.host_query_reset(),
        "lavapipe and desktop GPUs support hostQueryReset"
    );
    let ctx = wrap(&host).expect("context");
    let mut timestamps = TimestampQueries::new(&ctx, 4).expect("timestamps");
    assert_eq!(timestamps.unsupported_reason(), None);
    host.record_and_wait(|cmd| {
        // SAFETY: `cmd` is the host's command buffer of the context's device, recording, on its
        // graphics and compute queue (timestamps valid), and `timestamps` lives past
        // record_and_wait's wait.
        unsafe { timestamps.mark(cmd, "start") };
        // SAFETY: as the mark before: the same recording command buffer, `timestamps` outliving its
        // execution.
        unsafe { timestamps.mark(cmd, "end") };
    })
    .expect("submission");
    let spans = timestamps.spans_ms().expect("spans");
    assert_eq!(spans.len(), 1);
    assert_eq!(spans[0].0, "end");
    drop((timestamps, ctx));
    host.assert_clean_teardown();
}

/// A host that creates its own device picks it with the library's preference: the device
/// `Context::headless` runs on, with what `for_device` says to enable there.
#[test]
fn a_host_chooses_the_device_the_library_would() {
    let host = Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    // SAFETY: the host's instance is live and was created for Vulkan 1.3.
    let (physical, family, requirements) =
        unsafe { DeviceRequirements::choose_device(&host.instance) }.expect("a device");
    // SAFETY: `physical` was enumerated from the host's instance.
    let props = unsafe { host.instance.get_physical_device_properties(physical) };
    let name = props
        .device_name_as_c_str()
        .expect("a name")
        .to_string_lossy();
    let headless = Context::headless(&ContextOptions::from_env()).expect("headless context");
    assert_eq!(name, headless.info().name, "the library's own preference");
    // SAFETY: as above.
    let families = unsafe {
        host.instance
            .get_physical_device_queue_family_properties(physical)
    };
    let flags = families[family as usize].queue_flags;
    assert!(flags.contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE));
    // SAFETY: as above.
    let expected = unsafe { DeviceRequirements::for_device(&host.instance, physical) }
        .expect("the chosen device is accepted");
    let optional = |r: &DeviceRequirements| {
        let f = &r.features;
        (f.host_query_reset(), f.storage_image_write_without_format())
    };
    assert!(requirements.features.missing_required().is_empty());
    assert_eq!(
        optional(&requirements),
        optional(&expected),
        "what for_device lists"
    );
    drop(headless);
    host.assert_clean_teardown();
}

/// A host that lets the library make its device (`create_device`) gets one a context accepts,
/// with the features the requirements listed (the optional ones included) reported as
/// enabled, and its queue of the chosen family; validation stays silent.
#[test]
fn a_device_made_from_the_requirements_is_accepted_with_what_they_enable() {
    let host = Host::new(true)
        .unwrap_or_else(|e| panic!("GPU tests need a Vulkan device and the validation layer: {e}"));
    // SAFETY: the host's instance is live and was created for Vulkan 1.3.
    let (physical, family, requirements) =
        unsafe { DeviceRequirements::choose_device(&host.instance) }.expect("a device");
    let listed = requirements.features;
    // SAFETY: `physical` is the device chosen on the host's instance, with what for_device
    // accepted there.
    let (device, queue, enabled) =
        unsafe { requirements.create_device(&host.instance, physical, family) }.expect("device");
    let optional =
        |f: &DeviceFeatures| (f.host_query_reset(), f.storage_image_write_without_format());
    assert_eq!(
        optional(&enabled),
        optional(&listed),
        "the features it was made with"
    );
    assert!(enabled.missing_required().is_empty());
    // The library's buffers on an allocator made for it: read by address.
    let allocator = Context::new_allocator(&host.instance, physical, &device).expect("allocator");
    // SAFETY: the device was made from `physical` of the host's instance with `queue` of
    // `family` and the features in `enabled`; it outlives the context (dropped first); the
    // allocator is the device's.
    let ctx = unsafe {
        let (instance, device) = (&host.instance, device.clone());
        Context::from_raw_with_allocator(
            instance, physical, device, family, queue, &enabled, allocator,
        )
    }
    .expect("the context accepts the device");
    // Its pipelines (geometry shaders, 64-bit atomics, ...) made on the device: validation
    // would report a feature they use that the device was made without.
    let light = motion_shadows::Light::spot(Vec3::new(0.0, 8.0, 0.0), Vec3::NEG_Y);
    let settings = motion_shadows::ShadowSettings::new(light.depth_range(0.5, 20.0));
    let shadow = motion_shadows::LightShadow::new(&ctx, settings).expect("a shadow");
    drop((shadow, ctx));
    // SAFETY: the context, the only user of the device, is gone.
    unsafe { device.destroy_device(None) };
    host.assert_clean_teardown();
}
