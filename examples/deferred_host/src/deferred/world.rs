//! The world: what the engine draws, plain data plus each mesh's transform over time.

use super::*;
/// The lights are the library's (`motion_shadows::Light`): the shading reads each from its map.
pub use motion_shadows::Light;

/// A vertex as the engine stores it: 24 bytes, position then normal (object space).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// A mesh's indices: 16-bit for small meshes, 32-bit for large ones.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshIndices {
    U16(Vec<u16>),
    U32(Vec<u32>),
}

impl MeshIndices {
    pub fn count(&self) -> usize {
        match self {
            Self::U16(i) => i.len(),
            Self::U32(i) => i.len(),
        }
    }
}

/// Object to world at frame time `f` (frame f's shutter runs from f - 1 to f), in f64 as a
/// scene graph might: the meshes move rigidly.
pub type Transform = Box<dyn Fn(f64) -> DMat4>;

/// One mesh of the world; `closed`: watertight, counter-clockwise seen from outside (the
/// shadow pass may skip its triangles that face away from the light all shutter).
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: MeshIndices,
    pub albedo: Vec3,
    pub closed: bool,
    pub transform: Transform,
}

/// The camera (right-handed, y up; the full vertical field of view).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// World to Vulkan clip space (y down, depth in [0, 1] from near to far).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
        let proj = vulkan::perspective(self.fov_y_deg.to_radians(), aspect, self.near, self.far);
        proj * look_at_mat4(self.eye, self.target, self.up)
    }
}

/// Everything the engine draws; radiance += ambient * albedo everywhere.
pub struct World {
    pub camera: Camera,
    pub lights: Vec<Light>,
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// A box of half extents `half`: four vertices a face, outward normals, counter-clockwise
/// seen from outside.
pub fn cuboid(half: Vec3) -> (Vec<Vertex>, Vec<u16>) {
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    // (normal, u, v) with u x v = normal.
    let (x, y, z) = (Vec3::X, Vec3::Y, Vec3::Z);
    let faces = [
        (x, -z, y),
        (-x, z, y),
        (y, x, -z),
        (-y, x, z),
        (z, x, y),
        (-z, -x, y),
    ];
    for (n, u, v) in faces {
        let (base, c, u, v) = (vertices.len() as u16, n * half, u * half, v * half);
        for p in [c - u - v, c + u - v, c + u + v, c - u + v] {
            vertices.push(Vertex {
                position: p.to_array(),
                normal: n.to_array(),
            });
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
    }
    (vertices, indices)
}

/// The still ground: a light grey `ground_grid(6, 4)` with 32-bit indices.
pub fn ground_mesh() -> Mesh {
    let (vertices, indices) = ground_grid(6.0, 4);
    let (name, indices, albedo) = ("ground".into(), MeshIndices::U32(indices), Vec3::splat(0.8));
    Mesh {
        name,
        vertices,
        indices,
        albedo,
        closed: false,
        transform: Box::new(|_| DMat4::IDENTITY),
    }
}

/// A flat grid in the xz plane facing +y: `cells` x `cells` quads over [-half, half]^2.
pub fn ground_grid(half: f32, cells: u32) -> (Vec<Vertex>, Vec<u32>) {
    let (n, step, normal) = (cells + 1, 2.0 * half / cells as f32, [0.0, 1.0, 0.0]);
    let at = |i: u32| {
        [
            -half + (i % n) as f32 * step,
            0.0,
            -half + (i / n) as f32 * step,
        ]
    };
    let vertices = (0..n * n)
        .map(|i| Vertex {
            position: at(i),
            normal,
        })
        .collect();
    // a = (x0, z0), b = a + n = (x0, z1), c = d + n = (x1, z1), d = (x1, z0): (a, b, c) and
    // (a, c, d) are counter-clockwise seen from +y.
    let cells = (0..cells).flat_map(|row| (0..cells).map(move |col| row * n + col));
    (
        vertices,
        cells
            .flat_map(|a| [a, a + n, a + 1 + n, a, a + 1 + n, a + 1])
            .collect(),
    )
}

impl World {
    /// The example's world: the ground, a box flying across it and turning, a still post;
    /// a spot light and a directional light.
    pub fn demo() -> World {
        let mesh = |name: &str, half, albedo, transform: Transform| {
            let (vertices, indices) = cuboid(half);
            let (name, indices) = (name.into(), MeshIndices::U16(indices));
            Mesh {
                name,
                vertices,
                indices,
                albedo,
                closed: true,
                transform,
            }
        };
        let at = |x, y, z| DMat4::from_translation(glam::DVec3::new(x, y, z));
        let flying =
            Box::new(move |f| at(1.2 * f - 3.0, 1.5, 0.6) * DMat4::from_rotation_y(0.35 * f));
        let (eye, target, up) = (Vec3::new(0.0, 7.5, 8.5), Vec3::new(0.2, 0.0, -0.6), Vec3::Y);
        let camera = Camera {
            eye,
            target,
            up,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 50.0,
        };
        let (position, direction) = (Vec3::new(-3.0, 7.5, -3.5), Vec3::new(3.3, -7.5, 4.0));
        let spot = Light::spot(position, direction).cone_half_angle(38.0);
        let spot = spot.intensity(110.0).depth_range(1.0, 30.0);
        let sun = Light::directional(Vec3::new(0.45, -1.0, 0.3), Vec3::ZERO, 7.5).distance(15.0);
        let sun = sun.intensity(0.9).depth_range(1.0, 40.0);
        let (red, blue) = (Vec3::new(0.8, 0.25, 0.2), Vec3::new(0.3, 0.5, 0.8));
        let flying_box = mesh("flying box", Vec3::splat(0.5), red, flying);
        let post = Box::new(move |_| at(2.4, 0.8, 1.4));
        let post = mesh("post", Vec3::new(0.3, 0.8, 0.3), blue, post);
        let meshes = vec![ground_mesh(), flying_box, post];
        World {
            camera,
            lights: vec![spot, sun],
            ambient: 0.04,
            meshes,
        }
    }
}
