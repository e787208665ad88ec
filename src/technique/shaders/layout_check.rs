//! The device-free layout check: every struct the Rust side shares with the shaders
//! (`gpu_types`, `push_constants`) against the layout the compiled shaders themselves use,
//! read from the SPIR-V build.rs wrote (the very bytes [`super`] embeds). Both sides are
//! flattened into scalars by byte offset: each GLSL scalar must have a Rust scalar of the
//! same kind at the same offset, belonging to a member of the same name, and the other way
//! round; only Rust fields in a GLSL struct's tail padding have no counterpart. Sizes (the
//! GLSL struct's rounded up to its std430 alignment) must be equal.

use super::rust_structs::{Flatten, leaves};
use super::spirv_structs::{Leaf, Module};
use super::*;
use crate::technique::gpu_types::{
    CameraParams, Counters, DrawRecord, GpuCameraEnd, GpuLight, GpuLightEnd, LongListHeader, Node,
    PlainMapHeader, Range, ShadowMapHeader,
};
use crate::technique::push_constants::{
    DrawPush, GBufferPush, LightingRasterPush, MapDrawPush, MapPush, MaskPush, RadiancePush,
    RasterCamera, RasterPush, ShadePush, TsmMaskPush,
};

/// Members named differently on the two sides: (Rust field, GLSL member).
const RENAMED: &[(&str, &str)] = &[
    // LongListHeader: an indirect dispatch's three counts, an array in Rust.
    ("groups", "groups_x"),
    ("groups", "groups_y"),
    ("groups", "groups_z"),
];

/// A Rust mirror: its name, its flattened scalars and its size.
struct Mirror {
    rust: &'static str,
    leaves: Vec<Leaf>,
    size: u32,
}

fn mirror<T: Flatten>(rust: &'static str) -> Mirror {
    Mirror {
        rust,
        leaves: leaves::<T>(),
        size: size_of::<T>() as u32,
    }
}

/// The structs shared through buffers and push constants, by their GLSL name.
fn shared_structs() -> Vec<(&'static str, Mirror)> {
    vec![
        ("MsLight", mirror::<GpuLight>("GpuLight")),
        // MsShadowMap ends where the moving light's pose begins (`light_end`: MsLightEnd,
        // read at MS_LIGHT_END_OFFSET, glsl/light_motion.glsl).
        (
            "MsShadowMap",
            Mirror {
                size: std::mem::offset_of!(ShadowMapHeader, light_end) as u32,
                ..mirror::<ShadowMapHeader>("ShadowMapHeader")
            },
        ),
        ("MsLightEnd", mirror::<GpuLightEnd>("GpuLightEnd")),
        ("PlainHeader", mirror::<PlainMapHeader>("PlainMapHeader")),
        ("Counters", mirror::<Counters>("Counters")),
        ("LongListHeader", mirror::<LongListHeader>("LongListHeader")),
        ("DrawRecord", mirror::<DrawRecord>("DrawRecord")),
        ("DrawPush", mirror::<DrawPush>("DrawPush")),
        ("MapDrawPush", mirror::<MapDrawPush>("MapDrawPush")),
        ("MapPush", mirror::<MapPush>("MapPush")),
        (
            "LightingRasterPush",
            mirror::<LightingRasterPush>("LightingRasterPush"),
        ),
        ("RasterCamera", mirror::<RasterCamera>("RasterCamera")),
        ("ShadePush", mirror::<ShadePush>("ShadePush")),
        ("MaskPush", mirror::<MaskPush>("MaskPush")),
        ("TsmMaskPush", mirror::<TsmMaskPush>("TsmMaskPush")),
        ("GBufferPush", mirror::<GBufferPush>("GBufferPush")),
        ("RadiancePush", mirror::<RadiancePush>("RadiancePush")),
        // Laid out by the layout witness only (build.rs).
        ("Node", mirror::<Node>("Node")),
        ("MsRange", mirror::<Range>("Range")),
        ("CameraParams", mirror::<CameraParams>("CameraParams")),
        ("CameraEnd", mirror::<GpuCameraEnd>("GpuCameraEnd")),
    ]
}

