//! Writes small glTF files for the tests: accessors packed into one buffer embedded as a
//! base64 data URI, the rest of the JSON given by each test.

use std::path::PathBuf;

use base64::Engine as _;
use serde_json::{Value, json};

#[derive(Default)]
pub(super) struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    fn view(&mut self, bytes: &[u8]) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()
        }));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// Float accessor of `ty` ("SCALAR", "VEC3", ...), with the min/max glTF requires of
    /// positions and animation inputs.
    pub(super) fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let n = components(ty);
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let column = |c: usize| data.iter().skip(c).step_by(n).copied();
        let min: Vec<f32> = (0..n).map(|c| column(c).fold(f32::MAX, f32::min)).collect();
        let max: Vec<f32> = (0..n).map(|c| column(c).fold(f32::MIN, f32::max)).collect();
        self.accessor(json!({
            "bufferView": view, "componentType": 5126, "count": data.len() / n,
            "type": ty, "min": min, "max": max
        }))
    }

    /// Unsigned integer accessor with components of `bytes` (1, 2 or 4) bytes each.
    pub(super) fn integers(&mut self, data: &[u32], ty: &str, bytes: usize) -> usize {
        let raw: Vec<u8> = data
            .iter()
            .flat_map(|&v| v.to_le_bytes()[..bytes].to_vec())
            .collect();
        let view = self.view(&raw);
        let component = match bytes {
            1 => 5121,
            2 => 5123,
            _ => 5125,
        };
        self.accessor(json!({
            "bufferView": view, "componentType": component,
            "count": data.len() / components(ty), "type": ty
        }))
    }

    /// The whole file: `root` plus asset, buffers, bufferViews and accessors.
    pub(super) fn finish(self, mut root: Value) -> String {
        let data = base64::engine::general_purpose::STANDARD.encode(&self.bin);
        root["asset"] = json!({ "version": "2.0" });
        root["buffers"] = json!([{
            "byteLength": self.bin.len(),
            "uri": format!("data:application/octet-stream;base64,{data}")
        }]);
        root["bufferViews"] = Value::Array(self.views);
        root["accessors"] = Value::Array(self.accessors);
        root.to_string()
    }
}

fn components(ty: &str) -> usize {
    match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT4" => 16,
        other => panic!("{other}"),
    }
}

/// Writes `text` to a fresh temporary file named `name` and returns its path.
pub(super) fn write_temp(name: &str, text: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!(
        "motion-shadows-gltf-{}-{nanos}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// The shipped models, found from the crate so a fresh clone has them.
pub(super) fn asset(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../assets/models")
        .join(name)
}
