//! Shader modules and pipelines. The technique's own pipelines are compute or attachment-less
//! graphics (fragment shaders write storage buffers); the ordinary shadow maps are drawn as
//! anyone would draw them, depth-tested into attachments.
//! They take no descriptor sets: shaders reach every buffer by device address through their
//! push constants, so a pipeline never needs anything rewritten between frames.

use super::context::{Context, Shared};
use super::image_bindings::ImageBindingLayout;
use super::retire::{Doomed, Handle};
use crate::error::{Error, Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// SPIR-V that may be handed to Vulkan: a module of valid SPIR-V for the device is a valid
/// usage rule of `vkCreateShaderModule` and of pipeline creation, which the library cannot
/// check, so making one from bytes is `unsafe`. The library's own shaders
/// ([`crate::technique::shaders`]) are already `Spirv`.
///
/// ```compile_fail,E0133
/// # use motion_shadows::gpu::Spirv;
/// let bytes = [0u8; 8];
/// let spirv = Spirv::new(&bytes);
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Spirv<'a>(&'a [u8]);

impl<'a> Spirv<'a> {
    /// Bytes of a SPIR-V module.
    ///
    /// # Safety
    /// `bytes` is a valid SPIR-V module (as `spirv-val` for the Vulkan 1.3 environment would
    /// accept) that uses only capabilities and extensions the device has enabled, with an
    /// entry point `main` for each stage it is used as; its push-constant block fits in the
    /// bytes the pipeline's layout gives ([`pipeline_layout`]'s `push_bytes`), its
    /// descriptor bindings match the set layouts given with it, and its specialization
    /// constants (`constant_id = i`) are 32-bit scalars.
    pub const unsafe fn new(bytes: &'a [u8]) -> Self {
        Self(bytes)
    }

    /// The library's own SPIR-V, compiled from `glsl/` by build.rs.
    pub(crate) const fn trusted(bytes: &'a [u8]) -> Self {
        Self(bytes)
    }

    /// The bytes.
    pub fn bytes(&self) -> &'a [u8] {
        self.0
    }
}

/// A SPIR-V module, destroyed on drop.
pub struct ShaderModule {
    shared: Arc<Shared>,
    raw: vk::ShaderModule,
}

impl ShaderModule {
    /// A module of `spirv` (`name` only for error messages).
    pub fn new(ctx: &Context, name: &str, spirv: Spirv<'_>) -> Result<Self> {
        let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv.bytes()))
            .map_err(|e| Error::InvalidArgument(format!("SPIR-V of {name}: {e}")))?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is the SPIR-V that `Spirv` vouches for (its unsafe constructor's
        // contract, or the library's own build.rs output), read into aligned words; `info` borrows
        // it for the call only.
        let raw =
            unsafe { ctx.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        Ok(Self {
            shared: ctx.shared.clone(),
            raw,
        })
    }
    /// The module handle.
    pub fn raw(&self) -> vk::ShaderModule {
        self.raw
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: a shader module is needed only while pipelines are created from it, which borrow
        // it for those calls; this module is of this device and destroyed once.
        unsafe { self.shared.device.destroy_shader_module(self.raw, None) };
    }
}

/// A pipeline and its layout, destroyed together (retired: once no pending frame can use
/// them). The handles are private: a handle replaced from outside would be destroyed here.
pub struct Pipeline {
    shared: Arc<Shared>,
    raw: vk::Pipeline,
    layout: vk::PipelineLayout,
    bind_point: vk::PipelineBindPoint,
}

impl Drop for Pipeline {
    /// Retires the pipeline and its layout: destroyed once no pending frame can use them.
    fn drop(&mut self) {
        self.shared.retire(Doomed::handles(vec![
            Handle::Pipeline(self.raw),
            Handle::PipelineLayout(self.layout),
        ]));
    }
}

impl Pipeline {
    /// The pipeline.
    pub fn raw(&self) -> vk::Pipeline {
        self.raw
    }
    /// Its layout (push constants, and the set layouts it was made with).
    pub fn layout(&self) -> vk::PipelineLayout {
        self.layout
    }
    /// Graphics or compute.
    pub fn bind_point(&self) -> vk::PipelineBindPoint {
        self.bind_point
    }

    /// Binds the pipeline.
    ///
    /// # Safety
    /// `device` is the device the pipeline was made on, `cmd` one of its command buffers in
    /// the recording state, and the pipeline outlives every submission of `cmd`.
    pub unsafe fn bind(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: the caller's contract.
        unsafe { device.cmd_bind_pipeline(cmd, self.bind_point, self.raw) };
    }

