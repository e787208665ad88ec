//! Small scenes built by hand, and their temporal shadow map from the library's passes alone:
//! what the prism and generation tests need, without the app. The types have the app's scene
//! types' fields (`motion_shadows_app::scene`), so a test reads the same on either side; the
//! upload does what the app's (`render::upload`) does, written again here because the
//! library's tests must not depend on the app: one interleaved vertex buffer (t0 and t1 positions,
//! stride 32), one draw per mesh, a mesh that does not move naming its t0 positions twice,
//! triangle ids in scene order.

use glam::{Vec3, Vec4};
use motion_shadows::gpu::{Buffer, BufferUsage, Context, OneShot};
use motion_shadows::technique::{
    CollectionPass, Counters, Draw, DrawList, GenerationPass, Indices, LightView, PositionStream,
    PrismConstruction, Pruning, RangeStorage, ShadowMapContents, TemporalShadowMap,
};

pub struct Scene {
    pub name: String,
    pub camera: Camera,
    pub light: Light,
    pub ambient: f32,
    pub meshes: Vec<Mesh>,
}

/// Triangle list: vertex i moves linearly from `t0[i]` to `t1[i]` over the shutter.
pub struct Mesh {
    pub name: String,
    pub albedo: Vec3,
    /// Watertight and consistently wound: drawn with back faces culled.
    pub closed: bool,
    pub t0: Vec<Vec3>,
    pub t1: Vec<Vec3>,
}

pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
}

#[derive(Debug, Clone)]
pub enum Light {
    Spot(SpotLight),
    Directional(DirectionalLight),
}

#[derive(Debug, Clone)]
pub struct SpotLight {
    pub position: Vec3,
    pub direction: Vec3,
    /// The cone's half angle.
    pub cone_angle_deg: f32,
    pub intensity: f32,
    pub near: f32,
    pub far: f32,
}

#[derive(Debug, Clone)]
pub struct DirectionalLight {
    pub direction: Vec3,
    pub irradiance: f32,
    pub center: Vec3,
    pub half_extent: f32,
    pub distance: f32,
    pub near: f32,
    pub far: f32,
}

/// The scene's light as the library sees it, at `shadow_size` (the app's `light_view`).
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

/// The temporal shadow map of `scene` at `shadow_size`, built with the default (exact)
/// prisms.
pub fn temporal_map(ctx: &Context, scene: &Scene, shadow_size: (u32, u32)) -> ShadowMapContents {
    temporal_map_with(ctx, scene, shadow_size, PrismConstruction::default(), true)
}

/// [`temporal_map`] with the prisms built as `prisms` says, and static draws in the static
/// layer or (`static_layer` false) in the lists: the collection and generation passes in one
/// submission, the map grown and the passes run again until nothing overflowed (as the app's
/// renderer builds it).
pub fn temporal_map_with(
    ctx: &Context,
    scene: &Scene,
    shadow_size: (u32, u32),
    prisms: PrismConstruction,
    static_layer: bool,
) -> ShadowMapContents {
    let pixels = shadow_size.0 * shadow_size.1;
    let light = LightView {
        prisms,
        static_layer,
        ..light_view(scene, shadow_size)
    };
    temporal_map_stored(
        ctx,
        scene,
        shadow_size,
        &light,
        RangeStorage::default(),
        Pruning::default(),
        pixels,
    )
    .0
}

/// The temporal map of `scene` lit by `light` (made for `shadow_size`), its collected ranges
/// kept as `storage` says (sorted ones pruned by `pruning`), starting with room for `range_capacity` ranges (grown and run
/// again until nothing overflowed), and the counters of its last run.
pub fn temporal_map_stored(
    ctx: &Context,
    scene: &Scene,
    shadow_size: (u32, u32),
    light: &LightView,
    storage: RangeStorage,
    pruning: Pruning,
    range_capacity: u32,
) -> (ShadowMapContents, Counters) {
    let (map, counts) = temporal_map_built(
        ctx,
        scene,
        shadow_size,
        light,
        storage,
        pruning,
        range_capacity,
    );
    (map.download(ctx).expect("download"), counts)
}

