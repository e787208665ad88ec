//! The descriptor set one record of the pass writes and binds, apart from the pass so that
//! its steps can write it without importing the pass back.

use crate::gpu::ImageBindings;

/// What one record binds: the descriptor set of the host's images and the two maps. One per
/// record that may be pending at the same time (per frame in flight and light), used once
/// per command buffer. Made by [`super::EngineTsmPass::bindings`].
pub struct EngineTsmBindings {
    pub(super) images: ImageBindings,
}
