//! The light as an engine describes it: a descriptor with named settings and defaults, turned
//! into the passes' [`LightView`] for the map's size.

use glam::Vec3;

use crate::error::{Error, Result};
use crate::technique::{DEFAULT_DEPTH_BIAS, DEFAULT_NORMAL_OFFSET_TEXELS, LightView};

/// Spot or directional, with what only that kind has.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Spot {
        cone_half_angle_deg: f32,
    },
    Directional {
        center: Vec3,
        half_extent: f32,
        distance: f32,
    },
}

/// A light, described by name instead of by position in an argument list:
///
/// ```
/// # use motion_shadows::{Light, glam::Vec3};
/// let spot = Light::spot(Vec3::new(0.0, 8.0, 0.0), Vec3::NEG_Y)
///     .cone_half_angle(40.0)
///     .depth_range(0.5, 50.0);
/// let sun = Light::directional(Vec3::new(-0.3, -1.0, 0.2), Vec3::ZERO, 10.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    kind: Kind,
    position: Vec3,
    direction: Vec3,
    near: f32,
    far: f32,
    intensity: f32,
    normal_offset_texels: f32,
    depth_bias: f32,
    receiver_plane: bool,
    /// The pose at shutter close, for a light that moves.
    end: Option<(Vec3, Vec3)>,
}

impl Light {
    /// A spot light at `position` shining along `direction`: a 45-degree cone half angle,
    /// depths 0.1 to 100 from it, intensity 1 (change them with the methods below).
    pub fn spot(position: Vec3, direction: Vec3) -> Self {
        Self::new(
            Kind::Spot {
                cone_half_angle_deg: 45.0,
            },
            position,
            direction,
            0.1,
            100.0,
        )
    }

    /// A directional light along `direction` whose map covers a square of half-width
    /// `half_extent` around `center`, seen from `2 * half_extent` back along the light with
    /// depths 0 to `4 * half_extent` from there ([`Self::depth_range`] and
    /// [`Self::distance`] change them).
    pub fn directional(direction: Vec3, center: Vec3, half_extent: f32) -> Self {
        let kind = Kind::Directional {
            center,
            half_extent,
            distance: 2.0 * half_extent,
        };
        Self::new(kind, center, direction, 0.0, 4.0 * half_extent)
    }

    fn new(kind: Kind, position: Vec3, direction: Vec3, near: f32, far: f32) -> Self {
        Self {
            kind,
            position,
            direction,
            near,
            far,
            intensity: 1.0,
            normal_offset_texels: DEFAULT_NORMAL_OFFSET_TEXELS,
            depth_bias: DEFAULT_DEPTH_BIAS,
            receiver_plane: false,
            end: None,
        }
    }

    /// A spot light's cone half angle in degrees (ignored by nothing: refused for a
    /// directional light when the view is made).
    pub fn cone_half_angle(mut self, degrees: f32) -> Self {
        if let Kind::Spot {
            cone_half_angle_deg,
        } = &mut self.kind
        {
            *cone_half_angle_deg = degrees;
        } else {
            // Kept to be refused by `view`: a setting that does not apply is an error.
            self.kind = Kind::Spot {
                cone_half_angle_deg: f32::NAN,
            };
        }
        self
    }

    /// How far back along the light a directional light's view is seen from.
    pub fn distance(mut self, distance: f32) -> Self {
        if let Kind::Directional { distance: d, .. } = &mut self.kind {
            *d = distance;
        } else {
            self.kind = Kind::Directional {
                center: Vec3::NAN,
                half_extent: f32::NAN,
                distance,
            };
        }
        self
    }

    /// The depths the map holds, from the light (spot) or from the point the directional
    /// view is seen from.
    pub fn depth_range(self, near: f32, far: f32) -> Self {
        Self { near, far, ..self }
    }

    /// Radiant intensity (spot, W/sr) or irradiance (directional, W/m^2), for shading that
    /// reads it from the map's header.
    pub fn intensity(self, intensity: f32) -> Self {
        Self { intensity, ..self }
    }

    /// Receivers are tested this many shadow texels along their normal (default 1).
    pub fn normal_offset_texels(self, texels: f32) -> Self {
        Self {
            normal_offset_texels: texels,
            ..self
        }
    }

    /// Relative depth bias (default 1e-4).
    pub fn depth_bias(self, bias: f32) -> Self {
        Self {
            depth_bias: bias,
            ..self
        }
    }

    /// Test receivers at their tangent plane's depth (see [`LightView::receiver_plane`]).
    pub fn receiver_plane(self) -> Self {
        Self {
            receiver_plane: true,
            ..self
        }
    }

    /// The light moves during the shutter to `position` and `direction` at shutter close
    /// (see [`LightView::moving_to`]).
    pub fn moving_to(self, position: Vec3, direction: Vec3) -> Self {
        Self {
            end: Some((position, direction)),
            ..self
        }
    }

    /// The passes' view of this light for a map of `size` texels; errors name the setting
    /// that is out of range or does not apply.
    pub fn view(&self, size: (u32, u32)) -> Result<LightView> {
        let bad = |what: String| Err(Error::InvalidArgument(format!("Light: {what}")));
        if self.direction.length() == 0.0 || !self.direction.is_finite() {
            return bad(format!(
                "direction {} must be finite and non-zero",
                self.direction
            ));
        }
        if !(self.near >= 0.0 && self.far > self.near && self.far.is_finite()) {
            return bad(format!(
                "depth range {} to {}: want 0 <= near < far",
                self.near, self.far
            ));
        }
        let mut view = match self.kind {
            Kind::Spot {
                cone_half_angle_deg,
            } => {
                if !(cone_half_angle_deg > 0.0 && cone_half_angle_deg < 90.0) {
                    return bad(format!(
                        "cone half angle {cone_half_angle_deg} (a spot light's, in (0, 90) \
                         degrees; NaN: set on a directional light)"
                    ));
                }
                if self.near == 0.0 {
                    return bad("a spot light's near depth must be above 0".into());
                }
                LightView::spot(
                    self.position,
                    self.direction,
                    cone_half_angle_deg,
                    self.intensity,
                    self.near,
                    self.far,
                    size,
                )
            }
            Kind::Directional {
                center,
                half_extent,
                distance,
            } => {
                if !(half_extent > 0.0 && center.is_finite() && distance.is_finite()) {
                    return bad(format!(
                        "half extent {half_extent}, center {center}, distance {distance} (a \
                         directional light's; NaN: set on a spot light)"
                    ));
                }
                LightView::directional(
                    self.direction,
                    self.intensity,
                    center,
                    half_extent,
                    distance,
                    self.near,
                    self.far,
                    size,
                )
            }
        };
        view.normal_offset_texels = self.normal_offset_texels;
        view.depth_bias = self.depth_bias;
        view.receiver_plane = self.receiver_plane;
        match self.end {
            Some((position, direction)) => view.moving_to(position, direction),
            None => Ok(view),
        }
    }
}
