//! The world: what the engine draws, plain data plus animation functions of the frame time.

use super::*;

// ---------------------------------------------------------------------------------------
// The world: what the engine draws. Plain data plus animation functions of the frame time.
// ---------------------------------------------------------------------------------------

/// A vertex as the engine stores it: 24 bytes, position then normal (object space).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
}

/// A mesh's index buffer contents: 16-bit indices for small meshes, 32-bit for large ones.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshIndices {
    U16(Vec<u16>),
    U32(Vec<u32>),
}

impl MeshIndices {
    /// How many indices (three per triangle).
    pub fn count(&self) -> usize {
        match self {
            Self::U16(i) => i.len(),
            Self::U32(i) => i.len(),
        }
    }
}

/// How a mesh moves. `f` is the frame time in frames: frame f's shutter runs from f - 1 to f.
pub enum Motion {
    /// A rigid object: its vertices stay in the static vertex buffer, and only its
    /// object-to-world transform changes (the shadow pass gets last frame's and this
    /// frame's). Computed in f64, as an engine's scene graph might.
    Rigid(Box<dyn Fn(f64) -> DMat4>),
    /// Deformed on the CPU (think skinning): world-space vertices of frame time f, written
    /// each frame into a per-frame-in-flight vertex buffer next to last frame's positions.
    Deformed(Box<dyn Fn(f64) -> Vec<Vertex>>),
}

/// One mesh of the world.
pub struct Mesh {
    pub name: String,
    /// Object-space vertices (for a deformed mesh: its rest pose, unused by the GPU).
    pub vertices: Vec<Vertex>,
    pub indices: MeshIndices,
    pub albedo: Vec3,
    /// Watertight and wound counter-clockwise seen from outside (lets the shadow pass skip
    /// triangles facing away from the light all frame).
    pub closed: bool,
    pub motion: Motion,
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
    /// World -> Vulkan clip space (depth in [0, 1], y down).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        use glam::camera::rh::{proj::vulkan, view::look_at_mat4};
        let view = look_at_mat4(self.eye, self.target, self.up);
        // Vulkan's clip space: y down, depth in [0, 1] (near to far).
        let proj = vulkan::perspective(self.fov_y_deg.to_radians(), aspect, self.near, self.far);
        proj * view
    }
}

/// A light of the world. Each gets a temporal shadow map per frame in flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// A point light with a hard cone; radiance falls off as 1 / d^2.
    Spot {
        position: Vec3,
        direction: Vec3,
        cone_half_angle_deg: f32,
        /// W/sr.
        intensity: f32,
        /// The shadow map's depth range.
        near: f32,
        far: f32,
    },
    /// A parallel light; its shadow map is an orthographic box around `center`.
    Directional {
        direction: Vec3,
        /// W/m^2 on a surface facing the light.
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
            Light::Spot {
                position,
                direction,
                cone_half_angle_deg,
                intensity,
                near,
                far,
            } => motion_shadows::Light::spot(position, direction)
                .cone_half_angle(cone_half_angle_deg)
                .intensity(intensity)
                .depth_range(near, far),
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
}

