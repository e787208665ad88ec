//! Reading a glTF 2.0 file (`.gltf` JSON or `.glb` binary) and its buffers. Buffers come
//! from the GLB `BIN` chunk, from base64 `data:` URIs, or from files next to the model; each
//! is read with the same size bound as the model, and the gltf crate's own importer (which
//! reads without a bound and decodes images) is not used.

use std::path::Path;

use base64::Engine as _;

use super::super::limits::MAX_GLTF_BYTES;
use super::super::read::read_bounded;

/// A parsed, validated model with every buffer's bytes.
pub(super) struct Source {
    pub document: gltf::Document,
    pub buffers: Vec<Vec<u8>>,
}

/// Extensions this loader can honour when a file requires them: none. Geometry under a
/// required extension (Draco, meshopt, quantisation) would be read wrongly, so it is refused.
const SUPPORTED_REQUIRED_EXTENSIONS: &[&str] = &[];

pub(super) fn load(path: &Path) -> Result<Source, String> {
    let bytes = read_bounded(path, MAX_GLTF_BYTES, false).map_err(|e| e.to_string())?;
    parse(bytes, Some(path.parent().unwrap_or(Path::new("."))))
}

/// A model already in memory (e.g. compiled into the binary). External buffers are read
/// relative to `base_dir`; without one only the GLB chunk and `data:` URIs can be used.
pub(super) fn parse(bytes: Vec<u8>, base_dir: Option<&Path>) -> Result<Source, String> {
    if bytes.len() as u64 > MAX_GLTF_BYTES {
        return Err(format!(
            "model of {} bytes is over the size limit",
            bytes.len()
        ));
    }
    // Unvalidated first so a required extension is reported by name rather than as one of
    // the validator's messages.
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| format!("not a glTF 2.0 file: {e}"))?;
    drop(bytes);
    let unsupported: Vec<&str> = gltf
        .extensions_required()
        .filter(|e| !SUPPORTED_REQUIRED_EXTENSIONS.contains(e))
        .collect();
    if !unsupported.is_empty() {
        return Err(format!(
            "requires glTF extensions this loader does not support: {}",
            unsupported.join(", ")
        ));
    }
    let mut blob = gltf.blob;
    let document = gltf::Document::from_json(gltf.document.into_json())
        .map_err(|e| format!("invalid glTF: {e}"))?;
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                format!(
                    "buffer {} refers to a missing GLB BIN chunk",
                    buffer.index()
                )
            })?,
            gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, base_dir).map_err(|e| format!("buffer {}: {e}", buffer.index()))?
            }
        };
        // The BIN chunk may be padded to 4 bytes; anything shorter than declared is broken.
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {} has {} bytes, fewer than its byteLength {}",
                buffer.index(),
                data.len(),
                buffer.length()
            ));
        }
        buffers.push(data);
    }
    Ok(Source { document, buffers })
}

fn read_uri(uri: &str, base_dir: Option<&Path>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_mime, payload) = rest
            .split_once(";base64,")
            .ok_or("a data: URI that is not base64")?;
        // Decoded size is 3/4 of the text, so bounding the text bounds the bytes.
        if payload.len() as u64 > MAX_GLTF_BYTES {
            return Err("data: URI over the size limit".into());
        }
        return base64::engine::general_purpose::STANDARD
            .decode(payload)
            .map_err(|e| format!("bad base64 in data: URI: {e}"));
    }
    if uri.contains("://") {
        return Err(format!(
            "{uri:?}: only data: URIs and relative file paths are read"
        ));
    }
    let Some(base_dir) = base_dir else {
        return Err(format!(
            "{uri:?}: a model read from memory can only use data: URIs"
        ));
    };
    let relative = percent_decode(uri);
    read_bounded(&base_dir.join(&relative), MAX_GLTF_BYTES, false)
        .map_err(|e| format!("{relative:?}: {e}"))
}

/// URIs in glTF are percent-encoded (a space is `%20`); anything malformed is kept as is.
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(b)) => {
                out.push(b);
                i += 3;
            }
            (b, _) => {
                out.push(b);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::percent_decode;

    #[test]
    fn uris_are_percent_decoded() {
        assert_eq!(percent_decode("a%20b.bin"), "a b.bin");
        assert_eq!(percent_decode("100%.bin"), "100%.bin");
    }
}
