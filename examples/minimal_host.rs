//! The smallest host engine: read this first. It owns its Vulkan instance, device, queue,
//! command buffer and fence; the library records into that command buffer. One frame: a
//! square moves 2 units along +x over the shutter under a light shining straight down, the
//! library builds the temporal shadow map, and the host's own compute shader (GLSL that
//! includes `motion_shadows.glsl`) asks `ms_lit_fraction` how long each ground point is lit.
//! The answers are checked against the closed form, and the validation layer (with
//! synchronization validation) must stay silent.
//!
//! `cargo run --example minimal_host`. The whole engine is `examples/deferred_host/`.

use ash::vk;
use glam::{Vec3, Vec4};
// The host's own probe runs on the library's small Vulkan helpers (any pipeline code would do).
use motion_shadows::research::gpu::{
    Access, Buffer, BufferUsage, Spirv, compute_pipeline, memory_barrier,
};
use motion_shadows::{
    Context, CpuGeometry, DeviceRequirements, GLSL_INCLUDE, Light, LightShadow, Mesh,
    PositionStream, ShadowSettings, ash, glam,
};
use std::ffi::c_void;
use std::sync::Mutex;
// Links shaderc (used to compile the host's shader) where the distribution's libshaderc.so
// cannot be linked as it is (Debian 12); see build-support/shaderc-link.
use motion_shadows_shaderc_link as _;

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

/// The host's shader: one ground point per invocation, its lit fraction of the shutter.
const PROBE: &str = r#"#version 450
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#include "motion_shadows.glsl"
layout(local_size_x = 64) in;
layout(buffer_reference, std430) readonly buffer Points { vec4 p[]; };
layout(buffer_reference, std430) writeonly buffer Lit { float v[]; };
layout(push_constant) uniform Push { uint64_t map; uint64_t points; uint64_t lit; uint count; } pc;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    vec3 p = Points(pc.points).p[i].xyz;
    Lit(pc.lit).v[i] = ms_lit_fraction(MsShadowMap(pc.map), p, vec3(0, 1, 0), MS_NO_TRIANGLE);
}
"#;

/// The probe's push constants (`Push` in PROBE, padded to 8 bytes).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    map: u64,
    points: u64,
    lit: u64,
    count: u32,
    pad: u32,
}

/// The caster: a square of side `SIDE` at height 2, from x = X0 at t = 0 to X0 + TRAVEL.
const SIDE: f32 = 1.0;
const X0: f32 = -1.5;
const TRAVEL: f32 = 2.0;
const SHADOW: u32 = 256;

/// Every warning and error of the validation layer.
static MESSAGES: Mutex<Vec<String>> = Mutex::new(Vec::new());

unsafe extern "system" fn on_message(
    _severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data.
    let text = unsafe { (*data).message_as_c_str() }.map(|m| m.to_string_lossy().into_owned());
    MESSAGES.lock().unwrap().push(text.unwrap_or_default());
    vk::FALSE
}

/// What the host made, destroyed in reverse order by Drop.
struct Host {
    _entry: ash::Entry,
    instance: ash::Instance,
    debug: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    physical: vk::PhysicalDevice,
    device: ash::Device,
    family: u32,
    queue: vk::Queue,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    requirements: DeviceRequirements,
}