/// Every shader build.rs compiles, with the Rust block its push constants mirror (`None`:
/// it has none).
fn shaders() -> Vec<(&'static str, Spirv<'static>, Option<Mirror>)> {
    let map_draw = || Some(mirror::<MapDrawPush>("MapDrawPush"));
    let map = || Some(mirror::<MapPush>("MapPush"));
    vec![
        (
            "scene.vert",
            SCENE_VERT,
            Some(mirror::<DrawPush>("DrawPush")),
        ),
        ("collection.geom", COLLECTION_GEOM, map_draw()),
        ("collection.frag", COLLECTION_FRAG, map_draw()),
        ("collection_exact.geom", COLLECTION_EXACT_GEOM, map_draw()),
        (
            "collection_conservative.geom",
            COLLECTION_CONSERVATIVE_GEOM,
            map_draw(),
        ),
        (
            "collection_conservative.frag",
            COLLECTION_CONSERVATIVE_FRAG,
            map_draw(),
        ),
        ("collection_exact.frag", COLLECTION_EXACT_FRAG, map_draw()),
        ("collection_ranges.frag", COLLECTION_RANGES_FRAG, map_draw()),
        ("collection_static.vert", COLLECTION_STATIC_VERT, map_draw()),
        ("collection_static.frag", COLLECTION_STATIC_FRAG, map_draw()),
        ("generation.comp", GENERATION_COMP, map()),
        ("generation_long.comp", GENERATION_LONG_COMP, map()),
        ("range_sort.comp", RANGE_SORT_COMP, map()),
        ("range_sort_long.comp", RANGE_SORT_LONG_COMP, map()),
        (
            "lighting.geom",
            LIGHTING_GEOM,
            Some(mirror::<LightingRasterPush>("LightingRasterPush")),
        ),
        (
            "lighting_camera_moves.geom",
            LIGHTING_CAMERA_MOVES_GEOM,
            Some(mirror::<LightingRasterPush>("LightingRasterPush")),
        ),
        (
            "lighting.frag",
            LIGHTING_FRAG,
            Some(mirror::<RasterPush>("RasterPush")),
        ),
        (
            "resolve.comp",
            RESOLVE_COMP,
            Some(mirror::<ShadePush>("ShadePush")),
        ),
        ("shadow_depth.vert", SHADOW_DEPTH_VERT, map_draw()),
        ("shadow_depth.frag", SHADOW_DEPTH_FRAG, None),
        ("coverage_caps.vert", COVERAGE_CAPS_VERT, map_draw()),
        ("coverage.frag", COVERAGE_FRAG, map_draw()),
        ("coverage_reset.frag", COVERAGE_RESET_FRAG, map_draw()),
        (
            "coverage_reset_exact.frag",
            COVERAGE_RESET_EXACT_FRAG,
            map_draw(),
        ),
        (
            "coverage_reset_static.frag",
            COVERAGE_RESET_STATIC_FRAG,
            map_draw(),
        ),
        (
            "visibility_mask.comp",
            VISIBILITY_MASK_COMP,
            Some(mirror::<MaskPush>("MaskPush")),
        ),
        (
            "tsm_mask.comp",
            TSM_MASK_COMP,
            Some(mirror::<TsmMaskPush>("TsmMaskPush")),
        ),
        (
            "radiance_to_image.comp",
            RADIANCE_TO_IMAGE_COMP,
            Some(mirror::<RadiancePush>("RadiancePush")),
        ),
        (
            "gbuffer.vert",
            GBUFFER_VERT,
            Some(mirror::<GBufferPush>("GBufferPush")),
        ),
        (
            "gbuffer.frag",
            GBUFFER_FRAG,
            Some(mirror::<GBufferPush>("GBufferPush")),
        ),
        // build.rs's layout witness (never run): the structs the stages read only as words.
        (
            "layout_witness.comp",
            Spirv::trusted(include_bytes!(concat!(
                env!("OUT_DIR"),
                "/layout_witness.comp.spv"
            ))),
            None,
        ),
    ]
}

