//! The host's geometry, read in place: per draw, position streams at shutter open and close
//! (any stride and offset), an optional 16- or 32-bit index stream, object transforms at
//! t = 0 and t = 1, and the global id of its first triangle. Nothing is copied or read back on
//! the CPU: a [`DrawList`] holds the draws' descriptions (160 bytes each) in a small GPU
//! buffer that every pass reads by address.

use super::declared_barriers::record_own;
use super::gpu_types::{
    DRAW_CLOSED, DRAW_STATIC, DRAW_UNTRANSFORMED, DrawRecord, INDEX_NONE, INDEX_U16, INDEX_U32,
};
use crate::error::{Error, Result};
use crate::gpu::{Buffer, BufferUsage, Context};
use ash::vk;
use glam::{Mat4, Vec3, Vec4};

/// Positions of one stream: 3 floats (x, y, z) per vertex, `stride` bytes apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PositionStream {
    address: u64,
    stride: u32,
    /// Bytes readable from `address` on (u64::MAX when the host vouches for the range).
    available: u64,
}

impl PositionStream {
    /// Positions inside one of the library's own buffers (it must have been created with
    /// [`BufferUsage::Storage`] or [`BufferUsage::HostToDevice`]), starting `offset` bytes in.
    /// The bytes the draw's vertex count needs are checked against the buffer's size when
    /// the draw is added to a [`DrawList`].
    pub fn from_buffer(buffer: &Buffer, offset: u64, stride: u32) -> Result<Self> {
        let address = buffer.device_address();
        if address == 0 || offset > buffer.size() {
            return Err(Error::InvalidArgument(format!(
                "position stream at offset {offset} of {} ({} bytes, device address {address:#x})",
                buffer.name(),
                buffer.size()
            )));
        }
        Ok(Self {
            address: address + offset,
            stride,
            available: buffer.size() - offset,
        })
    }

    /// Positions in a host buffer, by device address (offset included).
    ///
    /// # Safety
    /// - `address` is the device address (`vkGetBufferDeviceAddress`, plus the offset) of a
    ///   buffer of the device the passes run on, created with
    ///   `VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT` and `STORAGE_BUFFER` usage.
    /// - For every draw using the stream, bytes `address .. address + (vertex_count - 1) *
    ///   stride + 12` lie inside that buffer, which stays alive and unchanged by the host
    ///   until every command buffer recording a pass with the draw has completed.
    /// - The host's writes to it (its skinning or upload) are made visible to shader reads
    ///   (`SHADER_STORAGE_READ` in the vertex, geometry, fragment and compute stages) by a
    ///   barrier of its own before the passes are recorded.
    pub unsafe fn from_device_address(address: u64, stride: u32) -> Self {
        Self {
            address,
            stride,
            available: u64::MAX,
        }
    }

    /// Positions in a host buffer given by its raw handle and size: the library asks the
    /// device for its address, and checks the bytes the draw's vertex count needs against
    /// `buffer_size - offset` when the draw is added to a [`DrawList`].
    ///
    /// # Safety
    /// `buffer` is a live buffer of `device` of `buffer_size` bytes, created with
    /// `SHADER_DEVICE_ADDRESS` and `STORAGE_BUFFER` usage and bound to memory allocated with
    /// the device-address flag; it stays alive and unchanged until every command buffer
    /// recording a pass with the draw has completed, and the host's writes to it are made
    /// visible to shader reads by a barrier of its own (as for
    /// [`Self::from_device_address`]).
    pub unsafe fn from_raw_buffer(
        device: &ash::Device,
        buffer: vk::Buffer,
        buffer_size: u64,
        offset: u64,
        stride: u32,
    ) -> Result<Self> {
        let info = vk::BufferDeviceAddressInfo::default().buffer(buffer);
        // SAFETY: the caller's contract: `buffer` is a live buffer of `device`, created with
        // SHADER_DEVICE_ADDRESS usage and bound to device-address memory, which is all
        // vkGetBufferDeviceAddress requires.
        let address = unsafe { device.get_buffer_device_address(&info) };
        if address == 0 || offset > buffer_size {
            return Err(Error::InvalidArgument(format!(
                "position stream at offset {offset} of a {buffer_size}-byte buffer (device address {address:#x})"
            )));
        }
        Ok(Self {
            address: address + offset,
            stride,
            available: buffer_size - offset,
        })
    }

    /// The device address of vertex 0's position.
    pub fn address(&self) -> u64 {
        self.address
    }

    /// Bytes between consecutive positions.
    pub fn stride(&self) -> u32 {
        self.stride
    }
}

