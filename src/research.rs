//! The layers under the engine API: the passes one by one ([`passes`]) and the thin layer
//! over ash ([`gpu`]), for the app, the papers' experiments, and hosts that record the
//! passes themselves. The papers' own passes (the lighting pass with stochastic
//! rasterization, the 2017 coverage map, plain and time-dependent shadow maps) are built with
//! the default feature `research`.

#[doc(inline)]
pub use crate::gpu;
#[doc(inline)]
pub use crate::technique as passes;
