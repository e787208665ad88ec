//! The repository's own checks, no device: the README's snippets are compiled doctests
//! (`readme`), the size report (`source_sizes`) and the example engine's
//! (`deferred_host_size`), the public GLSL include's two forms (`glsl_include`), and the
//! library as a crate outside the repository builds and links it (`external_dependent`).

mod deferred_host_size;
mod external_dependent;
mod glsl_include;
mod readme;
mod source_sizes;
