//! The constants the shaders and the Rust side share, written once: build.rs turns the tables
//! [`GLSL_UINTS`], [`GLSL_INTS`] and [`GLSL_FLOATS`] into `const` declarations in the
//! generated include `gpu_constants.glsl` (in `OUT_DIR`), which `glsl/shared.glsl` and the
//! mask shaders include. The tunables whose value both sides depend on (a bound the host sizes
//! a buffer or a ceiling by, a margin a CPU model repeats) are here too, not copied by hand.
//! A shader naming a constant missing from the table fails to compile; a value changed here
//! changes on both sides.
//!
//! build.rs compiles this file as its own module (`#[path]`), so it holds plain constants only.

/// The most fragments one shadow-map pixel may hold. The generation pass sorts a pixel's list
/// in private memory; this bound also keeps every shader loop far below lavapipe's limit of
/// 65535 loop iterations per invocation, past which it silently leaves loops.
pub const MAX_LIST_NODES: u32 = 512;

/// Texels on a side of the tiles the generation pass visits (one 8x8 workgroup per tile,
/// through the indirect dispatch the collection sets).
pub const TILE_TEXELS: u32 = 8;

/// The map's `tiles` buffer holds three indirect dispatches of 4 words (x, y, z group counts
/// and a pad), set when the collection is recorded: the generation's pairing, the sort of
/// each texel's collected ranges, and the sort of the long lists (whose groups the first sort
/// counts into it). The word each starts at, and the buffer's words:
pub const DISPATCH_PAIRING: u32 = 0;
/// See [`DISPATCH_PAIRING`].
pub const DISPATCH_SORT: u32 = 4;
/// See [`DISPATCH_PAIRING`].
pub const DISPATCH_SORT_LONG: u32 = 8;
/// See [`DISPATCH_PAIRING`].
pub const DISPATCH_WORDS: u32 = 12;

/// The sort's tile list (issue 39): after its dispatch words, the `tiles` buffer holds a mark
/// per tile of the map, then the list of the tiles the collection stored a range in (each
/// marked and listed by the first range it stores there), which the sort's dispatch visits
/// instead of every tile of the map (on lavapipe a workgroup that finds nothing still costs
/// its setup). Its workgroups: this many across, in rows (a short row, so that the frames of
/// most tests, with more than 128 tiles holding ranges, go through the rows' arithmetic; the
/// dispatch's 65,535 rows then reach 8,388,480 tiles, maps of about 23,000 x 23,000 texels,
/// and a map with more tiles is refused); the pad word of the sort's dispatch counts the
/// listed tiles.
pub const SORT_TILE_ROW: u32 = 128;

/// `DrawRecord::index_kind`: no index stream.
pub const INDEX_NONE: u32 = 0;
/// `DrawRecord::index_kind`: 16-bit indices.
pub const INDEX_U16: u32 = 1;
/// `DrawRecord::index_kind`: 32-bit indices.
pub const INDEX_U32: u32 = 2;

/// Draw flag: the mesh is closed (a triangle facing away all frame may be culled).
pub const DRAW_CLOSED: u32 = 1;
/// Draw flag: both transforms are the identity (the shaders skip them).
pub const DRAW_UNTRANSFORMED: u32 = 2;
/// Draw flag: the same positions and transform at t = 0 and t = 1 (nothing moves; the exact
/// construction rasterizes its triangles directly).
pub const DRAW_STATIC: u32 = 4;
/// 64-bit words per draw record (160 bytes), as `load_draw` reads them.
pub const DRAW_RECORD_WORDS: u32 = 20;

/// The most samples of a pixel one lighting chunk renders: the shading keeps a chunk's hits
/// in private arrays of this size.
pub const MAX_SAMPLES_PER_CHUNK: u32 = 16;

/// The lighting pass's push flags: every sample at the pushed time.
pub const FIXED_TIME: u32 = 1;
/// A drawing pass's push flags: this draw counts its invalid triangles (once per frame).
pub const COUNT_INVALID: u32 = 4;
/// The conservative collection's push flag: this (static) draw's triangles go to the static
/// name lists (the exact lookup's static layer), not to the frame's ranges.
pub const STATIC_NAMES: u32 = 8;

/// `PlainMapHeader::size.w`: depth and triangle id.
pub const DEPTH_AND_ID: u32 = 0;
/// The same: depth alone (as the papers' time-dependent shadow maps store it).
pub const DEPTH_ONLY: u32 = 1;