impl Host {
    fn new() -> Result<Self> {
        // SAFETY: loading the Vulkan loader runs its initialization; `entry` is kept in Host, so
        // the library stays loaded while the instance lives.
        let entry = unsafe { ash::Entry::load() }?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let extensions = [ash::ext::debug_utils::NAME.as_ptr()];
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions)
            .push_next(&mut features);
        // SAFETY: `info` and what it points at (application info, layer and extension names,
        // validation features) are locals alive for the call.
        let instance = unsafe { entry.create_instance(&info, None) }?;
        let debug = ash::ext::debug_utils::Instance::new(&entry, &instance);
        let messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_message));
        // SAFETY: the instance has debug utils enabled (the extension above), and `on_message`
        // touches only the static MESSAGES; `messenger_info` lives through the call.
        let messenger = unsafe { debug.create_debug_utils_messenger(&messenger_info, None) }?;
        // The first device with a graphics+compute queue and what the library needs.
        let mut chosen = None;
        // SAFETY: `instance` is live.
        for physical in unsafe { instance.enumerate_physical_devices() }? {
            // SAFETY: `physical` was just enumerated from `instance`.
            let families =
                unsafe { instance.get_physical_device_queue_family_properties(physical) };
            let family = families.iter().position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            });
            // SAFETY: `physical` is a device of `instance`, which supports Vulkan 1.3.
            let requirements = unsafe { DeviceRequirements::for_device(&instance, physical) };
            if let (Some(family), Ok(requirements)) = (family, requirements) {
                chosen = Some((physical, family as u32, requirements));
                break;
            }
        }
        let (physical, family, mut requirements) = chosen.ok_or("no suitable Vulkan device")?;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let extensions = requirements.extension_names();
        let info = requirements.chain(
            vk::DeviceCreateInfo::default()
                .queue_create_infos(&queues)
                .enabled_extension_names(&extensions),
        );
        // SAFETY: `physical` belongs to `instance` and supports every feature the requirements
        // chain (DeviceRequirements::for_device checked it); `info` and what it points at are
        // locals alive for the call.
        let device = unsafe { instance.create_device(physical, &info, None) }?;
        // SAFETY: the device was created just above with one queue of `family`.
        let queue = unsafe { device.get_device_queue(family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(family);
        // SAFETY: `family` is a queue family the device was created with.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .command_buffer_count(1);
        // SAFETY: `pool` was just made on this device; one primary buffer.
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }?[0];
        // SAFETY: creating an unsignalled fence on the live device has no precondition.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }?;
        Ok(Self {
            _entry: entry,
            instance,
            debug,
            messenger,
            physical,
            device,
            family,
            queue,
            pool,
            cmd,
            fence,
            requirements,
        })
    }

    /// Records `record` into the host's command buffer, submits it and waits for its fence.
    fn submit_and_wait(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<()> {
        let d = &self.device;
        // SAFETY: the previous submission (if any) was waited for, so nothing from the pool is
        // pending; one thread uses the host.
        unsafe {
            d.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty())?;
            d.reset_fences(&[self.fence])?;
            d.begin_command_buffer(self.cmd, &vk::CommandBufferBeginInfo::default())?;
        }
        let recorded = record(self.cmd);
        // SAFETY: `record` received only the handle and recorded into it; it is still in the
        // recording state.
        unsafe { d.end_command_buffer(self.cmd) }?;
        recorded?;
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = [vk::SubmitInfo2::default().command_buffer_infos(&cmds)];
        // SAFETY: the command buffer was ended, the fence reset above, and the queue is used by
        // this thread only; the wait keeps everything the recording used alive until the GPU is
        // done.
        unsafe {
            d.queue_submit2(self.queue, &submit, self.fence)?;
            d.wait_for_fences(&[self.fence], true, u64::MAX)?;
        }
        Ok(())
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: the context (and every library object) was dropped before the host (`run` drops
        // `ctx` first), and waiting idle means nothing is pending; children go before their device,
        // the device and messenger before the instance.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.debug
                .destroy_debug_utils_messenger(self.messenger, None);
            self.instance.destroy_instance(None);
        }
    }
}

/// The exact lit fraction of ground point `x` (its z inside the square's): the part of the
/// shutter the square's shadow, [X0 + TRAVEL t, X0 + TRAVEL t + SIDE], does not cover it.
fn closed_form(x: f32) -> f32 {
    let enters = ((x - X0 - SIDE) / TRAVEL).clamp(0.0, 1.0);
    let leaves = ((x - X0) / TRAVEL).clamp(0.0, 1.0);
    1.0 - (leaves - enters)
}

/// Compiles the probe with the library's header.
fn compile_probe() -> Result<Vec<u8>> {
    let compiler = shaderc::Compiler::new()?;
    let mut options = shaderc::CompileOptions::new()?;
    options.set_target_env(
        shaderc::TargetEnv::Vulkan,
        shaderc::EnvVersion::Vulkan1_2 as u32,
    );
    options.set_include_callback(|name, _, _, _| match name {
        "motion_shadows.glsl" => Ok(shaderc::ResolvedInclude {
            resolved_name: name.into(),
            content: GLSL_INCLUDE.into(),
        }),
        other => Err(format!("no header {other}")),
    });
    let kind = shaderc::ShaderKind::Compute;
    let spirv = compiler.compile_into_spirv(PROBE, kind, "probe.comp", "main", Some(&options))?;
    Ok(spirv.as_binary_u8().to_vec())
}

/// What one run found.
pub struct Outcome {
    /// Ground points checked against the closed form, and the largest difference.
    pub checked: usize,
    pub worst: f32,
    /// The lit fractions along the row z = 0.5, for the eye.
    pub row: Vec<f32>,
}

/// Renders one frame and checks it.
pub fn run() -> Result<Outcome> {
    let host = Host::new()?;
    // SAFETY: the device was made from `physical` of `instance` with the requirements'
    // features and a graphics+compute queue of `family`; `host` outlives `ctx` (dropped
    // first, below); nothing is pending when the context goes (each frame is waited for).
    let ctx = unsafe {
        Context::from_raw(
            &host.instance,
            host.physical,
            host.device.clone(),
            host.family,
            host.queue,
            &host.requirements.features,
        )
    }?;
    let outcome = frame(&host, &ctx);
    drop(ctx);
    let messages = std::mem::take(&mut *MESSAGES.lock().unwrap());
    drop(host);
    let outcome = outcome?;
    let late = MESSAGES.lock().unwrap().len();
    if !messages.is_empty() || late > 0 {
        return Err(format!("validation reported:\n{}", messages.join("\n")).into());
    }
    Ok(outcome)
}

