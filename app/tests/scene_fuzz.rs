//! A bounded-time generator test of the scene parser: documents built from the documented
//! grammar (docs/scene-format.md) with random, extreme and wrong values, then often mutated
//! as text. For every one the parser must not panic, must stay within a memory bound, and
//! must give either a valid scene or an error of at most `MAX_ERROR_CHARS` characters.
//!
//! Seeded (same cases every run): a fixed 30,000 cases (no wall-clock bound); it prints how
//! many ran and how long they took. Its own test binary, so the allocation counter
//! (support/counting_alloc.rs) sees only it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use motion_shadows_app::scene::limits::MAX_ERROR_CHARS;
use motion_shadows_app::scene::parse_scene_json;

#[path = "support/counting_alloc.rs"]
mod counting_alloc;

/// What one case may use at its peak: a few hundred MiB for the largest meshes the generator
/// can ask for (boxes of 256 x 256 quads a face), far below what the probes needed (GiBs).
const CASE_PEAK_LIMIT: usize = 1 << 30;

use motion_shadows_test_support::rng::Rng;

struct Generator {
    rng: Rng,
    /// Mostly plausible values (small positive numbers, valid names): such documents get
    /// past the checks, so building meshes is exercised too, not only the errors.
    sane: bool,
    /// OBJ paths to draw from: good and broken models, a directory, a device, nothing.
    obj_paths: Vec<String>,
}

impl Generator {
    fn number(&mut self) -> String {
        if self.sane && self.rng.chance(0.85) {
            let v = 0.1 + (self.rng.next() % 491) as f64 / 100.0;
            return format!("{v}");
        }
        const SPECIAL: &[&str] = &[
            "0",
            "1",
            "-1",
            "0.5",
            "2",
            "45",
            "89",
            "90",
            "180",
            "1e-3",
            "1e4",
            "9.9e3",
            "1.01e4",
            "1e5",
            "1e7",
            "1e10",
            "1e38",
            "3.5e38",
            "1e39",
            "-1e39",
            "1e999",
            "-0",
            "1e-45",
            "1e-400",
            "0.1",
            "100",
            "-5",
            "12345678901234567890",
        ];
        if self.rng.chance(0.6) {
            self.rng.pick(SPECIAL).to_string()
        } else {
            let v = (self.rng.next() % 2001) as f64 / 100.0 - 10.0;
            format!("{v}")
        }
    }

    fn vec(&mut self, n: usize) -> String {
        let len = if self.rng.chance(0.05) {
            self.rng.below(5)
        } else {
            n
        };
        let items: Vec<String> = (0..len).map(|_| self.number()).collect();
        if self.rng.chance(0.02) {
            return "\"[1, 2, 3]\"".into();
        }
        format!("[{}]", items.join(", "))
    }

    fn string(&mut self) -> String {
        if self.sane && self.rng.chance(0.8) {
            return format!("\"scene-{}\"", self.rng.below(100));
        }
        match self.rng.below(8) {
            0 => format!("{:?}", "x".repeat(1 + self.rng.below(200_000))),
            1 => "\"../../escaped\"".into(),
            2 => "\"/abs/name\"".into(),
            3 => "\".hidden\"".into(),
            4 => "\"\"".into(),
            5 => "\"sp ace\\u0000nul\"".into(),
            6 => "\"caf\u{e9}\"".into(),
            _ => format!("\"scene-{}\"", self.rng.below(100)),
        }
    }

    fn transform(&mut self) -> String {
        let mut fields = Vec::new();
        for (name, n) in [("translation", 3), ("rotation_axis", 3), ("scale", 3)] {
            if self.rng.chance(0.5) {
                fields.push(format!("\"{name}\": {}", self.vec(n)));
            }
        }
        if self.rng.chance(0.5) {
            fields.push(format!("\"rotation_deg\": {}", self.number()));
        }
        format!("{{ {} }}", fields.join(", "))
    }

