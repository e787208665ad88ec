//! The viewer's shading pass: the G-buffer and the library's mask to the 8-bit sRGB image the
//! window shows (`glsl/shade.comp`, compiled when the viewer starts, as an engine compiles
//! its own shaders). Per-triangle albedos are read by address from a buffer made once.

use crate::scene::Scene;
use anyhow::{Context as _, anyhow};
use ash::vk;
use glam::{Mat4, Vec4};
use motion_shadows::gpu::{
    Buffer, BufferUsage, Context, ImageBindingLayout, ImageBindings, Pipeline, Spirv,
    compute_pipeline_with_sets,
};
use motion_shadows::technique::{LightView, MaskInputs};
// Named so that rustc loads it and links its native arguments: Debian 12's libshaderc.so
// links only with them (build-support/shaderc-link).
use motion_shadows_shaderc_link as _;

const SHADE_GLSL: &str = include_str!("glsl/shade.comp");
/// The shader's workgroup side (`local_size_x`, `local_size_y`).
const GROUP: u32 = 8;
/// The output image's format (`rgba8` in the shader).
pub const OUTPUT_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The shader's push constants (`Push` in shade.comp): 128 bytes, the least any device
/// offers.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ShadePush {
    inv_view_proj: Mat4,
    light_position: Vec4,
    light_direction: Vec4,
    albedos: u64,
    overlay: u64,
    emission: f32,
    ambient: f32,
    exposure_scale: f32,
    /// Width | height << 15 of the overlay's grid (0 without one) | [`STOCHASTIC`] |
    /// [`SPLIT`].
    overlay_size: u32,
}

/// The push constants' flag: show the stochastic frame's radiance image.
const STOCHASTIC: u32 = 1 << 31;
/// The push constants' flag: the split view, the right half's lit shares from the split
/// image.
const SPLIT: u32 = 1 << 30;

/// What one frame's shading reads besides its images.
#[derive(Clone, Copy)]
pub struct ShadeFrame<'a> {
    /// The frame's light; a moving one shades where it is at `camera_time`, as the offline
    /// deferred frame shades it (`render::upload::light_at`).
    pub light: &'a LightView,
    /// The shutter time the G-buffer shows.
    pub camera_time: f32,
    pub inv_view_proj: Mat4,
    pub exposure: f32,
    /// The overlay's codes (device address) and grid size (`overlay.rs`), if shown.
    pub overlay: Option<(u64, (u32, u32))>,
    /// Show the radiance image (the stochastic frame) instead of shading the G-buffer.
    pub stochastic: bool,
    /// The split view: the right half's lit shares (R32F, storage, in GENERAL), the
    /// columns from `width / 2` on shaded with them.
    pub split_lit: Option<vk::ImageView>,
    /// The shaded image written (`OUTPUT_FORMAT`, storage, in GENERAL).
    pub output: vk::ImageView,
    /// The stochastic frame's radiance (RGBA32F, storage, in GENERAL; bound in every frame).
    pub radiance: vk::ImageView,
}

pub struct ShadePass {
    layout: ImageBindingLayout,
    pipeline: Pipeline,
    albedos: Buffer,
    /// What `albedos` holds.
    table: Vec<[u32; 4]>,
    ambient: f32,
}

/// `shade.comp`'s `Albedos`: the number of triangles (then three unused words), then the
/// albedo of every triangle by global id, mesh by mesh as the upload numbers them
/// (`render::upload::scene_draws`: `t0.len() / 3` ids a mesh, drawn or not).
fn albedo_table(scene: &Scene) -> anyhow::Result<Vec<[u32; 4]>> {
    let triangles: usize = scene.meshes.iter().map(|m| m.t0.len() / 3).sum();
    let count = u32::try_from(triangles).map_err(|_| {
        anyhow!("{triangles} triangles: more than the viewer's albedo table counts")
    })?;
    let albedos = scene.meshes.iter().flat_map(|mesh| {
        std::iter::repeat_n(
            mesh.albedo.extend(1.0).to_array().map(f32::to_bits),
            mesh.t0.len() / 3,
        )
    });
    Ok(std::iter::once([count, 0, 0, 0]).chain(albedos).collect())
}