/// Everything the engine draws.
pub struct World {
    pub camera: Camera,
    pub lights: Vec<Light>,
    /// Radiance += ambient * albedo everywhere.
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// Four vertices per face, outward normals, counter-clockwise seen from outside.
pub fn cuboid(half: Vec3) -> (Vec<Vertex>, Vec<u16>) {
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    // (normal, u, v) with u x v = normal.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    for (n, u, v) in faces {
        let base = vertices.len() as u16;
        let (c, u, v) = (n * half, u * half, v * half);
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

/// The static ground of both demo worlds: a light grey `ground_grid(6, 4)`, 32-bit indices.
pub fn ground_mesh() -> Mesh {
    let (vertices, indices) = ground_grid(6.0, 4);
    Mesh {
        name: "ground".into(),
        vertices,
        indices: MeshIndices::U32(indices),
        albedo: Vec3::splat(0.8),
        closed: false,
        motion: Motion::Rigid(Box::new(|_| DMat4::IDENTITY)),
    }
}

/// A flat grid in the xz plane facing +y: `cells` x `cells` quads over [-half, half]^2.
pub fn ground_grid(half: f32, cells: u32) -> (Vec<Vertex>, Vec<u32>) {
    let n = cells + 1;
    let step = 2.0 * half / cells as f32;
    let vertices = (0..n * n)
        .map(|i| Vertex {
            position: [
                -half + (i % n) as f32 * step,
                0.0,
                -half + (i / n) as f32 * step,
            ],
            normal: [0.0, 1.0, 0.0],
        })
        .collect();
    let mut indices = Vec::new();
    for row in 0..cells {
        for col in 0..cells {
            // a = (x0, z0), b = (x0, z1), c = (x1, z1), d = (x1, z0): (a, b, c) and (a, c, d)
            // are counter-clockwise seen from +y.
            let (a, d) = (row * n + col, row * n + col + 1);
            let (b, c) = (a + n, d + n);
            indices.extend([a, b, c, a, c, d]);
        }
    }
    (vertices, indices)
}

/// The bent strip's vertices: `segments` quads along its length, tilted by `tilt_deg` about
/// the x axis around `centre`, bent by a wave that travels with the frame time.
pub(super) fn strip_vertices(centre: Vec3, tilt_deg: f32, segments: u32, f: f64) -> Vec<Vertex> {
    let (half_length, half_width, amplitude) = (1.2f32, 0.55f32, 0.22f32);
    let tilt = tilt_deg.to_radians();
    let (ex, ev) = (Vec3::X, Vec3::new(0.0, tilt.sin(), tilt.cos()));
    let en = ev.cross(ex); // the strip's unbent normal, upward
    let phase = f as f32 * 1.3;
    let mut out = Vec::new();
    for side in [-half_width, half_width] {
        for i in 0..=segments {
            let u = -half_length + 2.0 * half_length * i as f32 / segments as f32;
            let wave = amplitude * (2.2 * u + phase).sin();
            let slope = amplitude * 2.2 * (2.2 * u + phase).cos();
            out.push(Vertex {
                position: (centre + u * ex + side * ev + wave * en).to_array(),
                normal: (en - slope * ex).normalize().to_array(),
            });
        }
    }
    out
}

pub(super) fn strip_indices(segments: u32) -> Vec<u32> {
    let n = segments + 1;
    let mut indices = Vec::new();
    for i in 0..segments {
        // Row 0 is the -v side, row 1 the +v side: (a, b, c), (a, c, d) face en.
        let (a, d) = (i, i + 1);
        let (b, c) = (i + n, i + 1 + n);
        indices.extend([a, b, c, a, c, d]);
    }
    indices
}

impl World {
    /// The example's world: a ground grid, a box flying across it and turning, a static
    /// pillar, and a bent strip that the CPU deforms every frame while it drifts; a spot
    /// light and a directional light.
    pub fn demo() -> World {
        let (box_v, box_i) = cuboid(Vec3::splat(0.5));
        let (pillar_v, pillar_i) = cuboid(Vec3::new(0.3, 0.8, 0.3));
        const SEGMENTS: u32 = 6;
        let strip = |f: f64| {
            let centre = Vec3::new(0.9, 1.5, -2.8 + 0.6 * f as f32);
            strip_vertices(centre, -30.0, SEGMENTS, f)
        };
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
                Mesh {
                    name: "flying box".into(),
                    vertices: box_v,
                    indices: MeshIndices::U16(box_i),
                    albedo: Vec3::new(0.8, 0.25, 0.2),
                    closed: true,
                    motion: Motion::Rigid(Box::new(|f| {
                        DMat4::from_translation(glam::DVec3::new(-3.0 + 1.2 * f, 1.5, 0.6))
                            * DMat4::from_rotation_y(0.35 * f)
                    })),
                },
                Mesh {
                    name: "pillar".into(),
                    vertices: pillar_v,
                    indices: MeshIndices::U16(pillar_i),
                    albedo: Vec3::new(0.3, 0.5, 0.8),
                    closed: true,
                    motion: Motion::Rigid(Box::new(|_| {
                        DMat4::from_translation(glam::DVec3::new(2.4, 0.8, 1.4))
                    })),
                },
                Mesh {
                    name: "bent strip".into(),
                    vertices: strip(0.0),
                    indices: MeshIndices::U32(strip_indices(SEGMENTS)),
                    albedo: Vec3::new(0.85, 0.75, 0.3),
                    closed: false,
                    motion: Motion::Deformed(Box::new(strip)),
                },
            ],
        }
    }
}
