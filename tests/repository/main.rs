//! The repository's own checks, no device: the README's snippets are compiled doctests
//! (`readme`), the size report (`source_sizes`), and the library as a crate outside the
//! repository builds and links it (`external_dependent`).

mod external_dependent;
mod readme;
mod source_sizes;
