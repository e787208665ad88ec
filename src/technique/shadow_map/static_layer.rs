//! The static layer kept across frames: what it was drawn for, and the host's word that the
//! pass that drew it was submitted.

use super::*;

/// What the static layer holds for keeping: nothing is kept on the strength of a recording
/// alone, so a recorded pass that is never submitted needs no undoing.
#[derive(Default)]
pub(super) struct StaticLayerState {
    /// What the layer holds, drawn by a submitted pass: later passes may keep it.
    kept: Option<StaticLayerSource>,
    /// What the last recorded pass that drew the layer drew it for, until the host says that
    /// pass was submitted.
    recorded: Option<StaticLayerSource>,
}

/// What a static layer's contents follow from: the light's view and projection and the
/// static draws (with their places in the draw list).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct StaticLayerSource {
    view: Mat4,
    proj: Mat4,
    draws: Vec<(usize, DrawRecord)>,
}

impl StaticLayerSource {
    /// What a collection of `draws` lit by `light` would draw into the static layer: the
    /// static draws, none under a moving light (nothing stands still in its frame), so that a
    /// layer kept from a still light's frames is redrawn once the light moves, and again
    /// once it stops.
    pub fn of(light: &LightView, draws: &DrawList) -> Self {
        let light_moves = light.is_moving();
        Self {
            view: light.view,
            proj: light.proj,
            draws: draws
                .records()
                .iter()
                .copied()
                .enumerate()
                .filter(|(_, r)| {
                    r.flags() & DRAW_STATIC != 0 && r.triangle_count > 0 && !light_moves
                })
                .collect(),
        }
    }
}

impl TemporalShadowMap {
    /// How many times a collection pass has drawn this map's static layer (with
    /// [`LightView::keep_static_layer`], once per change of light or static draws; new
    /// buffers from [`Self::grow_to_fit`] or [`Self::reserve`] start again from 0).
    pub fn static_layer_builds(&self) -> u32 {
        self.static_layer_builds.load(Ordering::Relaxed)
    }

    fn static_layer_state(&self) -> std::sync::MutexGuard<'_, StaticLayerState> {
        self.static_layer_source
            .lock()
            .unwrap_or_else(|e| e.into_inner())
    }

    /// Makes the next collection pass redraw the static layer, kept or not: call it when a
    /// static draw's buffer contents changed in place.
    pub fn forget_static_layer(&self) {
        *self.static_layer_state() = StaticLayerState::default();
    }

    /// Tells the map that the command buffer with its last recorded collection pass was
    /// submitted: a static layer that pass drew may then be kept by later passes (with
    /// [`LightView::keep_static_layer`]). Recording alone never marks a layer as kept, so a
    /// recorded pass that is not submitted needs nothing undone; without this call the layer
    /// is redrawn by every pass (slower, never wrong).
    ///
    /// Call it after the submission and before recording this map's next collection pass.
    /// (Saying so of a pass that was not submitted makes later passes keep a layer that was
    /// never drawn: wrong shadows, though no memory is misused.)
    pub fn static_layer_submitted(&self) {
        let mut state = self.static_layer_state();
        if let Some(recorded) = state.recorded.take() {
            state.kept = Some(recorded);
        }
    }

    /// Whether the static layer holds what `source` would draw (a kept layer).
    pub(crate) fn static_layer_is(&self, source: &StaticLayerSource) -> bool {
        self.static_layer_state().kept.as_ref() == Some(source)
    }

    /// Notes that a recorded pass draws the static layer for `source` (`None`: not to be
    /// kept). What the layer held is not kept any more; `source` is, once the pass is
    /// submitted ([`Self::static_layer_submitted`]).
    pub(crate) fn static_layer_drawn(&self, source: Option<StaticLayerSource>) {
        self.static_layer_builds.fetch_add(1, Ordering::Relaxed);
        let mut state = self.static_layer_state();
        state.kept = None;
        state.recorded = source;
    }
}