    fn subdivisions(&mut self) -> String {
        if self.sane && self.rng.chance(0.9) {
            // 256, the limit, now and then: the largest mesh one object can be.
            return self.rng.pick(&["1", "2", "3", "8", "16", "256"]).into();
        }
        self.rng
            .pick(&[
                "1",
                "2",
                "3",
                "8",
                "0",
                "-1",
                "1.5",
                "257",
                "1024",
                "4294967295",
                "1e9",
            ])
            .into()
    }

    fn mesh(&mut self) -> String {
        match self.rng.below(5) {
            0 => format!(
                "{{ \"box\": {{ \"size\": {}, \"subdivisions\": {} }} }}",
                self.vec(3),
                self.subdivisions()
            ),
            1 => format!(
                "{{ \"plane\": {{ \"size\": {}, \"subdivisions\": {} }} }}",
                self.vec(2),
                self.subdivisions()
            ),
            2 => {
                let path = self.obj_paths[self.rng.below(self.obj_paths.len())].clone();
                format!("{{ \"obj\": {path:?} }}")
            }
            3 => {
                let n = [0, 1, 2, 3, 6, 9, 300][self.rng.below(7)];
                let t0: Vec<String> = (0..n).map(|_| self.vec(3)).collect();
                let mut spec = format!("\"t0\": [{}]", t0.join(", "));
                if self.rng.chance(0.4) {
                    let m = if self.rng.chance(0.8) {
                        n
                    } else {
                        self.rng.below(7)
                    };
                    let t1: Vec<String> = (0..m).map(|_| self.vec(3)).collect();
                    let _ = write!(spec, ", \"t1\": [{}]", t1.join(", "));
                }
                format!("{{ \"triangles\": {{ {spec} }} }}")
            }
            _ => self
                .rng
                .pick(&[
                    "{}",
                    "{ \"sphere\": {} }",
                    "null",
                    "{ \"box\": {}, \"plane\": {} }",
                ])
                .into(),
        }
    }

    fn object(&mut self) -> String {
        let albedo = if self.rng.chance(0.7) {
            "[0.5, 0.5, 0.5]".to_string()
        } else {
            self.vec(3)
        };
        let mut fields = vec![format!("\"albedo\": {albedo}")];
        fields.push(format!("\"mesh\": {}", self.mesh()));
        if self.rng.chance(0.5) {
            fields.push(format!("\"name\": {}", self.string()));
        }
        if self.rng.chance(0.5) {
            fields.push(format!(
                "\"closed\": {}",
                self.rng.pick(&["true", "false", "1"])
            ));
        }
        if self.rng.chance(0.4) {
            fields.push(format!("\"t0\": {}", self.transform()));
        }
        if self.rng.chance(0.4) {
            fields.push(format!("\"t1\": {}", self.transform()));
        }
        if self.rng.chance(0.05) {
            fields.push(format!("{}: 1", self.string()));
        }
        self.shuffle_drop(&mut fields);
        format!("{{ {} }}", fields.join(", "))
    }

    /// Occasionally drops a required field or swaps the order.
    fn shuffle_drop(&mut self, fields: &mut Vec<String>) {
        let drop = if self.sane { 0.01 } else { 0.05 };
        if self.rng.chance(drop) && !fields.is_empty() {
            let i = self.rng.below(fields.len());
            fields.remove(i);
        }
        if fields.len() > 1 && self.rng.chance(0.3) {
            let (i, j) = (self.rng.below(fields.len()), self.rng.below(fields.len()));
            fields.swap(i, j);
        }
    }

