#![allow(dead_code)]
pub mod prism_model;
