//! Device-free checks of the engine layer's descriptions: the draw and the room come from one
//! mesh description, and what does not hold together is refused with the reason.

use glam::{Mat4, Vec3};

use super::{CpuGeometry, Light, Mesh, MeshBound};
use crate::technique::{Bounded, IndexStream, Indices, PositionStream, RangeCeiling};

/// A stream at a made-up address: `draw` only checks and copies descriptions (nothing reads
/// the address without a device).
fn stream(address: u64) -> PositionStream {
    // SAFETY: never dereferenced: these tests build descriptions only.
    unsafe { PositionStream::from_device_address(address, 16) }
}

fn indices(address: u64) -> IndexStream {
    // SAFETY: as `stream`.
    unsafe { IndexStream::from_device_address(address) }
}

fn message(result: crate::Result<impl std::fmt::Debug>) -> String {
    result.expect_err("refused").to_string()
}

/// Under the old API a draw naming one stream twice was static on the GPU while its
/// `HostDraw` (two slices) counted as moving, or the reverse: the two could disagree. Here
/// still or moving is said once, and a description whose GPU streams say otherwise is
/// refused.
#[test]
fn still_or_moving_is_said_once_and_a_contradiction_is_refused() {
    let one = stream(0x1000);
    let moving_in_name_only = Mesh::moving(one, one, 3).transform(Mat4::IDENTITY);
    assert!(message(moving_in_name_only.draw(4)).contains("mesh 4: described as moving"));
    let turning = Mat4::from_rotation_y(0.3);
    let still_but_turning = Mesh::still(one, 3).transforms(Mat4::IDENTITY, turning);
    assert!(message(still_but_turning.draw(0)).contains("described as still"));
    // Described still: the GPU draw is static (the static layer holds it), and the room
    // reservation leaves it out for the same reason.
    let still = Mesh::still(one, 3).transform(turning);
    assert!(still.draw(0).expect("still draw").is_static());
    assert!(Bounded::is_still(&still));
    let moving = Mesh::moving(one, stream(0x2000), 3);
    assert!(!moving.draw(0).expect("moving draw").is_static());
    assert!(!Bounded::is_still(&moving));
}

/// The CPU geometry must say what the GPU description says: its counts, its motion and its
/// index width; otherwise the room would be reserved for another mesh than the one drawn.
#[test]
fn cpu_geometry_that_disagrees_with_the_gpu_description_is_refused() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Z, Vec3::Y];
    let q = [Vec3::ONE; 4];
    let (a, b) = (stream(0x1000), stream(0x2000));
    let cases = [
        (
            Mesh::moving(a, b, 3).cpu(CpuGeometry::moving(&p, &q)),
            "4 CPU positions at shutter open, the GPU streams have 3",
        ),
        (
            Mesh::moving(a, b, 4).cpu(CpuGeometry::still(&p)),
            "a moving mesh with still CPU geometry",
        ),
        (
            Mesh::still(a, 4).cpu(CpuGeometry::moving(&p, &q)),
            "a still mesh with moving CPU geometry",
        ),
        (
            Mesh::still(a, 4)
                .indexed(Indices::U32(indices(0x3000)), 1)
                .cpu(CpuGeometry::still(&p).indices_u16(&[0, 1, 2])),
            "CPU indices u16 and GPU indices u32 differ in width",
        ),
        (
            Mesh::still(a, 4)
                .indexed(Indices::U16(indices(0x3000)), 2)
                .cpu(CpuGeometry::still(&p).indices_u16(&[0, 1, 2])),
            "3 CPU indices for 2 triangles",
        ),
    ];
    for (k, (mesh, expected)) in cases.iter().enumerate() {
        let error = message(mesh.draw(k));
        assert!(error.contains(expected), "case {k}: {error}");
    }
}

/// Room for a mesh with neither CPU geometry nor a bound is refused, naming both ways to
/// give it; an index past the CPU positions is refused, not bounded wrongly.
#[test]
fn a_mesh_without_cpu_geometry_or_bound_is_refused_room() {
    let light = Light::spot(Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y)
        .view((32, 32))
        .expect("light");
    let ceiling = RangeCeiling::new(&light, 32, 32).expect("bounded");
    let gpu_only = Mesh::moving(stream(0x1000), stream(0x2000), 3).first_triangle_id(7);
    let error = message(gpu_only.ranges_at_most(&ceiling));
    assert!(
        error.contains("ids from 7 has neither CPU geometry (Mesh::cpu) nor a bound (Mesh::bound)"),
        "{error}"
    );
    let p = [Vec3::ZERO, Vec3::X, Vec3::Z];
    let bad_index = Mesh::still(stream(0x1000), 3)
        .indexed(Indices::U32(indices(0x3000)), 1)
        .cpu(CpuGeometry::still(&p).indices_u32(&[0, 1, 3]));
    assert!(message(bad_index.ranges_at_most(&ceiling)).contains("index 2 is 3"));
}

