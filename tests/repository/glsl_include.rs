//! The public GLSL include comes in two forms that must hold the same code: the file
//! `glsl/motion_shadows.glsl`, which hosts compiling against the library's `glsl/` directory
//! include (it includes its parts, one concept each, from `glsl/motion_shadows/`), and the
//! string `GLSL_INCLUDE`, which hosts serve from their own include callback under the name
//! `motion_shadows.glsl` and which must therefore be self-contained.

use std::path::Path;

use motion_shadows::GLSL_INCLUDE;

/// The parts `glsl/motion_shadows.glsl` includes, in its order. Every other line of it must be
/// a comment or blank: code there would be missing from `GLSL_INCLUDE`.
fn included_parts(glsl_dir: &Path) -> Vec<String> {
    let path = glsl_dir.join("motion_shadows.glsl");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    let mut parts = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with("//") {
            continue;
        }
        let name = line
            .strip_prefix("#include \"")
            .and_then(|rest| rest.strip_suffix('"'))
            .unwrap_or_else(|| {
                panic!(
                    "glsl/motion_shadows.glsl line {}: `{line}` is neither a comment nor an \
                     #include of a part (GLSL_INCLUDE holds only the parts)",
                    number + 1
                )
            });
        parts.push(name.to_owned());
    }
    parts
}

#[test]
fn glsl_include_is_the_parts_the_public_file_includes_in_its_order() {
    let glsl_dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("glsl");
    let parts = included_parts(&glsl_dir);
    assert!(
        !parts.is_empty(),
        "glsl/motion_shadows.glsl includes no part"
    );
    let mut expected = String::new();
    for part in &parts {
        let path = glsl_dir.join(part);
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("reading {} (included): {e}", path.display()));
        assert!(
            !text.lines().any(|l| l.trim_start().starts_with("#include")),
            "{part} includes another file: GLSL_INCLUDE would not be self-contained"
        );
        expected.push_str(&text);
    }
    assert!(
        GLSL_INCLUDE == expected,
        "GLSL_INCLUDE is not the concatenation of {parts:?} (src/technique/mod.rs must list \
         the parts glsl/motion_shadows.glsl includes, in its order)"
    );
}
