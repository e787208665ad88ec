//! Quoting user text in error messages without letting it grow them: a 100 MB scene name or
//! field name must give a one-line error, not a 100 MB one.

use std::borrow::Cow;
use std::path::Path;

use super::limits::MAX_QUOTED_CHARS;

/// `text` itself when it has at most `max_chars` characters; otherwise its first
/// `max_chars` characters and a note of how long the whole was.
pub fn clip(text: &str, max_chars: usize) -> Cow<'_, str> {
    match text.char_indices().nth(max_chars) {
        None => Cow::Borrowed(text),
        Some((end, _)) => Cow::Owned(format!("{}... ({} bytes in all)", &text[..end], text.len())),
    }
}

/// User text (names, field names, parser messages) as quoted in errors.
pub fn quoted(text: &str) -> Cow<'_, str> {
    clip(text, MAX_QUOTED_CHARS)
}

/// A path as shown in errors.
pub fn quoted_path(path: &Path) -> String {
    quoted(&path.to_string_lossy()).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_text_is_kept_and_long_text_is_cut_at_a_character() {
        assert_eq!(clip("abc", 3), "abc");
        assert_eq!(clip("abcd", 3), "abc... (4 bytes in all)");
        // Multi-byte characters are never split.
        assert_eq!(clip("ééé", 2), "éé... (6 bytes in all)");
        let long = "x".repeat(1_000_000);
        assert!(quoted(&long).len() < MAX_QUOTED_CHARS + 40);
        assert!(quoted_path(Path::new(&long)).len() < MAX_QUOTED_CHARS + 40);
    }
}
