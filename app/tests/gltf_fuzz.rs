//! The glTF loader on mutated documents: CesiumMan (the walker's model, with its buffer
//! embedded) with one to three of its accessor, buffer view, sparse, animation, skin, node
//! and mesh fields replaced by extreme or wrong values, removed, or emptied. For every one the
//! loader must not panic, must stay within a memory bound, and must give either meshes of
//! finite vertices within the scene limits or an error of at most `MAX_ERROR_CHARS`
//! characters.
//!
//! Seeded: the same cases every run, a fixed number of them (no wall-clock bound). Its own
//! test binary, so the allocation counter (support/counting_alloc.rs) sees only it.

use motion_shadows_app::scene::gltf::{AnimationRef, GltfOptions, load_gltf_motion_from_bytes};
use motion_shadows_app::scene::limits::{MAX_ERROR_CHARS, MAX_SCENE_TRIANGLES};
use serde_json::Value;

#[path = "support/counting_alloc.rs"]
mod counting_alloc;

/// What one case may use at its peak: the model's decoded buffers and meshes take a few MiB;
/// a document that asks for billions of elements must be refused before it allocates them.
const CASE_PEAK_LIMIT: usize = 512 << 20;
/// Cases run (each parses and loads the whole model: about 1 ms in the test profile).
const CASES: usize = 4000;

use motion_shadows_test_support::rng::Rng;

/// The top-level arrays whose fields decide how much the loader reads and builds.
const SECTIONS: &[&str] = &[
    "accessors",
    "bufferViews",
    "buffers",
    "animations",
    "skins",
    "nodes",
    "meshes",
    "scenes",
];

