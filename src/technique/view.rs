//! The camera and the light as the passes see them: matrices and the few scalars the shaders
//! need, packed into [`GpuLight`] (in a shadow map's header) and [`CameraParams`] (in a
//! lighting target's header).

use super::gpu_types::{CameraParams, GpuLight};
use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
use glam::{Mat4, UVec4, Vec3, Vec4};

/// A perspective camera (right-handed view, Vulkan projection: z in [0, w], y down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraView {
    /// Eye position in the world.
    pub position: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// World -> view.
    pub view: Mat4,
    /// View -> clip.
    pub proj: Mat4,
    /// Near plane distance.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
    /// The camera's pose at shutter close when it moves during the shutter (default `None`:
    /// still, the fields above are its pose all shutter). Set it with
    /// [`CameraView::moving_to`], which documents the motion between the two poses.
    pub end: Option<super::camera_motion::CameraEnd>,
}

impl CameraView {
    /// A camera at `position` looking at `target`.
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
            end: None,
        }
    }
}

/// What the light is: a point light with a hard cone (spot) or a parallel light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// A point light with a hard cone.
    Spot {
        /// Cosine of the cone's half angle.
        cos_cone: f32,
        /// Radiant intensity in W/sr.
        intensity: f32,
    },
    /// A parallel light.
    Directional {
        /// Irradiance in W/m^2 on a surface facing the light.
        irradiance: f32,
    },
}

/// The light's view: the shadow map is rendered with `view` and `proj`, and looked up with
/// the receiver offset and depth bias below.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// Spot or directional, with its emission.
    pub kind: LightKind,
    /// Position (spot) or the point the orthographic view is seen from (directional).
    pub position: Vec3,
    /// Unit direction the light points in.
    pub direction: Vec3,
    /// World -> light view.
    pub view: Mat4,
    /// Light view -> clip.
    pub proj: Mat4,
    /// World size of one shadow texel: per unit depth (spot), or absolute (directional).
    pub texel: f32,
    /// A receiver is tested this many shadow texels along its normal (default 1), so that
    /// neighbouring triangles of one surface do not shadow it where the map is coarser than
    /// the image.
    pub normal_offset_texels: f32,
    /// Relative depth bias: a receiver at light depth d is tested at d * (1 - bias)
    /// (default 1e-4).
    pub depth_bias: f32,
    /// How the collection pass turns each moving triangle into fragments (default exact).
    pub prisms: PrismConstruction,
    /// Test a receiver at its tangent plane's depth at the texel's centre instead of at its
    /// own depth (receiver-plane depth): a planar receiver's neighbours stop shadowing it
    /// without a normal offset, which keeps contact shadows at grazing light. Default off;
    /// with it on, `normal_offset_texels` is usually 0. Applies to every map's lookup.
    pub receiver_plane: bool,
    /// Keep static draws' triangles in the temporal map's static layer (the nearest one per
    /// texel; with [`Lookup::Exact`], a list per texel of those whose shadow touches it)
    /// rather than as fragments and ranges in the lists (default on; used with the
    /// exact construction and no coverage map, see
    /// [`super::TemporalShadowMap::uses_static_layer`]). Off reproduces the papers' lists.
    pub static_layer: bool,
    /// Keep the static layer from an earlier frame instead of redrawing it (default off).
    /// With it on, the collection pass redraws the layer only when the map's last build was
    /// for another light view (view and projection) or other static draws (their
    /// [`super::Draw`] descriptions: streams, indices, transforms, counts, ids, in order),
    /// and otherwise draws only what moves. Turn it on only if the contents of your static
    /// draws' buffers do not change while their descriptions stay the same; otherwise call
    /// [`super::TemporalShadowMap::forget_static_layer`] when they do. A layer is kept only
    /// once the host has said the pass that drew it was submitted
    /// ([`super::TemporalShadowMap::static_layer_submitted`]).
    pub keep_static_layer: bool,
    /// What the map's ranges are for (default [`Lookup::DepthLine`], the papers' test).
    pub lookup: Lookup,
    /// The light's pose at shutter close when it moves during the shutter (default `None`:
    /// still, every field above is its pose all shutter). Set it with
    /// [`LightView::moving_to`], which documents the motion between the two poses.
    pub end: Option<super::light_motion::LightEnd>,
}

