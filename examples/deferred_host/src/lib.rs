//! The example deferred engine (`main.rs` runs it): its own device ([`gpu`]) and the engine
//! ([`deferred`]), a library so that the GPU tests drive the same code, compiled once.

pub mod deferred;
pub mod gpu;