/// The lighting pass's shadow test: the depth-time ranges (and coverage map).
pub const SHADOW_TEMPORAL: u32 = 0;
/// The same: one ordinary map (depth and id) for every sample.
pub const SHADOW_PLAIN: u32 = 1;
/// The same: no shadows.
pub const SHADOW_NONE: u32 = 2;
/// The same: time-dependent shadow maps, a sample in stratum s tests map s.
pub const SHADOW_TSM: u32 = 3;

/// Mask passes' flags: read the host's normal image (else rebuild normals from depth).
pub const MASK_HAS_NORMALS: u32 = 1;
/// Mask passes' flags: the normal image stores `n * 0.5 + 0.5`.
pub const MASK_NORMALS_UNORM: u32 = 2;
/// Visibility mask's flag: read the host's triangle-id image.
pub const MASK_HAS_IDS: u32 = 4;
/// Mask passes' flag: read the host's position image (else rebuild positions from depth).
pub const MASK_HAS_POSITIONS: u32 = 8;
/// Visibility mask's flag, moving receivers: a pixel whose motion is zero is tested as a
/// standing receiver is (the receiver-plane test, no normal offset).
pub const MASK_STILL_PIXELS_PLANE: u32 = 0x40;
/// Engine TSM mask's flag: the first batch (write the count, do not add).
pub const TSM_FIRST_BATCH: u32 = 0x10;
/// Engine TSM mask's flag: the last batch (turn the count into the lit fraction).
pub const TSM_LAST_BATCH: u32 = 0x20;

/// The most covered runs the exact prism finds in one texel (`ExactRuns` in
/// `glsl/exact_prism.glsl`): at most 6 edge roots and 3 light crossings cut the shutter into
/// 10 pieces, at most 5 covered. The room reserved for the exact construction's ranges
/// (`range_ceiling`) is this many per texel a moving triangle touches. A GLSL `int`.
pub const EXACT_MAX_RUNS: u32 = 5;

/// Pruning's margin, relative to the depths compared (`glsl/range_sort_lists.glsl`,
/// `glsl/range_cover.glsl`; docs/src/pruning.md): about 80 float ulps, far above a lookup's
/// rounding, far below the depth bias (1e-4 by default). The tests' CPU model of pruning
/// uses it too.
pub const PRUNE_MARGIN: f32 = 1e-5;

/// The most steps of pruning's cover sweep per texel (`glsl/range_cover.glsl`): far below
/// lavapipe's 65,535 loop iterations per invocation with the sort's own loops. A texel that
/// runs out keeps the ranges it has not decided.
pub const PRUNE_BUDGET: u32 = 16384;

/// The visibility mask's overflow queues (`mask_queue.rs`, `glsl/visibility_mask.comp`): 32-bit
/// words of a round's header (x, y, z groups of its indirect dispatch, its count of entries, its
/// count of carried unions).
pub const QUEUE_HEADER_WORDS: u32 = 5;
/// Words of a queue entry: pixel, t, texel, sum, limit, cursor, carry slot.
pub const QUEUE_ENTRY_WORDS: u32 = 7;
/// Words of a carried union of shadowed intervals (its vectors s0, s1, e0, e1).
pub const CARRY_WORDS: u32 = 16;
/// A carry pool holds one union per this many queue entries (rounded up).
pub const CARRY_SHARE: u32 = 8;

