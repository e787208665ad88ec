//! One sample's radiance, as glsl/resolve.comp shades it, with its shadow found by a ray.
//!
//! The shading is the GPU's, term for term (docs/scene-format.md): two-sided Lambert, the
//! normal turned toward the camera; no direct light where that normal faces away from the
//! light or (spot) where the point lies outside the cone; `albedo / pi * E * cos / d^2`
//! (d = 1 for a directional light); `ambient * albedo` everywhere. The light's numbers are
//! the ones the GPU shades with ([`LightView::gpu`]: the normalised direction, the cone's
//! cosine and the emission as f32), so the two differ only in visibility.
//!
//! Visibility is a shadow ray from the hit point at the sample's time to the light where it is
//! at that time (a moving light: [`ShadingLight::at`]), against every triangle at that same
//! time but the hit one, with no normal offset or depth bias:
//!  - spot: the segment to the light's position, whatever the shadow map's near and far
//!    planes (a caster nearer to the light than the map's near plane still casts its shadow);
//!  - directional: a ray against the light's direction to infinity. The GPU methods see only
//!    casters inside the shadow map's box and shadow no receiver outside it; the box is a
//!    setting of those methods, not of the light, so the truth ignores it and comparisons
//!    show what a too-small box loses.

use super::bvh::Bvh;
use super::intersect::Ray;
use super::triangles::Triangle;
use glam::DVec3;
use motion_shadows::technique::LightView;

/// The shadow ray starts and (spot) ends this share of its length away from its ends. The
/// hit point is computed in f64 (~1e-15 of the scene's size off its triangle's plane), so a
/// coplanar neighbour of the hit triangle is crossed at most ~1e-15 / sin(angle) of the way
/// out; 1e-7 keeps such self-hits out down to 1e-8 rad of grazing and loses no blocker
/// farther than 1 um from a receiver 10 units from the light.
pub const SHADOW_EPSILON: f64 = 1e-7;

/// The light as the GPU shades with it.
#[derive(Debug, Clone, Copy)]
pub struct ShadingLight {
    spot: bool,
    position: DVec3,
    /// Unit: the direction the light points (spot axis) or travels (directional).
    direction: DVec3,
    cos_cone: f64,
    emission: f64,
    /// Length scale of the directional shadow ray's epsilon (the scene's size).
    scale: f64,
    /// A moving light's position and unit direction at t = 1 (`position` and `direction`
    /// are then those at t = 0); `None`: still.
    end: Option<(DVec3, DVec3)>,
}

impl ShadingLight {
    pub fn new(light: &LightView, scene_scale: f64) -> Self {
        let gpu = light.gpu();
        Self {
            spot: gpu.position.w > 0.5,
            position: gpu.position.truncate().as_dvec3(),
            direction: gpu.direction.truncate().as_dvec3(),
            cos_cone: f64::from(gpu.direction.w),
            emission: f64::from(gpu.emission.x),
            scale: scene_scale.max(f64::MIN_POSITIVE),
            end: light
                .end
                .map(|end| (end.position.as_dvec3(), end.direction.as_dvec3())),
        }
    }

    /// This light moving during the shutter to `position` (spot) and `direction` at t = 1.
    /// For tests that ask [`super::shutter`] about bare geometry.
    pub fn moving_to(self, position: DVec3, direction: DVec3) -> Self {
        Self {
            end: Some((position, direction.normalize())),
            ..self
        }
    }

    /// The still light this one is at shutter time `t`: position linear, direction the
    /// normalised blend of the two ends (`LightView::moving_to`). A still light is returned
    /// as it is, so its arithmetic is exactly that of a light that never moves.
    pub fn at(&self, t: f64) -> Self {
        match self.end {
            None => *self,
            Some((position, direction)) => Self {
                position: self.position.lerp(position, t),
                // A direction that does not turn is kept as it is (normalising it again
                // could move its last bit), so a light that only translates, or does not
                // move at all, shades exactly as a still light.
                direction: if direction == self.direction {
                    direction
                } else {
                    self.direction.lerp(direction, t).normalize()
                },
                end: None,
                ..*self
            },
        }
    }

    /// The unit direction the light points (spot axis) or travels (directional) at t = 0.
    pub fn direction(&self) -> DVec3 {
        self.direction
    }

