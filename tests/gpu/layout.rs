//! The Rust mirrors in `technique::gpu_types` and `technique::push_constants` have the
//! layouts of the GLSL structs (`glsl/motion_shadows.glsl`, `light_motion.glsl`,
//! `shared.glsl`): a probe shader (`tests/glsl/layout_probe.comp`) reads every struct the
//! host writes (headers, draw record, camera, push constants, the long-pixel list's header)
//! field by field and dumps the scalars, which must equal the host's fields in order; and it
//! writes known values through the structs shaders write (Node, MsRange, Counters).

use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::test_shader::compile_compute;
use glam::{Mat4, UVec4, Vec4};
use motion_shadows::gpu::{
    Access, Buffer, BufferUsage, OneShot, Spirv, compute_pipeline, memory_barrier,
};
use motion_shadows::technique::push_constants::{
    DrawPush, GBufferPush, LightingRasterPush, MapDrawPush, MapPush, MaskPush, PushBlock,
    RadiancePush, RasterCamera, RasterPush, ShadePush, TsmMaskPush,
};
use motion_shadows::technique::{
    CameraParams, Counters, DrawRecord, GpuLight, LongListHeader, Node, PlainMapHeader, Range,
    ShadowMapHeader,
};

/// SPIR-V of the probe, its `#include`s resolved from `glsl/` (and the generated constants).
fn probe_spirv() -> Vec<u8> {
    compile_compute(
        "layout_probe.comp",
        include_str!("../glsl/layout_probe.comp"),
    )
}

/// Distinct values for every field, so that a shifted field cannot pass.
struct Values(u32);

impl Values {
    fn f(&mut self) -> f32 {
        self.0 += 1;
        self.0 as f32 + 0.5
    }
    fn u(&mut self) -> u32 {
        self.0 += 1;
        1000 + self.0
    }
    fn a(&mut self) -> u64 {
        self.0 += 1;
        0x1234_5678_0000_0000 | self.0 as u64
    }
    fn v(&mut self) -> Vec4 {
        Vec4::new(self.f(), self.f(), self.f(), self.f())
    }
    fn uv(&mut self) -> UVec4 {
        UVec4::new(self.u(), self.u(), self.u(), self.u())
    }
    fn m(&mut self) -> Mat4 {
        Mat4::from_cols(self.v(), self.v(), self.v(), self.v())
    }
    fn draw(&mut self) -> DrawPush {
        DrawPush {
            draws: self.a(),
            draw_index: self.u(),
            draw_count: self.u(),
        }
    }
    fn f3(&mut self) -> [f32; 3] {
        [self.f(), self.f(), self.f()]
    }
    fn light(&mut self) -> GpuLight {
        GpuLight {
            view: self.m(),
            proj: self.m(),
            position: self.v(),
            direction: self.v(),
            emission: self.v(),
            bias: self.v(),
        }
    }
}

/// The host's side of the dump: the same scalars, field by field, in declaration order.
#[derive(Default)]
struct Dump(Vec<u32>);

impl Dump {
    fn f(&mut self, x: f32) {
        self.0.push(x.to_bits());
    }
    fn u(&mut self, x: u32) {
        self.0.push(x);
    }
    fn a(&mut self, x: u64) {
        self.0.push(x as u32);
        self.0.push((x >> 32) as u32);
    }
    fn v(&mut self, x: Vec4) {
        x.to_array().into_iter().for_each(|c| self.f(c));
    }
    fn uv(&mut self, x: UVec4) {
        x.to_array().into_iter().for_each(|c| self.u(c));
    }
    fn m(&mut self, x: Mat4) {
        x.to_cols_array().into_iter().for_each(|c| self.f(c));
    }
    fn draw(&mut self, d: &DrawPush) {
        self.a(d.draws);
        self.u(d.draw_index);
        self.u(d.draw_count);
    }
    fn light(&mut self, l: &GpuLight) {
        self.m(l.view);
        self.m(l.proj);
        self.v(l.position);
        self.v(l.direction);
        self.v(l.emission);
        self.v(l.bias);
    }
}