/// Indices of a draw: three per triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Indices {
    /// Triangle i is vertices 3i, 3i + 1, 3i + 2.
    None,
    /// 16-bit indices (address 2-byte aligned).
    U16(IndexStream),
    /// 32-bit indices (address 4-byte aligned).
    U32(IndexStream),
}

/// Where an index stream lives. An index at or past the draw's vertex count drops its
/// triangle (no pass reads past the position streams) and is counted
/// ([`super::Counters::invalid_triangles`]), so a bad index is an error the host can see.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndexStream {
    address: u64,
    available: u64,
}

impl IndexStream {
    /// Indices inside one of the library's own buffers, starting `offset` bytes in.
    pub fn from_buffer(buffer: &Buffer, offset: u64) -> Result<Self> {
        let address = buffer.device_address();
        if address == 0 || offset > buffer.size() {
            return Err(Error::InvalidArgument(format!(
                "index stream at offset {offset} of {} ({} bytes)",
                buffer.name(),
                buffer.size()
            )));
        }
        Ok(Self {
            address: address + offset,
            available: buffer.size() - offset,
        })
    }

    /// Indices in a host buffer given by its raw handle and size (see
    /// [`PositionStream::from_raw_buffer`], whose contract applies).
    ///
    /// # Safety
    /// As [`PositionStream::from_raw_buffer`].
    pub unsafe fn from_raw_buffer(
        device: &ash::Device,
        buffer: vk::Buffer,
        buffer_size: u64,
        offset: u64,
    ) -> Result<Self> {
        let info = vk::BufferDeviceAddressInfo::default().buffer(buffer);
        // SAFETY: the caller's contract, as in PositionStream::from_raw_buffer: a live buffer of
        // `device` with device-address usage and memory.
        let address = unsafe { device.get_buffer_device_address(&info) };
        if address == 0 || offset > buffer_size {
            return Err(Error::InvalidArgument(format!(
                "index stream at offset {offset} of a {buffer_size}-byte buffer (device address {address:#x})"
            )));
        }
        Ok(Self {
            address: address + offset,
            available: buffer_size - offset,
        })
    }

    /// Indices in a host buffer, by device address (offset included).
    ///
    /// # Safety
    /// As [`PositionStream::from_device_address`], for bytes `address .. address + 3 *
    /// triangle_count * index size` of every draw using the stream. For 16-bit indices the
    /// library reads the aligned 32-bit words containing them, so the buffer must also
    /// contain the whole word of the first and last index.
    pub unsafe fn from_device_address(address: u64) -> Self {
        Self {
            address,
            available: u64::MAX,
        }
    }
}

/// One draw of the host's geometry: what the shadow passes (and the library's own lighting
/// pass) draw. Vertex v of the draw is at `transform_t0 * positions_t0[v]` at shutter open
/// and `transform_t1 * positions_t1[v]` at shutter close, and moves linearly in between.
///
/// Give a draw that does not move the same stream twice (and equal transforms): it is then
/// [static](Draw::is_static), and the collection pass rasterizes its triangles directly
/// instead of solving their covered times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Draw {
    /// Object-space positions at shutter open (for a skinned mesh: last frame's skinning).
    pub positions_t0: PositionStream,
    /// Object-space positions at shutter close (this frame's).
    pub positions_t1: PositionStream,
    /// Vertices in each position stream (fold a base vertex into the streams' addresses).
    pub vertex_count: u32,
    /// The draw's index stream, or [`Indices::None`].
    pub indices: Indices,
    /// Triangles drawn.
    pub triangle_count: u32,
    /// Global id of the draw's first triangle; triangle i has id `first_triangle_id + i`.
    /// Ids of different draws must not overlap: they tell a receiver's own triangle apart
    /// from every other (the self-shadow test), across meshes.
    pub first_triangle_id: u32,
    /// Object to world at shutter open (affine: bottom row 0, 0, 0, 1).
    pub transform_t0: Mat4,
    /// Object to world at shutter close (affine).
    pub transform_t1: Mat4,
    /// The mesh is closed and consistently wound (counter-clockwise seen from outside), and
    /// neither the light nor the camera is inside it: triangles facing away from the light
    /// all frame may then be skipped.
    pub closed: bool,
    /// Albedo, for the library's own lighting pass only (a host shading with its own
    /// materials may leave it at zero).
    pub albedo: Vec3,
}

