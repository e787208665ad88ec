#![allow(dead_code)]
pub mod gpu;
pub mod host;
pub mod prism_model;
pub mod sampling;
