//! The static draws: alone they make TSM an ordinary shadow map, and their map is drawn once
//! and kept across frames until the host says it changed.

use super::rig::{Frame, Mesh, Rig, errors, light, nearest_pixel, rect, shifted};
use super::{CONFIGS, HALF, SHADOW, TEXEL};
use crate::support::gpu::{assert_no_validation_messages, context};
use glam::Vec3;
use motion_shadows::Error;
use motion_shadows::technique::{EngineTsmMap, MAX_TSM_LAYERS, MAX_TSM_MAPS, TsmStart};

/// With static draws only, TSM-1 is an ordinary shadow map: a still square under a slanted
/// directional light shadows the ground points whose ray toward the light meets it, exactly
/// 0 there and 1 elsewhere (pixels within three texels of the shadow's edge left out), and
/// TSM-4 gives the same mask. Bad map counts are refused before anything is recorded, bad
/// sizes and layer counts when the map is made.
#[test]
fn engine_tsm_of_static_draws_is_an_ordinary_shadow_map() {
    let ctx = context();
    let (x0, x1, z0, z1) = (-0.5f32, 0.7f32, -0.8f32, 0.6f32);
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let caster = Mesh::new(&ctx, &rect(x0, x1, z0, z1, 1.0), None);
    let receivers = [ground.draw(0)];
    let casters = [ground.draw(0), caster.draw(2)];
    let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
    let light = light(direction, false);
    let closed_form = |p: Vec3| {
        if p.x.abs() > HALF - 0.5 || p.z.abs() > HALF - 0.5 {
            return None;
        }
        // Where the ray toward the light reaches the square's height.
        let q = p - direction * (1.0 / -direction.y);
        let inside = (q.x - x0).min(x1 - q.x).min(q.z - z0).min(z1 - q.z);
        if inside.abs() < 3.0 * TEXEL {
            return None;
        }
        Some(if inside > 0.0 { 0.0 } else { 1.0 })
    };
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let mut masks = Vec::new();
        for n in [1, 4] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: n,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            let mask = rig.run(&frame, &map).expect("frame");
            let found = errors(&rig, &mask, closed_form);
            let shadowed = found.iter().filter(|(_, _, e)| *e == 0.0).count();
            assert!(
                shadowed > 150 && found.len() - shadowed > 1000,
                "{start}: {shadowed} shadowed of {} pixels tested",
                found.len()
            );
            let wrong: Vec<_> = found.iter().filter(|(_, got, e)| got != e).collect();
            assert!(
                wrong.is_empty(),
                "{start}, N = {n}: {} pixels differ from the square's shadow, e.g. {:?}",
                wrong.len(),
                &wrong[..wrong.len().min(5)]
            );
            masks.push(mask);
        }
        assert!(masks[0] == masks[1], "{start}: TSM-4 differs from TSM-1");
        for maps in [0, MAX_TSM_MAPS + 1] {
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer: true,
            };
            match rig.run(&frame, &map) {
                Err(Error::InvalidArgument(message)) => {
                    assert!(
                        message.contains(&format!("{maps} time-dependent")),
                        "{message}"
                    )
                }
                other => panic!("{maps} maps: {other:?}"),
            }
        }
    }
    for (what, size, layers) in [
        ("size 0x512", (0, SHADOW), 1),
        ("0 time-dependent shadow map layers", (SHADOW, SHADOW), 0),
        (
            "65 time-dependent shadow map layers",
            (SHADOW, SHADOW),
            MAX_TSM_LAYERS + 1,
        ),
    ] {
        match EngineTsmMap::new(&ctx, size.0, size.1, layers, TsmStart::Copy) {
            Err(Error::InvalidArgument(message)) => {
                assert!(message.contains(what), "{message}")
            }
            Err(other) => panic!("{what}: {other:?}"),
            Ok(_) => panic!("{what}: made"),
        }
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}

/// The static map is drawn once and kept: with `keep_static_layer`, a second frame does not
/// redraw it (the build count stays 1) and gives the same mask bit for bit, even though the
/// static square's buffer was moved in place meanwhile (so a redraw would show it moved);
/// after `forget_static_map` the next frame redraws it (count 2) and shows the square where
/// it now is. A moving caster is drawn in every frame as well. Fails when the static map is
/// redrawn every frame, or when a kept map loses its contents.
#[test]
fn engine_tsm_keeps_its_static_map() {
    let ctx = context();
    let ground = Mesh::new(&ctx, &rect(-6.0, 6.0, -6.0, 6.0, 0.0), None);
    let square = |x0: f32| rect(x0, x0 + 0.8, -1.0, 1.0, 1.0);
    let mut still = Mesh::new(&ctx, &square(-1.5), None);
    let bar = rect(0.8, 1.0, -2.0, 2.0, 1.5);
    let moving = Mesh::new(&ctx, &bar, Some(&shifted(&bar, Vec3::X * 0.6)));
    let light = light(Vec3::NEG_Y, true);
    let receivers = [ground.draw(0)];
    let mut rig = Rig::new(&ctx);
    for (start, layers) in CONFIGS {
        let map = EngineTsmMap::new(&ctx, SHADOW, SHADOW, layers, start).expect("map");
        let start = format!("{start:?} x{layers}");
        let run = |rig: &mut Rig, still: &Mesh, draw_gbuffer: bool| -> Vec<f32> {
            let casters = [ground.draw(0), still.draw(2), moving.draw(4)];
            let frame = Frame {
                receivers: &receivers,
                casters: &casters,
                light: &light,
                maps: 4,
                gbuffer_time: 1.0,
                moving_receivers: false,
                draw_gbuffer,
            };
            rig.run(&frame, &map).expect("frame")
        };
        still.rewrite(&square(-1.5));
        let first = run(&mut rig, &still, true);
        assert_eq!(map.static_map_builds(), 1);
        // The square is where it was drawn: shadowed under it, lit beside it.
        let (under, beside) = (nearest_pixel(&rig, -1.1), nearest_pixel(&rig, -0.2));
        assert_eq!((first[under], first[beside]), (0.0, 1.0), "{start}");

        still.rewrite(&square(-0.6));
        let kept = run(&mut rig, &still, false);
        assert_eq!(
            map.static_map_builds(),
            1,
            "{start}: the kept map was redrawn"
        );
        assert!(
            kept == first,
            "{start}: the kept static map changed the mask"
        );

        map.forget_static_map();
        let redrawn = run(&mut rig, &still, false);
        assert_eq!(map.static_map_builds(), 2, "{start}");
        assert_eq!(
            (redrawn[under], redrawn[beside]),
            (1.0, 0.0),
            "{start}: the redrawn map does not show the square where it now is"
        );
    }
    drop(rig);
    assert_no_validation_messages(&ctx);
}