/// Every constant above by its GLSL name.
pub const GLSL_UINTS: &[(&str, u32)] = &[
    ("MAX_LIST_NODES", MAX_LIST_NODES),
    ("TILE_TEXELS", TILE_TEXELS),
    ("DISPATCH_PAIRING", DISPATCH_PAIRING),
    ("SORT_TILE_ROW", SORT_TILE_ROW),
    ("DISPATCH_SORT", DISPATCH_SORT),
    ("DISPATCH_SORT_LONG", DISPATCH_SORT_LONG),
    ("DISPATCH_WORDS", DISPATCH_WORDS),
    ("INDEX_NONE", INDEX_NONE),
    ("INDEX_U16", INDEX_U16),
    ("INDEX_U32", INDEX_U32),
    ("DRAW_CLOSED", DRAW_CLOSED),
    ("DRAW_UNTRANSFORMED", DRAW_UNTRANSFORMED),
    ("DRAW_STATIC", DRAW_STATIC),
    ("DRAW_RECORD_WORDS", DRAW_RECORD_WORDS),
    ("MAX_SAMPLES_PER_CHUNK", MAX_SAMPLES_PER_CHUNK),
    ("FIXED_TIME", FIXED_TIME),
    ("COUNT_INVALID", COUNT_INVALID),
    ("STATIC_NAMES", STATIC_NAMES),
    ("DEPTH_AND_ID", DEPTH_AND_ID),
    ("DEPTH_ONLY", DEPTH_ONLY),
    ("SHADOW_TEMPORAL", SHADOW_TEMPORAL),
    ("SHADOW_PLAIN", SHADOW_PLAIN),
    ("SHADOW_NONE", SHADOW_NONE),
    ("SHADOW_TSM", SHADOW_TSM),
    ("MASK_HAS_NORMALS", MASK_HAS_NORMALS),
    ("MASK_NORMALS_UNORM", MASK_NORMALS_UNORM),
    ("MASK_HAS_IDS", MASK_HAS_IDS),
    ("MASK_HAS_POSITIONS", MASK_HAS_POSITIONS),
    ("MASK_STILL_PIXELS_PLANE", MASK_STILL_PIXELS_PLANE),
    ("TSM_FIRST_BATCH", TSM_FIRST_BATCH),
    ("TSM_LAST_BATCH", TSM_LAST_BATCH),
    ("PRUNE_BUDGET", PRUNE_BUDGET),
    ("QUEUE_HEADER_WORDS", QUEUE_HEADER_WORDS),
    ("QUEUE_ENTRY_WORDS", QUEUE_ENTRY_WORDS),
    ("CARRY_WORDS", CARRY_WORDS),
    ("CARRY_SHARE", CARRY_SHARE),
];

/// The constants the shaders declare as `int` (array sizes and loop bounds compared with
/// `int` counters).
pub const GLSL_INTS: &[(&str, i32)] = &[("EXACT_MAX_RUNS", EXACT_MAX_RUNS as i32)];

/// The constants the shaders declare as `float`.
pub const GLSL_FLOATS: &[(&str, f32)] = &[("PRUNE_MARGIN", PRUNE_MARGIN)];

/// Every name the generated include declares.
pub fn glsl_names() -> impl Iterator<Item = &'static str> {
    let uints = GLSL_UINTS.iter().map(|(n, _)| *n);
    let ints = GLSL_INTS.iter().map(|(n, _)| *n);
    uints.chain(ints).chain(GLSL_FLOATS.iter().map(|(n, _)| *n))
}

/// The generated GLSL include: one `const uint NAME = VALUEu;` per entry of [`GLSL_UINTS`],
/// `const int` per entry of [`GLSL_INTS`], `const float` per entry of [`GLSL_FLOATS`] (written
/// so that it reads back as the same f32: Rust's shortest round-trip form, which always has a
/// `.` or an exponent).
pub fn glsl_header() -> String {
    let mut s = String::from(
        "// Generated by build.rs from src/technique/gpu_constants.rs: edit the constants there.\n\
         #ifndef MS_GPU_CONSTANTS\n#define MS_GPU_CONSTANTS\n",
    );
    for (name, value) in GLSL_UINTS {
        s.push_str(&format!("const uint {name} = {value}u;\n"));
    }
    for (name, value) in GLSL_INTS {
        s.push_str(&format!("const int {name} = {value};\n"));
    }
    for (name, value) in GLSL_FLOATS {
        s.push_str(&format!("const float {name} = {value:?};\n"));
    }
    s.push_str("#endif\n");
    s
}

