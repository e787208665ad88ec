//! The kept static layer does not depend on recordings being submitted: a collection pass
//! recorded and never submitted leaves nothing to undo (before, the map counted the layer as
//! drawn at record time, so the next pass kept a layer that was never drawn unless the host
//! called `forget_static_layer`). A layer is kept only after `static_layer_submitted`.

use crate::support::gpu::{assert_no_validation_messages, context};
use motion_shadows::Error;
use motion_shadows::glam::Vec3;
use motion_shadows::gpu::{Buffer, BufferUsage, Context, OneShot};
use motion_shadows::technique::{
    CollectionPass, Draw, DrawList, GenerationPass, Indices, LightView, Lookup, PositionStream,
    TemporalShadowMap,
};

const SIZE: u32 = 32;
/// The static triangle's id: not 0, so that zeroed memory does not pass for it.
const ID: u32 = 5;

/// A static triangle at y = 1 under a spot light at y = 8 looking down, covering the map's
/// centre and not its corners.
fn static_triangle(ctx: &Context) -> (Buffer, Draw) {
    let points = [
        [-2.0f32, 1.0, -2.0, 1.0],
        [2.0, 1.0, -2.0, 1.0],
        [0.0, 1.0, 2.0, 1.0],
    ];
    let buffer = Buffer::with_data(ctx, "triangle", BufferUsage::HostToDevice, &points)
        .expect("vertex buffer");
    let stream = PositionStream::from_buffer(&buffer, 0, 16).expect("stream");
    let draw = Draw::new(stream, stream, 3, Indices::None, 1, ID);
    assert!(draw.is_static());
    (buffer, draw)
}

struct Frame<'a> {
    ctx: &'a Context,
    collection: CollectionPass,
    generation: GenerationPass,
    draws: DrawList,
    light: LightView,
}

impl Frame<'_> {
    /// Records the collection pass of `map` and, if `submit`, submits the frame (with the
    /// generation and the counters) and waits; otherwise the recording is dropped.
    fn run(&self, map: &TemporalShadowMap, submit: bool) {
        let device = self.ctx.device();
        let result = OneShot::new(self.ctx).expect("command buffer").run(|cmd| {
            // SAFETY: a OneShot command buffer of the context, recording, outside rendering;
            // the draw list was uploaded in an earlier submission.
            unsafe {
                self.collection
                    .record(device, cmd, &self.draws, &self.light, map, None)?;
                if !submit {
                    return Err(Error::InvalidArgument("not submitted".into()));
                }
                self.generation.record(device, cmd, map);
                map.record_counter_readback(device, cmd);
            }
            Ok(())
        });
        assert_eq!(result.is_ok(), submit, "{result:?}");
    }
}

/// The texel (x, y)'s static-layer triangle id, if any.
fn layer_id(ctx: &Context, map: &TemporalShadowMap, x: u32, y: u32) -> Option<u32> {
    let layer = map.download_static_layer(ctx).expect("static layer");
    let id = layer[(y * SIZE + x) as usize] as u32;
    (id != u32::MAX).then_some(id)
}