/// What a temporal shadow map's ranges answer, and so how the collection builds them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Lookup {
    /// The papers' test: each range's depth line against the receiver's depth (with the
    /// receiver offset and bias), per texel.
    #[default]
    DepthLine,
    /// The exact lookup (docs/src/exact-lookups.md): each range only names a triangle that
    /// may block some point of its texel during the shutter, and the lookup tests the
    /// receiver's shadow ray against the named triangles themselves (their corners at t = 0
    /// and t = 1, from triangle records the collection writes): no texels, no offset, no
    /// bias. The collection is conservative (every texel whose area a triangle's swept
    /// shadow touches gets a range over the whole shutter), so the static layer and pruning,
    /// decided at texel centres, are off: static triangles go into the lists. Wants the
    /// exact construction and no coverage map, and a map with triangle records
    /// ([`super::TemporalShadowMap::reserve_triangle_records`]). Read by the visibility mask
    /// (receivers still or moving) and by the lighting pass (each sample's ray at its time,
    /// `ms_visible_exact`; no shadow filter); `ms_visibility`/`ms_lit_fraction` read depth
    /// lines, which such a map does not hold.
    Exact,
}

/// How the collection pass finds, per shadow-map texel, when a moving triangle covers it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum PrismConstruction {
    /// Per texel, the covered times solved in closed form (where each edge passes the texel
    /// centre: a quadratic in t for linear vertex motion), from one footprint per triangle
    /// that the light's near and far planes do not clip. Exact for any linear vertex motion
    /// (rotation, hinges, deformation), static edges add no fragments, and casters between
    /// the light and its near plane keep their shadow.
    #[default]
    Exact,
    /// The papers' prism: caps at t = 0 and t = 1 and each side triangulated around its
    /// centre (t = 0.5). Exact only while edges translate; kept so both can be measured.
    Paper,
}

/// Default [`LightView::normal_offset_texels`].
pub const DEFAULT_NORMAL_OFFSET_TEXELS: f32 = 1.0;
/// Default [`LightView::depth_bias`].
pub const DEFAULT_DEPTH_BIAS: f32 = 1e-4;

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
            normal_offset_texels: DEFAULT_NORMAL_OFFSET_TEXELS,
            depth_bias: DEFAULT_DEPTH_BIAS,
            prisms: PrismConstruction::default(),
            static_layer: true,
            keep_static_layer: false,
            receiver_plane: false,
            lookup: Lookup::DepthLine,
            end: None,
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
            normal_offset_texels: DEFAULT_NORMAL_OFFSET_TEXELS,
            depth_bias: DEFAULT_DEPTH_BIAS,
            prisms: PrismConstruction::default(),
            static_layer: true,
            keep_static_layer: false,
            receiver_plane: false,
            lookup: Lookup::DepthLine,
            end: None,
        }
    }

    /// Whether the collection pass of a frame lit by this view, with or without a coverage
    /// map, keeps static draws in the static layer and stores each covered run of a moving
    /// triangle as its range at once (no node stored, nothing left for the generation pass):
    /// the exact construction with [`Self::static_layer`] and no coverage map (whose passes
    /// need every fragment). See [`super::TemporalShadowMap::collects_ranges`].
    /// With [`Lookup::Exact`] always (its collection stores ranges directly, see
    /// [`super::CollectionPass::record`] for what it needs).
    pub fn collects_ranges(&self, with_coverage_map: bool) -> bool {
        (self.static_layer || self.lookup == Lookup::Exact)
            && self.prisms == PrismConstruction::Exact
            && !with_coverage_map
    }

    /// Whether static draws go to the static layer rather than the lists: where the
    /// collection stores ranges directly ([`Self::collects_ranges`]). For the depth-line
    /// lookup the layer keeps the nearest static triangle at each texel centre; for the exact
    /// lookup, which needs every triangle near a texel named, it is a list per texel of the
    /// static triangles whose shadow touches it (the static name lists,
    /// [`super::TemporalShadowMap::static_name_capacity`]).
    /// A moving light has none: every triangle moves relative to it (still ones too), so
    /// every draw is collected as moving ([`Self::is_moving`]).
    pub fn uses_static_layer(&self, with_coverage_map: bool) -> bool {
        self.static_layer && self.collects_ranges(with_coverage_map) && !self.is_moving()
    }

    /// Whether it is a spot light (perspective map) rather than directional (orthographic).
    pub fn is_spot(&self) -> bool {
        matches!(self.kind, LightKind::Spot { .. })
    }

    /// The light as shaders read it.
    pub fn gpu(&self) -> GpuLight {
        let (w, emission, cos_cone) = match self.kind {
            LightKind::Spot {
                cos_cone,
                intensity,
            } => (1.0, intensity, cos_cone),
            LightKind::Directional { irradiance } => (0.0, irradiance, -1.0),
        };
        GpuLight {
            view: self.view,
            proj: self.proj,
            position: self.position.extend(w),
            direction: self.direction.extend(cos_cone),
            emission: Vec4::new(emission, if self.is_moving() { 1.0 } else { 0.0 }, 0.0, 0.0),
            bias: Vec4::new(
                self.normal_offset_texels,
                self.depth_bias,
                self.texel,
                if self.receiver_plane { 1.0 } else { 0.0 },
            ),
        }
    }
}

