#![allow(dead_code)]
pub mod coverage_oracle;
pub mod frame;
pub mod gpu;
pub mod host;
pub mod prism_model;
pub mod sampling;
