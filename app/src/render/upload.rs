//! Scene (app data) to what the passes consume: flat GPU vertex/triangle arrays, and the
//! camera and light as matrices.

use crate::scene::{Light, Scene};
use motion_shadows::technique::{
    CameraView, LightView, SceneVertex, TRIANGLE_CLOSED, TRIANGLE_MOVING, TriangleInfo,
};

/// Every mesh's triangles in scene order; triangle ids follow that order.
pub fn flatten(scene: &Scene) -> (Vec<SceneVertex>, Vec<TriangleInfo>) {
    let mut vertices = Vec::with_capacity(scene.triangle_count() * 3);
    let mut triangles = Vec::with_capacity(scene.triangle_count());
    for mesh in &scene.meshes {
        for (p0, p1) in mesh.t0.iter().zip(&mesh.t1) {
            vertices.push(SceneVertex {
                p0: p0.extend(1.0),
                p1: p1.extend(1.0),
            });
        }
        let closed = if mesh.closed { TRIANGLE_CLOSED } else { 0 };
        for (t0, t1) in mesh.t0.chunks_exact(3).zip(mesh.t1.chunks_exact(3)) {
            let moving = if t0 == t1 { 0 } else { TRIANGLE_MOVING };
            triangles.push(TriangleInfo::new(mesh.albedo, closed | moving));
        }
    }
    (vertices, triangles)
}

pub fn camera_view(scene: &Scene, image_size: (u32, u32)) -> CameraView {
    let c = &scene.camera;
    CameraView::perspective(
        c.position,
        c.target,
        c.up,
        c.fov_y_deg,
        image_size.0 as f32 / image_size.1 as f32,
        c.near,
        c.far,
    )
}

pub fn light_view(scene: &Scene, shadow_size: (u32, u32)) -> LightView {
    match &scene.light {
        Light::Spot(s) => LightView::spot(
            s.position,
            s.direction,
            s.cone_angle_deg,
            s.intensity,
            s.near,
            s.far,
            shadow_size,
        ),
        Light::Directional(d) => LightView::directional(
            d.direction,
            d.irradiance,
            d.center,
            d.half_extent,
            d.distance,
            d.near,
            d.far,
            shadow_size,
        ),
    }
}
