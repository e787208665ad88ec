//! The engine layer on a real device: one mesh description drives both the draw and the room
//! reserved for its shadow; a mesh only the GPU holds (skinned) is reserved a sound bound
//! from a box, a box too small is reported after the frame, and the kept static layer
//! follows the frames the context was told completed. The expectations are the ceiling over
//! the host's own triangles (`RangeCeiling`, the old API's `HostDraw`) and the device's own
//! count of what it stored.

use crate::support::gpu::{assert_no_validation_messages, context};
use glam::{Mat4, Quat, Vec3, Vec4};
use motion_shadows::ash::vk;
use motion_shadows::gpu::{Buffer, BufferUsage, OneShot};
use motion_shadows::technique::{HostDraw, RangeCeiling};
use motion_shadows::{
    Context, CpuGeometry, Error, IndexStream, Indices, Light, LightShadow, MaskInputs, Mesh,
    MeshBound, PositionStream, ShadowSettings, StaticLayer,
};

const SIZE: (u32, u32) = (96, 96);

/// The shared unit cube with 16-bit indices.
fn cube() -> (Vec<Vec3>, Vec<u16>) {
    let (corners, indices) = crate::support::scene::indexed_unit_cube();
    let narrow = indices.into_iter().map(|i| i as u16).collect();
    (corners, narrow)
}

/// The scene's host data and GPU buffers: a still ground (two triangles, not indexed) and a
/// cube turning and sliding, deformed "on the GPU": its object-space positions at shutter
/// open and close are two streams (a skinning pass's output), with 16-bit indices.
struct Scene {
    ground: Vec<Vec3>,
    open: Vec<Vec3>,
    close: Vec<Vec3>,
    indices: Vec<u16>,
    ground_buffer: Buffer,
    skinned: Buffer,
    index_buffer: Buffer,
}

impl Scene {
    fn new(ctx: &Context) -> Self {
        let g = 4.0;
        let ground = vec![
            Vec3::new(-g, 0.0, -g),
            Vec3::new(g, 0.0, g),
            Vec3::new(g, 0.0, -g),
            Vec3::new(-g, 0.0, -g),
            Vec3::new(-g, 0.0, g),
            Vec3::new(g, 0.0, g),
        ];
        let (corners, indices) = cube();
        let pose = |angle: f32, at: Vec3| {
            Mat4::from_rotation_translation(Quat::from_rotation_y(angle), at)
        };
        let (m0, m1) = (
            pose(0.2, Vec3::new(-0.8, 1.5, 0.0)),
            pose(0.9, Vec3::new(0.8, 1.8, 0.3)),
        );
        let open: Vec<Vec3> = corners.iter().map(|&p| m0.transform_point3(p)).collect();
        let close: Vec<Vec3> = corners.iter().map(|&p| m1.transform_point3(p)).collect();
        let padded = |v: &[Vec3]| -> Vec<Vec4> { v.iter().map(|p| p.extend(1.0)).collect() };
        let skinned: Vec<Vec4> = padded(&open).into_iter().chain(padded(&close)).collect();
        let mut words = indices.clone();
        words.resize(indices.len().next_multiple_of(2), 0);
        Self {
            ground_buffer: Buffer::with_data(
                ctx,
                "ground",
                BufferUsage::HostToDevice,
                &padded(&ground),
            )
            .expect("ground"),
            skinned: Buffer::with_data(ctx, "skinned", BufferUsage::HostToDevice, &skinned)
                .expect("skinned positions"),
            index_buffer: Buffer::with_data(ctx, "indices", BufferUsage::HostToDevice, &words)
                .expect("indices"),
            ground,
            open,
            close,
            indices,
        }
    }

    fn ground(&self) -> Mesh<'_> {
        let stream = PositionStream::from_buffer(&self.ground_buffer, 0, 16).expect("stream");
        Mesh::still(stream, 6).cpu(CpuGeometry::still(&self.ground))
    }

    /// The cube as the GPU holds it (no CPU geometry yet).
    fn cube(&self) -> Mesh<'_> {
        let n = self.open.len() as u32;
        let at =
            |offset: u64| PositionStream::from_buffer(&self.skinned, offset, 16).expect("stream");
        let indices = IndexStream::from_buffer(&self.index_buffer, 0).expect("indices");
        Mesh::moving(at(0), at(16 * u64::from(n)), n)
            .indexed(Indices::U16(indices), self.indices.len() as u32 / 3)
            .first_triangle_id(2)
    }

    /// The box holding the cube at each end.
    fn box_bound(&self) -> MeshBound {
        let bounds = |v: &[Vec3]| {
            let lo = v.iter().copied().fold(Vec3::INFINITY, Vec3::min);
            (lo, v.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max))
        };
        MeshBound {
            at_open: bounds(&self.open),
            at_close: bounds(&self.close),
        }
    }
}

