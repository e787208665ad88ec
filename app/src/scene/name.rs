//! Scene names become output file names (`DIR/<name>-<method>.png`), so they are held to a
//! set that cannot leave the output directory or hide a file: 1 to 64 characters of
//! `[A-Za-z0-9._-]`, not starting with `.`. An explicit `"name"` outside it is an error; a
//! name taken from the scene file's name is made to fit (see [`name_from_file_stem`]).

use super::clip::quoted;
use super::limits::MAX_NAME_CHARS;

fn allowed(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-')
}

/// Why `name` cannot name a scene, or `None` when it can.
pub fn scene_name_problem(name: &str) -> Option<String> {
    let chars = name.chars().count();
    if chars == 0 {
        return Some("scene name is empty".into());
    }
    if chars > MAX_NAME_CHARS {
        return Some(format!(
            "scene name {:?} has {chars} characters, more than {MAX_NAME_CHARS}",
            quoted(name)
        ));
    }
    if let Some(c) = name.chars().find(|&c| !allowed(c)) {
        return Some(format!(
            "scene name {name:?} contains {c:?}; names become file names, so only \
             letters, digits, '.', '_' and '-' are allowed"
        ));
    }
    if name.starts_with('.') {
        return Some(format!(
            "scene name {name:?} starts with '.' (it would name a hidden file)"
        ));
    }
    None
}

/// A valid scene name made from a file's stem: characters outside the set become '_', a
/// leading '.' becomes '_', and the name is cut to 64 characters ("scene" if nothing is left).
pub fn name_from_file_stem(stem: &str) -> String {
    let mut name: String = stem
        .chars()
        .take(MAX_NAME_CHARS)
        .map(|c| if allowed(c) { c } else { '_' })
        .collect();
    if name.starts_with('.') {
        name.replace_range(..1, "_");
    }
    if name.is_empty() {
        name = "scene".into();
    }
    name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_that_could_leave_the_output_directory_are_refused() {
        for good in ["cubes-toward-light", "a", "v1.2_final", &"x".repeat(64)] {
            assert_eq!(scene_name_problem(good), None, "{good}");
        }
        for bad in [
            "",
            "../../escaped",
            "/abs",
            "a/b",
            "a\\b",
            ".hidden",
            "..",
            "sp ace",
            "nul\0",
            "é",
            &"x".repeat(65),
        ] {
            assert!(scene_name_problem(bad).is_some(), "{bad:?}");
        }
        let huge = "y".repeat(10_000_000);
        let message = scene_name_problem(&huge).unwrap();
        assert!(message.len() < 400, "{} bytes", message.len());
    }

    #[test]
    fn file_stems_are_made_valid() {
        assert_eq!(name_from_file_stem("my scene (2)"), "my_scene__2_");
        assert_eq!(name_from_file_stem(".hidden"), "_hidden");
        assert_eq!(name_from_file_stem(""), "scene");
        assert_eq!(name_from_file_stem(&"z".repeat(100)).len(), 64);
        for stem in ["..", "a/../b", "é", "x y"] {
            assert_eq!(
                scene_name_problem(&name_from_file_stem(stem)),
                None,
                "{stem}"
            );
        }
    }
}
