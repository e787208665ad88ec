//! The exact lookup's conservative collection (`Lookup::Exact`) against a CPU model that
//! shares nothing with its geometry shader (no hull, no growing): every triangle, moving as
//! its corners say, is sampled at many times, and each map point of a dense grid (16 x 16
//! per texel) its projection covers then is looked up. Every texel holding such a point must
//! name the triangle in its list: the exact lookup tests only the triangles a texel names, so
//! one missing would let light through. Still triangles go to the static layer's name lists
//! (kept across frames): the same holds for them there.

use crate::support::coverage_oracle::{MovingTriangle, scene_triangles};
use crate::support::gpu::{assert_no_validation_messages, context};
use crate::support::rng::Rng;
use crate::support::scene::{
    Scene, light_view, mesh, overhead_directional, overhead_spot, scene, temporal_map_stored,
};
use glam::{DVec2, DVec3, DVec4, Vec3};
use motion_shadows::technique::{LightView, Lookup, Pruning, RangeStorage, ShadowMapContents};

const SIZE: (u32, u32) = (16, 16);
/// Sample points per texel and axis.
const POINTS: u32 = 16;
/// Sample times over the shutter (both ends included).
const TIMES: u32 = 64;

/// `n` triangles with random corners and random per-corner motion (translation, turns and
/// deformation alike), within `reach` of the light's axis, between heights 0.5 and 3; then
/// `still` more that do not move, in a static draw of their own.
fn random_triangles(rng: &mut Rng, n: usize, still: usize, reach: f32) -> Scene {
    let mut at0 = Vec::new();
    let mut at1 = Vec::new();
    let mut still_at = Vec::new();
    let coord = |rng: &mut Rng, lo: f32, hi: f32| lo + (hi - lo) * rng.unit();
    for k in 0..n + still {
        let centre = Vec3::new(
            coord(rng, -reach, reach),
            coord(rng, 0.5, 3.0),
            coord(rng, -reach, reach),
        );
        for _ in 0..3 {
            let corner = centre
                + Vec3::new(
                    coord(rng, -1.0, 1.0),
                    coord(rng, -0.3, 0.3),
                    coord(rng, -1.0, 1.0),
                );
            let motion = Vec3::new(
                coord(rng, -1.5, 1.5),
                coord(rng, -0.3, 0.3),
                coord(rng, -1.5, 1.5),
            );
            if k < n {
                at0.push(corner);
                at1.push(corner + motion);
            } else {
                still_at.push(corner);
            }
        }
    }
    scene(
        "random",
        overhead_directional(4.0),
        vec![
            mesh("tris", at0, at1, false),
            mesh("still", still_at.clone(), still_at, false),
        ],
    )
}

/// Where a world point falls on the map, in texels from its corner (the GPU's convention:
/// texel (x, y) spans [x, x + 1) x [y, y + 1) of (ndc * 0.5 + 0.5) * size), in f64.
fn map_point(light: &LightView, p: DVec3) -> DVec2 {
    let clip = light.proj.as_dmat4() * light.view.as_dmat4() * DVec4::from((p, 1.0));
    assert!(
        clip.w > 0.0,
        "the model's triangles stay in front of the light"
    );
    let ndc = DVec2::new(clip.x, clip.y) / clip.w;
    (ndc * 0.5 + 0.5) * DVec2::new(SIZE.0 as f64, SIZE.1 as f64)
}

