//! What the engine's shaders read (std140 constants), and where its geometry lives.

use super::*;

// What the engine's shaders read, and where its geometry lives.

/// Per-frame constants, `Frame` in `glsl/frame.glsl` (std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct FrameConstants {
    pub(super) view_proj: Mat4,
    pub(super) inv_view_proj: Mat4,
    pub(super) eye: Vec4,
    pub(super) info: UVec4,
    pub(super) shading: Vec4,
    pub(super) lights: [LightConstants; MAX_LIGHTS],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub(super) struct LightConstants {
    pub(super) position: Vec4,
    pub(super) direction: Vec4,
    pub(super) emission: Vec4,
}

/// The G-buffer pass's push constants (`Draw` in gbuffer.vert): 128 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct DrawConstants {
    pub(super) model: [Vec4; 3],
    pub(super) previous_model: [Vec4; 3],
    pub(super) albedo: Vec4,
    /// The mesh's first global triangle id (its `Draw`'s): plus the primitive's index, the
    /// id the G-buffer stores.
    pub(super) first_id: u32,
    pub(super) pad: [u32; 3],
}

/// The shading pass's push constants (`Push` in shade.comp): 24 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(super) struct ShadeConstants {
    pub(super) maps: [u64; MAX_LIGHTS],
    pub(super) lookup: u32,
    pub(super) time: f32,
}

pub(super) const LOOKUP_MASKS: u32 = 0;
pub(super) const LOOKUP_LIT_FRACTION: u32 = 1;
pub(super) const LOOKUP_AT_TIME: u32 = 2;

/// Bytes per deformed vertex in the per-frame vertex buffer: last frame's position, this
/// frame's position, this frame's normal, each padded to 16 bytes.
pub(super) const DEFORMED_STRIDE: u32 = 48;

/// Where a mesh's data lives.
#[derive(Debug, Clone, Copy)]
pub(super) struct MeshSlot {
    /// Rigid: byte offset of its vertices in the static vertex buffer. Deformed: in each
    /// frame's deformed-vertex buffer.
    pub(super) vertex_offset: u64,
    pub(super) vertex_count: u32,
    /// Byte offset of its indices in the index buffer, and their type.
    pub(super) index_offset: u64,
    pub(super) index_type: vk::IndexType,
    pub(super) index_count: u32,
    /// Global id of its first triangle (ids of different meshes never overlap).
    pub(super) first_triangle_id: u32,
}

/// The engine's own geometry buffers, shared by every frame (never written after upload).
pub(super) struct Geometry {
    pub(super) static_vertices: HostBuffer,
    pub(super) indices: HostBuffer,
    pub(super) meshes: Vec<MeshSlot>,
    /// Bytes of deformed vertices each frame writes.
    pub(super) deformed_bytes: u64,
}

impl Geometry {
    pub(super) fn upload(gpu: &Gpu, allocator: &SharedAllocator, world: &World) -> Result<Self> {
        let (mut vertices, mut index_bytes, mut meshes) =
            (Vec::new(), Vec::<u8>::new(), Vec::new());
        let (mut deformed_bytes, mut next_id) = (0u64, 0u32);
        for mesh in &world.meshes {
            // Indices: each mesh at a 4-byte aligned offset of one buffer.
            index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
            let index_offset = index_bytes.len() as u64;
            let index_type = match &mesh.indices {
                MeshIndices::U16(i) => {
                    index_bytes.extend(i.iter().flat_map(|v| v.to_le_bytes()));
                    vk::IndexType::UINT16
                }
                MeshIndices::U32(i) => {
                    index_bytes.extend(i.iter().flat_map(|v| v.to_le_bytes()));
                    vk::IndexType::UINT32
                }
            };
            let vertex_offset = match mesh.motion {
                Motion::Rigid(_) => {
                    let offset = (vertices.len() * std::mem::size_of::<Vertex>()) as u64;
                    vertices.extend_from_slice(&mesh.vertices);
                    offset
                }
                Motion::Deformed(_) => {
                    let offset = deformed_bytes;
                    deformed_bytes += mesh.vertices.len() as u64 * DEFORMED_STRIDE as u64;
                    offset
                }
            };
            meshes.push(MeshSlot {
                vertex_offset,
                vertex_count: mesh.vertices.len() as u32,
                index_offset,
                index_type,
                index_count: mesh.indices.count() as u32,
                first_triangle_id: next_id,
            });
            next_id += mesh.triangle_count();
        }
        // The library reads 16-bit indices as whole 32-bit words: pad the buffer's end.
        index_bytes.resize(index_bytes.len().next_multiple_of(4), 0);
        // Vertex or index buffers for the rasterizer, storage buffers with a device address
        // for the library's shadow pass: one buffer, both usages.
        let shared =
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        Ok(Self {
            static_vertices: HostBuffer::with_data(
                gpu,
                allocator,
                &vertices,
                vk::BufferUsageFlags::VERTEX_BUFFER | shared,
            )?,
            indices: HostBuffer::with_data(
                gpu,
                allocator,
                &index_bytes,
                vk::BufferUsageFlags::INDEX_BUFFER | shared,
            )?,
            meshes,
            deformed_bytes,
        })
    }
}