    /// Pushes `constants` to every stage of the layout.
    ///
    /// # Safety
    /// As [`Self::bind`]; and the layout's push-constant range covers `size_of::<T>()` bytes
    /// (it was made by [`pipeline_layout`] with at least that many).
    pub unsafe fn push<T: bytemuck::Pod>(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        constants: &T,
    ) {
        let bytes = bytemuck::bytes_of(constants);
        // SAFETY: the caller's contract.
        unsafe { device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::ALL, 0, bytes) };
    }
}

/// A layout with no descriptor sets and `push_bytes` of push constants visible to all stages.
pub fn pipeline_layout(ctx: &Context, push_bytes: u32) -> Result<vk::PipelineLayout> {
    pipeline_layout_with_sets(ctx, &[], push_bytes)
}

/// A layout with the given descriptor set layouts (for passes that read a host's images,
/// which cannot be reached by address) and `push_bytes` of push constants for all stages.
/// The caller destroys the layout it returns.
pub fn pipeline_layout_with_sets(
    ctx: &Context,
    set_layouts: &[&ImageBindingLayout],
    push_bytes: u32,
) -> Result<vk::PipelineLayout> {
    layout_on(&ctx.shared, set_layouts, push_bytes)
}

fn layout_on(
    shared: &Shared,
    set_layouts: &[&ImageBindingLayout],
    push_bytes: u32,
) -> Result<vk::PipelineLayout> {
    let device = &shared.device;
    let limit = shared.max_push_constants_size;
    if push_bytes % 4 != 0 || push_bytes > limit {
        return Err(Error::InvalidArgument(format!(
            "{push_bytes} bytes of push constants: a multiple of 4 up to {limit} (the device's maxPushConstantsSize)"
        )));
    }
    let set_layouts: Vec<vk::DescriptorSetLayout> = set_layouts.iter().map(|l| l.raw()).collect();
    let ranges = [vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::ALL,
        offset: 0,
        size: push_bytes,
    }];
    let mut info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
    if push_bytes > 0 {
        info = info.push_constant_ranges(&ranges);
    }
    // SAFETY: `push_bytes` was checked against the device's limit and a multiple of 4 above, the
    // set layouts are live ImageBindingLayouts of this device borrowed for the call, and `info`
    // points at locals that outlive it.
    unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")
}

/// A compute pipeline of one SPIR-V module (entry point `main`).
pub fn compute_pipeline(
    ctx: &Context,
    push_bytes: u32,
    name: &str,
    spirv: Spirv<'_>,
) -> Result<Pipeline> {
    compute_pipeline_with_sets(ctx, &[], push_bytes, name, spirv)
}

/// A compute pipeline whose layout also has `set_layouts`.
pub fn compute_pipeline_with_sets(
    ctx: &Context,
    set_layouts: &[&ImageBindingLayout],
    push_bytes: u32,
    name: &str,
    spirv: Spirv<'_>,
) -> Result<Pipeline> {
    specialized_compute_pipeline(ctx, set_layouts, push_bytes, name, spirv, &[])
}

/// A compute pipeline whose specialization constants `constant_id = i` take `constants[i]`
/// (each a 32-bit scalar: `uint`, `int`, `float` bits, or `bool` as 0 or 1). Variants fixed
/// this way cost nothing at run time: the compiler folds them and drops the paths not taken.
pub fn specialized_compute_pipeline(
    ctx: &Context,
    set_layouts: &[&ImageBindingLayout],
    push_bytes: u32,
    name: &str,
    spirv: Spirv<'_>,
    constants: &[u32],
) -> Result<Pipeline> {
    let module = ShaderModule::new(ctx, name, spirv)?;
    compute_of_module(&ctx.shared, set_layouts, push_bytes, &module, constants)
}