fn settings() -> ShadowSettings {
    let light = Light::spot(Vec3::new(0.3, 7.0, 0.2), Vec3::NEG_Y)
        .cone_half_angle(40.0)
        .depth_range(0.5, 20.0);
    ShadowSettings {
        map_size: SIZE,
        frames_in_flight: 1,
        ..ShadowSettings::new(light)
    }
}

/// Records frame `frame` of `meshes` in a OneShot and tells the context it completed.
fn frame(
    ctx: &Context,
    shadow: &mut LightShadow,
    frame: u64,
    meshes: &[Mesh],
) -> motion_shadows::Result<()> {
    OneShot::new(ctx).expect("command buffer").run(|cmd| {
        // SAFETY: a OneShot command buffer of `ctx`, recording outside rendering on its
        // graphics and compute queue; the buffers outlive the run, which waits.
        unsafe { shadow.record_frame(ctx, cmd, frame, meshes, None) }.map(|_| ())
    })?;
    // SAFETY: the OneShot waited for the frame's command buffer.
    unsafe { ctx.collect(frame) };
    Ok(())
}

/// The skinned cube reserved from its box holds at least what the host's triangles bound
/// (the ceiling over the cube's CPU corners, computed here with the old API) and the frame
/// fits; described with its CPU geometry instead, the reservation is exactly that ceiling,
/// and the map's room that plus the half `LightShadow` adds when a map grows.
#[test]
fn a_skinned_mesh_is_reserved_a_sound_bound_from_its_box() {
    let ctx = context();
    let scene = Scene::new(&ctx);
    let light = settings().light.view(SIZE).expect("light");
    let ceiling = RangeCeiling::new(&light, SIZE.0, SIZE.1).expect("bounded");
    let wide: Vec<u32> = scene.indices.iter().map(|&i| u32::from(i)).collect();
    let host = HostDraw::new(&scene.open, &scene.close, Some(&wide));
    let expected = ceiling.draw(&host).expect("host ceiling");
    let cpu = CpuGeometry::moving(&scene.open, &scene.close).indices_u16(&scene.indices);
    let mut reserved = Vec::new();
    for cube in [scene.cube().cpu(cpu), scene.cube().bound(scene.box_bound())] {
        let mut shadow = LightShadow::new(&ctx, settings()).expect("shadow");
        frame(&ctx, &mut shadow, 1, &[scene.ground(), cube]).expect("frame");
        shadow.finish_frame(&ctx, 1).expect("complete frame");
        let map = shadow.map(1);
        let stored = u64::from(map.read_counters().expect("counters").range_count);
        let room = u64::from(map.range_capacity());
        eprintln!("reserved {room}, stored {stored}, host ceiling {expected}");
        assert!(
            stored > 100 && stored <= room,
            "stored {stored}, room {room}"
        );
        reserved.push(room);
    }
    assert_eq!(
        reserved[0],
        expected + expected / 4 * 2,
        "CPU geometry: the ceiling over its triangles, and half again"
    );
    assert!(
        reserved[1] >= expected,
        "box bound {} below {expected}",
        reserved[1]
    );
    assert_no_validation_messages(&ctx);
}

/// A box that does not hold the skinned positions reserves too little: the frame's overflow
/// is reported by `finish_frame` (not dropped), the map grown, and the next frame fits.
#[test]
fn a_bound_too_small_is_reported_after_the_frame() {
    let ctx = context();
    let scene = Scene::new(&ctx);
    let point = MeshBound::box_all_shutter(Vec3::new(0.0, 1.5, 0.0), Vec3::new(0.01, 1.51, 0.01));
    let meshes = [scene.ground(), scene.cube().bound(point)];
    let mut shadow = LightShadow::new(&ctx, settings()).expect("shadow");
    frame(&ctx, &mut shadow, 1, &meshes).expect("frame 1");
    match shadow.finish_frame(&ctx, 1) {
        Err(Error::RoomExceeded {
            frame: 1,
            stored,
            reserved,
        }) => {
            assert!(stored > reserved, "stored {stored}, reserved {reserved}")
        }
        other => panic!("a box holding none of the cube was not reported: {other:?}"),
    }
    frame(&ctx, &mut shadow, 2, &meshes).expect("frame 2");
    shadow
        .finish_frame(&ctx, 2)
        .expect("the grown map holds frame 2");
    assert_no_validation_messages(&ctx);
}