/// Compiles `glsl/shade.comp` to SPIR-V.
fn compile() -> anyhow::Result<Vec<u8>> {
    let compiler = shaderc::Compiler::new().context("the shaderc compiler could not be created")?;
    let mut options =
        shaderc::CompileOptions::new().context("the shaderc options could not be created")?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        // 1.3 would emit LocalSizeId, which needs maintenance4 (not a library requirement).
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    let spirv = compiler
        .compile_into_spirv(
            SHADE_GLSL,
            shaderc::ShaderKind::Compute,
            "shade.comp",
            "main",
            Some(&options),
        )
        .context("compiling the viewer's shade.comp")?;
    Ok(spirv.as_binary_u8().to_vec())
}

impl ShadePass {
    /// The pipeline, and the albedo of every triangle of `scene` (by global id, mesh by mesh
    /// as the upload numbers them).
    pub fn new(ctx: &Context, scene: &Scene) -> anyhow::Result<Self> {
        let types = [
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            vk::DescriptorType::STORAGE_IMAGE,
            vk::DescriptorType::STORAGE_IMAGE,
            vk::DescriptorType::STORAGE_IMAGE,
            vk::DescriptorType::STORAGE_IMAGE,
        ];
        let layout = ImageBindingLayout::new(ctx, &types)?;
        let spirv = compile()?;
        let pipeline = compute_pipeline_with_sets(
            ctx,
            &[&layout],
            std::mem::size_of::<ShadePush>() as u32,
            "shade.comp",
            // SAFETY: shaderc's module for Vulkan 1.2, entry point `main`; it uses buffer
            // device addresses (a feature the library requires) and storage images of
            // declared formats; its push block is `ShadePush`, its bindings `types`.
            unsafe { Spirv::new(&spirv) },
        )?;
        let table = albedo_table(scene)?;
        let albedos = Buffer::with_data(ctx, "viewer albedos", BufferUsage::HostToDevice, &table)?;
        Ok(Self {
            layout,
            pipeline,
            albedos,
            table,
            ambient: scene.ambient,
        })
    }

    /// The albedos of `scene` posed anew: where its triangles or their albedos differ from
    /// the table's, a new table (true: an allocation; the old one is retired past the frames
    /// in flight that read it, never written while they may).
    pub fn set_scene(&mut self, ctx: &Context, scene: &Scene) -> anyhow::Result<bool> {
        let table = albedo_table(scene)?;
        self.ambient = scene.ambient;
        if table == self.table {
            return Ok(false);
        }
        self.albedos = Buffer::with_data(ctx, "viewer albedos", BufferUsage::HostToDevice, &table)?;
        self.table = table;
        Ok(true)
    }

    /// A descriptor set for one frame slot.
    pub fn bindings(&self) -> anyhow::Result<ImageBindings> {
        Ok(self.layout.allocate()?)
    }

