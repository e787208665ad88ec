//! The engine's pipelines, made once for all frames, and its GLSL (`glsl/`) compiled at run
//! time by shaderc for Vulkan 1.2 SPIR-V, as the book says.

use super::*;
use motion_shadows::research::gpu::{Attachments, ImageBindingLayout, Spirv};
use motion_shadows::research::gpu::{compute_pipeline_with_sets, graphics_pipeline};
// Links shaderc where the distribution's libshaderc.so cannot be linked as it is.
use motion_shadows_shaderc_link as _;

/// The G-buffer: depth, then normal, albedo, world motion and triangle id.
pub(super) const FORMATS: [vk::Format; 5] = [
    vk::Format::D32_SFLOAT,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R8G8B8A8_UNORM,
    vk::Format::R16G16B16A16_SFLOAT,
    vk::Format::R32_UINT,
];

/// `Draw` in glsl/gbuffer.vert (128 bytes): the frame's constants and the mesh's vertex
/// buffer by address, object to world at t = 1 and t = 0 (three rows each), the albedo, and
/// the mesh's first global triangle id (its shadow draw's).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct DrawConstants {
    pub(super) addresses: [u64; 2],
    pub(super) model: [Vec4; 3],
    pub(super) previous_model: [Vec4; 3],
    pub(super) albedo: Vec3,
    pub(super) first_id: u32,
}

/// `Frame` in glsl/frame.glsl (read by address): `info` = width, height, lights.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct FrameConstants {
    pub(super) view_proj: Mat4,
    pub(super) inv_view_proj: Mat4,
    pub(super) eye: Vec4,
    pub(super) info: UVec4,
    pub(super) ambient: Vec4,
}

/// The G-buffer's and the shading's pipelines; the shading's set holds depth, normal, albedo,
/// mask 0 and mask 1.
pub(super) struct Pipelines {
    pub(super) gbuffer: Pipeline,
    pub(super) shade: Pipeline,
    pub(super) shade_set: ImageBindingLayout,
}

impl Pipelines {
    pub(super) fn new(ctx: &Context) -> Result<Self> {
        use {shaderc::ShaderKind as K, vk::ShaderStageFlags as Stage};
        let vert = compile(
            "gbuffer.vert",
            include_str!("../../glsl/gbuffer.vert"),
            K::Vertex,
        )?;
        let frag = compile(
            "gbuffer.frag",
            include_str!("../../glsl/gbuffer.frag"),
            K::Fragment,
        )?;
        let comp = compile(
            "shade.comp",
            include_str!("../../glsl/shade.comp"),
            K::Compute,
        )?;
        let shade_set =
            ImageBindingLayout::new(ctx, &[vk::DescriptorType::COMBINED_IMAGE_SAMPLER; 5])?;
        // SAFETY: shaderc's SPIR-V of the engine's GLSL (entry points `main`), whose push
        // constants fit the layouts' bytes (DrawConstants; five addresses) and whose set is
        // `shade_set`'s five sampled images.
        let (vert, frag, comp) =
            unsafe { (Spirv::new(&vert), Spirv::new(&frag), Spirv::new(&comp)) };
        let stages = [
            (Stage::VERTEX, "gbuffer.vert", vert),
            (Stage::FRAGMENT, "gbuffer.frag", frag),
        ];
        let attachments = Attachments {
            depth: Some(FORMATS[0]),
            colors: &FORMATS[1..],
        };
        let push = size_of::<DrawConstants>() as u32;
        Ok(Pipelines {
            gbuffer: graphics_pipeline(ctx, push, &stages, attachments)?,
            shade: compute_pipeline_with_sets(ctx, &[&shade_set], 40, "shade.comp", comp)?,
            shade_set,
        })
    }
}

/// One stage as Vulkan 1.2 SPIR-V; `#include` serves the library's header (`GLSL_INCLUDE`)
/// and the engine's own `frame.glsl`.
fn compile(name: &str, source: &str, kind: shaderc::ShaderKind) -> Result<Vec<u8>> {
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_include_callback(|requested, _, _, _| {
        let content = match requested {
            "motion_shadows.glsl" => GLSL_INCLUDE,
            "frame.glsl" => include_str!("../../glsl/frame.glsl"),
            _ => return Err(format!("no header {requested}")),
        };
        Ok(shaderc::ResolvedInclude {
            resolved_name: requested.into(),
            content: content.into(),
        })
    });
    let compiler = shaderc::Compiler::new()?;
    let spirv = compiler.compile_into_spirv(source, kind, name, "main", Some(&options))?;
    Ok(spirv.as_binary_u8().into())
}
