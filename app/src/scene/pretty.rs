//! Re-indents compact JSON for people: objects one field per line, arrays of plain values
//! (vectors like `[0.0, 1.0, 0.0]`) on one line. serde_json's pretty printer puts every
//! number on its own line, which makes exported scenes unreadable. Working on the compact
//! text (instead of a `serde_json::Value`) keeps serde_json's shortest f32 spelling.

/// `compact` must be serde_json's compact output (no insignificant whitespace).
pub(crate) fn pretty_json(compact: &str) -> String {
    let bytes = compact.as_bytes();
    let mut out = String::with_capacity(compact.len() * 2);
    let mut indent = 0usize;
    // For each open bracket: whether its contents are laid out inline.
    let mut inline_stack: Vec<bool> = Vec::new();
    let mut i = 0;
    let newline = |out: &mut String, indent: usize| {
        out.push('\n');
        out.extend(std::iter::repeat_n("  ", indent));
    };
    while i < bytes.len() {
        let c = bytes[i];
        match c {
            b'"' => {
                let end = string_end(bytes, i);
                out.push_str(&compact[i..end]);
                i = end;
                continue;
            }
            b'{' | b'[' => {
                let close = if c == b'{' { b'}' } else { b']' };
                out.push(c as char);
                if bytes.get(i + 1) == Some(&close) {
                    out.push(close as char);
                    i += 2;
                    continue;
                }
                let inline = c == b'[' && is_flat_array(bytes, i);
                inline_stack.push(inline);
                if !inline {
                    indent += 1;
                    newline(&mut out, indent);
                }
            }
            b'}' | b']' => {
                if !inline_stack.pop().unwrap_or(false) {
                    indent = indent.saturating_sub(1);
                    newline(&mut out, indent);
                }
                out.push(c as char);
            }
            b',' => {
                out.push(',');
                if inline_stack.last().copied().unwrap_or(false) {
                    out.push(' ');
                } else {
                    newline(&mut out, indent);
                }
            }
            b':' => out.push_str(": "),
            _ => {
                // Numbers, literals: copy the run up to the next structural byte.
                let end = bytes[i..]
                    .iter()
                    .position(|b| b",:]}".contains(b))
                    .map_or(bytes.len(), |n| i + n);
                out.push_str(&compact[i..end]);
                i = end;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Index just past the string literal starting at `start` (a `"`), honouring escapes.
fn string_end(bytes: &[u8], start: usize) -> usize {
    let mut i = start + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    bytes.len()
}

/// True if the array opening at `start` holds no objects, arrays or strings.
fn is_flat_array(bytes: &[u8], start: usize) -> bool {
    bytes[start + 1..]
        .iter()
        .take_while(|&&b| b != b']')
        .all(|b| !b"[{\"".contains(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_content_preserved() {
        let compact = r#"{"a":[1.0,-2.5e-8,3],"b":{"s":"x,[\"]{:","e":[],"o":{}},"c":[[1,2],[3,4]],"d":[{"k":true}]}"#;
        let pretty = pretty_json(compact);
        let expected = r#"{
  "a": [1.0, -2.5e-8, 3],
  "b": {
    "s": "x,[\"]{:",
    "e": [],
    "o": {}
  },
  "c": [
    [1, 2],
    [3, 4]
  ],
  "d": [
    {
      "k": true
    }
  ]
}"#;
        assert_eq!(pretty, expected);
        let a: serde_json::Value = serde_json::from_str(compact).unwrap();
        let b: serde_json::Value = serde_json::from_str(&pretty).unwrap();
        assert_eq!(a, b);
    }
}
