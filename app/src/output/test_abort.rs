//! A test-only way to end the process at a chosen point of a commit, as a kill would there
//! (no destructor runs, nothing is cleaned up), so that tests can check what the next run
//! makes of what is left. `MOTION_SHADOWS_TEST_ABORT=<point>`: `before-commit` (every
//! temporary file complete, no target replaced) or `between-renames` (after the first
//! target is replaced). Not for users: a run told to abort fails.

const VAR: &str = "MOTION_SHADOWS_TEST_ABORT";

/// Aborts the process if the variable names `point`, saying so on stderr.
pub(super) fn abort_if_asked(point: &str) {
    if std::env::var_os(VAR).is_some_and(|v| v == point) {
        eprintln!("{VAR}={point}: aborting here, as a test asked");
        std::process::abort();
    }
}
