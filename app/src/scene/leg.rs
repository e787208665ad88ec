//! `leg-toward-light` (Hong & Oh 2018, Fig. 10): "the light source is in front of the
//! character and the leg is moving toward the light source". There is no character asset, so
//! the character is a procedural figure of tessellated boxes: a static body (pelvis, torso,
//! head, arms) and static left leg, and a right leg (thigh, shin, foot) that kicks forward
//! toward a spot light in front of it. Each leg part is a rigid object with its own t0/t1
//! pose, built so that its joint point (hip, knee, ankle) is the same world point for both
//! parts it connects at both ends of the shutter; since vertices move linearly, the joints
//! then stay connected at every time t. A back wall catches the leg's shadow as well as the
//! ground.

use glam::{Quat, Vec2, Vec3};

use super::file::{
    BoxSpec, CameraFile, LightFile, MeshSpec, ObjectFile, PlaneSpec, SCENE_FORMAT, SceneFile,
    TransformFile,
};
use super::parts::{object, translate};

/// The character faces +z, toward the light; x is to its left, the kicking leg is on -x.
const HIP_Y: f32 = 0.9;
const HIP_X: f32 = 0.1;
/// Full sizes (x, y, z) of the leg parts; the thigh and shin hang along -y in their rest pose.
const THIGH: Vec3 = Vec3::new(0.14, 0.44, 0.14);
const SHIN: Vec3 = Vec3::new(0.11, 0.40, 0.11);
const FOOT: Vec3 = Vec3::new(0.11, 0.055, 0.24);
/// The ankle sits on the foot's top face this far behind the foot's centre (toward the heel).
const ANKLE_BEHIND_FOOT_CENTRE: f32 = 0.05;
/// Quads per face edge of the kicking leg's parts: fine, because the renderer moves
/// vertices and the leg's own surfaces are where the self-shadow test is hard.
const KICK_SUBDIVISIONS: [u32; 3] = [14, 14, 8];
/// The kicking leg's forward swing, degrees about -x (positive: toward +z, the light),
/// measured from hanging straight down (the foot: from flat): (thigh, shin, foot) at t = 0
/// and t = 1. At t = 0 the thigh hangs down, the knee bent 30 degrees and the toe a little
/// down; at t = 1 the leg is kicked forward and up (the ankle moves ~0.94, from 0.11 to 0.43
/// above the ground), knee bent 20 degrees, toe up. Vertices move on straight lines, so mid-
/// shutter the parts are the chord blend of the two poses: turning 65 (thigh), 75 (shin) and
/// 35 (foot) degrees, they are up to cos(75/2) ~ 0.8 of their length at t = 0.5.
const POSE_T0: [f32; 3] = [0.0, -30.0, -10.0];
const POSE_T1: [f32; 3] = [65.0, 45.0, 25.0];

pub(super) const LIGHT: Vec3 = Vec3::new(0.8, 1.25, 3.0);
const LIGHT_AIM: Vec3 = Vec3::new(-0.2, 0.6, -0.8);
pub(super) const WALL_Z: f32 = -1.8;

pub(super) fn hip() -> Vec3 {
    Vec3::new(-HIP_X, HIP_Y, 0.0)
}

/// Rotation of a leg part swung `deg` degrees forward (toward +z) about the hip axis.
fn swing(deg: f32) -> Quat {
    Quat::from_axis_angle(Vec3::NEG_X, deg.to_radians())
}

/// Rigid pose of a part, rotated `deg` forward, that puts its local point `anchor` at
/// `joint`; returns the pose and where its local point `other` lands.
fn place(deg: f32, anchor: Vec3, joint: Vec3, other: Vec3) -> (TransformFile, Vec3) {
    let r = swing(deg);
    let translation = joint - r * anchor;
    let pose = TransformFile {
        translation: Some(translation),
        rotation_axis: Some(Vec3::NEG_X),
        rotation_deg: Some(deg),
        scale: None,
    };
    (pose, translation + r * other)
}

/// Local joint points of the leg parts, in each part's box frame (centred at the origin).
pub(super) const THIGH_HIP: Vec3 = Vec3::new(0.0, THIGH.y * 0.5, 0.0);
pub(super) const THIGH_KNEE: Vec3 = Vec3::new(0.0, -THIGH.y * 0.5, 0.0);
pub(super) const SHIN_KNEE: Vec3 = Vec3::new(0.0, SHIN.y * 0.5, 0.0);
pub(super) const SHIN_ANKLE: Vec3 = Vec3::new(0.0, -SHIN.y * 0.5, 0.0);
pub(super) const FOOT_ANKLE: Vec3 = Vec3::new(0.0, FOOT.y * 0.5, -ANKLE_BEHIND_FOOT_CENTRE);