impl Draw {
    /// A draw of `triangle_count` triangles with both transforms the identity, not closed.
    pub fn new(
        positions_t0: PositionStream,
        positions_t1: PositionStream,
        vertex_count: u32,
        indices: Indices,
        triangle_count: u32,
        first_triangle_id: u32,
    ) -> Self {
        Self {
            positions_t0,
            positions_t1,
            vertex_count,
            indices,
            triangle_count,
            first_triangle_id,
            transform_t0: Mat4::IDENTITY,
            transform_t1: Mat4::IDENTITY,
            closed: false,
            albedo: Vec3::ZERO,
        }
    }

    /// Nothing moves: the same position stream (address and stride) and the same transform
    /// at t = 0 and t = 1.
    pub fn is_static(&self) -> bool {
        self.positions_t0.address == self.positions_t1.address
            && self.positions_t0.stride == self.positions_t1.stride
            && self.transform_t0 == self.transform_t1
    }

    /// The ids after the draw's last (`first_triangle_id + triangle_count`).
    fn end_id(&self) -> u64 {
        self.first_triangle_id as u64 + self.triangle_count as u64
    }

    fn check(&self, which: usize) -> Result<DrawRecord> {
        let fail = |what: String| Err(Error::InvalidArgument(format!("draw {which}: {what}")));
        if self.end_id() >= u32::MAX as u64 {
            return fail(format!(
                "triangle ids {} + {} reach u32::MAX, which marks \"no triangle\"",
                self.first_triangle_id, self.triangle_count
            ));
        }
        for (name, s) in [("t0", &self.positions_t0), ("t1", &self.positions_t1)] {
            if s.stride < 12 || s.stride % 4 != 0 || s.address % 4 != 0 {
                return fail(format!(
                    "positions at {name}: stride {} and address {:#x} must be multiples of 4, stride at least 12 (3 floats)",
                    s.stride, s.address
                ));
            }
            let needed = if self.vertex_count == 0 {
                0
            } else {
                (self.vertex_count as u64 - 1) * s.stride as u64 + 12
            };
            if needed > s.available {
                return fail(format!(
                    "positions at {name}: {} vertices of stride {} need {needed} bytes, the buffer has {} from the stream's start",
                    self.vertex_count, s.stride, s.available
                ));
            }
        }
        let index_count = 3 * self.triangle_count as u64;
        let (kind, address) = match self.indices {
            Indices::None => {
                if index_count > self.vertex_count as u64 {
                    return fail(format!(
                        "{} triangles without indices need {index_count} vertices, the draw has {}",
                        self.triangle_count, self.vertex_count
                    ));
                }
                (INDEX_NONE, 0)
            }
            Indices::U16(s) | Indices::U32(s) => {
                let (kind, size) = match self.indices {
                    Indices::U16(_) => (INDEX_U16, 2),
                    _ => (INDEX_U32, 4),
                };
                // 16-bit indices are read as aligned 32-bit words.
                let span = if size == 2 {
                    (s.address + index_count * 2).next_multiple_of(4) - s.address
                } else {
                    index_count * 4
                };
                if s.address % size != 0 || (index_count > 0 && span > s.available) {
                    return fail(format!(
                        "{index_count} indices of {size} bytes at {:#x}: misaligned or past the buffer ({} bytes available)",
                        s.address, s.available
                    ));
                }
                (kind, s.address)
            }
        };
        let rows = |m: Mat4, name: &str| -> Result<[Vec4; 3]> {
            let affine = m.row(3) == Vec4::W && m.is_finite();
            if !affine {
                return Err(Error::InvalidArgument(format!(
                    "draw {which}: transform at {name} must be finite and affine (bottom row 0, 0, 0, 1)"
                )));
            }
            Ok([m.row(0), m.row(1), m.row(2)])
        };
        if !self.albedo.is_finite() {
            return fail(format!("albedo {} is not finite", self.albedo));
        }
        let untransformed =
            self.transform_t0 == Mat4::IDENTITY && self.transform_t1 == Mat4::IDENTITY;
        let flags = if self.closed { DRAW_CLOSED } else { 0 }
            | if untransformed { DRAW_UNTRANSFORMED } else { 0 }
            | if self.is_static() { DRAW_STATIC } else { 0 };
        Ok(DrawRecord {
            positions0: self.positions_t0.address,
            positions1: self.positions_t1.address,
            indices: address,
            stride0: self.positions_t0.stride,
            stride1: self.positions_t1.stride,
            index_kind: kind,
            vertex_count: self.vertex_count,
            first_id: self.first_triangle_id,
            triangle_count: self.triangle_count,
            albedo_flags: self.albedo.extend(flags as f32),
            model0: rows(self.transform_t0, "t0")?,
            model1: rows(self.transform_t1, "t1")?,
        })
    }
}