/// Whether q lies in the 2D triangle (edges included).
fn inside(q: DVec2, c: [DVec2; 3]) -> bool {
    let side = |a: DVec2, b: DVec2| (b - a).perp_dot(q - a);
    let s = [side(c[0], c[1]), side(c[1], c[2]), side(c[2], c[0])];
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

/// Texels in which the model sees `tri` cover a sample point at a sample time, with the
/// first and last such time.
fn covered_texels(light: &LightView, tri: &MovingTriangle) -> Vec<((u32, u32), (f64, f64))> {
    let mut hit: Vec<Option<(f64, f64)>> = vec![None; (SIZE.0 * SIZE.1) as usize];
    for k in 0..TIMES {
        let t = f64::from(k) / f64::from(TIMES - 1);
        let c = tri.at(t).map(|p| map_point(light, p));
        let lo = c[0].min(c[1]).min(c[2]);
        let hi = c[0].max(c[1]).max(c[2]);
        let step = 1.0 / f64::from(POINTS);
        let first = |v: f64| ((v / step - 0.5).ceil().max(0.0)) as u32;
        let last = |v: f64, n: u32| (v / step - 0.5).floor().min(f64::from(n * POINTS) - 1.0);
        let (x0, y0) = (first(lo.x), first(lo.y));
        let (x1, y1) = (last(hi.x, SIZE.0), last(hi.y, SIZE.1));
        if x1 < 0.0 || y1 < 0.0 {
            continue;
        }
        for j in y0..=y1 as u32 {
            for i in x0..=x1 as u32 {
                let q = DVec2::new((f64::from(i) + 0.5) * step, (f64::from(j) + 0.5) * step);
                if inside(q, c) {
                    let times = &mut hit[((j / POINTS) * SIZE.0 + i / POINTS) as usize];
                    *times =
                        Some(times.map_or((t, t), |(first, last)| (first.min(t), last.max(t))));
                }
            }
        }
    }
    (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .filter_map(|(x, y)| hit[(y * SIZE.0 + x) as usize].map(|times| ((x, y), times)))
        .collect()
}

/// How far a range's times may fall short of the model's covering times: f32 rounding of the
/// collection's roots (the model's times are exact samples).
const TIME_SLACK: f64 = 1e-5;

/// Every (texel, triangle) pair the model covers is in the map's lists: a moving triangle's
/// in the texel's ranges, over times that hold every time the model saw it cover the texel,
/// a still one's (ids from `first_still`) in its static name list, and neither in the other;
/// returns how many pairs were checked and how many the lists
/// hold in all (the collection's overhead).
fn check(
    map: &ShadowMapContents,
    light: &LightView,
    s: &Scene,
    first_still: u32,
) -> (usize, usize) {
    let mut checked = 0;
    for (id, tri) in scene_triangles(s).iter().enumerate() {
        let id = id as u32;
        for ((x, y), (first, last)) in covered_texels(light, tri) {
            checked += 1;
            let range = map.ranges_at(x, y).into_iter().find(|r| r.id == id);
            let in_ranges = range.is_some();
            if let (Some(r), true) = (range, id < first_still) {
                assert!(
                    f64::from(r.t_s) <= first + TIME_SLACK && f64::from(r.t_e) >= last - TIME_SLACK,
                    "{}: triangle {id} covers texel ({x}, {y}) from t = {first} to {last}, its \
                     range spans {} to {}",
                    s.name,
                    r.t_s,
                    r.t_e
                );
            }
            let in_static = map.static_names_at(x, y).contains(&id);
            let (found, list) = if id >= first_still {
                (in_static && !in_ranges, "static name list")
            } else {
                (in_ranges && !in_static, "ranges")
            };
            assert!(
                found,
                "{}: triangle {id} covers texel ({x}, {y}) but is not (only) in its {list} \
                 (in the ranges: {in_ranges}, in the static names: {in_static})",
                s.name
            );
        }
    }
    let held = (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .map(|(x, y)| map.ranges_at(x, y).len() + map.static_names_at(x, y).len())
        .sum();
    (checked, held)
}

/// A light's name, how to make it, and how far from its axis the random triangles lie.
type LightCase = (&'static str, fn() -> crate::support::scene::Light, f32);

fn run(lights: &[LightCase]) {
    let ctx = context();
    let mut rng = Rng(35);
    for &(name, light_of, reach) in lights {
        for round in 0..4 {
            let (moving, still) = (6, 4);
            let mut s = random_triangles(&mut rng, moving, still, reach);
            s.light = light_of();
            s.name = format!("{name} round {round}");
            let light = LightView {
                lookup: Lookup::Exact,
                ..light_view(&s, SIZE)
            };
            let (map, _) = temporal_map_stored(
                &ctx,
                &s,
                SIZE,
                &light,
                RangeStorage::Lists,
                Pruning::default(),
                1024,
            );
            let (checked, held) = check(&map, &light, &s, moving as u32);
            assert!(
                checked > 20,
                "{}: the model covered only {checked} pairs",
                s.name
            );
            println!(
                "{}: {checked} covered (texel, triangle) pairs, {held} held",
                s.name
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

#[test]
fn every_texel_a_triangle_touches_names_it_orthographic() {
    run(&[("directional", || overhead_directional(4.0), 2.5)]);
}

#[test]
fn every_texel_a_triangle_touches_names_it_spot() {
    run(&[("spot", || overhead_spot(6.0, 40.0), 1.8)]);
}

/// Five still triangles each covering the whole 16 x 16 map (and one moving): 1,280 names at
/// least, five times the static name lists' first capacity (one per texel). The frame that
/// overflows says so (`needs_more_room`), `grow_to_fit` makes room, and the lists then name
/// every triangle in every texel, their count exactly the names held.
#[test]
fn the_static_name_lists_grow_until_every_name_fits() {
    let ctx = context();
    let big = |y: f32, turn: f32| {
        let (s, c) = turn.sin_cos();
        [(-12.0f32, -12.0f32), (12.0, -12.0), (0.0, 14.0)]
            .map(|(x, z)| Vec3::new(c * x - s * z, y, s * x + c * z))
    };
    let still: Vec<Vec3> = (0..5)
        .flat_map(|k| big(0.8 + 0.4 * k as f32, 0.3 * k as f32))
        .collect();
    let flyer = vec![
        Vec3::new(-1.0, 3.0, 0.0),
        Vec3::new(0.0, 3.0, 1.0),
        Vec3::new(1.0, 3.0, 0.0),
    ];
    let flown = flyer.iter().map(|&p| p + Vec3::X).collect();
    let mut s = scene(
        "five still covers",
        overhead_directional(4.0),
        vec![
            mesh("flyer", flyer, flown, false),
            mesh("still", still.clone(), still, false),
        ],
    );
    s.name = "five still covers".into();
    let light = LightView {
        lookup: Lookup::Exact,
        ..light_view(&s, SIZE)
    };
    let (map, counts) = temporal_map_stored(
        &ctx,
        &s,
        SIZE,
        &light,
        RangeStorage::Lists,
        Pruning::default(),
        1024,
    );
    let texels = SIZE.0 * SIZE.1;
    let mut held = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let mut names = map.static_names_at(x, y);
            held += names.len() as u32;
            names.sort_unstable();
            assert_eq!(names, vec![1, 2, 3, 4, 5], "texel ({x}, {y})");
        }
    }
    assert_eq!(counts.static_names, held, "the count is the names held");
    assert!(held >= 5 * texels);
    let (checked, _) = check(&map, &light, &s, 1);
    assert!(checked > 5 * texels as usize);
    assert_no_validation_messages(&ctx);
}
