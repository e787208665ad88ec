//! The receiver test at grazing light: contact shadows kept, no acne.
//!
//! A block stands on a finely triangulated ground under a directional light 7 degrees above
//! it, so one shadow-map texel covers 1 / sin 7 ~ 8 texel widths of ground along the light.
//! A receiver offset one texel along its normal (the papers' test) moves every shadow
//! boundary that runs across the light by a whole texel of the map, eight texel widths on
//! the ground: the block's shadow comes out short. The receiver-plane test compares the
//! ground's own plane with the map at the texel centre, so its boundaries are where the
//! texel centres put them (within half a texel), and the ground's many neighbouring
//! triangles still do not shadow each other.
//!
//! The expectation is geometric, not another renderer: a ground point is in shadow iff its
//! position in the light's image lies inside the block's image (a rectangle: the block's
//! edges run along and across the light). Pixels whose four corners are all more than
//! `MARGIN` texels inside (or outside) that rectangle must be dark (lit). The ray tracer,
//! which knows no shadow map, is checked against the same classification first, so a wrong
//! set-up of the test shows as such.

use crate::support::gpu::{assert_no_validation_messages, context, mesh, render};
use crate::support::sampling::CameraRays;
use glam::{DVec2, DVec3, Vec2, Vec3};
use motion_shadows_app::render::upload::{camera_view, light_view};
use motion_shadows_app::render::{Method, ReceiverTest, RenderSettings};
use motion_shadows_app::scene::{Camera, DirectionalLight, Light, Scene};

const IMAGE: (u32, u32) = (200, 200);
const SHADOW: (u32, u32) = (512, 512);
const ELEVATION_DEG: f32 = 7.0;
const IRRADIANCE: f32 = 3.0;
const ALBEDO: f32 = 0.8;
/// The block: x in [-1, 1], y in [0, HEIGHT], z in [0, 1]; the light travels toward -z.
const HEIGHT: f32 = 0.25;
/// A texel centre is at most half a texel from any point of its texel, per axis.
const MARGIN: f64 = 0.6;

fn grazing_scene() -> Scene {
    let e = ELEVATION_DEG.to_radians();
    let ground = motion_shadows_app::scene::plane_mesh(Vec2::splat(12.0), 24);
    let block: Vec<Vec3> = motion_shadows_app::scene::box_mesh(Vec3::new(2.0, HEIGHT, 1.0), 2)
        .into_iter()
        .map(|p| p + Vec3::new(0.0, HEIGHT * 0.5, 0.5))
        .collect();
    Scene {
        name: "grazing-block".into(),
        camera: Camera {
            position: Vec3::new(0.0, 12.0, -1.0),
            target: Vec3::new(0.0, 0.0, -1.0),
            up: Vec3::NEG_Z,
            fov_y_deg: 30.0,
            near: 1.0,
            far: 30.0,
            t1: None,
        },
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(0.0, -e.sin(), -e.cos()),
            irradiance: IRRADIANCE,
            center: Vec3::new(0.0, 0.0, -1.0),
            half_extent: 4.0,
            distance: 20.0,
            near: 1.0,
            far: 40.0,
            t1: None,
        }),
        ambient: 0.0,
        meshes: vec![
            mesh("ground", ground.clone(), ground, false),
            mesh("block", block.clone(), block, true),
        ],
    }
}

/// Where a pixel's ground points stand against the block's shadow.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Class {
    /// Every corner more than `MARGIN` texels inside the shadow's image.
    Shadowed,
    /// Every corner more than `MARGIN` texels outside it.
    Lit,
    /// Near the boundary, or the camera sees the block there.
    Unsure,
}

struct Expectation {
    class: Vec<Class>,
    /// How far each pixel's centre is inside the shadow's image from its nearest boundary
    /// across the light (in texels along the image's y, the axis the receiver offset moves
    /// points along; negative outside).
    depth_into_shadow: Vec<f64>,
}

fn expectation(scene: &Scene) -> Expectation {
    let rays = CameraRays::of(&camera_view(scene, IMAGE), IMAGE);
    let light = light_view(scene, SHADOW);
    let to_light = (light.proj * light.view).as_dmat4();
    let texel_of = |p: DVec3| {
        let c = to_light * p.extend(1.0);
        let ndc = DVec2::new(c.x / c.w, c.y / c.w);
        (ndc * 0.5 + DVec2::splat(0.5)) * DVec2::new(f64::from(SHADOW.0), f64::from(SHADOW.1))
    };
    let origin = rays.origin.as_dvec3();
    let ground_point = |x: f64, y: f64| {
        let d = rays.direction(x as f32, y as f32);
        origin + d * (-origin.y / d.y)
    };
    // The block's image in the light: the bounding rectangle of its corners (it is that
    // rectangle exactly: the light's x axis is the world's, the block is axis-aligned).
    let h = f64::from(HEIGHT);
    let corners = [-1.0, 1.0].iter().flat_map(|&x| {
        [0.0, h]
            .into_iter()
            .flat_map(move |y| [0.0, 1.0].map(move |z| DVec3::new(x, y, z)))
    });
    let (lo, hi) = corners.fold(
        (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)),
        |(lo, hi), p| (lo.min(texel_of(p)), hi.max(texel_of(p))),
    );
    // Positive inside, in texels (Chebyshev: a rectangle's inside is the min over its sides).
    let inside = |t: DVec2| (t - lo).min(hi - t).min_element();
    let on_block = |p: DVec3| p.x.abs() < 1.05 && p.z > -0.05 && p.z < 1.05;
    let mut class = Vec::new();
    let mut depth_into_shadow = Vec::new();
    for y in 0..IMAGE.1 {
        for x in 0..IMAGE.0 {
            let (x, y) = (f64::from(x), f64::from(y));
            let points = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(dx, dy)| ground_point(x + dx, y + dy));
            let depths = points.map(|p| inside(texel_of(p)));
            class.push(if points.iter().any(|&p| on_block(p)) {
                Class::Unsure
            } else if depths.iter().all(|&d| d > MARGIN) {
                Class::Shadowed
            } else if depths.iter().all(|&d| d < -MARGIN) {
                Class::Lit
            } else {
                Class::Unsure
            });
            let centre = texel_of(ground_point(x + 0.5, y + 0.5));
            depth_into_shadow.push((centre.y - lo.y).min(hi.y - centre.y));
        }
    }
    Expectation {
        class,
        depth_into_shadow,
    }
}