/// What differs between a GLSL struct (its scalars and rounded size) and its mirror, one
/// line per difference, each naming the byte offset, both members and both kinds.
fn differences(
    glsl: &str,
    (glsl_leaves, glsl_size): (&[Leaf], u32),
    mirror: &Mirror,
) -> Vec<String> {
    let rust = mirror.rust;
    let end = glsl_leaves
        .iter()
        .map(|l| l.offset + l.scalar.bytes())
        .max()
        .unwrap_or(0);
    let mut found = Vec::new();
    for g in glsl_leaves {
        match mirror.leaves.iter().find(|r| r.offset == g.offset) {
            None => found.push(format!(
                "{glsl}.{} ({:?} at byte {}) has no Rust field there in {rust}",
                g.name, g.scalar, g.offset
            )),
            Some(r) if r.scalar != g.scalar => found.push(format!(
                "at byte {}: {glsl}.{} is {:?} but {rust}.{} is {:?}",
                g.offset, g.name, g.scalar, r.name, r.scalar
            )),
            Some(r)
                if r.name != g.name && !RENAMED.contains(&(r.name.as_str(), g.name.as_str())) =>
            {
                found.push(format!(
                    "at byte {}: {glsl}.{} but {rust}.{}",
                    g.offset, g.name, r.name
                ))
            }
            Some(_) => {}
        }
    }
    for r in &mirror.leaves {
        // Rust fields in the GLSL struct's tail padding (zeroed, so the struct is plain
        // data) have no GLSL counterpart; any other must have one.
        if r.offset < end && !glsl_leaves.iter().any(|g| g.offset == r.offset) {
            found.push(format!(
                "{rust}.{} ({:?} at byte {}) has no GLSL member there in {glsl}",
                r.name, r.scalar, r.offset
            ));
        }
    }
    if glsl_size != mirror.size {
        found.push(format!(
            "{glsl} is {glsl_size} bytes (std430, rounded to its alignment), {rust} {}",
            mirror.size
        ));
    }
    found
}

/// Every shared struct and push block of every shader, against its mirror: the
/// differences, and how many GLSL structs were compared for each name.
fn check() -> (Vec<String>, std::collections::BTreeMap<&'static str, usize>) {
    let structs = shared_structs();
    let mut problems = Vec::new();
    let mut compared: std::collections::BTreeMap<&str, usize> =
        structs.iter().map(|(g, _)| (*g, 0)).collect();
    for (shader, spirv, push) in shaders() {
        let module = match Module::parse(spirv.bytes()) {
            Ok(m) => m,
            Err(e) => {
                problems.push(format!("{shader}: {e}"));
                continue;
            }
        };
        let mut compare = |glsl: &str, id: u32, mirror: &Mirror| match module.flatten(id) {
            Ok((leaves, size)) => problems.extend(
                differences(glsl, (&leaves, size), mirror)
                    .into_iter()
                    .map(|d| format!("{shader}: {d}")),
            ),
            Err(e) => problems.push(format!("{shader}: {glsl}: {e}")),
        };
        for (glsl, mirror) in &structs {
            for id in module.laid_out_structs(glsl) {
                compare(glsl, id, mirror);
                *compared.get_mut(glsl).unwrap() += 1;
            }
        }
        let blocks = module.laid_out_structs("Push");
        match (&push, blocks.as_slice()) {
            (Some(mirror), &[id]) => compare("Push", id, mirror),
            (None, &[]) => {}
            _ => problems.push(format!(
                "{shader}: {} push-constant blocks, the table says {}",
                blocks.len(),
                push.as_ref().map_or("none", |m| m.rust)
            )),
        }
    }
    (problems, compared)
}

#[test]
fn every_shared_struct_matches_the_compiled_shaders() {
    let (problems, compared) = check();
    assert!(
        problems.is_empty(),
        "layouts differ:\n{}",
        problems.join("\n")
    );
    // A struct no shader lays out is checked nowhere: that is a failure, not a pass.
    let unseen: Vec<_> = compared.iter().filter(|(_, n)| **n == 0).collect();
    assert!(unseen.is_empty(), "no compiled shader lays out {unseen:?}");
}

#[test]
fn the_check_covers_every_compiled_shader() {
    let listed: Vec<String> = shaders().iter().map(|(n, ..)| format!("{n}.spv")).collect();
    let out = std::path::Path::new(env!("OUT_DIR"));
    for entry in std::fs::read_dir(out).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        if name.ends_with(".spv") {
            assert!(
                listed.contains(&name),
                "{name} is not in the layout check's table"
            );
        }
    }
}

/// The moving light's pose sits where the shaders read it: MS_LIGHT_END_OFFSET, which
/// glsl/light_motion.glsl writes itself (it is served to hosts beside the public header).
#[test]
fn the_light_end_sits_where_the_shaders_read_it() {
    let source = include_str!("../../../glsl/light_motion.glsl");
    let prefix = "const uint64_t MS_LIGHT_END_OFFSET = ";
    let literal = source
        .lines()
        .find_map(|l| l.trim_start().strip_prefix(prefix))
        .expect("light_motion.glsl defines MS_LIGHT_END_OFFSET");
    let offset: usize = literal
        .split(';')
        .next()
        .and_then(|v| v.trim().trim_end_matches("UL").parse().ok())
        .expect("MS_LIGHT_END_OFFSET is a decimal literal");
    assert_eq!(offset, std::mem::offset_of!(ShadowMapHeader, light_end));
}
