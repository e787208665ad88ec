//! The shadow methods the viewer switches between, each the offline deferred frame's
//! (`render --frame deferred --method ...`): the temporal map read with the papers' depth
//! lines or with the exact lookup, TSM-N, and plain (one map at mid-shutter, TSM-1).

use crate::render::deferred::{
    DeferredMethod, DeferredSettings, deferred_light, still_pixels_plane,
};
use crate::render::upload::with_motion;
use crate::render::{Method, RenderSettings, forward_light};
use crate::scene::Scene;
use motion_shadows::technique::{LightView, Lookup};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViewMethod {
    Temporal,
    /// The temporal map read with the exact lookup.
    TemporalExact,
    /// `maps` depth maps at the strata's centres; 1 is the plain shadow map.
    Tsm {
        maps: u32,
    },
}

impl ViewMethod {
    /// The offline frame's name for it (`render --frame deferred` names its files so).
    pub fn name(&self) -> String {
        self.deferred(&DeferredSettings::default()).name()
    }

    /// The method after this one, the order the method key cycles through (TSM with
    /// `tsm_maps`).
    pub fn next(self, tsm_maps: u32) -> Self {
        match self {
            Self::Temporal => Self::TemporalExact,
            Self::TemporalExact => Self::Tsm { maps: tsm_maps },
            Self::Tsm { maps } if maps > 1 => Self::Tsm { maps: 1 },
            Self::Tsm { .. } => Self::Temporal,
        }
    }

    /// The split view's right-hand method after `right` (None: the split is off) with
    /// `self` on the left: every other method in the method key's order, then off again.
    pub fn next_split(self, right: Option<Self>, tsm_maps: u32) -> Option<Self> {
        let next = right.unwrap_or(self).next(tsm_maps);
        (next != self).then_some(next)
    }

    /// `base` with this method (and its lookup).
    pub fn deferred(&self, base: &DeferredSettings) -> DeferredSettings {
        let (method, lookup) = match *self {
            Self::Temporal => (DeferredMethod::Temporal, Lookup::DepthLine),
            Self::TemporalExact => (DeferredMethod::Temporal, Lookup::Exact),
            Self::Tsm { maps: 1 } => (DeferredMethod::Plain, Lookup::DepthLine),
            Self::Tsm { maps } => (DeferredMethod::Tsm { maps }, Lookup::DepthLine),
        };
        DeferredSettings {
            method,
            lookup,
            ..*base
        }
    }

    /// The light and the still pixels' plane test of this method's frame, as the offline
    /// frame sets them up (a moving light with its pose at t = 1). Errors where the scene's
    /// light cannot move so (it turns 90 degrees or more; the scene's validation refuses it
    /// first).
    pub fn light(
        &self,
        scene: &Scene,
        settings: &RenderSettings,
        base: &DeferredSettings,
    ) -> crate::error::Result<(LightView, bool)> {
        let deferred = self.deferred(base);
        Ok((
            with_motion(scene, deferred_light(scene, settings, &deferred))?,
            still_pixels_plane(settings, &deferred),
        ))
    }
}

impl ViewMethod {
    /// The stochastic frame's light (`render`'s forward frame of the temporal map, read with
    /// this method's lookup), its static layer kept from frame to frame; None for the TSM
    /// methods (the viewer's stochastic frame is the temporal map's).
    pub fn forward_light(&self, scene: &Scene, settings: &RenderSettings) -> Option<LightView> {
        let lookup = match self {
            Self::Temporal => Lookup::DepthLine,
            Self::TemporalExact => Lookup::Exact,
            Self::Tsm { .. } => return None,
        };
        let settings = RenderSettings {
            method: Method::Temporal,
            lookup,
            keep_static_layer: settings.static_layer,
            ..settings.clone()
        };
        Some(forward_light(scene, &settings))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_method_key_visits_every_method_and_comes_back() {
        let mut method = ViewMethod::Temporal;
        let mut names = Vec::new();
        for _ in 0..4 {
            names.push(method.name());
            method = method.next(8);
        }
        assert_eq!(method, ViewMethod::Temporal);
        assert_eq!(names, ["temporal", "temporal-exact", "tsm-8", "plain"]);
    }

    /// The split key shows each other method on the right once, then turns the split off.
    #[test]
    fn the_split_key_visits_every_other_method_then_turns_it_off() {
        for left in [
            ViewMethod::Temporal,
            ViewMethod::TemporalExact,
            ViewMethod::Tsm { maps: 8 },
            ViewMethod::Tsm { maps: 1 },
        ] {
            let mut right = None;
            let mut shown = Vec::new();
            for _ in 0..4 {
                right = left.next_split(right, 8);
                shown.extend(right);
            }
            assert_eq!(right, None, "off after the other three ({left:?})");
            assert_eq!(shown.len(), 3, "{left:?}: {shown:?}");
            assert!(!shown.contains(&left), "{left:?}: {shown:?}");
        }
    }
}