fn frame(host: &Host, ctx: &Context) -> Result<Outcome> {
    // The caster's corners at t = 0 (w = 1) and t = 1, interleaved (stride 32). An engine
    // passes its own buffers' device addresses (`PositionStream::from_device_address`).
    let (xs, zs) = (
        [0.0, SIDE, SIDE, 0.0, SIDE, 0.0],
        [0.0, 0.0, SIDE, 0.0, SIDE, SIDE],
    );
    let at = |dx: f32| -> Vec<Vec3> {
        let corner = |(x, z): (&f32, &f32)| Vec3::new(X0 + dx + x, 2.0, *z);
        xs.iter().zip(&zs).map(corner).collect()
    };
    let (at0, at1) = (at(0.0), at(TRAVEL));
    let vertices: Vec<[Vec4; 2]> = at0
        .iter()
        .zip(&at1)
        .map(|(p, q)| [p.extend(1.0), q.extend(1.0)])
        .collect();
    let positions = Buffer::with_data(ctx, "square", BufferUsage::HostToDevice, &vertices)?;
    // The mesh, described once: its GPU streams at both ends of the shutter and the host's
    // CPU copy, from which the shadow's room is reserved (a mesh only the GPU holds gives a
    // `MeshBound` instead).
    let square = Mesh::moving(
        PositionStream::from_buffer(&positions, 0, 32)?,
        PositionStream::from_buffer(&positions, 16, 32)?,
        6,
    )
    .cpu(CpuGeometry::moving(&at0, &at1));
    // Straight down, a map covering 8 x 8 units around the origin.
    let light = Light::directional(Vec3::NEG_Y, Vec3::ZERO, 4.0)
        .distance(10.0)
        .depth_range(0.1, 20.0);
    let settings = ShadowSettings {
        map_size: (SHADOW, SHADOW),
        frames_in_flight: 1,
        ..ShadowSettings::new(light)
    };
    let mut shadow = LightShadow::new(ctx, settings)?;
    // Ground points y = 0, x in [-2, 2), z in {0.5}: 64 of them; and their lit fractions.
    let points: Vec<[f32; 4]> = (0..64)
        .map(|i| [-2.0 + i as f32 / 16.0, 0.0, 0.5, 1.0])
        .collect();
    let queries = Buffer::with_data(ctx, "points", BufferUsage::HostToDevice, &points)?;
    let lit = Buffer::new(
        ctx,
        "lit",
        4 * points.len() as u64,
        BufferUsage::DeviceToHost,
    )?;
    let spirv = compile_probe()?;
    let push_bytes = std::mem::size_of::<Push>() as u32;
    // SAFETY: shaderc's SPIR-V for Vulkan 1.2 of PROBE: int64 and buffer references (which
    // the library requires), `Push` as push constants, no descriptor sets.
    let probe = compute_pipeline(ctx, push_bytes, "probe.comp", unsafe { Spirv::new(&spirv) })?;
    let device = &host.device;
    host.submit_and_wait(|cmd| unsafe {
        // SAFETY: the host's command buffer, recording, outside a render pass, on a
        // graphics+compute queue; every object outlives the wait.
        let frame = shadow.record_frame(ctx, cmd, 1, &[square], None)?;
        // The shadow leaves its map readable by every shader stage: no barrier needed here.
        probe.bind(device, cmd);
        let push = Push {
            map: frame.map_header,
            points: queries.device_address(),
            lit: lit.device_address(),
            count: points.len() as u32,
            pad: 0,
        };
        probe.push(device, cmd, &push); // the layout has 32 bytes: `Push`'s size
        device.cmd_dispatch(cmd, points.len().div_ceil(64) as u32, 1, 1);
        memory_barrier(device, cmd, Access::COMPUTE_RW, Access::HOST_READ);
        Ok(())
    })?;
    // SAFETY: the frame's fence has signalled.
    unsafe { ctx.collect(1) };
    // The frame's shadow is complete (room reserved from the mesh never runs out).
    shadow.finish_frame(ctx, 1)?;
    let row: Vec<f32> = lit.read(points.len())?;
    // Within a shadow-map texel (8 / 256 units, 1/64 of the shutter) of the square's edges
    // sweeping by, the texel decides; elsewhere the lit fraction is exact.
    let mut worst = 0.0f32;
    let mut checked = 0;
    for (p, &got) in points.iter().zip(&row) {
        let x = p[0];
        let near_edge = [X0, X0 + SIDE, X0 + TRAVEL, X0 + TRAVEL + SIDE]
            .iter()
            .any(|e| (x - e).abs() < 0.05);
        if !near_edge {
            worst = worst.max((got - closed_form(x)).abs());
            checked += 1;
        }
    }
    if worst > 0.05 {
        return Err(format!("lit fractions off the closed form by {worst}").into());
    }
    Ok(Outcome {
        checked,
        worst,
        row,
    })
}

fn main() -> Result<()> {
    let outcome = run()?;
    let shades: String = outcome
        .row
        .iter()
        .map(|&v| [' ', '.', ':', '#'][(v * 3.0).round() as usize])
        .collect();
    println!("lit along z = 0.5, x from -2 to 2: [{shades}]");
    println!(
        "{} points match the closed form (worst {:.4}); validation silent",
        outcome.checked, outcome.worst
    );
    Ok(())
}
