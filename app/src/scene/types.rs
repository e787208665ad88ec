//! Runtime scene description handed to the renderer. Plain data: file parsing lives in
//! `file.rs`, checks in `validate.rs`. Conventions: right-handed, y up, metres-free units,
//! shutter time t in [0, 1].

use glam::Vec3;

#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub name: String,
    pub camera: Camera,
    pub light: Light,
    /// Ambient term: outgoing radiance adds `ambient * albedo` everywhere, shadowed or not.
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// Triangle list: t0.len() == t1.len(), multiple of 3. Vertex i moves linearly from `t0[i]`
/// to `t1[i]` over the shutter t in `[0, 1]`. Front faces are counter-clockwise, i.e.
/// cross(b - a, c - a) is the outward normal.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    pub name: String,
    /// Diffuse reflectance per channel, in [0, 1].
    pub albedo: Vec3,
    /// True when the surface is watertight and consistently wound (may be used for culling
    /// or silhouette tricks); open surfaces such as ground planes are false.
    pub closed: bool,
    pub t0: Vec<Vec3>,
    pub t1: Vec<Vec3>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Full vertical field of view, degrees.
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
    /// The pose at t = 1 of a camera that moves during the shutter; `None`: still.
    pub t1: Option<CameraPose>,
}

/// A moving camera's pose at t = 1. Between the two ends its position, target and up each
/// move linearly and the camera looks from the position at the target ([`Camera::at`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPose {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
}

impl Camera {
    /// Whether the camera moves during the shutter (the scene file gave it a `t1`).
    pub fn moves(&self) -> bool {
        self.t1.is_some()
    }

    /// The still camera where this one is at shutter time `t`: position, target and up
    /// blended linearly (a pan, position and target carried together, keeps its orientation
    /// exactly). A still camera is returned as it is, so its arithmetic is untouched.
    pub fn at(&self, t: f32) -> Camera {
        let Some(end) = self.t1 else {
            return self.clone();
        };
        // a + (b - a) t rather than glam's lerp: an end equal to t = 0's stays bit for bit.
        let blend = |a: Vec3, b: Vec3| a + (b - a) * t;
        Camera {
            position: blend(self.position, end.position),
            target: blend(self.target, end.target),
            up: blend(self.up, end.up),
            t1: None,
            ..*self
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Light {
    Spot(SpotLight),
    Directional(DirectionalLight),
}

/// A point light with a hard cone. cone_angle_deg is the HALF angle of the cone
/// (0 < a <= 89). intensity: radiant intensity in W/sr, so a surface at distance d whose
/// normal makes angle theta with the light direction gets radiance
/// albedo/pi * intensity * cos(theta) / d^2 (times visibility).
/// `direction` is unit length in scenes built by this module; hand-built scenes only need
/// it non-zero. near/far bound the shadow map's perspective depth range.
#[derive(Debug, Clone, PartialEq)]
pub struct SpotLight {
    pub position: Vec3,
    pub direction: Vec3,
    pub cone_angle_deg: f32,
    pub intensity: f32,
    pub near: f32,
    pub far: f32,
    /// The pose at t = 1 of a light that moves during the shutter; `None`: still.
    pub t1: Option<SpotPose>,
}

/// A moving spot light's pose at t = 1: it moves linearly from its t = 0 position and its
/// direction is the normalised blend of the two (`LightView::moving_to`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpotPose {
    pub position: Vec3,
    pub direction: Vec3,
}

/// Parallel light travelling along `direction`; `irradiance` in W/m^2 on a surface facing
/// it, so radiance = albedo/pi * irradiance * cos(theta) (times visibility).
///
/// Shadow map: the light "eye" sits at `eye() = center - direction * distance` and looks
/// along `direction`; the orthographic box spans [-half_extent, half_extent] on both axes
/// across the direction and depths [near, far] measured from the eye along `direction`.
/// So `center` is at depth `distance`, and near < distance < far keeps it inside.
#[derive(Debug, Clone, PartialEq)]
pub struct DirectionalLight {
    pub direction: Vec3,
    pub irradiance: f32,
    pub center: Vec3,
    pub half_extent: f32,
    pub distance: f32,
    pub near: f32,
    pub far: f32,
    /// The pose at t = 1 of a light that turns (or whose shadow box moves) during the
    /// shutter; `None`: still.
    pub t1: Option<DirectionalPose>,
}

/// A moving directional light's pose at t = 1: its direction (the normalised blend of the
/// two between) and its shadow box's centre (linear between).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DirectionalPose {
    pub direction: Vec3,
    pub center: Vec3,
}

impl DirectionalLight {
    /// Where the orthographic shadow camera sits (see the type's documentation).
    pub fn eye(&self) -> Vec3 {
        self.center - self.direction.normalize_or_zero() * self.distance
    }

    /// Where it sits at t = 1 (the same point for a still light).
    pub fn eye_t1(&self) -> Vec3 {
        match &self.t1 {
            None => self.eye(),
            Some(end) => end.center - end.direction.normalize_or_zero() * self.distance,
        }
    }
}

impl Light {
    /// Whether the light moves during the shutter (the scene file gave it a `t1`).
    pub fn moves(&self) -> bool {
        match self {
            Light::Spot(s) => s.t1.is_some(),
            Light::Directional(d) => d.t1.is_some(),
        }
    }
}

#[cfg(test)]
impl Camera {
    /// Where `p` lands on screen, in NDC of a square image (the narrowest aspect a built-in
    /// scene should frame for); asserts it lies between the near and far planes.
    pub(crate) fn ndc_unit_aspect(&self, p: Vec3) -> glam::Vec2 {
        let forward = (self.target - self.position).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let tan_half = (self.fov_y_deg.to_radians() * 0.5).tan();
        let rel = p - self.position;
        let depth = rel.dot(forward);
        assert!(
            depth > self.near && depth < self.far,
            "{p} is outside the depth range"
        );
        glam::Vec2::new(rel.dot(right), rel.dot(up)) / (depth * tan_half)
    }
}

impl Mesh {
    pub fn triangle_count(&self) -> usize {
        self.t0.len() / 3
    }
}

impl Scene {
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(Mesh::triangle_count).sum()
    }

    /// Axis-aligned bounds (min, max) over all t0 and t1 positions, i.e. over the whole
    /// shutter (linear motion stays inside). A scene without vertices gives (0, 0), so no
    /// infinities reach camera or shadow-map fitting.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut points = self
            .meshes
            .iter()
            .flat_map(|m| m.t0.iter().chain(m.t1.iter()));
        let Some(&first) = points.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        points.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }
}