    /// The motion of a moving light over the shutter: the change of its position and of its
    /// (unnormalised, linearly blended) direction from t = 0 to t = 1; `None` when still.
    pub fn motion(&self) -> Option<(DVec3, DVec3)> {
        self.end
            .map(|(position, direction)| (position - self.position, direction - self.direction))
    }

    /// A light for shadow rays only (no cone, no emission): a spot light at `position`, or
    /// (`None`) a directional one travelling along `direction`, whose shadow ray's epsilon
    /// scales with `scene_scale`. For tests that ask [`super::shutter`] about bare geometry.
    pub fn for_shadows(position: Option<DVec3>, direction: DVec3, scene_scale: f64) -> Self {
        Self {
            spot: position.is_some(),
            position: position.unwrap_or(DVec3::ZERO),
            direction: direction.normalize(),
            cos_cone: -1.0,
            emission: 0.0,
            scale: scene_scale.max(f64::MIN_POSITIVE),
            end: None,
        }
    }

    /// The light's position if it is a spot light (directional lights have none).
    pub fn spot_position(&self) -> Option<DVec3> {
        self.spot.then_some(self.position)
    }

    /// The shadow ray from `p` and the range of its parameter that must be free of
    /// triangles for `p` to see the light (see the module's documentation).
    pub fn shadow_ray(&self, p: DVec3) -> (Ray, f64, f64) {
        if self.spot {
            let ray = Ray::new(p, self.position - p);
            (ray, SHADOW_EPSILON, 1.0 - SHADOW_EPSILON)
        } else {
            let ray = Ray::new(p, (-self.direction).normalize());
            (ray, SHADOW_EPSILON * self.scale, f64::INFINITY)
        }
    }
}

/// What shading a sample needs besides the hit.
pub struct Shading<'a> {
    pub bvh: &'a Bvh,
    pub light: ShadingLight,
    /// Per mesh: `albedo` and `ambient * albedo`.
    pub albedo: Vec<(DVec3, DVec3)>,
}

impl Shading<'_> {
    /// Radiance of a sample at time `t` whose camera ray `ray` hits `tri` at parameter `s`.
    pub fn radiance(&self, ray: &Ray, s: f64, tri: &Triangle, t: f64) -> DVec3 {
        let p = ray.origin + s * ray.dir;
        let (direct, ambient) = self.unshadowed(p, ray.dir, tri, t);
        match direct {
            Some(direct) if !self.occluded(p, t, tri.id) => direct + ambient,
            _ => ambient,
        }
    }

    /// The two terms of the radiance at `p` on `tri` at time `t`, seen along `view_dir`:
    /// the direct term as if nothing shadowed it (`None` where the light cannot reach it
    /// whatever the shadows: the normal faces away from the light, or the point is outside a
    /// spot's cone) and the ambient term. The deferred truth weights the direct term by a
    /// lit fraction instead of one shadow ray.
    pub fn unshadowed(
        &self,
        p: DVec3,
        view_dir: DVec3,
        tri: &Triangle,
        t: f64,
    ) -> (Option<DVec3>, DVec3) {
        let n = facing_normal(tri, t, view_dir);
        let (albedo, ambient) = self.albedo[tri.mesh as usize];
        let light = &self.light.at(t);
        let to_light = if light.spot {
            light.position - p
        } else {
            -light.direction
        };
        let dist2 = if light.spot {
            to_light.length_squared()
        } else {
            1.0
        };
        let l = to_light.normalize();
        let cos_theta = n.dot(l);
        if cos_theta <= 0.0 {
            return (None, ambient);
        }
        if light.spot && (-l).dot(light.direction) < light.cos_cone {
            return (None, ambient);
        }
        let direct = albedo / std::f64::consts::PI * light.emission * cos_theta / dist2;
        (Some(direct), ambient)
    }

    /// Whether a triangle other than the one with id `skip` blocks the light (where it is at
    /// time `t`) from `p` at time `t`.
    pub fn occluded(&self, p: DVec3, t: f64, skip: u32) -> bool {
        let (shadow, s_min, s_max) = self.light.at(t).shadow_ray(p);
        self.bvh.occluded(&shadow, t, s_min, s_max, skip)
    }
}

/// The unit normal of `tri` at time `t`, turned toward the viewer (two-sided shading).
pub fn facing_normal(tri: &Triangle, t: f64, view_dir: DVec3) -> DVec3 {
    let [a, b, c] = tri.at(t);
    let n = (b - a).cross(c - a).normalize();
    if n.dot(-view_dir) < 0.0 { -n } else { n }
}