#[test]
fn shared_structs_match_glsl() {
    let ctx = context();
    let device = ctx.device();
    let spirv = probe_spirv();
    let pipeline = compute_pipeline(
        &ctx,
        MapPush::BYTES,
        "layout_probe.comp",
        // SAFETY: shaderc's SPIR-V of tests/glsl/layout_probe.comp for Vulkan 1.2, using what
        // the library's shaders use, push constants of MapPush's size, no sets.
        unsafe { Spirv::new(&spirv) },
    )
    .unwrap();

    let mut val = Values(0);
    let shadow = ShadowMapHeader {
        light: val.light(),
        size: val.uv(),
        range_heads: val.a(),
        ranges: val.a(),
        coverage: val.a(),
        cover_depth: val.a(),
        heads: val.a(),
        nodes: val.a(),
        counters: val.a(),
        long_pixels: val.a(),
        nearest: val.a(),
        static_nearest: val.a(),
        tiles: val.a(),
        list_ranges: val.a(),
        triangles: val.a(),
        static_names: val.a(),
        light_end: bytemuck::cast(std::array::from_fn::<Vec4, 10, _>(|_| val.v())),
    };
    let plain = PlainMapHeader {
        light: val.light(),
        size: val.uv(),
        depths: val.a(),
        ids: val.a(),
    };
    let draw = DrawRecord {
        positions0: val.a(),
        positions1: val.a(),
        indices: val.a(),
        stride0: val.u(),
        stride1: val.u(),
        index_kind: val.u(),
        vertex_count: val.u(),
        first_id: val.u(),
        triangle_count: val.u(),
        albedo_flags: val.v(),
        model0: [val.v(), val.v(), val.v()],
        model1: [val.v(), val.v(), val.v()],
    };
    let camera = CameraParams {
        view_proj: val.m(),
        position: val.v(),
        forward: val.v(),
        ray00: val.v(),
        ray_dx: val.v(),
        ray_dy: val.v(),
        image: val.uv(),
        shading: val.v(),
        visibility: val.a(),
        radiance: val.a(),
        counters: val.a(),
        camera_end: val.a(),
    };
    let map_draw = MapDrawPush {
        draw: val.draw(),
        map: val.a(),
        time: val.f(),
        flags: val.u(),
    };
    let raster = RasterPush {
        pass: LightingRasterPush {
            draw: val.draw(),
            visibility: val.a(),
            target: val.a(),
            first_sample: val.u(),
            sample_count: val.u(),
            time: val.f(),
            flags: val.u(),
        },
        camera: RasterCamera {
            origin: val.f3(),
            near: val.f(),
            far: val.f(),
            ray00: val.f3(),
            ray_dx: val.f3(),
            ray_dy: val.f3(),
            width: val.u(),
            spp: val.u(),
            seed: val.u(),
        },
        padding: 0,
    };
    let shade = ShadePush {
        draws: val.a(),
        shadow: val.a(),
        target: val.a(),
        draw_count: val.u(),
        first_sample: val.u(),
        time: val.f(),
        flags: val.u(),
    };
    let long_list = LongListHeader {
        count: val.u(),
        groups: [val.u(), val.u(), val.u()],
    };
    let mask = MaskPush {
        inv_view_proj: val.m(),
        map: val.a(),
        size: [val.u(), val.u()],
        background_depth: val.f(),
        flags: val.u(),
        over_budget: val.a(),
        loop_budget: val.u(),
        time: val.f(),
        queue: val.a(),
        round: val.u(),
        rounds: val.u(),
        capacity: val.u(),
        probe: val.u(),
    };
    let tsm_mask = TsmMaskPush {
        inv_view_proj: val.m(),
        light: val.a(),
        size: [val.u(), val.u()],
        background_depth: val.f(),
        flags: val.u(),
        map_size: [val.u(), val.u()],
        time: val.f(),
        maps: val.f(),
        inv_maps: val.f(),
        first_map: val.u(),
        batch: val.u(),
        reserved: [val.u(), 0, 0],
    };
    let gbuffer = GBufferPush {
        view_proj: val.m(),
        eye: val.v(),
        draws: val.a(),
        draw_index: val.u(),
        time: val.f(),
    };
    let radiance = RadiancePush {
        radiance: val.a(),
        size: [val.u(), val.u()],
    };

    let input = |name, data: &[u8]| {
        Buffer::with_data(&ctx, name, BufferUsage::HostToDevice, data).expect("input buffer")
    };
    fn bytes<T: Copy>(value: &T) -> Vec<u8> {
        // SAFETY: plain data.
        unsafe {
            std::slice::from_raw_parts(value as *const T as *const u8, std::mem::size_of::<T>())
        }
        .to_vec()
    }
    let shadow_in = input("shadow header", &bytes(&shadow));
    let plain_in = input("plain header", &bytes(&plain));
    let draw_in = input("draw record", &bytes(&draw));
    let camera_in = input("camera", &bytes(&camera));
    let map_draw_in = input("map draw push", &bytes(&map_draw));
    let raster_in = input("raster push", &bytes(&raster));
    let shade_in = input("shade push", &bytes(&shade));
    let long_list_in = input("long-pixel list header", &bytes(&long_list));
    let mask_in = input("mask push", &bytes(&mask));
    let tsm_mask_in = input("tsm mask push", &bytes(&tsm_mask));
    let gbuffer_in = input("g-buffer push", &bytes(&gbuffer));
    let radiance_in = input("radiance push", &bytes(&radiance));
    let out = |name, size| Buffer::new(&ctx, name, size, BufferUsage::Storage).unwrap();
    let dump = out("dump", 4096);
    let nodes = out("nodes", 32);
    let ranges = out("ranges", 48);
    let counters = out("counters", 48);
    let table: Vec<u64> = [
        &shadow_in,
        &plain_in,
        &draw_in,
        &camera_in,
        &dump,
        &nodes,
        &ranges,
        &counters,
        &map_draw_in,
        &raster_in,
        &shade_in,
        &long_list_in,
        &mask_in,
        &tsm_mask_in,
        &gbuffer_in,
        &radiance_in,
    ]
    .iter()
    .map(|b| b.device_address())
    .collect();
    let table_in = input(
        "probe table",
        &bytes(&<[u64; 16]>::try_from(table).unwrap()),
    );

    let push = MapPush {
        map: table_in.device_address(),
    };
    OneShot::new(&ctx)
        .unwrap()
        .run(|cmd| {
            // SAFETY: `cmd` is the OneShot's command buffer, recording outside rendering; the probe
            // pipeline is a compute pipeline of this context, alive through the run.
            unsafe { pipeline.bind(device, cmd) };
            // SAFETY: the probe's layout has MapPush's size as its push range (MapPush::BYTES).
            unsafe { pipeline.push(device, cmd, &push) };
            // SAFETY: the pipeline is bound and pushed; the probe reads the table of buffer
            // addresses, every buffer alive until the OneShot has waited.
            unsafe { device.cmd_dispatch(cmd, 1, 1, 1) };
            // SAFETY: outside rendering, on the context's compute queue.
            unsafe { memory_barrier(device, cmd, Access::COMPUTE_RW, Access::TRANSFER_READ) };
            Ok(())
        })
        .unwrap();

    let mut expected = Dump::default();
    expected.light(&shadow.light);
    expected.uv(shadow.size);
    for a in [
        shadow.range_heads,
        shadow.ranges,
        shadow.coverage,
        shadow.cover_depth,
        shadow.heads,
        shadow.nodes,
        shadow.counters,
        shadow.long_pixels,
        shadow.nearest,
        shadow.static_nearest,
        shadow.tiles,
        shadow.list_ranges,
        shadow.triangles,
        shadow.static_names,
    ] {
        expected.a(a);
    }
    let end: [Vec4; 10] = bytemuck::cast(shadow.light_end);
    end.iter().for_each(|&v| expected.v(v));
    expected.light(&plain.light);
    expected.uv(plain.size);
    expected.a(plain.depths);
    expected.a(plain.ids);
    let expect_draw = |expected: &mut Dump| {
        expected.a(draw.positions0);
        expected.a(draw.positions1);
        expected.a(draw.indices);
        for u in [
            draw.stride0,
            draw.stride1,
            draw.index_kind,
            draw.vertex_count,
            draw.first_id,
            draw.triangle_count,
        ] {
            expected.u(u);
        }
        expected.v(draw.albedo_flags);
        draw.model0
            .iter()
            .chain(&draw.model1)
            .for_each(|&r| expected.v(r));
    };
    expect_draw(&mut expected);
    let expect_camera = |expected: &mut Dump| {
        expected.m(camera.view_proj);
        for v in [
            camera.position,
            camera.forward,
            camera.ray00,
            camera.ray_dx,
            camera.ray_dy,
        ] {
            expected.v(v);
        }
        expected.uv(camera.image);
        expected.v(camera.shading);
        for a in [
            camera.visibility,
            camera.radiance,
            camera.counters,
            camera.camera_end,
        ] {
            expected.a(a);
        }
    };
    expect_camera(&mut expected);
    expected.a(push.map);
    expected.draw(&map_draw.draw);
    expected.a(map_draw.map);
    expected.f(map_draw.time);
    expected.u(map_draw.flags);
    let pass = &raster.pass;
    expected.draw(&pass.draw);
    expected.a(pass.visibility);
    expected.a(pass.target);
    expected.u(pass.first_sample);
    expected.u(pass.sample_count);
    expected.f(pass.time);
    expected.u(pass.flags);
    let cam = &raster.camera;
    cam.origin.iter().for_each(|&x| expected.f(x));
    expected.f(cam.near);
    expected.f(cam.far);
    for v in [cam.ray00, cam.ray_dx, cam.ray_dy] {
        v.iter().for_each(|&x| expected.f(x));
    }
    for u in [cam.width, cam.spp, cam.seed] {
        expected.u(u);
    }
    for a in [shade.draws, shade.shadow, shade.target] {
        expected.a(a);
    }
    expected.u(shade.draw_count);
    expected.u(shade.first_sample);
    expected.f(shade.time);
    expected.u(shade.flags);
    expected.u(long_list.count);
    long_list.groups.iter().for_each(|&g| expected.u(g));
    expected.m(mask.inv_view_proj);
    expected.a(mask.map);
    mask.size.iter().for_each(|&x| expected.u(x));
    expected.f(mask.background_depth);
    expected.u(mask.flags);
    expected.a(mask.over_budget);
    expected.u(mask.loop_budget);
    expected.f(mask.time);
    expected.a(mask.queue);
    expected.u(mask.round);
    expected.u(mask.rounds);
    expected.u(mask.capacity);
    expected.u(mask.probe);
    expected.m(tsm_mask.inv_view_proj);
    expected.a(tsm_mask.light);
    tsm_mask.size.iter().for_each(|&x| expected.u(x));
    expected.f(tsm_mask.background_depth);
    expected.u(tsm_mask.flags);
    tsm_mask.map_size.iter().for_each(|&x| expected.u(x));
    for x in [tsm_mask.time, tsm_mask.maps, tsm_mask.inv_maps] {
        expected.f(x);
    }
    expected.u(tsm_mask.first_map);
    expected.u(tsm_mask.batch);
    expected.u(tsm_mask.reserved[0]);
    expected.m(gbuffer.view_proj);
    expected.v(gbuffer.eye);
    expected.a(gbuffer.draws);
    expected.u(gbuffer.draw_index);
    expected.f(gbuffer.time);
    expected.a(radiance.radiance);
    radiance.size.iter().for_each(|&x| expected.u(x));
    // ms_load's copy of the header, read as 64-bit words.
    expected.light(&shadow.light);
    expected.uv(UVec4::new(shadow.size.x, shadow.size.y, 0, 0));
    for a in [
        shadow.range_heads,
        shadow.ranges,
        shadow.coverage,
        shadow.cover_depth,
        shadow.static_nearest,
        shadow.triangles,
    ] {
        expected.a(a);
    }
    // load_draw's copy of the draw record, read as 64-bit words.
    expect_draw(&mut expected);
    // load_camera's copy of the camera header, read as 64-bit words.
    expect_camera(&mut expected);
    // The node and the range the probe stored, read back through load_node and ms_range.
    for x in [1.5f32, 0.25] {
        expected.f(x);
    }
    expected.u(7);
    expected.u(9);
    for x in [0.125f32, 0.75, 2.5, 3.5] {
        expected.f(x);
    }
    expected.u(11);
    expected.u(13);

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
                // SAFETY: `staging` was made with exactly `bytes` and every caller passes at most
                // the size `b` was made with (dump 4096, nodes 32, ranges and counters 48); both
                // live until the OneShot has waited, and the probe's writes were made visible to
                // transfer reads by the barrier after its dispatch.
                unsafe { device.cmd_copy_buffer(cmd, b.raw(), staging.raw(), &region) };
                // SAFETY: outside rendering; host reads are a valid destination once the OneShot's
                // fence signals.
                unsafe { memory_barrier(device, cmd, Access::TRANSFER_WRITE, Access::HOST_READ) };
                Ok(())
            })
            .unwrap();
        staging.read::<u8>(bytes).unwrap()
    };
    let dumped: Vec<u32> = download(&dump, expected.0.len() * 4)
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let first_difference = dumped.iter().zip(&expected.0).position(|(a, b)| a != b);
    assert_eq!(
        first_difference,
        None,
        "GLSL read a field at another offset than Rust wrote it (scalar {first_difference:?} of the dump: shader {:?}, host {:?})",
        first_difference.map(|i| dumped[i]),
        first_difference.map(|i| expected.0[i]),
    );

    fn cast<T: Copy + Default>(bytes: &[u8], index: usize) -> T {
        let size = std::mem::size_of::<T>();
        let mut value = T::default();
        // SAFETY: the source is exactly `size` bytes (the slice is bounds-checked), the
        // destination a local T of that size, so they do not overlap; T is one of the
        // library's plain GPU records (Node, Range, Counters: u32 and f32 fields, no padding),
        // for which any bytes are a valid value.
        unsafe {
            std::ptr::copy_nonoverlapping(
                bytes[index * size..(index + 1) * size].as_ptr(),
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
    let c: Counters = cast(&download(&counters, 48), 0);
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
            invalid_triangles: 34,
            wrapped: 35,
            ranges_direct: 36,
            sorted_count: 37,
            static_names: 38,
        }
    );
    drop(pipeline);
    assert_no_validation_messages(&ctx);
}