/// [`temporal_map_stored`]'s map itself, on the device (for lookups in test shaders), with
/// triangle records where `light` asks for the exact lookup.
pub fn temporal_map_built(
    ctx: &Context,
    scene: &Scene,
    shadow_size: (u32, u32),
    light: &LightView,
    storage: RangeStorage,
    pruning: Pruning,
    range_capacity: u32,
) -> (TemporalShadowMap, Counters) {
    let vertices: Vec<[Vec4; 2]> = (scene.meshes.iter())
        .flat_map(|m| m.t0.iter().zip(&m.t1))
        .map(|(p0, p1)| [p0.extend(1.0), p1.extend(1.0)])
        .collect();
    let buffer = Buffer::with_data(ctx, "scene vertices", BufferUsage::HostToDevice, &vertices)
        .expect("vertex buffer");
    let stride = std::mem::size_of::<[Vec4; 2]>() as u32;
    let (mut first_vertex, mut first_id) = (0u64, 0u32);
    let mut draws = Vec::new();
    for mesh in &scene.meshes {
        let count = mesh.t0.len() as u32;
        let offset = first_vertex * u64::from(stride);
        if count >= 3 {
            let t1_offset = if mesh.t0 == mesh.t1 {
                offset
            } else {
                offset + 16
            };
            let mut draw = Draw::new(
                PositionStream::from_buffer(&buffer, offset, stride).expect("t0 stream"),
                PositionStream::from_buffer(&buffer, t1_offset, stride).expect("t1 stream"),
                count,
                Indices::None,
                count / 3,
                first_id,
            );
            draw.closed = mesh.closed;
            draw.albedo = mesh.albedo;
            draws.push(draw);
        }
        first_vertex += u64::from(count);
        first_id += count / 3;
    }
    let device = ctx.device();
    let collection = CollectionPass::new(ctx).expect("collection pass");
    let generation = GenerationPass::new(ctx).expect("generation pass");
    let mut list = DrawList::new(ctx, draws.len() as u32).expect("draw list");
    let pixels = shadow_size.0 * shadow_size.1;
    let nodes = if light.collects_ranges(false) {
        1
    } else {
        pixels.saturating_mul(2)
    };
    let mut map = TemporalShadowMap::with_storage(
        ctx,
        shadow_size.0,
        shadow_size.1,
        nodes,
        range_capacity,
        storage,
    )
    .expect("temporal shadow map")
    .with_pruning(pruning);
    map.prepare_for(ctx, light, None)
        .expect("the light's buffers");
    if light.lookup == motion_shadows::technique::Lookup::Exact {
        map.reserve_triangle_records(ctx, u64::from(first_id))
            .expect("triangle records");
    }
    loop {
        OneShot::new(ctx)
            .expect("command buffer")
            .run(|cmd| {
                // SAFETY: a OneShot command buffer of `ctx`, recording, outside rendering;
                // every object outlives the submission, which `run` waits for.
                unsafe {
                    list.record_update(device, cmd, &draws)?;
                    collection.record(device, cmd, &list, light, &map, None)?;
                    generation.record(device, cmd, &map);
                    map.record_counter_readback(device, cmd);
                }
                Ok(())
            })
            .expect("shadow pass");
        let counts = map.read_counters().expect("counters");
        if !map.needs_more_room(&counts) {
            map.check_complete(&counts).expect("complete map");
            return (map, counts);
        }
        map.grow_to_fit(ctx, &counts).expect("grow");
    }
}

pub fn mesh(name: &str, t0: Vec<Vec3>, t1: Vec<Vec3>, closed: bool) -> Mesh {
    Mesh {
        name: name.into(),
        albedo: Vec3::splat(0.8),
        closed,
        t0,
        t1,
    }
}