/// A bound is sound: never below what the triangles inside it can store (each triangle's
/// own ceiling from its CPU corners), for triangles still and moving, under the light and
/// reaching beside and behind it.
#[test]
fn a_box_bound_is_never_below_the_cpu_bound_of_triangles_inside_it() {
    let light = Light::spot(Vec3::new(0.0, 4.0, 0.0), Vec3::NEG_Y)
        .cone_half_angle(50.0)
        .depth_range(0.2, 20.0)
        .view((48, 48))
        .expect("light");
    let ceiling = RangeCeiling::new(&light, 48, 48).expect("bounded");
    let mut seed = 0x5eed_u64;
    let mut unit = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 33) as f32) / (1u64 << 31) as f32
    };
    for case in 0..200 {
        let centre = Vec3::new(6.0 * unit() - 3.0, 5.0 * unit() - 0.5, 6.0 * unit() - 3.0);
        let size = 0.2 + 2.0 * unit();
        let shift = Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5) * 2.0;
        let open: Vec<Vec3> = (0..3)
            .map(|_| centre + (Vec3::new(unit(), unit(), unit()) - 0.5) * size)
            .collect();
        let close: Vec<Vec3> = open.iter().map(|&p| p + shift).collect();
        let (at_open, at_close) = (bounds(&open), bounds(&close));
        let (t0, t1) = ([open[0], open[1], open[2]], [close[0], close[1], close[2]]);
        let exact = ceiling.triangle(&t0, &t1, false);
        let gpu_only =
            Mesh::moving(stream(0x1000), stream(0x2000), 3).bound(MeshBound { at_open, at_close });
        let bound = gpu_only.ranges_at_most(&ceiling).expect("bounded");
        assert!(
            bound >= exact,
            "case {case}: box bound {bound} < triangle's {exact}"
        );
        let still = ceiling.triangle(&t0, &t0, false);
        let still_mesh =
            Mesh::still(stream(0x1000), 3).bound(MeshBound::box_all_shutter(at_open.0, at_open.1));
        let still_bound = still_mesh.ranges_at_most(&ceiling).expect("bounded");
        assert!(
            still_bound >= still,
            "case {case}: still box bound {still_bound} < {still}"
        );
    }
}

/// The smallest box holding `points`.
fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let lo = points.iter().copied().fold(Vec3::INFINITY, Vec3::min);
    let hi = points.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
    (lo, hi)
}

/// A setting that does not apply to the light's kind, or out of range, is refused by name.
#[test]
fn light_settings_that_do_not_apply_are_refused() {
    let sun = Light::directional(Vec3::NEG_Y, Vec3::ZERO, 5.0);
    assert!(sun.view((64, 64)).is_ok());
    let error = message(sun.cone_half_angle(30.0).view((64, 64)));
    assert!(error.contains("cone half angle"), "{error}");
    let spot = Light::spot(Vec3::Y, Vec3::NEG_Y);
    assert!(message(spot.distance(3.0).view((64, 64))).contains("distance"));
    assert!(message(spot.depth_range(0.0, 5.0).view((64, 64))).contains("near depth"));
    assert!(message(spot.depth_range(2.0, 1.0).view((64, 64))).contains("depth range"));
}

/// A host's barrier between two declared passes: its images move from the layout the earlier
/// pass left them in (or from UNDEFINED when it did not use them) into the later pass's,
/// waiting for the earlier use's last accesses; an image kept in its layout, or one the host
/// did not name, gets no transition; the memory dependency joins every access of both.
#[test]
fn host_barriers_move_each_named_image_into_its_declared_layout() {
    use super::{HostBarrier, HostImage};
    use crate::technique::{AccessData, PassAccesses};
    use ash::vk::{self, AccessFlags2 as A, Handle, ImageLayout as L, PipelineStageFlags2 as S};
    let range = vk::ImageSubresourceRange::default()
        .layer_count(1)
        .level_count(1);
    let image = |n: u64| HostImage {
        image: vk::Image::from_raw(n),
        view: vk::ImageView::from_raw(100 + n),
        range,
    };
    let (depth, mask, kept, unnamed) = (image(1), image(2), image(3), image(4));
    let access = |stages, access| AccessData { stages, access };
    let sampled = access(S::COMPUTE_SHADER, A::SHADER_SAMPLED_READ);
    let before = PassAccesses::host_images(
        &[depth.view, kept.view],
        L::READ_ONLY_OPTIMAL,
        sampled,
        false,
    );
    let tests = access(S::LATE_FRAGMENT_TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE);
    let storage = access(S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE);
    let after = PassAccesses::host_images(&[depth.view], L::DEPTH_ATTACHMENT_OPTIMAL, tests, true)
        .and(&PassAccesses::host_images(
            &[mask.view, unnamed.view],
            L::GENERAL,
            storage,
            true,
        ))
        .and(&PassAccesses::host_images(
            &[kept.view],
            L::READ_ONLY_OPTIMAL,
            sampled,
            false,
        ));
    let barrier = HostBarrier::between(&before, &after, &[depth, mask, kept]);
    let got: Vec<_> = barrier
        .images
        .iter()
        .map(|b| {
            (
                b.image,
                b.old_layout,
                b.new_layout,
                b.src_access_mask,
                b.dst_stage_mask,
            )
        })
        .collect();
    let want = [
        (
            depth.image,
            L::READ_ONLY_OPTIMAL,
            L::DEPTH_ATTACHMENT_OPTIMAL,
            A::SHADER_SAMPLED_READ,
            S::LATE_FRAGMENT_TESTS,
        ),
        (
            mask.image,
            L::UNDEFINED,
            L::GENERAL,
            A::SHADER_SAMPLED_READ,
            S::COMPUTE_SHADER,
        ),
    ];
    assert_eq!(got, want);
    assert_eq!(barrier.images[0].subresource_range.layer_count, 1);
    let memory = (barrier.memory.src_stage_mask, barrier.memory.dst_stage_mask);
    assert_eq!(
        memory,
        (
            S::COMPUTE_SHADER,
            S::LATE_FRAGMENT_TESTS | S::COMPUTE_SHADER
        )
    );
    let access = (
        barrier.memory.src_access_mask,
        barrier.memory.dst_access_mask,
    );
    let written = A::DEPTH_STENCIL_ATTACHMENT_WRITE | A::SHADER_STORAGE_WRITE;
    assert_eq!(
        access,
        (A::SHADER_SAMPLED_READ, written | A::SHADER_SAMPLED_READ)
    );
}