/// A compute pipeline of `module` (entry point `main`) with its specialization constants
/// `constant_id = i` set to `constants[i]`.
pub(crate) fn compute_of_module(
    shared: &Arc<Shared>,
    set_layouts: &[&ImageBindingLayout],
    push_bytes: u32,
    module: &ShaderModule,
    constants: &[u32],
) -> Result<Pipeline> {
    let device = &shared.device;
    let entries: Vec<vk::SpecializationMapEntry> = (0..constants.len() as u32)
        .map(|i| vk::SpecializationMapEntry {
            constant_id: i,
            offset: 4 * i,
            size: 4,
        })
        .collect();
    let data: Vec<u8> = constants.iter().flat_map(|c| c.to_ne_bytes()).collect();
    let specialization = vk::SpecializationInfo::default()
        .map_entries(&entries)
        .data(&data);
    let layout = layout_on(shared, set_layouts, push_bytes)?;
    let mut stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.raw())
        .name(c"main");
    if !constants.is_empty() {
        stage = stage.specialization_info(&specialization);
    }
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    // SAFETY: `stage` names a module of this device (borrowed by the caller for the call) whose
    // SPIR-V `Spirv` vouches for, `layout` was made on this device with the push range and sets the
    // shader declares (Spirv's contract), and the specialization data lives through the call.
    let raw = unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    match raw {
        Ok(p) => Ok(Pipeline {
            shared: shared.clone(),
            raw: p[0],
            layout,
            bind_point: vk::PipelineBindPoint::COMPUTE,
        }),
        Err((_, result)) => {
            // SAFETY: pipeline creation failed, so no pipeline references `layout`, which was made
            // for it alone.
            unsafe { device.destroy_pipeline_layout(layout, None) };
            Err(Error::Vulkan {
                call: "vkCreateComputePipelines",
                result,
            })
        }
    }
}

/// The attachments a graphics pipeline renders to (none: fragment shaders write storage).
#[derive(Debug, Clone, Copy, Default)]
pub struct Attachments<'a> {
    /// A depth attachment of this format, tested LESS and written.
    pub depth: Option<vk::Format>,
    /// Colour attachments of these formats, written without blending.
    pub colors: &'a [vk::Format],
}

