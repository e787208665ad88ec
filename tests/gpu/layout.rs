//! The Rust mirrors in `technique::gpu_types` have the layout of `glsl/shared.glsl`: a probe
//! shader writes known values through each GLSL struct and copies the frame parameters back.

use crate::support::gpu::{assert_no_validation_messages, context};
use glam::{Mat4, UVec4, Vec3, Vec4};
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, DescriptorBinding, DescriptorKind, DescriptorSet, OneShot,
    compute_pipeline, memory_barrier,
};
use motion_shadows::technique::{
    Counters, FrameParams, Node, PassConstants, Range, SceneVertex, shaders,
};

#[test]
fn shared_structs_match_glsl() {
    let ctx = context();
    let device = ctx.device();
    let binding = |binding, kind| DescriptorBinding {
        binding,
        kind,
        stages: ash::vk::ShaderStageFlags::COMPUTE,
    };
    use DescriptorKind::{Storage, Uniform};
    let mut set = DescriptorSet::new(
        &ctx,
        &[
            binding(0, Uniform),
            binding(1, Storage),
            binding(2, Storage),
            binding(3, Storage),
            binding(4, Storage),
            binding(5, Storage),
            binding(6, Storage),
        ],
    )
    .unwrap();
    let pipeline = compute_pipeline(
        &ctx,
        set.layout(),
        std::mem::size_of::<PassConstants>() as u32,
        "layout_probe.comp",
        shaders::LAYOUT_PROBE_COMP,
    )
    .unwrap();

    // Every field distinct, so a shifted field cannot pass.
    let mut params = FrameParams::default();
    let mut next = 1.0f32;
    let mut value = || {
        next += 1.0;
        next
    };
    let mut mat = || Mat4::from_cols_array(&std::array::from_fn(|_| value()));
    params.light_view = mat();
    params.light_proj = mat();
    params.camera_view_proj = mat();
    params.camera_inv_view_proj = mat();
    let mut vec = || Vec4::new(value(), value(), value(), value());
    params.camera_position = vec();
    params.camera_forward = vec();
    params.light_position = vec();
    params.light_direction = vec();
    params.light_params = vec();
    params.light_texel = vec();
    params.camera_ray00 = vec();
    params.camera_ray_dx = vec();
    params.camera_ray_dy = vec();
    params.sizes = UVec4::new(101, 102, 103, 104);
    params.sampling = UVec4::new(105, 106, 107, 108);

    let frame = Buffer::with_data(&ctx, "frame", BufferUsage::Uniform, &[params]).unwrap();
    let out = |name, bytes| Buffer::new(&ctx, name, bytes, BufferUsage::Storage).unwrap();
    let nodes = out("nodes", 32);
    let ranges = out("ranges", 48);
    let vertices = out("vertices", 64);
    let counters = out("counters", 32);
    let frame_copy = out("frame copy", std::mem::size_of::<FrameParams>() as u64);
    let push_copy = out("push copy", std::mem::size_of::<PassConstants>() as u64);
    set.bind(&[
        &frame,
        &nodes,
        &ranges,
        &vertices,
        &counters,
        &frame_copy,
        &push_copy,
    ]);
    let constants = PassConstants {
        first_triangle: 21,
        first_sample: 22,
        sample_count: 23,
        mode: 24,
        time: 0.625,
        flags: 26,
        reserved: [27, 28],
        node_address: 0x1234_5678_9abc_def0,
        range_address: 0x0fed_cba9_8765_4321,
    };
    OneShot::new(&ctx)
        .unwrap()
        .run(|cmd| {
            pipeline.bind(device, cmd, set.raw());
            pipeline.push(device, cmd, &constants);
            unsafe { device.cmd_dispatch(cmd, 1, 1, 1) };
            memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_READ);
            Ok(())
        })
        .unwrap();

    let download = |b: &Buffer, bytes: usize| -> Vec<u8> {
        let staging = Buffer::new(&ctx, "staging", bytes as u64, BufferUsage::Readback).unwrap();
        OneShot::new(&ctx)
            .unwrap()
            .run(|cmd| {
                let region = [ash::vk::BufferCopy {
                    src_offset: 0,
                    dst_offset: 0,
                    size: bytes as u64,
                }];
                unsafe { device.cmd_copy_buffer(cmd, b.raw(), staging.raw(), &region) };
                memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ);
                Ok(())
            })
            .unwrap();
        staging.read::<u8>(bytes).unwrap()
    };
    fn cast<T: Copy + Default>(bytes: &[u8], index: usize) -> T {
        let size = std::mem::size_of::<T>();
        let mut value = T::default();
        unsafe {
            std::ptr::copy_nonoverlapping(
                bytes[index * size..].as_ptr(),
                &mut value as *mut T as *mut u8,
                size,
            )
        };
        value
    }

    let node: Node = cast(&download(&nodes, 32), 1);
    assert_eq!(
        node,
        Node {
            depth: 1.5,
            time: 0.25,
            id: 7,
            next: 9
        }
    );
    let range: Range = cast(&download(&ranges, 48), 1);
    assert_eq!(
        range,
        Range {
            t_s: 0.125,
            t_e: 0.75,
            d_s: 2.5,
            d_e: 3.5,
            id: 11,
            next: 13
        }
    );
    let vertex: SceneVertex = cast(&download(&vertices, 64), 1);
    assert_eq!(vertex.p0, Vec4::new(1.0, 2.0, 3.0, 4.0));
    assert_eq!(vertex.p1, Vec3::new(5.0, 6.0, 7.0).extend(8.0));
    let c: Counters = cast(&download(&counters, 32), 0);
    assert_eq!(
        c,
        Counters {
            node_count: 21,
            node_capacity: 22,
            range_count: 23,
            range_capacity: 24,
            overlong_pixels: 31,
            longest_list: 32,
            ranges_without_coverage: 33,
            reserved: 34,
        }
    );
    let copy: FrameParams = cast(
        &download(&frame_copy, std::mem::size_of::<FrameParams>()),
        0,
    );
    assert_eq!(
        copy, params,
        "FrameParams: std140 in GLSL vs repr(C) in Rust"
    );
    drop((set, pipeline));
    assert_no_validation_messages(&ctx);
}
