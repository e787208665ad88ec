//! Tests of the glTF loader: small models written here whose motion is known in closed
//! form, the shipped models against the figures in assets/models/README.md, and errors.

mod builder;
mod errors;
mod geometry;
mod models;
mod morph;
mod skinning;
