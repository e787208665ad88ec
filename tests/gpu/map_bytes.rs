//! A temporal shadow map allocates only the buffers its path uses (issue 37, item 5): its
//! bytes against the table of docs/src/integration.md#bytes-per-map, written out here from
//! the documented sizes (not from the library's constants), for the default path and for two
//! others; and a map made for the default path refuses a frame whose path needs a buffer it
//! lacks, naming `prepare_for`.

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::OneShot;
use motion_shadows::technique::{CollectionPass, DrawList, LightView, Lookup, TemporalShadowMap};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 32;
const NODES: u32 = 1000;
const RANGES: u32 = 2000;

/// The map's 8x8-texel tiles.
const TILES: u64 = (WIDTH as u64).div_ceil(8) * (HEIGHT as u64).div_ceil(8);

/// The table's fixed part, in bytes: the header (480), the counters (48), the generation's
/// dispatches (48) and the sort's tile marks and list (4 + 4 per tile).
const FIXED: u64 = 480 + 48 + 48 + (4 + 4) * TILES;

fn light() -> LightView {
    LightView::spot(
        Vec3::new(0.0, 8.0, 0.0),
        Vec3::NEG_Y,
        30.0,
        100.0,
        0.5,
        20.0,
        (WIDTH, HEIGHT),
    )
}

fn texels() -> u64 {
    u64::from(WIDTH) * u64::from(HEIGHT)
}

/// The default path (exact construction, static layer, depth lines, sorted ranges): node and
/// range heads (4 + 4 per texel), the ranges and their sorting's lists (24 + 24 per range),
/// the long lists (16 + 4 per texel) and the static layer (8 per texel); no node buffer (one
/// node, 16).
#[test]
fn the_default_map_holds_the_default_paths_buffers_only() {
    let ctx = context();
    let mut map = TemporalShadowMap::new(&ctx, WIDTH, HEIGHT, NODES, RANGES).expect("map");
    let (p, r) = (texels(), u64::from(RANGES));
    let expected = FIXED + (4 + 4) * p + (24 + 24) * r + (16 + 4 * p) + 8 * p + 16;
    assert_eq!(map.allocated_bytes(), expected);
    map.prepare_for(&ctx, &light(), None).expect("prepared");
    assert_eq!(
        map.allocated_bytes(),
        expected,
        "the default light changes nothing"
    );
    assert_no_validation_messages(&ctx);
}

/// Two other paths, after `prepare_for`: the papers' lists (static layer off: the node buffer
/// at 16 per node and the long lists, no sorting lists (one range, 24) and no static layer
/// (one key, 8)); the exact lookup (no node buffer, sorting lists, long lists (their 16-byte
/// header only) or static layer).
#[test]
fn a_map_prepared_for_another_path_holds_that_paths_buffers_only() {
    let ctx = context();
    let (p, n, r) = (texels(), u64::from(NODES), u64::from(RANGES));
    let lists = LightView {
        static_layer: false,
        ..light()
    };
    let exact = LightView {
        lookup: Lookup::Exact,
        ..light()
    };
    let heads_and_ranges = FIXED + (4 + 4) * p + 24 * r;
    for (what, light, expected) in [
        (
            "the papers' lists",
            lists,
            heads_and_ranges + 16 * n + 24 + (16 + 4 * p) + 8,
        ),
        (
            "the exact lookup",
            exact,
            heads_and_ranges + 16 + 24 + 16 + 8,
        ),
    ] {
        let mut map = TemporalShadowMap::new(&ctx, WIDTH, HEIGHT, NODES, RANGES).expect("map");
        map.prepare_for(&ctx, &light, None).expect("prepared");
        assert_eq!(map.allocated_bytes(), expected, "{what}");
        assert_eq!(map.node_capacity(), NODES, "{what}");
        assert_eq!(map.range_capacity(), RANGES, "{what}");
    }
    assert_no_validation_messages(&ctx);
}

/// A map made for the default path has no node buffer: a frame that stores fragments (static
/// layer off) is refused before anything is recorded, naming what to call.
#[test]
fn a_frame_whose_path_the_map_was_not_prepared_for_is_refused() {
    let ctx = context();
    let map = TemporalShadowMap::new(&ctx, WIDTH, HEIGHT, NODES, RANGES).expect("map");
    let collection = CollectionPass::new(&ctx).expect("collection");
    let draws = DrawList::new(&ctx, 1).expect("draw list");
    let lists = LightView {
        static_layer: false,
        ..light()
    };
    let mut refusal = None;
    let submitted = OneShot::new(&ctx).expect("command buffer").run(|cmd| {
        // SAFETY: a OneShot command buffer of the context, recording, outside rendering; the
        // draw list holds no draw.
        refusal = unsafe { collection.record(ctx.device(), cmd, &draws, &lists, &map, None) }.err();
        Err(Error::InvalidArgument("not submitted".into()))
    });
    assert!(submitted.is_err());
    let refusal = refusal.expect("refused").to_string();
    assert!(
        refusal.contains("TemporalShadowMap::prepare_for"),
        "{refusal}"
    );
    assert!(refusal.contains("node"), "{refusal}");
    assert_no_validation_messages(&ctx);
}

/// A map with more 8x8-texel tiles than the sort's dispatch reaches (128 across, 65,535
/// rows: 8,388,480 tiles) is refused by name before anything is allocated, rather than
/// leaving its farthest tiles unsorted.
#[test]
fn a_map_past_the_sorts_dispatch_is_refused() {
    let ctx = context();
    // 2,900 x 2,893 = 8,389,700 tiles.
    match TemporalShadowMap::new(&ctx, 23200, 23144, 1, 1) {
        Err(Error::InvalidArgument(message)) => assert!(
            message.contains("23200x23144") && message.contains("tiles"),
            "{message}"
        ),
        Err(other) => panic!("refused for another reason: {other}"),
        Ok(_) => panic!("a 23200x23144 map was made"),
    }
    assert_no_validation_messages(&ctx);
}
