//! `moving-light`: a flashlight carried past four still posts and a box sliding the other
//! way, the light translating during the shutter (issue 38). Every shadow blurs, the still
//! posts' too, and the translating light is the case the light's moving frame holds exactly.

use glam::Vec3;

use super::file::{
    BoxSpec, CameraFile, LightFile, MeshSpec, SCENE_FORMAT, SceneFile, SpotPoseFile,
};
use super::parts::{ground, object, translate};

/// The flashlight's position at t = 0 and how far it is carried (along +x) by t = 1.
pub(super) const LIGHT_START: Vec3 = Vec3::new(-1.0, 2.6, -3.5);
pub(super) const LIGHT_CARRIED: Vec3 = Vec3::new(2.0, 0.0, 0.0);

pub(super) fn moving_light() -> SceneFile {
    let post = MeshSpec::Box(BoxSpec {
        size: Vec3::new(0.3, 2.0, 0.3),
        subdivisions: 1,
    });
    let crate_box = MeshSpec::Box(BoxSpec {
        size: Vec3::splat(0.8),
        subdivisions: 2,
    });
    let mut objects = vec![ground(16.0, 8)];
    for (i, x) in [-3.0f32, -1.0, 1.0, 3.0].into_iter().enumerate() {
        objects.push(object(
            &format!("post-{i}"),
            Vec3::new(0.75, 0.7, 0.55),
            true,
            post.clone(),
            translate(Vec3::new(x, 1.0, -1.0)),
            None,
        ));
    }
    objects.push(object(
        "box",
        Vec3::new(0.3, 0.5, 0.8),
        true,
        crate_box,
        translate(Vec3::new(1.5, 0.4, 1.0)),
        Some(translate(Vec3::new(-0.5, 0.4, 1.0))),
    ));
    // Behind the posts, so that their shadows fall toward the camera. The ground 3.9 units
    // ahead of the light at radiance ~0.4: I = 0.4 pi / 0.8 d^2.
    let direction = Vec3::new(0.0, -1.0, 0.9);
    SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some("moving-light".to_owned()),
        camera: CameraFile {
            position: Vec3::new(0.0, 6.0, 9.0),
            target: Vec3::new(0.0, 0.5, -0.5),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 40.0,
            t1: None,
        },
        light: LightFile::Spot {
            position: LIGHT_START,
            direction,
            cone_angle_deg: 50.0,
            intensity: 24.0,
            near: 0.3,
            far: 30.0,
            t1: Some(SpotPoseFile {
                position: Some(LIGHT_START + LIGHT_CARRIED),
                direction: None,
            }),
        },
        ambient: 0.02,
        objects,
    }
}