/// Each pixel's share of its samples that see the light: the lit ground's radiance is
/// albedo / pi * irradiance * sin(elevation), and the ambient term is 0.
fn visibility(rgb: &[f32]) -> Vec<f64> {
    let lit = f64::from(ALBEDO) / std::f64::consts::PI
        * f64::from(IRRADIANCE)
        * f64::from(ELEVATION_DEG).to_radians().sin();
    rgb.chunks(3).map(|c| f64::from(c[1]) / lit).collect()
}

/// (wrongly lit shadowed pixels, wrongly dark lit pixels, shadowed count, lit count).
fn mistakes(expected: &Expectation, vis: &[f64]) -> (usize, usize, usize, usize) {
    let (mut leaks, mut acne, mut shadowed, mut lit) = (0, 0, 0, 0);
    for (class, &v) in expected.class.iter().zip(vis) {
        match class {
            Class::Shadowed => {
                shadowed += 1;
                leaks += usize::from(v > 0.02);
            }
            Class::Lit => {
                lit += 1;
                acne += usize::from((v - 1.0).abs() > 0.02);
            }
            Class::Unsure => {}
        }
    }
    (leaks, acne, shadowed, lit)
}

#[test]
fn receiver_plane_keeps_grazing_shadows_whole_without_acne() {
    let ctx = context();
    let scene = grazing_scene();
    let expected = expectation(&scene);
    let settings = |method, receiver| RenderSettings {
        width: IMAGE.0,
        height: IMAGE.1,
        spp: 4,
        seed: 5,
        shadow_size: Some(SHADOW),
        method,
        receiver,
        ..RenderSettings::default()
    };

    // The classification itself, against the exact renderer.
    let truth = motion_shadows_app::raytrace::render(
        &scene,
        &settings(Method::Raytrace, ReceiverTest::Auto),
        &mut |_| {},
    )
    .expect("raytrace");
    let (leaks, acne, shadowed, lit) = mistakes(&expected, &visibility(&truth.image.rgb));
    eprintln!("raytrace: {leaks} of {shadowed} shadowed pixels lit, {acne} of {lit} lit dark");
    assert!(
        shadowed > 2000 && lit > 20000,
        "{shadowed} shadowed, {lit} lit"
    );
    assert_eq!((leaks, acne), (0, 0), "the test's classification is wrong");

    // The default receiver test of the temporal method is the plane's.
    let plane = render(
        &ctx,
        &scene,
        &settings(Method::Temporal, ReceiverTest::Auto),
    );
    assert!(plane.stats.receiver_plane);
    let plane_vis = visibility(&plane.image.rgb);
    let (leaks, acne, _, _) = mistakes(&expected, &plane_vis);
    eprintln!("temporal, plane: {leaks} leaks, {acne} acne");
    assert_eq!(
        (leaks, acne),
        (0, 0),
        "receiver plane: leaks or acne outside the half-texel boundary band"
    );

    // The papers' offset moves the receiver a texel across the light (0.99 of one in the
    // light's image at this elevation): much of the shadowed band between MARGIN and one
    // texel inside that boundary comes out lit (how much depends on where the texel centres
    // fall; at least a third of it).
    let offset = render(
        &ctx,
        &scene,
        &settings(Method::Temporal, ReceiverTest::Offset),
    );
    assert!(!offset.stats.receiver_plane);
    let offset_vis = visibility(&offset.image.rgb);
    let band: Vec<usize> = (0..expected.class.len())
        .filter(|&i| {
            expected.class[i] == Class::Shadowed
                && (MARGIN..1.0).contains(&expected.depth_into_shadow[i])
        })
        .collect();
    let lost = band.iter().filter(|&&i| offset_vis[i] > 0.5).count();
    let lost_by_plane = band.iter().filter(|&&i| plane_vis[i] > 0.5).count();
    eprintln!(
        "offset: {lost} of {} pixels between {MARGIN} and 1 texel inside the shadow come out lit \
         (plane: {lost_by_plane})",
        band.len()
    );
    assert!(
        band.len() > 50,
        "too few pixels in the band: {}",
        band.len()
    );
    assert!(
        lost * 3 > band.len(),
        "the normal offset was expected to lose this band of the shadow"
    );
    assert_no_validation_messages(&ctx);
}