/// How the lighting pass turns a temporal shadow map into a sample's shadow term.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ShadowEstimator {
    /// The papers' test: shadowed or not at exactly the sample's time (noise over time,
    /// like every stochastic estimate).
    #[default]
    Sampled,
    /// For a sample on a triangle that does not move during the shutter, the exact fraction
    /// of the shutter its point sees the light (`ms_lit_fraction`): no time noise. Samples on
    /// moving triangles keep the per-sample test. Ordinary shadow maps (plain, TSM) ignore it.
    Analytic,
}

/// How the lighting pass reads a shadow map around a receiver.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ShadowFilter {
    /// The receiver's own texel: shadow edges are steps one texel wide.
    #[default]
    None,
    /// The 2x2 texels nearest to the receiver's projection, weighted by their overlap with
    /// a one-texel box centred on it (percentage-closer filtering; on the temporal map each
    /// texel's answer is its ranges' at the sample's time, or with the analytic estimator its
    /// exact lit fraction of the shutter): edges ramp over one texel. GLSL:
    /// `ms_visibility_filtered`, `ms_lit_fraction_filtered`. Applies to every map.
    Bilinear,
    /// [`Bilinear`](Self::Bilinear) averaged over the pixel's footprint on the receiver's
    /// tangent plane (a grid of up to 4x4 points, as many per axis as the footprint spans
    /// texels), centred on the pixel: with the analytic estimator, a static receiver's pixel
    /// gets its lit share of both its area and the shutter from one sample. GLSL:
    /// `ms_visibility_footprint`, `ms_lit_fraction_footprint`.
    Footprint,
}

/// How the library's own lighting pass samples the camera view and shades.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightingView {
    /// The camera.
    pub camera: CameraView,
    /// Seed of the samples' positions and times (same seed, same bytes).
    pub seed: u32,
    /// Constant ambient radiance factor (radiance += ambient * albedo).
    pub ambient: f32,
    /// How the shadow term of the temporal shadow map is estimated.
    pub estimator: ShadowEstimator,
    /// How the shadow maps are read around each receiver.
    pub filter: ShadowFilter,
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

impl CameraParams {
    /// The camera part of a lighting target's header (the buffer addresses are the
    /// target's own, filled in by it).
    pub fn new(view: &LightingView, image_size: (u32, u32), spp: u32) -> Self {
        let camera = &view.camera;
        let [ray00, ray_dx, ray_dy] = camera_ray_basis(camera, image_size);
        Self {
            view_proj: camera.proj * camera.view,
            position: camera.position.extend(camera.near),
            forward: camera.forward.extend(camera.far),
            ray00,
            ray_dx,
            ray_dy,
            image: UVec4::new(image_size.0, image_size.1, spp, view.seed),
            shading: Vec4::new(view.ambient, 0.0, 0.0, 0.0),
            ..Self::default()
        }
    }
}