/// The public header (`glsl/motion_shadows.glsl`, served to hosts as `GLSL_INCLUDE`) must
/// stand alone in a host's shader compiler, so it writes its own `MS_*` constants: these
/// tests hold each to its Rust counterpart, and the generated table to the shaders' use.
#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::{GLSL_INCLUDE, gpu_types::NO_TRIANGLE};

    /// The value of `const uint NAME = VALUE;` in `source` (decimal or 0x hex, `u` suffix).
    fn glsl_uint(source: &str, name: &str) -> u32 {
        let prefix = format!("const uint {name} = ");
        let line = source
            .lines()
            .find_map(|l| l.trim_start().strip_prefix(prefix.as_str()))
            .unwrap_or_else(|| panic!("no `{prefix}...` in the GLSL"));
        let literal = line.split(';').next().unwrap().trim().trim_end_matches('u');
        match literal.strip_prefix("0x") {
            Some(hex) => u32::from_str_radix(hex, 16).unwrap(),
            None => literal.parse().unwrap(),
        }
    }

    #[test]
    fn the_public_header_agrees_with_the_rust_constants() {
        // List links are index + 1: 0 ends a list (Node::next, Range::next).
        assert_eq!(glsl_uint(GLSL_INCLUDE, "MS_END_OF_LIST"), 0);
        assert_eq!(glsl_uint(GLSL_INCLUDE, "MS_NO_TRIANGLE"), NO_TRIANGLE);
        // A texel's lists hold at most MAX_LIST_NODES entries, so no more ranges than that.
        assert_eq!(
            glsl_uint(GLSL_INCLUDE, "MS_MAX_TEXEL_RANGES"),
            MAX_LIST_NODES
        );
        assert_eq!(
            glsl_uint(GLSL_INCLUDE, "MS_SORTED_RANGES"),
            crate::technique::shadow_map::MS_SORTED_RANGES
        );
    }

    /// The value of `const TYPE NAME = VALUE;` in `source`, as written.
    fn glsl_literal<'a>(source: &'a str, ty: &str, name: &str) -> &'a str {
        let prefix = format!("const {ty} {name} = ");
        let line = source
            .lines()
            .find_map(|l| l.trim_start().strip_prefix(prefix.as_str()))
            .unwrap_or_else(|| panic!("no `{prefix}...` in the GLSL"));
        line.split(';').next().unwrap().trim()
    }

    #[test]
    fn the_generated_header_declares_every_constant_once() {
        let header = glsl_header();
        for (name, value) in GLSL_UINTS {
            assert_eq!(glsl_uint(&header, name), *value, "{name}");
        }
        for (name, value) in GLSL_INTS {
            assert_eq!(
                glsl_literal(&header, "int", name).parse::<i32>(),
                Ok(*value)
            );
        }
        for (name, value) in GLSL_FLOATS {
            // GLSL reads the literal as the nearest f32, as Rust's parse does.
            let literal = glsl_literal(&header, "float", name);
            assert!(
                literal.contains(['.', 'e']),
                "{name} = {literal} is not a float literal"
            );
            let read: f32 = literal.parse().unwrap();
            assert_eq!(read.to_bits(), value.to_bits(), "{name}");
        }
        for name in glsl_names() {
            assert_eq!(header.matches(&format!(" {name} ")).count(), 1, "{name}");
        }
    }

    /// Where `source` defines `name` itself: a `const` of any type, or a `#define`.
    fn defines(source: &str, name: &str) -> Option<String> {
        source
            .lines()
            .map(str::trim)
            .find(|line| {
                let mut words = line.split(|c: char| c.is_whitespace() || c == '=');
                let words: Vec<_> = words.by_ref().filter(|w| !w.is_empty()).take(3).collect();
                match words.as_slice() {
                    ["#define", n, ..] => *n == name || n.starts_with(&format!("{name}(")),
                    ["const", _, n] => *n == name,
                    _ => false,
                }
            })
            .map(str::to_owned)
    }

    /// No GLSL file, the library's or the tests' probes, writes one of the table's values by
    /// hand, of any type: each comes from gpu_constants.glsl only.
    #[test]
    fn no_shader_writes_a_generated_constant_by_hand() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut files = 0;
        for dir in ["glsl", "tests/glsl"] {
            for path in crate::technique::glsl_files::glsl_files(&root.join(dir)) {
                let source = std::fs::read_to_string(&path).unwrap();
                files += 1;
                for name in glsl_names() {
                    if let Some(line) = defines(&source, name) {
                        panic!(
                            "{} defines {name} itself (`{line}`): it comes from \
                             gpu_constants.glsl (src/technique/gpu_constants.rs)",
                            path.display()
                        );
                    }
                }
            }
        }
        assert!(files > 40, "read only {files} GLSL files");
    }

    #[test]
    fn the_definition_finder_sees_every_form() {
        assert!(defines("  const float PRUNE_MARGIN = 1e-5;", "PRUNE_MARGIN").is_some());
        assert!(defines("const int EXACT_MAX_RUNS=5;", "EXACT_MAX_RUNS").is_some());
        assert!(defines("#define CARRY_WORDS 16u", "CARRY_WORDS").is_some());
        assert!(defines("#define CARRY_WORDS(x) x", "CARRY_WORDS").is_some());
        assert!(defines("float m = PRUNE_MARGIN * d;", "PRUNE_MARGIN").is_none());
        assert!(defines("const uint PRUNE_BUDGETS = 1u;", "PRUNE_BUDGET").is_none());
    }
}
