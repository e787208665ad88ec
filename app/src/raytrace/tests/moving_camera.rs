//! The truth under a moving camera over a still scene: the image is the shutter's average of
//! what the camera sees along its path, so it must equal the average of still renders at
//! many poses along that path (each from the still camera's own rays, the old arithmetic).

use crate::render::{Method, RenderSettings};
use crate::scene::{BuiltinOptions, Scene, builtin};
use glam::Vec3;

const WIDTH: u32 = 48;
const HEIGHT: u32 = 36;
const SPP: u32 = 64;
/// Still poses along the path, at the midpoints of equal time slices.
const POSES: u32 = 32;
/// Block means compared (BLOCK x BLOCK pixels), so that a block's noise is small next to
/// what a wrong camera time moves across it.
const BLOCK: u32 = 6;

/// `camera-pan` with its cubes held at t = 0 and the pan widened to a quarter of the image,
/// so that only the camera moves and a camera seen at the wrong time shows.
fn panning_over_still_scene() -> Scene {
    let mut scene = builtin("camera-pan", &BuiltinOptions::default()).unwrap();
    for mesh in &mut scene.meshes {
        mesh.t1 = mesh.t0.clone();
    }
    let end = scene.camera.t1.as_mut().unwrap();
    end.position = scene.camera.position + Vec3::X * 5.0;
    end.target = scene.camera.target + Vec3::X * 5.0;
    scene
}

fn trace(scene: &Scene) -> crate::output::RadianceImage {
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        spp: SPP,
        method: Method::Raytrace,
        ..RenderSettings::default()
    };
    crate::raytrace::render(scene, &settings, &mut |_| {})
        .unwrap()
        .image
}

/// The luminance-free sum of a block's channels, averaged over its pixels.
fn block_means(rgb: &[f32]) -> Vec<f64> {
    let (bw, bh) = (WIDTH / BLOCK, HEIGHT / BLOCK);
    let mut means = vec![0.0; (bw * bh) as usize];
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = 3 * (y * WIDTH + x) as usize;
            let sum: f32 = rgb[i..i + 3].iter().sum();
            means[((y / BLOCK) * bw + x / BLOCK) as usize] += f64::from(sum);
        }
    }
    means.iter().map(|m| m / f64::from(BLOCK * BLOCK)).collect()
}

/// The bound: a block mean averages B = BLOCK^2 x SPP independent samples (the pixels'
/// sample streams are independent), each a channel sum in [0, L], so its standard deviation
/// is at most L / (2 sqrt B). The still poses' average is no noisier than one still render
/// (an average of estimates each that noisy), so the difference's deviation is at most
/// sqrt 2 times that; 5 of those over the 48 blocks leaves a chance of a false failure
/// below 3e-5 even at this worst-case variance. L is the brightest pixel of any still render
/// times 1.25 (a pixel averages SPP samples of one small patch; the brightest are broad lit
/// faces). The midpoint rule over POSES poses adds an error of at most (pan in pixels /
/// POSES) / BLOCK of an edge's contrast per block, the pan being under 13 pixels (5 units
/// across at about 17 units, 2.6 pixels a unit): 13 / 32 / 6 of L, counted in. With the
/// same seed the stills share the moving render's sample positions, so the difference
/// measured is far below the bound (0.007 against 0.23); the camera held at t = 0 is 0.6 off.
#[test]
fn a_moving_camera_over_a_still_scene_averages_the_still_renders_along_its_path() {
    let scene = panning_over_still_scene();
    let moving = block_means(&trace(&scene).rgb);
    let mut average = vec![0.0; moving.len()];
    let mut brightest: f32 = 0.0;
    for i in 0..POSES {
        let t = (i as f32 + 0.5) / POSES as f32;
        let mut still = scene.clone();
        still.camera = scene.camera.at(t);
        let image = trace(&still);
        brightest = image
            .rgb
            .chunks(3)
            .map(|p| p.iter().sum::<f32>())
            .fold(brightest, f32::max);
        for (a, m) in average.iter_mut().zip(block_means(&image.rgb)) {
            *a += m / f64::from(POSES);
        }
    }
    let range = 1.25 * f64::from(brightest);
    let samples = f64::from(BLOCK * BLOCK * SPP);
    let noise = 5.0 * 2f64.sqrt() * range / (2.0 * samples.sqrt());
    let quadrature = range * 13.0 / f64::from(POSES * BLOCK);
    let bound = noise + quadrature;
    let worst = moving
        .iter()
        .zip(&average)
        .map(|(m, a)| (m - a).abs())
        .fold(0.0, f64::max);
    eprintln!("worst block difference {worst:.4}, bound {bound:.4} (L {range:.3})");
    assert!(worst <= bound, "worst block {worst} > bound {bound}");
    // The test can see a camera seen at one time only: the t = 0 render is far off.
    let at_start = {
        let mut still = scene.clone();
        still.camera = scene.camera.at(0.0);
        block_means(&trace(&still).rgb)
    };
    let off = at_start
        .iter()
        .zip(&average)
        .map(|(m, a)| (m - a).abs())
        .fold(0.0, f64::max);
    assert!(off > 2.0 * bound, "the t = 0 camera is only {off} off");
}

/// A still camera takes the old arithmetic: `t1` equal to t = 0's pose renders bit for bit
/// as no `t1` (each sample's ray rebuilt from the pose at its time, which is t = 0's).
#[test]
fn a_camera_whose_t1_is_its_t0_renders_bit_for_bit_as_a_still_one() {
    let mut scene = builtin("cubes-toward-light", &BuiltinOptions::default()).unwrap();
    let still = trace(&scene);
    let c = scene.camera.clone();
    scene.camera.t1 = Some(crate::scene::CameraPose {
        position: c.position,
        target: c.target,
        up: c.up,
    });
    assert_eq!(trace(&scene).rgb, still.rgb);
}
