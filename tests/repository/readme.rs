//! Every Rust snippet of the README is compiled: the README is the doc comment of an item of
//! the library compiled only for doctests (`src/lib.rs`, `ReadmeSnippets`), so `cargo test
//! --doc` compiles each ```rust block from the README itself, with the setup a snippet needs
//! in hidden `#` lines. This test keeps that true: every snippet is a compiled doctest
//! (`no_run`: they need a host's device), none is skipped, and the library still includes the
//! README.

/// The info strings of the README's Rust code blocks (` ```rust...`), with each block's first
/// line for the message.
fn rust_blocks(readme: &str) -> Vec<(String, String)> {
    let mut blocks = Vec::new();
    let mut lines = readme.lines();
    while let Some(line) = lines.next() {
        let Some(info) = line.trim_start().strip_prefix("```") else {
            continue;
        };
        let info = info.trim().to_owned();
        let first = lines.next().unwrap_or_default().to_owned();
        let closed = first.trim_start().starts_with("```");
        if info.split(',').next() == Some("rust") {
            blocks.push((info, first));
        }
        // Skip to the block's closing fence, so that it is not read as an opening one.
        if !closed {
            for line in lines.by_ref() {
                if line.trim_start().starts_with("```") {
                    break;
                }
            }
        }
    }
    blocks
}

#[test]
fn every_readme_rust_snippet_is_compiled_here() {
    let readme = include_str!("../../README.md");
    let blocks = rust_blocks(readme);
    assert!(
        blocks.len() >= 2,
        "the README's integration snippets: {}",
        blocks.len()
    );
    for (info, first) in &blocks {
        // `ignore` would skip the block, `compile_fail` would pass on a broken one.
        assert_eq!(
            info, "rust,no_run",
            "a README snippet is not compiled as a doctest (starts {first:?})"
        );
    }
    let lib = include_str!("../../src/lib.rs");
    assert!(
        lib.contains("#[cfg(doctest)]\n#[doc = include_str!(\"../README.md\")]"),
        "src/lib.rs no longer compiles the README's snippets as doctests"
    );
}