/// A graphics pipeline with no attachments: triangles in, fragment shader side effects out.
/// Viewport and scissor are dynamic; no culling, no depth test (the shaders do their own).
pub fn attachmentless_pipeline(
    ctx: &Context,
    push_bytes: u32,
    stages: &[(vk::ShaderStageFlags, &str, Spirv<'_>)],
) -> Result<Pipeline> {
    graphics_pipeline(ctx, push_bytes, stages, Attachments::default())
}

/// Refuses what pipeline creation would not accept: stages other than one vertex shader and
/// at most one geometry and one fragment shader, attachment formats the device cannot
/// render to.
fn check_graphics(
    ctx: &Context,
    stages: &[(vk::ShaderStageFlags, &str, Spirv<'_>)],
    attachments: Attachments<'_>,
) -> Result<()> {
    let count = |s| stages.iter().filter(|(stage, _, _)| *stage == s).count();
    let (vertex, geometry, fragment) = (
        count(vk::ShaderStageFlags::VERTEX),
        count(vk::ShaderStageFlags::GEOMETRY),
        count(vk::ShaderStageFlags::FRAGMENT),
    );
    if vertex != 1 || geometry > 1 || fragment > 1 || vertex + geometry + fragment != stages.len() {
        let names: Vec<_> = stages
            .iter()
            .map(|(s, n, _)| format!("{n} ({s:?})"))
            .collect();
        return Err(Error::InvalidArgument(format!(
            "a graphics pipeline takes one vertex shader and at most one geometry and one fragment shader, not {}",
            names.join(", ")
        )));
    }
    let formats = attachments
        .colors
        .iter()
        .map(|&f| (f, vk::FormatFeatureFlags::COLOR_ATTACHMENT))
        .chain(
            attachments
                .depth
                .map(|f| (f, vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)),
        );
    for (format, needed) in formats {
        if !ctx.format_features(format).contains(needed) {
            return Err(Error::InvalidArgument(format!(
                "the device cannot render to {format:?} ({needed:?})"
            )));
        }
    }
    Ok(())
}

/// A graphics pipeline drawing triangle lists into `attachments`, viewport and scissor
/// dynamic, no culling; `stages` may omit the fragment shader (depth-only rendering).
pub fn graphics_pipeline(
    ctx: &Context,
    push_bytes: u32,
    stages: &[(vk::ShaderStageFlags, &str, Spirv<'_>)],
    attachments: Attachments<'_>,
) -> Result<Pipeline> {
    check_graphics(ctx, stages, attachments)?;
    let modules = stages
        .iter()
        .map(|(_, name, spirv)| ShaderModule::new(ctx, name, *spirv))
        .collect::<Result<Vec<_>>>()?;
    let stage_infos: Vec<_> = stages
        .iter()
        .zip(&modules)
        .map(|((stage, _, _), m)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(*stage)
                .module(m.raw())
                .name(c"main")
        })
        .collect();
    let layout = pipeline_layout(ctx, push_bytes)?;
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let blend_states: Vec<_> = attachments
        .colors
        .iter()
        .map(|_| {
            vk::PipelineColorBlendAttachmentState::default()
                .color_write_mask(vk::ColorComponentFlags::RGBA)
        })
        .collect();
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_states);
    let depth_test = attachments.depth.is_some();
    let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(depth_test)
        .depth_write_enable(depth_test)
        .depth_compare_op(vk::CompareOp::LESS);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(attachments.colors)
        .depth_attachment_format(attachments.depth.unwrap_or(vk::Format::UNDEFINED));
    let info = [vk::GraphicsPipelineCreateInfo::default()
        .stages(&stage_infos)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth_stencil)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering)];
    // SAFETY: every state struct `info` points at is a local alive for the call, the stages'
    // modules are this device's and valid SPIR-V (Spirv), the attachment formats were checked
    // renderable above, and `layout` is this device's.
    let raw = unsafe {
        ctx.device()
            .create_graphics_pipelines(vk::PipelineCache::null(), &info, None)
    };
    match raw {
        Ok(p) => Ok(Pipeline {
            shared: ctx.shared.clone(),
            raw: p[0],
            layout,
            bind_point: vk::PipelineBindPoint::GRAPHICS,
        }),
        Err((_, result)) => {
            // SAFETY: pipeline creation failed, so no pipeline references `layout`, which was made
            // for it alone.
            unsafe { ctx.device().destroy_pipeline_layout(layout, None) };
            Err(Error::Vulkan {
                call: "vkCreateGraphicsPipelines",
                result,
            })
        }
    }
}

/// Begins attachment-less dynamic rendering over `width` x `height` with matching viewport.
///
/// # Safety
/// `cmd` is a command buffer of `device` in the recording state, outside a render pass (the
/// caller ends the rendering it begins with `cmd_end_rendering`).
pub unsafe fn begin_attachmentless(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    width: u32,
    height: u32,
) {
    // SAFETY: the caller's contract.
    unsafe { begin_rendering(device, cmd, width, height, None, None) };
}

/// Begins dynamic rendering over `width` x `height` with matching viewport, into `depth` (a
/// view in DEPTH_ATTACHMENT_OPTIMAL, cleared to the given depth) and `color` (a view of an
/// unsigned-integer format in COLOR_ATTACHMENT_OPTIMAL, cleared to the given value), each
/// stored at the end.
///
/// # Safety
/// As [`begin_attachmentless`]; the views are of `device`, in those layouts, with the
/// attachment usages, `width` x `height` or larger, and outlive the execution of `cmd`.
pub unsafe fn begin_rendering(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    width: u32,
    height: u32,
    depth: Option<(vk::ImageView, f32)>,
    color: Option<(vk::ImageView, u32)>,
) {
    let colors: Vec<_> = color.into_iter().collect();
    // SAFETY: the caller's contract.
    unsafe { begin_rendering_colors(device, cmd, width, height, depth, &colors) };
}

/// [`begin_rendering`] into any number of colour attachments, each cleared to the bits of its
/// value in every channel (0 is 0.0 in float formats).
///
/// # Safety
/// As [`begin_rendering`], for every view in `colors`.
pub unsafe fn begin_rendering_colors(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    width: u32,
    height: u32,
    depth: Option<(vk::ImageView, f32)>,
    colors: &[(vk::ImageView, u32)],
) {
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent: vk::Extent2D { width, height },
    };
    let depth_attachment = depth.map(|(view, clear)| {
        vk::RenderingAttachmentInfo::default()
            .image_view(view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: clear,
                    stencil: 0,
                },
            })
    });
    let color_attachments: Vec<_> = colors
        .iter()
        .map(|&(view, clear)| {
            vk::RenderingAttachmentInfo::default()
                .image_view(view)
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    color: vk::ClearColorValue { uint32: [clear; 4] },
                })
        })
        .collect();
    let mut info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color_attachments);
    if let Some(attachment) = depth_attachment.as_ref() {
        info = info.depth_attachment(attachment);
    }
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: width as f32,
        height: height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the caller's contract.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}