    fn light(&mut self) -> String {
        let mut fields = if self.rng.chance(0.5) {
            vec![
                "\"type\": \"spot\"".to_string(),
                format!("\"position\": {}", self.vec(3)),
                format!("\"direction\": {}", self.vec(3)),
                format!("\"cone_angle_deg\": {}", self.number()),
                format!("\"intensity\": {}", self.number()),
            ]
        } else {
            vec![
                format!(
                    "\"type\": {}",
                    self.rng.pick(&["\"directional\"", "\"area\"", "3"])
                ),
                format!("\"direction\": {}", self.vec(3)),
                format!("\"irradiance\": {}", self.number()),
                format!("\"center\": {}", self.vec(3)),
                format!("\"half_extent\": {}", self.number()),
                format!("\"distance\": {}", self.number()),
            ]
        };
        fields.push(format!("\"near\": {}", self.number()));
        fields.push(format!("\"far\": {}", self.number()));
        self.shuffle_drop(&mut fields);
        format!("{{ {} }}", fields.join(", "))
    }

    fn document(&mut self) -> String {
        self.sane = self.rng.chance(0.5);
        let format = self.rng.pick(&[
            "\"motion-shadows-scene/1\"",
            "\"motion-shadows-scene/1\"",
            "\"motion-shadows-scene/1\"",
            "\"motion-shadows-scene/2\"",
            "1",
            "null",
        ]);
        let mut fields = vec![format!("\"format\": {format}")];
        if self.rng.chance(0.6) {
            fields.push(format!("\"name\": {}", self.string()));
        }
        // Half the documents get a known-good camera and light and mostly plausible objects,
        // so that valid scenes come out too, not only errors.
        if self.sane {
            fields.push(
                "\"camera\": { \"position\": [0, 4, 6], \"target\": [0, 0, 0], \"fov_y_deg\": 45, \
                 \"near\": 0.1, \"far\": 50 }"
                    .into(),
            );
            fields.push(
                "\"light\": { \"type\": \"spot\", \"position\": [0, 6, 0], \"direction\": [0, -1, 0], \
                 \"cone_angle_deg\": 40, \"intensity\": 10, \"near\": 0.5, \"far\": 20 }"
                    .into(),
            );
            let count = 1 + self.rng.below(3);
            let objects: Vec<String> = (0..count).map(|_| self.object()).collect();
            fields.push(format!("\"objects\": [{}]", objects.join(", ")));
            return format!("{{ {} }}", fields.join(",\n"));
        }
        let mut camera = vec![
            format!("\"position\": {}", self.vec(3)),
            format!("\"target\": {}", self.vec(3)),
            format!("\"fov_y_deg\": {}", self.number()),
            format!("\"near\": {}", self.number()),
            format!("\"far\": {}", self.number()),
        ];
        if self.rng.chance(0.3) {
            camera.push(format!("\"up\": {}", self.vec(3)));
        }
        self.shuffle_drop(&mut camera);
        fields.push(format!("\"camera\": {{ {} }}", camera.join(", ")));
        fields.push(format!("\"light\": {}", self.light()));
        if self.rng.chance(0.3) {
            fields.push(format!("\"ambient\": {}", self.number()));
        }
        let count = [0, 1, 1, 2, 3, 5][self.rng.below(6)];
        let objects: Vec<String> = (0..count).map(|_| self.object()).collect();
        fields.push(format!("\"objects\": [{}]", objects.join(", ")));
        self.shuffle_drop(&mut fields);
        format!("{{ {} }}", fields.join(",\n"))
    }

    /// Text-level damage: cuts, duplications, junk tokens, deep nesting.
    fn mutate(&mut self, text: String) -> String {
        let mut bytes = text.into_bytes();
        for _ in 0..1 + self.rng.below(3) {
            let len = bytes.len().max(1);
            let at = self.rng.below(len).min(bytes.len());
            match self.rng.below(5) {
                0 => {
                    let end = (at + self.rng.below(40)).min(bytes.len());
                    bytes.drain(at..end);
                }
                1 => {
                    let end = (at + self.rng.below(200)).min(bytes.len());
                    let copy = bytes[at..end].to_vec();
                    insert(&mut bytes, at, &copy);
                }
                2 => {
                    let junk = self.rng.pick(&[
                        "{", "}", "[", "]", ",", ":", "\"", "null", "1e999", "-", "\\u", "\u{ff}",
                        "true",
                    ]);
                    insert(&mut bytes, at, junk.as_bytes());
                }
                3 => {
                    let depth = 1 + self.rng.below(5000);
                    insert(&mut bytes, at, "[".repeat(depth).as_bytes());
                }
                _ => bytes.truncate(at),
            }
        }
        String::from_utf8_lossy(&bytes).into_owned()
    }
}