/// With the static layer kept, the ground is drawn once: frames 2 and 3 keep the layer
/// frame 1 drew, since the context was told frame 1 completed; no "submitted" call. Redrawn,
/// it is drawn every frame.
#[test]
fn the_kept_static_layer_follows_the_completed_frames() {
    let ctx = context();
    let scene = Scene::new(&ctx);
    for (layer, builds) in [(StaticLayer::Kept, 1), (StaticLayer::Redrawn, 3)] {
        let settings = ShadowSettings {
            static_layer: layer,
            ..settings()
        };
        let mut shadow = LightShadow::new(&ctx, settings).expect("shadow");
        let meshes = [scene.ground(), scene.cube().bound(scene.box_bound())];
        for f in 1..=3 {
            frame(&ctx, &mut shadow, f, &meshes).expect("frame");
            shadow.finish_frame(&ctx, f).expect("complete frame");
        }
        assert_eq!(shadow.map(3).static_layer_builds(), builds, "{layer:?}");
    }
    assert_no_validation_messages(&ctx);
}

/// Mask inputs and the mask setting must agree: neither is dropped silently.
#[test]
fn mask_inputs_without_the_mask_setting_are_refused() {
    let ctx = context();
    let scene = Scene::new(&ctx);
    let meshes = [scene.ground()];
    let inputs = MaskInputs::new(
        vk::ImageView::null(),
        vk::ImageLayout::GENERAL,
        vk::ImageView::null(),
        (8, 8),
        Mat4::IDENTITY,
    );
    let mut shadow = LightShadow::new(&ctx, settings()).expect("shadow");
    let with_mask = ShadowSettings {
        mask: true,
        ..settings()
    };
    let mut masked = LightShadow::new(&ctx, with_mask).expect("shadow with mask");
    OneShot::new(&ctx)
        .expect("command buffer")
        .run(|cmd| {
            // SAFETY: as in `frame`; both calls are refused before recording anything.
            let off = unsafe { shadow.record_frame(&ctx, cmd, 1, &meshes, Some(&inputs)) };
            let message = off.expect_err("inputs without the mask").to_string();
            assert!(message.contains("ShadowSettings::mask is off"), "{message}");
            // SAFETY: as above.
            let on = unsafe { masked.record_frame(&ctx, cmd, 1, &meshes, None) };
            let message = on.expect_err("the mask without inputs").to_string();
            assert!(message.contains("needs the mask's inputs"), "{message}");
            Ok(())
        })
        .expect("one shot");
    assert_no_validation_messages(&ctx);
}

/// The shader stages whose shaders read storage buffers: where a host's lookups can run.
const SHADER_STAGES: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::from_raw(
    vk::PipelineStageFlags2::VERTEX_SHADER.as_raw()
        | vk::PipelineStageFlags2::GEOMETRY_SHADER.as_raw()
        | vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw()
        | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
);

/// The declared lookups of frame 1 of the ground under `settings`.
fn declared_lookups(ctx: &Context, settings: ShadowSettings) -> motion_shadows::PassAccesses {
    let scene = Scene::new(ctx);
    let meshes = [scene.ground()];
    let mut shadow = LightShadow::new(ctx, settings).expect("shadow");
    let mut lookups = None;
    OneShot::new(ctx)
        .expect("command buffer")
        .run(|cmd| {
            // SAFETY: as in `frame`.
            let recorded = unsafe { shadow.record_frame(ctx, cmd, 1, &meshes, None) }?;
            lookups = Some(recorded.lookups);
            Ok(())
        })
        .expect("frame");
    lookups.expect("recorded")
}

