//! The camera and the light as the passes see them: matrices and the few scalars the shaders
//! need, packed into [`FrameParams`].

use super::gpu_types::FrameParams;
use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, UVec4, Vec3, Vec4};

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraView {
    pub position: Vec3,
    pub forward: Vec3,
    pub view: Mat4,
    pub proj: Mat4,
    pub near: f32,
    pub far: f32,
}

impl CameraView {
    pub fn perspective(
        position: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_deg: f32,
        aspect: f32,
        near: f32,
        far: f32,
    ) -> Self {
        Self {
            position,
            forward: (target - position).normalize(),
            view: look_at_mat4(position, target, up),
            proj: vulkan::perspective(fov_y_deg.to_radians(), aspect, near, far),
            near,
            far,
        }
    }
}

/// What the light is: a point light with a hard cone (spot) or a parallel light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// `cos_cone`: cosine of the cone's half angle; `intensity` in W/sr.
    Spot { cos_cone: f32, intensity: f32 },
    /// `irradiance` in W/m^2 on a surface facing the light.
    Directional { irradiance: f32 },
}

/// The light's view: the shadow map is rendered with `view` and `proj`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    pub kind: LightKind,
    pub position: Vec3,
    pub direction: Vec3,
    pub view: Mat4,
    pub proj: Mat4,
    /// World size of one shadow texel: per unit depth (spot), or absolute (directional).
    pub texel: f32,
}

fn up_for(direction: Vec3) -> Vec3 {
    if direction.normalize().dot(Vec3::Y).abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

impl LightView {
    /// A spot light whose square shadow map just contains its cone.
    pub fn spot(
        position: Vec3,
        direction: Vec3,
        cone_half_angle_deg: f32,
        intensity: f32,
        near: f32,
        far: f32,
        shadow_size: (u32, u32),
    ) -> Self {
        let direction = direction.normalize();
        let half = cone_half_angle_deg.to_radians();
        let aspect = shadow_size.0 as f32 / shadow_size.1 as f32;
        Self {
            kind: LightKind::Spot {
                cos_cone: half.cos(),
                intensity,
            },
            position,
            direction,
            view: look_at_mat4(position, position + direction, up_for(direction)),
            proj: vulkan::perspective(2.0 * half, aspect, near, far),
            texel: 2.0 * half.tan() / shadow_size.1 as f32,
        }
    }

    /// A directional light: an orthographic box of half-width `half_extent` around `center`,
    /// seen from `distance` back along the light, depths in [near, far] from there.
    #[allow(clippy::too_many_arguments)]
    pub fn directional(
        direction: Vec3,
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
        shadow_size: (u32, u32),
    ) -> Self {
        let direction = direction.normalize();
        let position = center - direction * distance;
        let aspect = shadow_size.0 as f32 / shadow_size.1 as f32;
        let (hx, hy) = (half_extent * aspect.max(1.0), half_extent / aspect.min(1.0));
        Self {
            kind: LightKind::Directional { irradiance },
            position,
            direction,
            view: look_at_mat4(position, center, up_for(direction)),
            proj: vulkan::orthographic(-hx, hx, -hy, hy, near, far),
            texel: 2.0 * hy / shadow_size.1 as f32,
        }
    }

    pub fn is_spot(&self) -> bool {
        matches!(self.kind, LightKind::Spot { .. })
    }
}

/// How the lighting pass samples and biases; see the README's shading model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameSettings {
    pub image_size: (u32, u32),
    pub shadow_size: (u32, u32),
    pub spp: u32,
    pub seed: u32,
    /// Constant ambient radiance factor (radiance += ambient * albedo).
    pub ambient: f32,
    /// Receiver offset along its normal, in shadow texels.
    pub normal_offset_texels: f32,
    /// Relative depth bias: a receiver at depth d is tested at d * (1 - bias).
    pub depth_bias: f32,
}

impl FrameSettings {
    pub fn new(image_size: (u32, u32), shadow_size: (u32, u32), spp: u32, seed: u32) -> Self {
        Self {
            image_size,
            shadow_size,
            spp,
            seed,
            ambient: 0.0,
            normal_offset_texels: 1.0,
            depth_bias: 1e-4,
        }
    }
}

/// Camera ray directions as an affine function of the pixel position (see `camera_ray` in
/// shared.glsl): the ray through pixel position (x, y) is `ray00 + x * dx + y * dy`.
fn camera_ray_basis(camera: &CameraView, image_size: (u32, u32)) -> [Vec4; 3] {
    let to_world = camera.view.inverse();
    let right = to_world.x_axis.truncate();
    let up = to_world.y_axis.truncate();
    let forward = -to_world.z_axis.truncate();
    // Vulkan projection: x_ndc = x_view / (aspect tan), y_ndc = -y_view / tan at unit depth.
    let half_w = 1.0 / camera.proj.x_axis.x;
    let half_h = 1.0 / camera.proj.y_axis.y.abs();
    let ray00 = forward - half_w * right + half_h * up;
    let dx = right * (2.0 * half_w / image_size.0 as f32);
    let dy = -up * (2.0 * half_h / image_size.1 as f32);
    [ray00.extend(0.0), dx.extend(0.0), dy.extend(0.0)]
}

impl FrameParams {
    pub fn new(camera: &CameraView, light: &LightView, settings: &FrameSettings) -> Self {
        let view_proj = camera.proj * camera.view;
        let [camera_ray00, camera_ray_dx, camera_ray_dy] =
            camera_ray_basis(camera, settings.image_size);
        let (light_w, light_value, cos_cone) = match light.kind {
            LightKind::Spot {
                cos_cone,
                intensity,
            } => (1.0, intensity, cos_cone),
            LightKind::Directional { irradiance } => (0.0, irradiance, -1.0),
        };
        Self {
            light_view: light.view,
            light_proj: light.proj,
            camera_view_proj: view_proj,
            camera_inv_view_proj: view_proj.inverse(),
            camera_position: camera.position.extend(camera.near),
            camera_forward: camera.forward.extend(camera.far),
            light_position: light.position.extend(light_w),
            light_direction: light.direction.extend(cos_cone),
            light_params: Vec4::new(
                light_value,
                settings.ambient,
                settings.normal_offset_texels,
                settings.depth_bias,
            ),
            light_texel: Vec4::new(light.texel, 0.0, 0.0, 0.0),
            camera_ray00,
            camera_ray_dx,
            camera_ray_dy,
            sizes: UVec4::new(
                settings.shadow_size.0,
                settings.shadow_size.1,
                settings.image_size.0,
                settings.image_size.1,
            ),
            sampling: UVec4::new(settings.spp, settings.seed, 0, 0),
        }
    }
}