    /// Records the shading of `inputs` (the mask pass's inputs: depth, normals, ids; its
    /// output the lit shares, in GENERAL), or of `frame.radiance` (the stochastic frame),
    /// into `frame.output`.
    ///
    /// # Safety
    /// `cmd` is recording, outside rendering, on a queue with compute; `bindings` was made by
    /// this pass and is not used by a pending command buffer; the G-buffer images are in
    /// `inputs`' layouts, written and made visible to compute sampled reads earlier in `cmd`;
    /// `inputs.output` (the lit shares), `frame.split_lit`, `frame.output` and `frame.radiance` are storage
    /// images of this device in GENERAL, earlier accesses ordered before compute reads and
    /// writes: the lit shares written by the mask passes (read unless `frame.stochastic`), the
    /// radiance by the lighting pass's output (read if `frame.stochastic`); the images stay
    /// alive until `cmd` completes.
    pub unsafe fn record(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        bindings: &mut ImageBindings,
        inputs: &MaskInputs,
        frame: ShadeFrame<'_>,
    ) -> anyhow::Result<()> {
        let normals = inputs
            .normals
            .ok_or_else(|| anyhow!("the viewer's G-buffer has normals"))?;
        let ids = inputs
            .ids
            .ok_or_else(|| anyhow!("the viewer's G-buffer has triangle ids"))?;
        let general = vk::ImageLayout::GENERAL;
        // SAFETY: the caller's contract: the set is not in use; the views are this device's,
        // of the usages the binding types need (sampled G-buffer images, storage images).
        unsafe {
            bindings.write(&[
                (inputs.depth, inputs.depth_layout),
                (normals.view, normals.layout),
                (ids.view, ids.layout),
                (inputs.output, general),
                (frame.output, general),
                (frame.radiance, general),
                // Without the split the lit shares again (bound, not read).
                (frame.split_lit.unwrap_or(inputs.output), general),
            ])
        };
        let (position, direction) = frame.light.pose_at(frame.camera_time);
        let gpu = LightView {
            position,
            direction,
            end: None,
            ..*frame.light
        }
        .gpu();
        let push = ShadePush {
            inv_view_proj: frame.inv_view_proj,
            light_position: gpu.position,
            light_direction: gpu.direction,
            albedos: self.albedos.device_address(),
            overlay: frame.overlay.map_or(0, |(address, _)| address),
            emission: gpu.emission.x,
            ambient: self.ambient,
            exposure_scale: frame.exposure.exp2(),
            overlay_size: frame.overlay.map_or(0, |(_, (w, h))| w | (h << 15))
                | if frame.stochastic { STOCHASTIC } else { 0 }
                | if frame.split_lit.is_some() { SPLIT } else { 0 },
        };
        let (width, height) = inputs.size;
        // SAFETY: the caller's contract: `cmd` is recording, outside rendering, on a compute
        // queue; the pipeline, its layout and the set (just written) are this pass's, and
        // `ShadePush` is the layout's push range (its size); the dispatch covers the images'
        // size, which the shader bounds-checks.
        unsafe {
            self.pipeline.bind(device, cmd);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.pipeline.layout(),
                0,
                &[bindings.raw()],
                &[],
            );
            self.pipeline.push(device, cmd, &push);
            device.cmd_dispatch(cmd, width.div_ceil(GROUP), height.div_ceil(GROUP), 1);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BuiltinOptions, builtin};

    /// The table's count is the ids the upload gives (the shader reads no albedo past it),
    /// and the albedo at each id is its mesh's: checked against the draws' own numbering
    /// (`first_id`, `albedo`), with a mesh of two corners (no triangle, no draw) among them.
    #[test]
    fn the_albedo_table_covers_every_triangle_id_and_no_more() {
        let mut scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
        let mut stub = scene.meshes[0].clone();
        stub.t0.truncate(2);
        stub.t1.truncate(2);
        stub.albedo = glam::Vec3::new(0.9, 0.1, 0.1);
        scene.meshes.insert(1, stub);
        scene.meshes[2].albedo = glam::Vec3::new(0.2, 0.7, 0.3);
        let table = albedo_table(&scene).unwrap();
        let ids: u32 = scene.meshes.iter().map(|m| m.t0.len() as u32 / 3).sum();
        assert_eq!(table[0][0], ids);
        assert_eq!(table.len() as u32, 1 + ids);
        for (mesh, first_id) in scene.meshes.iter().zip(first_ids(&scene)) {
            for id in first_id..first_id + mesh.t0.len() as u32 / 3 {
                let albedo = Vec4::from_array(table[1 + id as usize].map(f32::from_bits));
                assert_eq!(albedo, mesh.albedo.extend(1.0), "id {id}");
            }
        }
    }

    /// Each mesh's first triangle id as `render::upload::scene_draws` numbers them.
    fn first_ids(scene: &Scene) -> Vec<u32> {
        let mut next = 0;
        scene
            .meshes
            .iter()
            .map(|m| {
                let first = next;
                next += m.t0.len() as u32 / 3;
                first
            })
            .collect()
    }
}
