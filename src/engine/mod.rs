//! The engine layer: what an engine uses instead of recording the passes itself. Describe
//! each mesh once ([`Mesh`]), choose a light's settings ([`ShadowSettings`]), make one
//! [`LightShadow`] per light, and each frame call [`LightShadow::record_frame`] into your
//! command buffer and, after the frame's fence, [`LightShadow::finish_frame`]. The book's
//! integration page (`docs/src/integration.md`) walks through a frame.

mod device;
mod frame;
mod host_barrier;
mod light;
mod mesh;
mod mesh_room;
mod settings;
mod shadow;

pub use frame::ShadowFrame;
pub use host_barrier::{HostBarrier, HostImage};
pub use light::Light;
pub use mesh::{CpuGeometry, Mesh, MeshBound};
pub use settings::{ShadowSettings, StaticLayer};
pub use shadow::LightShadow;
#[cfg(test)]
mod tests;