/// Every path (keys and indices) under `value` that ends at a number, string, array or
/// object member.
fn leaves(value: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    match value {
        Value::Object(map) => {
            for (key, child) in map {
                // The base64 buffer itself: mutating its text only tests the decoder.
                if key == "uri" {
                    continue;
                }
                path.push(Step::Key(key.clone()));
                out.push(path.clone());
                leaves(child, path, out);
                path.pop();
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate().take(64) {
                path.push(Step::Index(i));
                out.push(path.clone());
                leaves(child, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

#[derive(Debug, Clone)]
enum Step {
    Key(String),
    Index(usize),
}

fn at<'a>(value: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(value, |v, step| match step {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

/// A replacement value: extreme integers and floats, wrong types, empty containers.
fn wild(rng: &mut Rng) -> Value {
    let numbers: [f64; 16] = [
        0.0,
        1.0,
        -1.0,
        2.0,
        3.0,
        255.0,
        65535.0,
        4294967295.0,
        4294967296.0,
        2147483647.0,
        33554432.0,
        1e15,
        9007199254740993.0,
        0.5,
        -1e9,
        1e308,
    ];
    match rng.below(10) {
        0..=5 => serde_json::json!(numbers[rng.below(numbers.len())]),
        6 => Value::String(["SCALAR", "VEC3", "MAT4", "", "LINEAR", "STEP"][rng.below(6)].into()),
        7 => Value::Array(vec![]),
        8 => serde_json::json!({}),
        _ => Value::Null,
    }
}

fn mutate(doc: &mut Value, rng: &mut Rng) {
    let section = SECTIONS[rng.below(SECTIONS.len())];
    let Some(part) = doc.get_mut(section) else {
        return;
    };
    let mut paths = Vec::new();
    leaves(part, &mut Vec::new(), &mut paths);
    if paths.is_empty() {
        return;
    }
    let path = paths[rng.below(paths.len())].clone();
    match rng.below(8) {
        // Remove the member (or empty the array element).
        0 => {
            if let (Some(Step::Key(key)), Some(parent)) =
                (path.last(), at(part, &path[..path.len() - 1]))
            {
                if let Some(map) = parent.as_object_mut() {
                    map.remove(key);
                }
            }
        }
        // An accessor made sparse with a count far beyond its data.
        1 if section == "accessors" => {
            let count = [1u64, 1000, 33554432, 4294967295][rng.below(4)];
            if let Some(accessor) = part.get_mut(rng.below(64)) {
                accessor["sparse"] = serde_json::json!({
                    "count": count,
                    "indices": {"bufferView": 0, "componentType": 5125},
                    "values": {"bufferView": 0},
                });
            }
        }
        _ => {
            if let Some(v) = at(part, &path) {
                *v = wild(rng);
            }
        }
    }
}

/// Ok(true): loaded, Ok(false): refused with a short error.
fn check(bytes: &[u8], case: usize) -> Result<bool, String> {
    let options = GltfOptions {
        animation: Some(AnimationRef::Index(0)),
        time: 0.5,
        shutter: 1.0 / 48.0,
        subdivide: 0,
    };
    let result =
        std::panic::catch_unwind(|| load_gltf_motion_from_bytes("fuzz.gltf", bytes, &options));
    match result {
        Err(_) => Err(format!("case {case}: the loader panicked")),
        Ok(Err(e)) => {
            let message = e.to_string();
            let chars = message.chars().count();
            if chars > MAX_ERROR_CHARS {
                return Err(format!("case {case}: a {chars}-character error"));
            }
            Ok(false)
        }
        Ok(Ok(meshes)) => {
            let triangles: u64 = meshes.iter().map(|m| m.t0.len() as u64 / 3).sum();
            if triangles > MAX_SCENE_TRIANGLES {
                return Err(format!("case {case}: {triangles} triangles"));
            }
            let finite = meshes
                .iter()
                .all(|m| m.t0.iter().chain(&m.t1).all(|p| p.is_finite()));
            if !finite {
                return Err(format!("case {case}: a mesh with non-finite vertices"));
            }
            Ok(true)
        }
    }
}

#[test]
fn the_gltf_loader_survives_mutated_documents() {
    let source = include_str!("../../assets/models/CesiumMan.gltf");
    let mut model: Value = serde_json::from_str(source).unwrap();
    // Its texture is ignored by the loader: dropped, so each case parses less.
    for key in ["images", "textures", "samplers", "materials"] {
        model.as_object_mut().unwrap().remove(key);
    }
    for mesh in model["meshes"].as_array_mut().unwrap() {
        for primitive in mesh["primitives"].as_array_mut().unwrap() {
            primitive.as_object_mut().unwrap().remove("material");
        }
    }
    let pristine = serde_json::to_vec(&model).unwrap();
    assert_eq!(check(&pristine, 0), Ok(true), "the unmutated model loads");

    let mut rng = Rng(0x6c74_6631);
    let (mut loaded, mut refused, mut largest_peak) = (0, 0, 0);
    let mut failures = Vec::new();
    std::panic::set_hook(Box::new(|_| {}));
    for case in 1..=CASES {
        let mut doc = model.clone();
        for _ in 0..1 + rng.below(3) {
            mutate(&mut doc, &mut rng);
        }
        let bytes = serde_json::to_vec(&doc).unwrap();
        let base = counting_alloc::start_case();
        let outcome = check(&bytes, case);
        let peak = counting_alloc::peak_since(base);
        largest_peak = largest_peak.max(peak);
        if peak > CASE_PEAK_LIMIT {
            failures.push(format!("case {case}: peak allocation {} MiB", peak >> 20));
        }
        match outcome {
            Ok(true) => loaded += 1,
            Ok(false) => refused += 1,
            Err(e) => failures.push(e),
        }
    }
    let _ = std::panic::take_hook();
    println!(
        "gltf fuzz: {CASES} cases, {loaded} loaded, {refused} refused, {} failures, largest \
         peak allocation {:.1} MiB",
        failures.len(),
        largest_peak as f64 / (1024.0 * 1024.0)
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        loaded > CASES / 20 && refused > CASES / 20,
        "the mutations should both pass and fail the checks: {loaded} loaded, {refused} refused"
    );
}