/// Poses of (thigh, shin, foot) for the given swing angles, chained from the hip.
fn leg_pose([thigh, shin, foot]: [f32; 3]) -> [TransformFile; 3] {
    let (thigh_pose, knee) = place(thigh, THIGH_HIP, hip(), THIGH_KNEE);
    let (shin_pose, ankle) = place(shin, SHIN_KNEE, knee, SHIN_ANKLE);
    let (foot_pose, _) = place(foot, FOOT_ANKLE, ankle, Vec3::ZERO);
    [thigh_pose, shin_pose, foot_pose]
}

fn cuboid(size: Vec3, subdivisions: u32) -> MeshSpec {
    MeshSpec::Box(BoxSpec { size, subdivisions })
}

fn plane(size: Vec2, subdivisions: u32) -> MeshSpec {
    MeshSpec::Plane(PlaneSpec { size, subdivisions })
}

/// A static closed box centred at `at`.
fn part(name: &str, albedo: Vec3, size: Vec3, subdivisions: u32, at: Vec3) -> ObjectFile {
    object(
        name,
        albedo,
        true,
        cuboid(size, subdivisions),
        translate(at),
        None,
    )
}

/// Hong & Oh 2018, Fig. 10: the character's right leg kicks toward a spot light in front of
/// it, so the leg's shadow on the ground and the back wall is blurred along the kick while
/// the body's stays sharp, and the leg shadows itself as it turns.
pub(super) fn leg_toward_light() -> SceneFile {
    let body = Vec3::new(0.3, 0.45, 0.7);
    let skin = Vec3::new(0.85, 0.68, 0.55);
    let kicking = Vec3::new(0.85, 0.42, 0.22);

    // The standing leg: the same parts hanging straight down, the foot flat just above the
    // ground (0.005 clearance so its sole is not coplanar with the ground).
    let standing_x = HIP_X;
    let knee_y = HIP_Y - THIGH.y;
    let ankle_y = knee_y - SHIN.y;
    let mut objects = backdrop();
    objects.extend([
        part(
            "pelvis",
            body,
            Vec3::new(0.36, 0.2, 0.22),
            6,
            Vec3::new(0.0, 0.95, 0.0),
        ),
        part(
            "torso",
            body,
            Vec3::new(0.42, 0.56, 0.24),
            10,
            Vec3::new(0.0, 1.33, 0.0),
        ),
        part(
            "head",
            skin,
            Vec3::new(0.2, 0.24, 0.22),
            5,
            Vec3::new(0.0, 1.76, 0.0),
        ),
        part(
            "arm-left",
            body,
            Vec3::new(0.09, 0.6, 0.1),
            5,
            Vec3::new(0.27, 1.3, 0.0),
        ),
        part(
            "arm-right",
            body,
            Vec3::new(0.09, 0.6, 0.1),
            5,
            Vec3::new(-0.27, 1.3, 0.0),
        ),
        part(
            "thigh-left",
            body,
            THIGH,
            5,
            Vec3::new(standing_x, HIP_Y - THIGH.y * 0.5, 0.0),
        ),
        part(
            "shin-left",
            body,
            SHIN,
            5,
            Vec3::new(standing_x, knee_y - SHIN.y * 0.5, 0.0),
        ),
        part(
            "foot-left",
            body,
            Vec3::new(FOOT.x, ankle_y - 0.005, FOOT.z),
            4,
            Vec3::new(
                standing_x,
                (ankle_y + 0.005) * 0.5,
                ANKLE_BEHIND_FOOT_CENTRE,
            ),
        ),
    ]);
    let names = ["thigh-right", "shin-right", "foot-right"];
    let sizes = [THIGH, SHIN, FOOT];
    for (((name, size), n), (t0, t1)) in names
        .into_iter()
        .zip(sizes)
        .zip(KICK_SUBDIVISIONS)
        .zip(leg_pose(POSE_T0).into_iter().zip(leg_pose(POSE_T1)))
    {
        objects.push(object(name, kicking, true, cuboid(size, n), t0, Some(t1)));
    }

    SceneFile {
        format: SCENE_FORMAT.to_owned(),
        name: Some("leg-toward-light".to_owned()),
        camera: side_camera(),
        light: front_spot(),
        ambient: 0.0,
        objects,
    }
}

