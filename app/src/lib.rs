//! The motion-shadows app: a client of the library's public API.
//!
//! [`scene`] (built-in scenes, scene files, OBJ), [`render`] (a standalone renderer that
//! creates its own headless context and drives the passes), [`raytrace`] (the exact CPU
//! reference every method can be judged against), [`frame`] (one frame by either), [`output`] (EXR/PNG), [`compare`]
//! and [`bench`] (the papers' experiments), [`chart`] (CSV and line charts), and [`cli`] (the
//! `motion-shadows` binary's commands).

pub mod bench;
pub mod chart;
pub mod cli;
pub mod compare;
pub mod error;
pub mod frame;
pub mod output;
pub mod raytrace;
pub mod render;
pub mod scene;
pub mod view;

pub use error::{Error, Result};
