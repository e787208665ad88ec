//! The minimal host example (`examples/minimal_host.rs`, the first file an engine developer
//! reads) runs as a test: its own device with validation and synchronization validation,
//! one frame, the host shader's lit fractions against the closed form of a square sliding
//! over the ground, and no validation message (`run` fails on any). Its size is kept by the
//! repository's size report (`tests/repository/source_sizes.rs`), as every file's.

#[path = "../../examples/minimal_host.rs"]
#[allow(dead_code)]
mod example;

#[test]
fn the_minimal_host_matches_the_closed_form_with_validation_silent() {
    let outcome = example::run().unwrap_or_else(|e| panic!("the minimal host failed: {e}"));
    assert!(outcome.checked >= 50, "{} points checked", outcome.checked);
    assert!(outcome.worst <= 0.05, "worst {}", outcome.worst);
    // Lit for the whole shutter, for half of it (the square's side over its travel), and the
    // ramps between: the row holds both plateaus (the half-lit one: x in [-0.5, 0.5]).
    assert!(outcome.row.iter().any(|&v| v > 0.99));
    assert!(
        outcome
            .row
            .iter()
            .filter(|&&v| (v - 0.5).abs() < 0.02)
            .count()
            >= 12
    );
}