/// Ground from the wall forward past the light, and the wall itself (the plane turned +90
/// degrees about x: its normal +y becomes +z, toward the figure and the light).
pub(super) fn backdrop() -> Vec<ObjectFile> {
    vec![
        object(
            "ground",
            Vec3::splat(0.8),
            false,
            plane(Vec2::new(8.0, 7.0), 16),
            translate(Vec3::new(0.0, 0.0, WALL_Z + 3.5)),
            None,
        ),
        object(
            "wall",
            Vec3::new(0.78, 0.75, 0.7),
            false,
            plane(Vec2::new(8.0, 4.0), 16),
            TransformFile {
                translation: Some(Vec3::new(0.0, 2.0, WALL_Z)),
                rotation_axis: Some(Vec3::X),
                rotation_deg: Some(90.0),
                scale: None,
            },
            None,
        ),
    ]
}

/// From the figure's right (-x) and in front, a little above hip height, so a figure at
/// the origin facing +z, its shadow on the ground behind it and on the wall are all in view.
pub(super) fn side_camera() -> CameraFile {
    CameraFile {
        position: Vec3::new(-2.6, 1.0, 2.8),
        target: Vec3::new(-0.2, 0.55, -0.6),
        up: Vec3::Y,
        fov_y_deg: 45.0,
        near: 0.1,
        far: 30.0,
        t1: None,
    }
}

/// In front of the figure, a little above hip height, off to its left (+x) so the shadows
/// fall beside it as `side_camera` sees it. Radiance 0.8/pi * 25 * cos / d^2: up to ~0.7 on
/// a leg (d ~ 3.1), 0.1-0.3 on the wall behind it (d ~ 5); the ground right behind the
/// figure, lit at a grazing angle, ~0.1.
pub(super) fn front_spot() -> LightFile {
    LightFile::Spot {
        position: LIGHT,
        direction: LIGHT_AIM - LIGHT,
        cone_angle_deg: 40.0,
        intensity: 25.0,
        near: 0.5,
        far: 20.0,
        t1: None,
    }
}

#[cfg(test)]
mod tests {
    use super::super::primitives::box_mesh;
    use super::super::{BuiltinOptions, Light, Mesh, Scene, builtin};
    use super::*;

    fn scene() -> Scene {
        builtin("leg-toward-light", &BuiltinOptions::default()).unwrap()
    }