fn insert(bytes: &mut Vec<u8>, at: usize, what: &[u8]) {
    let tail = bytes.split_off(at);
    bytes.extend_from_slice(what);
    bytes.extend_from_slice(&tail);
}

fn obj_fixtures(dir: &Path) -> Vec<String> {
    std::fs::create_dir_all(dir).unwrap();
    let write = |name: &str, text: &str| {
        let path: PathBuf = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_string_lossy().into_owned()
    };
    vec![
        write(
            "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nf 1 2 3 4\n",
        ),
        write("bad-index.obj", "v 0 0 0\nf 1 2 9\n"),
        write("empty.obj", ""),
        write("junk.obj", "\u{0}\u{1}{[ not an obj at all\nf -7 x\n"),
        write("nan.obj", "v nan 0 0\nv 1 inf 0\nv 0 0 1e39\nf 1 2 3\n"),
        dir.to_string_lossy().into_owned(),
        "/dev/zero".into(),
        "/nonexistent/model.obj".into(),
        "relative/missing.obj".into(),
    ]
}

#[test]
fn the_scene_parser_survives_generated_and_mutated_documents() {
    let dir = std::env::temp_dir().join(format!("motion-shadows-fuzz-{}", std::process::id()));
    let mut generator = Generator {
        rng: Rng(0x5eed_0010),
        sane: false,
        obj_paths: obj_fixtures(&dir),
    };
    // A fixed number of cases (no time budget: the same cases run on every machine).
    const CASES: usize = 30_000;
    let start = Instant::now();
    let (mut cases, mut valid, mut largest_peak) = (0usize, 0usize, 0usize);
    let mut failures = Vec::new();
    // The panic hook would print every caught panic; the failures are reported below.
    std::panic::set_hook(Box::new(|_| {}));
    while cases < CASES {
        let mut text = generator.document();
        if generator.rng.chance(0.4) {
            text = generator.mutate(text);
        }
        let baseline = counting_alloc::start_case();
        let outcome = std::panic::catch_unwind(|| {
            parse_scene_json(&text, &dir, "fuzz.json").map_err(|e| e.to_string())
        });
        let peak = counting_alloc::peak_since(baseline);
        largest_peak = largest_peak.max(peak);
        let problem = match outcome {
            Err(_) => Some("panicked".to_string()),
            Ok(Err(message)) if message.chars().count() > MAX_ERROR_CHARS => Some(format!(
                "error of {} characters: {}...",
                message.chars().count(),
                message.chars().take(200).collect::<String>()
            )),
            Ok(Ok(_)) => {
                valid += 1;
                None
            }
            Ok(Err(_)) => None,
        };
        let problem = problem.or_else(|| {
            (peak > CASE_PEAK_LIMIT).then(|| format!("allocated {} MiB at its peak", peak >> 20))
        });
        if let Some(problem) = problem {
            let input: String = text.chars().take(300).collect();
            failures.push(format!("case {cases}: {problem}; input starts: {input}"));
        }
        cases += 1;
    }
    let _ = std::panic::take_hook();
    let seconds = start.elapsed().as_secs_f64();
    println!(
        "scene fuzz: {cases} cases in {seconds:.1} s, {valid} valid scenes, {} failures, \
         largest peak allocation {:.1} MiB",
        failures.len(),
        largest_peak as f64 / (1024.0 * 1024.0)
    );
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        failures.is_empty(),
        "{} of {cases} cases failed:\n{}",
        failures.len(),
        failures
            .iter()
            .take(10)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(
        valid > 0,
        "no generated document was a valid scene: the generator is off"
    );
}