/// What a frame declares for the host's own lookups reads the map's buffers in exactly the
/// stages that read it, never in every command's stage (a render graph given "all commands"
/// orders transfers and attachments after the generation for nothing).
#[test]
fn the_frames_lookups_declare_only_the_stages_that_read_the_map() {
    let ctx = context();
    let lookups = declared_lookups(&ctx, settings());
    assert!(!lookups.uses.is_empty(), "the map's buffers are declared");
    for u in &lookups.uses {
        assert!(!u.writes, "{u:?}");
        for access in [u.first, u.last] {
            assert_eq!(access.stages, SHADER_STAGES, "{u:?}");
            assert_eq!(
                access.access,
                vk::AccessFlags2::SHADER_STORAGE_READ,
                "{u:?}"
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

/// A host that reads the map from fragment shaders only says so, and the frame declares
/// that; one that reads it only through the mask declares no lookups; a stage no shader runs
/// in is refused by the setting's name.
#[test]
fn the_lookup_stages_setting_narrows_the_declared_lookups() {
    let ctx = context();
    let fragment = vk::PipelineStageFlags2::FRAGMENT_SHADER;
    let narrowed = ShadowSettings {
        lookup_stages: fragment,
        ..settings()
    };
    let lookups = declared_lookups(&ctx, narrowed);
    assert!(!lookups.uses.is_empty());
    for u in &lookups.uses {
        assert_eq!(
            (u.first.stages, u.last.stages),
            (fragment, fragment),
            "{u:?}"
        );
    }
    let none = ShadowSettings {
        lookup_stages: vk::PipelineStageFlags2::empty(),
        ..settings()
    };
    assert_eq!(declared_lookups(&ctx, none).uses, Vec::new());
    for stray in [
        vk::PipelineStageFlags2::TRANSFER,
        vk::PipelineStageFlags2::ALL_COMMANDS,
        fragment | vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
    ] {
        let refused = ShadowSettings {
            lookup_stages: stray,
            ..settings()
        };
        let err = LightShadow::new(&ctx, refused).err().expect("refused");
        assert!(matches!(err, Error::InvalidArgument(_)), "{err}");
        assert!(
            err.to_string().contains("ShadowSettings::lookup_stages"),
            "{err}"
        );
    }
    assert_no_validation_messages(&ctx);
}

/// `set_light` with the light the shadow has keeps its maps (the kept static layer is not
/// redrawn); with another light the maps are new: the next frame redraws the layer and
/// stores what a shadow made for that light stores.
#[test]
fn a_moved_light_gets_new_maps_and_the_same_light_keeps_them() {
    let ctx = context();
    let scene = Scene::new(&ctx);
    let kept = ShadowSettings {
        static_layer: StaticLayer::Kept,
        ..settings()
    };
    let meshes = [scene.ground(), scene.cube().bound(scene.box_bound())];
    let mut shadow = LightShadow::new(&ctx, kept).expect("shadow");
    let counts = |shadow: &LightShadow, f| {
        let c = shadow.map(f).read_counters().expect("counters");
        (c.node_count, c.range_count)
    };
    for f in 1..=2 {
        shadow.set_light(&ctx, kept.light).expect("the same light");
        frame(&ctx, &mut shadow, f, &meshes).expect("frame");
        shadow.finish_frame(&ctx, f).expect("complete frame");
    }
    assert_eq!(
        shadow.map(2).static_layer_builds(),
        1,
        "the same light keeps the layer"
    );
    // New maps are new buffers: the old ones are not freed before the next collect.
    let address = shadow.map(2).header_address();
    shadow.set_light(&ctx, kept.light).expect("the same light");
    assert_eq!(shadow.map(2).header_address(), address, "the same maps");
    let before = counts(&shadow, 2);
    let moved = Light::spot(Vec3::new(-1.5, 7.0, 0.5), Vec3::NEG_Y)
        .cone_half_angle(40.0)
        .depth_range(0.5, 20.0);
    shadow.set_light(&ctx, moved).expect("a moved light");
    assert_eq!(shadow.settings().light, moved);
    assert_ne!(shadow.map(3).header_address(), address, "new maps");
    frame(&ctx, &mut shadow, 3, &meshes).expect("frame 3");
    shadow.finish_frame(&ctx, 3).expect("complete frame");
    assert_eq!(
        shadow.map(3).static_layer_builds(),
        1,
        "new maps draw their layer"
    );
    let mut fresh = LightShadow::new(
        &ctx,
        ShadowSettings {
            light: moved,
            ..kept
        },
    )
    .expect("shadow");
    frame(&ctx, &mut fresh, 3, &meshes).expect("fresh frame");
    fresh.finish_frame(&ctx, 3).expect("complete frame");
    assert_ne!(
        counts(&shadow, 3),
        before,
        "the moved light's shadow differs"
    );
    assert_eq!(
        counts(&shadow, 3),
        counts(&fresh, 3),
        "as a shadow made for the moved light"
    );
    assert_no_validation_messages(&ctx);
}