pub fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 6.0, 8.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: 100.0,
    }
}

/// Straight down onto the xz plane, an orthographic box of half-width `half_extent`.
pub fn overhead_directional(half_extent: f32) -> Light {
    Light::Directional(DirectionalLight {
        direction: Vec3::NEG_Y,
        irradiance: 3.0,
        center: Vec3::ZERO,
        half_extent,
        distance: 10.0,
        near: 0.5,
        far: 20.0,
    })
}

pub fn overhead_spot(height: f32, cone_deg: f32) -> Light {
    Light::Spot(SpotLight {
        position: Vec3::new(0.0, height, 0.0),
        direction: Vec3::NEG_Y,
        cone_angle_deg: cone_deg,
        intensity: 40.0,
        near: 0.5,
        far: 50.0,
    })
}

pub fn scene(name: &str, light: Light, meshes: Vec<Mesh>) -> Scene {
    Scene {
        name: name.into(),
        camera: camera(),
        light,
        ambient: 0.0,
        meshes,
    }
}

/// Two triangles of a square in the xz plane at height y, corner (x, z), side s, facing +y.
pub fn square(x: f32, z: f32, s: f32, y: f32) -> Vec<Vec3> {
    let a = Vec3::new(x, y, z);
    let b = Vec3::new(x, y, z + s);
    let c = Vec3::new(x + s, y, z + s);
    let d = Vec3::new(x + s, y, z);
    vec![a, b, c, a, c, d]
}

pub fn translated(points: &[Vec3], by: Vec3) -> Vec<Vec3> {
    points.iter().map(|p| *p + by).collect()
}

/// The CPU prism model's view of the scene's light, with the matrices the renderer uses.
pub fn light_setup(s: &Scene, size: (u32, u32)) -> super::prism_model::LightSetup {
    let light = light_view(s, size);
    super::prism_model::LightSetup {
        view: light.view,
        proj: light.proj,
        orthographic: !light.is_spot(),
        width: size.0,
        height: size.1,
    }
}

/// A unit cube centred on the origin: its 8 corners and its 12 triangles as indices,
/// counter-clockwise seen from outside.
pub fn indexed_unit_cube() -> (Vec<Vec3>, Vec<u32>) {
    let corners = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32) - 0.5)
        .collect();
    let quads: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let indices = quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect();
    (corners, indices)
}

// The app's `scene::box_mesh` (app/src/scene/primitives.rs), copied: a box's triangles.

/// Box of the given full size centred at the origin; each face is a `subdivisions` x
/// `subdivisions` grid (0 is treated as 1), so 12 * n^2 triangles, wound counter-clockwise
/// seen from outside (cross(b - a, c - a) points outward).
pub fn box_mesh(size: Vec3, subdivisions: u32) -> Vec<Vec3> {
    let n = subdivisions.max(1);
    let h = size * 0.5;
    let (x, y, z) = (Vec3::X * h.x, Vec3::Y * h.y, Vec3::Z * h.z);
    // (outward normal offset, u, v) with u x v along the outward normal.
    let faces = [
        (x, y, z),
        (-x, z, y),
        (y, z, x),
        (-y, x, z),
        (z, x, y),
        (-z, y, x),
    ];
    let mut out = Vec::with_capacity(36 * (n * n) as usize);
    for (c, u, v) in faces {
        push_grid(&mut out, c, u, v, n);
    }
    out
}

fn push_grid(out: &mut Vec<Vec3>, center: Vec3, u: Vec3, v: Vec3, n: u32) {
    let point = |i: u32, j: u32| {
        let a = 2.0 * i as f32 / n as f32 - 1.0;
        let b = 2.0 * j as f32 / n as f32 - 1.0;
        center + u * a + v * b
    };
    for i in 0..n {
        for j in 0..n {
            let (p00, p10, p11, p01) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            out.extend_from_slice(&[p00, p10, p11, p00, p11, p01]);
        }
    }
}