    fn mesh<'a>(s: &'a Scene, name: &str) -> &'a Mesh {
        s.meshes.iter().find(|m| m.name == name).unwrap()
    }

    const KICK: [&str; 3] = ["thigh-right", "shin-right", "foot-right"];

    /// Where the box part's local point `local` (box frame, centred at the origin) is at the
    /// start and end of the shutter, read off the mesh itself: the mesh is an affine image
    /// of `box_mesh(size, n)` vertex for vertex, so the images of four corners fix the map.
    fn world_of_local(m: &Mesh, size: Vec3, n: u32, local: Vec3) -> [Vec3; 2] {
        let rest = box_mesh(size, n);
        assert_eq!(
            rest.len(),
            m.t0.len(),
            "{}: not a box of {size} x {n}",
            m.name
        );
        let h = size * 0.5;
        let corner = |c: Vec3| rest.iter().position(|&p| p == c).unwrap();
        let origin = corner(-h);
        let axes = [Vec3::X, Vec3::Y, Vec3::Z].map(|a| corner(-h + 2.0 * h * a));
        let rel = (local + h) / size;
        [&m.t0, &m.t1].map(|pts| {
            let o = pts[origin];
            o + (0..3).map(|k| (pts[axes[k]] - o) * rel[k]).sum::<Vec3>()
        })
    }

    #[test]
    fn size_motion_and_rigid_body() {
        let s = scene();
        let n = s.triangle_count();
        assert!((8_000..14_000).contains(&n), "{n} triangles");
        let moving = super::super::character::test_support::moving_meshes(&s);
        assert_eq!(moving, KICK, "only the kicking leg moves");
        for m in &s.meshes {
            // Every part above the ground (the planes are at or behind it).
            if m.closed {
                for &p in m.t0.iter().chain(&m.t1) {
                    assert!(p.y > 0.004 && p.z > WALL_Z + 0.5, "{} at {p}", m.name);
                }
            }
        }
        // The kick moves the foot well forward, toward the light, and up.
        let [a0, a1] = world_of_local(
            mesh(&s, "foot-right"),
            FOOT,
            KICK_SUBDIVISIONS[2],
            FOOT_ANKLE,
        );
        assert!((a1 - a0).length() > 0.8, "{a0} -> {a1}");
        assert!((LIGHT - a1).length() < (LIGHT - a0).length() - 0.6);
        assert!(a1.y > a0.y);
    }

    #[test]
    fn joints_stay_connected() {
        let s = scene();
        let [thigh, shin, foot] = KICK.map(|name| mesh(&s, name));
        let [nt, ns, nf] = KICK_SUBDIVISIONS;
        let close = |a: [Vec3; 2], b: [Vec3; 2], what: &str| {
            for t in 0..2 {
                assert!(
                    (a[t] - b[t]).length() < 1e-4,
                    "{what} at t{t}: {} vs {}",
                    a[t],
                    b[t]
                );
            }
        };
        close(
            world_of_local(thigh, THIGH, nt, THIGH_HIP),
            [hip(); 2],
            "hip",
        );
        close(
            world_of_local(thigh, THIGH, nt, THIGH_KNEE),
            world_of_local(shin, SHIN, ns, SHIN_KNEE),
            "knee",
        );
        close(
            world_of_local(shin, SHIN, ns, SHIN_ANKLE),
            world_of_local(foot, FOOT, nf, FOOT_ANKLE),
            "ankle",
        );
        // The hip is inside the pelvis, so the thigh's top never shows a gap.
        let pelvis = mesh(&s, "pelvis");
        let (lo, hi) = pelvis
            .t0
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
        assert!(hip().cmpgt(lo).all() && hip().cmplt(hi).all());
        // Rigid: the part lengths are the same at both ends.
        let [k0, k1] = world_of_local(thigh, THIGH, nt, THIGH_KNEE);
        assert!(((k0 - hip()).length() - THIGH.y).abs() < 1e-4);
        assert!(((k1 - hip()).length() - THIGH.y).abs() < 1e-4);
    }

    /// The whole kicking leg is lit at both ends of the shutter (so at every time: the cone
    /// is convex and vertices move on straight lines), and so is the figure.
    #[test]
    fn leg_inside_light_cone() {
        let s = scene();
        for m in s.meshes.iter().filter(|m| m.closed) {
            super::super::character::test_support::assert_inside_spot_cone(&s, m);
        }
    }

    /// The kicking leg's shadow lands on the ground or the wall, inside them, in view of the
    /// camera (aspect 1, the narrowest likely), and lit surfaces have radiance ~0.1-1.
    #[test]
    fn shadow_on_screen_and_radiance_in_range() {
        let s = scene();
        let Light::Spot(light) = &s.light else {
            panic!("spot expected")
        };
        let ndc = |p: Vec3| s.camera.ndc_unit_aspect(p);
        let cos_cone = light.cone_angle_deg.to_radians().cos();
        let (mut on_ground, mut on_wall) = (0, 0);
        for m in KICK.map(|name| mesh(&s, name)) {
            for &p in m.t0.iter().chain(&m.t1) {
                let ray = p - light.position;
                assert!(
                    ray.y < 0.0 && ray.z < 0.0,
                    "{} not below/behind the light",
                    m.name
                );
                let to_ground = light.position.y / -ray.y;
                let to_wall = (WALL_Z - light.position.z) / ray.z;
                let hit = light.position + ray * to_ground.min(to_wall);
                if to_ground < to_wall {
                    on_ground += 1;
                } else {
                    on_wall += 1;
                }
                assert!(ray.normalize().dot(light.direction) > cos_cone);
                assert!(
                    hit.x.abs() < 4.0 && hit.y < 4.0,
                    "shadow off the wall: {hit}"
                );
                let ndc = ndc(hit);
                assert!(
                    ndc.x.abs() < 0.95 && ndc.y.abs() < 0.95,
                    "{} shadow off screen: {ndc}",
                    m.name
                );
            }
        }
        assert!(on_ground > 0 && on_wall > 0, "{on_ground} {on_wall}");

        let radiance = |p: Vec3, normal: Vec3, albedo: f32| {
            let d = light.position - p;
            albedo / std::f32::consts::PI * light.intensity * normal.dot(d.normalize())
                / d.length_squared()
        };
        let leg = radiance(hip() + Vec3::new(0.0, -0.2, 0.07), Vec3::Z, 0.85);
        let wall = radiance(Vec3::new(-0.5, 0.8, WALL_Z), Vec3::Z, 0.78);
        let ground = radiance(Vec3::new(0.0, 0.0, -1.0), Vec3::Y, 0.8);
        for (what, r) in [("leg", leg), ("wall", wall), ("ground", ground)] {
            assert!((0.05..1.0).contains(&r), "{what}: {r}");
        }
    }
}