/// The draws of a frame on the GPU. Per frame in flight (the passes read it while the frame
/// runs); [`DrawList::record_update`] rewrites it inside the frame's command buffer, so the
/// host never writes memory the GPU may be reading.
pub struct DrawList {
    buffer: Buffer,
    capacity: u32,
    /// Sorted by first id (the lighting pass finds a triangle's draw by binary search).
    records: Vec<DrawRecord>,
    /// Records its entry and exit barriers (off: the host's, [`Self::with_host_barriers`]).
    pub(crate) outer_barriers: bool,
}

impl DrawList {
    /// Room for `capacity` draws (160 bytes each).
    pub fn new(ctx: &Context, capacity: u32) -> Result<Self> {
        let capacity = capacity.max(1);
        let bytes = capacity as u64 * std::mem::size_of::<DrawRecord>() as u64;
        Ok(Self {
            buffer: Buffer::new(ctx, "draw list", bytes, BufferUsage::Storage)?,
            capacity,
            records: Vec::new(),
            outer_barriers: true,
        })
    }

    /// Checks `draws` (strides, alignment, the bytes they need against the buffers the library
    /// knows, disjoint triangle ids, affine transforms) and records their upload into this
    /// list, with the barriers that order it after earlier passes that read the list and
    /// before later ones (from [`Self::update_accesses`] and [`Self::read_accesses`]; none
    /// on a list made [`Self::with_host_barriers`]: the caller's then). On error nothing is
    /// recorded and the list is unchanged.
    ///
    /// # Safety
    /// `cmd` is in the recording state, outside a render pass (or dynamic rendering), on a
    /// queue with graphics and compute; no command buffer that reads this list is pending
    /// when this one executes unless it was submitted earlier on the same queue.
    pub unsafe fn record_update(
        &mut self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        draws: &[Draw],
    ) -> Result<()> {
        if draws.len() > self.capacity as usize {
            return Err(Error::InvalidArgument(format!(
                "{} draws, the draw list has room for {}",
                draws.len(),
                self.capacity
            )));
        }
        let mut records = draws
            .iter()
            .enumerate()
            .map(|(i, d)| d.check(i))
            .collect::<Result<Vec<_>>>()?;
        records.sort_by_key(|r| r.first_id);
        for pair in records.windows(2) {
            if pair[0].first_id as u64 + pair[0].triangle_count as u64 > pair[1].first_id as u64 {
                return Err(Error::InvalidArgument(format!(
                    "draws with triangle ids from {} ({} triangles) and from {} overlap: every triangle needs its own id",
                    pair[0].first_id, pair[0].triangle_count, pair[1].first_id
                )));
            }
        }
        // Earlier passes of this or an earlier frame may still read the list.
        let own = super::own_barriers::draw_list_update(self);
        let check = self.buffer.access_check();
        if self.outer_barriers {
            // SAFETY: `cmd` is recording outside a render pass on a graphics and compute queue
            // (the contract), which supports every shader stage and the transfer stage.
            unsafe {
                record_own(
                    device,
                    cmd,
                    check,
                    "draw list update entry",
                    own.entry.as_ref(),
                )
            };
        }
        self.update_accesses()
            .declare_run(check, "draw list update");
        // SAFETY: the caller's contract; the buffer holds `capacity` records.
        unsafe { self.buffer.record_write(device, cmd, &records) };
        if self.outer_barriers {
            // SAFETY: as the barrier before: the same command buffer, outside a render pass.
            unsafe {
                record_own(
                    device,
                    cmd,
                    check,
                    "draw list update exit",
                    own.exit.as_ref(),
                )
            };
        }
        self.records = records;
        Ok(())
    }

    /// The draws as uploaded, sorted by first triangle id.
    pub fn records(&self) -> &[DrawRecord] {
        &self.records
    }

    /// Triangles in all draws.
    pub fn triangle_count(&self) -> u64 {
        self.records.iter().map(|r| r.triangle_count as u64).sum()
    }

    /// One past the largest triangle id (0 without draws).
    pub fn id_end(&self) -> u64 {
        self.records
            .last()
            .map_or(0, |r| r.first_id as u64 + r.triangle_count as u64)
    }

    /// The device address of the draw table.
    pub fn address(&self) -> u64 {
        self.buffer.device_address()
    }

    /// The list's one allocation, by name, with its bytes (see
    /// [`super::TemporalShadowMap::allocations`]).
    pub fn allocations(&self) -> Vec<(&str, u64)> {
        vec![(self.buffer.name(), self.buffer.allocated_bytes())]
    }

    /// The draw table's buffer.
    pub(crate) fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    pub(crate) fn draw_count(&self) -> u32 {
        self.records.len() as u32
    }
}
