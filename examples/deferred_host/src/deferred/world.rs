//! The world: what the engine draws, plain data plus each mesh's transform as a function of
//! the frame time.

use super::*;

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

/// Object to world at frame time `f` (in frames: frame f's shutter runs from f - 1 to f),
/// in f64 as an engine's scene graph might: the meshes move rigidly.
pub type Transform = Box<dyn Fn(f64) -> DMat4>;

/// One mesh of the world.
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: MeshIndices,
    pub albedo: Vec3,
    /// Watertight, wound counter-clockwise seen from outside (the shadow pass may skip its
    /// triangles that face away from the light all shutter).
    pub closed: bool,
    pub transform: Transform,
}

impl Mesh {
    pub fn triangle_count(&self) -> u32 {
        (self.indices.count() / 3) as u32
    }
}

/// The engine's camera (right-handed, y up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Full vertical field of view.
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

/// A light of the world; each gets a `LightShadow` (a map per frame in flight, the mask).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A point light with a hard cone, falling off as 1 / d^2; `intensity` in W/sr.
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_half_angle_deg: f32,
        intensity: f32,
        /// The shadow map's depth range.
        near: f32,
        far: f32,
    },
    /// A parallel light (`irradiance` in W/m^2 facing it); its shadow map is an
    /// orthographic box around `center`.
    Directional {
        direction: Vec3,
        irradiance: f32,
        center: Vec3,
        half_extent: f32,
        distance: f32,
        near: f32,
        far: f32,
    },
}

impl Light {
    /// The library's description of the light (what its shadow is made for).
    pub fn engine_light(&self) -> motion_shadows::Light {
        match *self {
            Light::Spot { position, direction, cone_half_angle_deg, intensity, near, far } => {
                motion_shadows::Light::spot(position, direction)
                    .cone_half_angle(cone_half_angle_deg)
                    .intensity(intensity)
                    .depth_range(near, far)
            }
            Light::Directional {
                direction,
                irradiance,
                center,
                half_extent,
                distance,
                near,
                far,
            } => motion_shadows::Light::directional(direction, center, half_extent)
                .distance(distance)
                .intensity(irradiance)
                .depth_range(near, far),
        }
    }

    /// `Light` in glsl/frame.glsl: position (w = 1 for a spot), direction (w = the cosine of
    /// the cone's half angle), emission.
    pub(super) fn constants(&self) -> [Vec4; 3] {
        match *self {
            Light::Spot { position, direction, cone_half_angle_deg: cone, intensity, .. } => [
                position.extend(1.0),
                direction.normalize().extend(cone.to_radians().cos()),
                Vec4::splat(intensity),
            ],
            Light::Directional { direction, irradiance, .. } => {
                [Vec4::ZERO, direction.normalize().extend(-1.0), Vec4::splat(irradiance)]
            }
        }
    }
}

/// Everything the engine draws.
pub struct World {
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// Radiance += ambient * albedo everywhere.
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// A box of half extents `half`: four vertices per face, outward normals, counter-clockwise
/// seen from outside.
pub fn cuboid(half: Vec3) -> (Vec<Vertex>, Vec<u16>) {
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    // (normal, u, v) with u x v = normal.
    for (n, u, v) in [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ] {
        let base = vertices.len() as u16;
        let (c, u, v) = (n * half, u * half, v * half);
        for p in [c - u - v, c + u - v, c + u + v, c - u + v] {
            let (position, normal) = (p.to_array(), n.to_array());
            vertices.push(Vertex { position, normal });
        }
        indices.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
    }
    (vertices, indices)
}

/// The still ground: a light grey `ground_grid(6, 4)` with 32-bit indices.
pub fn ground_mesh() -> Mesh {
    let (vertices, indices) = ground_grid(6.0, 4);
    Mesh {
        name: "ground".into(),
        vertices,
        indices: MeshIndices::U32(indices),
        albedo: Vec3::splat(0.8),
        closed: false,
        transform: Box::new(|_| DMat4::IDENTITY),
    }
}

/// A flat grid in the xz plane facing +y: `cells` x `cells` quads over [-half, half]^2.
pub fn ground_grid(half: f32, cells: u32) -> (Vec<Vertex>, Vec<u32>) {
    let (n, step) = (cells + 1, 2.0 * half / cells as f32);
    let vertices = (0..n * n)
        .map(|i| Vertex {
            position: [-half + (i % n) as f32 * step, 0.0, -half + (i / n) as f32 * step],
            normal: [0.0, 1.0, 0.0],
        })
        .collect();
    let mut indices = Vec::new();
    for (row, col) in (0..cells).flat_map(|r| (0..cells).map(move |c| (r, c))) {
        // a = (x0, z0), b = (x0, z1), c = (x1, z1), d = (x1, z0): (a, b, c) and (a, c, d)
        // are counter-clockwise seen from +y.
        let (a, d) = (row * n + col, row * n + col + 1);
        indices.extend([a, a + n, d + n, a, d + n, d]);
    }
    (vertices, indices)
}

impl World {
    /// The example's world: the ground, a box flying across it and turning, a still post;
    /// a spot light and a directional light.
    pub fn demo() -> World {
        let mesh = |name: &str, (vertices, indices): (Vec<Vertex>, Vec<u16>), albedo, transform| {
            let indices = MeshIndices::U16(indices);
            let (name, closed) = (String::from(name), true);
            Mesh { name, vertices, indices, albedo, closed, transform }
        };
        let flying: Transform = Box::new(|f| {
            DMat4::from_translation(glam::DVec3::new(-3.0 + 1.2 * f, 1.5, 0.6))
                * DMat4::from_rotation_y(0.35 * f)
        });
        let post: Transform =
            Box::new(|_| DMat4::from_translation(glam::DVec3::new(2.4, 0.8, 1.4)));
        World {
            camera: Camera {
                eye: Vec3::new(0.0, 7.5, 8.5),
                target: Vec3::new(0.2, 0.0, -0.6),
                up: Vec3::Y,
                fov_y_deg: 45.0,
                near: 0.1,
                far: 50.0,
            },
            lights: vec![
                Light::Spot {
                    position: Vec3::new(-3.0, 7.5, -3.5),
                    direction: Vec3::new(3.3, -7.5, 4.0),
                    cone_half_angle_deg: 38.0,
                    intensity: 110.0,
                    near: 1.0,
                    far: 30.0,
                },
                Light::Directional {
                    direction: Vec3::new(0.45, -1.0, 0.3),
                    irradiance: 0.9,
                    center: Vec3::ZERO,
                    half_extent: 7.5,
                    distance: 15.0,
                    near: 1.0,
                    far: 40.0,
                },
            ],
            ambient: 0.04,
            meshes: vec![
                ground_mesh(),
                mesh("flying box", cuboid(Vec3::splat(0.5)), Vec3::new(0.8, 0.25, 0.2), flying),
                mesh("post", cuboid(Vec3::new(0.3, 0.8, 0.3)), Vec3::new(0.3, 0.5, 0.8), post),
            ],
        }
    }
}