#[test]
fn a_recorded_pass_that_is_not_submitted_needs_nothing_undone() {
    let ctx = context();
    let (vertices, draw) = static_triangle(&ctx);
    let mut draws = DrawList::new(&ctx, 1).expect("draw list");
    OneShot::new(&ctx)
        .expect("command buffer")
        // SAFETY: `cmd` is the OneShot's command buffer of this context, recording outside
        // rendering on its graphics and compute queue; no command buffer reads the new draw list
        // yet.
        .run(|cmd| unsafe { draws.record_update(ctx.device(), cmd, &[draw]) })
        .expect("draw list upload");
    let mut light = LightView::spot(
        Vec3::new(0.0, 8.0, 0.0),
        Vec3::NEG_Y,
        40.0,
        50.0,
        0.5,
        50.0,
        (SIZE, SIZE),
    );
    light.keep_static_layer = true;
    let frame = Frame {
        ctx: &ctx,
        collection: CollectionPass::new(&ctx).expect("collection pass"),
        generation: GenerationPass::new(&ctx).expect("generation pass"),
        draws,
        light,
    };
    let map = TemporalShadowMap::new(&ctx, SIZE, SIZE, 1, 1 << 12).expect("map");
    assert!(map.uses_static_layer(&frame.light, None));

    // Recorded, never submitted, nothing undone: the next (submitted) pass draws the layer.
    frame.run(&map, false);
    frame.run(&map, true);
    assert_eq!(
        map.static_layer_builds(),
        2,
        "the submitted pass drew the layer"
    );
    assert_eq!(
        layer_id(&ctx, &map, SIZE / 2, SIZE / 2),
        Some(ID),
        "the triangle at the centre"
    );
    assert_eq!(layer_id(&ctx, &map, 0, 0), None, "nothing in the corner");

    // Without `static_layer_submitted` a layer is not kept: redrawn.
    frame.run(&map, true);
    assert_eq!(map.static_layer_builds(), 3);
    // Once the host says the pass was submitted, later passes keep it.
    map.static_layer_submitted();
    frame.run(&map, true);
    frame.run(&map, true);
    assert_eq!(map.static_layer_builds(), 3, "kept");
    assert_eq!(layer_id(&ctx, &map, SIZE / 2, SIZE / 2), Some(ID));

    // After `forget_static_layer`, a redraw recorded and not submitted keeps nothing: the
    // next pass redraws.
    map.forget_static_layer();
    frame.run(&map, false);
    assert_eq!(map.static_layer_builds(), 4);
    frame.run(&map, true);
    assert_eq!(map.static_layer_builds(), 5);
    assert_eq!(layer_id(&ctx, &map, SIZE / 2, SIZE / 2), Some(ID));

    drop((map, frame, vertices));
    assert_no_validation_messages(&ctx);
}

/// The exact lookup's static name lists are redrawn, not added to: after a change of light
/// the redrawn lists name the triangle once in each texel (not also from the earlier draw),
/// and the count is the names held.
#[test]
fn the_exact_static_names_are_cleared_before_a_redraw() {
    let ctx = context();
    let (vertices, draw) = static_triangle(&ctx);
    let mut draws = DrawList::new(&ctx, 1).expect("draw list");
    OneShot::new(&ctx)
        .expect("command buffer")
        // SAFETY: `cmd` is the OneShot's command buffer of this context, recording outside
        // rendering on its graphics and compute queue; no command buffer reads the new draw list
        // yet.
        .run(|cmd| unsafe { draws.record_update(ctx.device(), cmd, &[draw]) })
        .expect("draw list upload");
    let spot_at = |x: f32| {
        let mut light = LightView::spot(
            Vec3::new(x, 8.0, 0.0),
            Vec3::NEG_Y,
            40.0,
            50.0,
            0.5,
            50.0,
            (SIZE, SIZE),
        );
        light.keep_static_layer = true;
        light.lookup = Lookup::Exact;
        light
    };
    let mut frame = Frame {
        ctx: &ctx,
        collection: CollectionPass::new(&ctx).expect("collection pass"),
        generation: GenerationPass::new(&ctx).expect("generation pass"),
        draws,
        light: spot_at(0.0),
    };
    let mut map = TemporalShadowMap::new(&ctx, SIZE, SIZE, 1, 1 << 12).expect("map");
    map.reserve_triangle_records(&ctx, u64::from(ID) + 1)
        .expect("records");
    // Room enough that no frame overflows.
    map.reserve_static_names(&ctx, 4 * SIZE * SIZE)
        .expect("static names");
    frame.run(&map, true);
    map.static_layer_submitted();
    frame.light = spot_at(0.3);
    frame.run(&map, true);
    assert_eq!(map.static_layer_builds(), 2, "redrawn for the new light");
    let contents = map.download(&ctx).expect("download");
    let mut held = 0;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let names = contents.static_names_at(x, y);
            assert!(names.len() <= 1, "texel ({x}, {y}) names {names:?}");
            held += names.len() as u32;
        }
    }
    assert_eq!(
        contents.static_names_at(SIZE / 2, SIZE / 2),
        vec![ID],
        "the triangle at the centre"
    );
    let counts = map.read_counters().expect("counters");
    assert_eq!(counts.static_names, held, "the count is the names held");
    drop((map, frame, vertices));
    assert_no_validation_messages(&ctx);
}
