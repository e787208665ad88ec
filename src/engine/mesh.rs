//! One description of a mesh, from which both the GPU draw and the room reserved for its
//! shadow are derived: the two cannot disagree, and whether it moves is said, not guessed
//! from its buffers.

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};
use crate::technique::{Draw, Indices, PositionStream};

/// Whether a mesh moves during the shutter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Motion {
    /// One position stream and one transform all shutter: the static layer may hold it.
    Still,
    /// Positions or transforms differ between shutter open and close.
    Moving,
}

/// The host's CPU copy of a mesh's geometry, when it has one: the room reserved for the
/// shadow is then bounded triangle by triangle (tight). Without it, give a [`MeshBound`].
#[derive(Debug, Clone, Copy)]
pub struct CpuGeometry<'a> {
    at_open: &'a [Vec3],
    /// None for a still mesh's one copy.
    at_close: Option<&'a [Vec3]>,
    indices: CpuIndices<'a>,
}

/// A [`CpuGeometry`]'s indices, of the width its GPU [`Indices`] have.
#[derive(Debug, Clone, Copy)]
enum CpuIndices<'a> {
    None,
    U16(&'a [u16]),
    U32(&'a [u32]),
}

impl<'a> CpuGeometry<'a> {
    /// The positions of a [`Mesh::still`] (object space), not indexed.
    pub fn still(positions: &'a [Vec3]) -> Self {
        Self {
            at_open: positions,
            at_close: None,
            indices: CpuIndices::None,
        }
    }

    /// The positions of a [`Mesh::moving`] at shutter open and close (object space).
    pub fn moving(at_open: &'a [Vec3], at_close: &'a [Vec3]) -> Self {
        Self {
            at_open,
            at_close: Some(at_close),
            indices: CpuIndices::None,
        }
    }

    /// With 16-bit indices (the mesh's GPU indices must be [`Indices::U16`]).
    pub fn indices_u16(self, indices: &'a [u16]) -> Self {
        Self {
            indices: CpuIndices::U16(indices),
            ..self
        }
    }

    /// With 32-bit indices (the mesh's GPU indices must be [`Indices::U32`]).
    pub fn indices_u32(self, indices: &'a [u32]) -> Self {
        Self {
            indices: CpuIndices::U32(indices),
            ..self
        }
    }
}

/// What the host knows cheaply of a mesh only the GPU holds (skinned by a compute pass):
/// an object-space box holding every vertex at shutter open and one at shutter close (the
/// triangle count is the mesh's). A box too small is reported after the frame
/// ([`super::LightShadow::finish_frame`]), never silently dropped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshBound {
    /// (min, max) corners at shutter open.
    pub at_open: (Vec3, Vec3),
    /// (min, max) corners at shutter close.
    pub at_close: (Vec3, Vec3),
}

impl MeshBound {
    /// One box holding every vertex all shutter.
    pub fn box_all_shutter(min: Vec3, max: Vec3) -> Self {
        Self {
            at_open: (min, max),
            at_close: (min, max),
        }
    }

    /// The 8 corners of a box, transformed.
    fn corners((min, max): (Vec3, Vec3), transform: Mat4) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            let pick = |bit: usize, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
            let p = Vec3::new(
                pick(1, min.x, max.x),
                pick(2, min.y, max.y),
                pick(4, min.z, max.z),
            );
            transform.transform_point3(p)
        })
    }
}

/// How the room for a mesh's shadow is bounded.
#[derive(Debug, Clone, Copy)]
enum Room<'a> {
    /// Neither said yet: reserving for it is refused.
    Unbounded,
    Cpu(CpuGeometry<'a>),
    Bound(MeshBound),
}

/// One mesh as the host describes it, once: its GPU position streams (one for a still mesh,
/// one per shutter end for a moving one), indices, transforms, and either its CPU geometry or
/// a cheap bound. [`super::LightShadow::record_frame`] derives the GPU draw and the room
/// reserved for the frame from it.
///
/// ```no_run
/// # use motion_shadows::{Indices, Mesh, MeshBound, PositionStream, IndexStream};
/// # use motion_shadows::glam::{Mat4, Vec3};
/// # let (prev, now, idx): (PositionStream, PositionStream, IndexStream) = todo!();
/// // A skinned character: last frame's and this frame's skinning output, a box per end.
/// let character = Mesh::moving(prev, now, 5000)
///     .indexed(Indices::U32(idx), 9000)
///     .transform(Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)))
///     .bound(MeshBound::box_all_shutter(Vec3::splat(-1.0), Vec3::splat(1.0)));
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Mesh<'a> {
    motion: Motion,
    at_open: PositionStream,
    at_close: PositionStream,
    vertex_count: u32,
    indices: Indices,
    triangle_count: u32,
    first_triangle_id: u32,
    transforms: (Mat4, Mat4),
    closed: bool,
    room: Room<'a>,
}

impl<'a> Mesh<'a> {
    /// A mesh that does not move during the shutter: `vertex_count` positions (3 floats each,
    /// `stride` bytes apart in `positions`), triangles of three consecutive vertices until
    /// [`Self::indexed`].
    pub fn still(positions: PositionStream, vertex_count: u32) -> Self {
        Self::with_motion(Motion::Still, positions, positions, vertex_count)
    }

    /// A mesh that moves: its positions at shutter open (for a skinned mesh, last frame's
    /// skinning) and at shutter close (this frame's), `vertex_count` in each.
    pub fn moving(at_open: PositionStream, at_close: PositionStream, vertex_count: u32) -> Self {
        Self::with_motion(Motion::Moving, at_open, at_close, vertex_count)
    }

    fn with_motion(
        motion: Motion,
        at_open: PositionStream,
        at_close: PositionStream,
        vertex_count: u32,
    ) -> Self {
        Self {
            motion,
            at_open,
            at_close,
            vertex_count,
            indices: Indices::None,
            triangle_count: vertex_count / 3,
            first_triangle_id: 0,
            transforms: (Mat4::IDENTITY, Mat4::IDENTITY),
            closed: false,
            room: Room::Unbounded,
        }
    }

    /// Draws `triangle_count` triangles of `indices` (16- or 32-bit, three per triangle).
    pub fn indexed(self, indices: Indices, triangle_count: u32) -> Self {
        Self {
            indices,
            triangle_count,
            ..self
        }
    }

    /// One object-to-world transform (affine) all shutter.
    pub fn transform(self, transform: Mat4) -> Self {
        self.transforms(transform, transform)
    }

    /// Object-to-world transforms (affine) at shutter open and close: only a
    /// [`Self::moving`] mesh may have two different ones.
    pub fn transforms(self, at_open: Mat4, at_close: Mat4) -> Self {
        Self {
            transforms: (at_open, at_close),
            ..self
        }
    }

    /// The global id of the mesh's first triangle (triangle i has `first + i`): ids of
    /// different meshes must not overlap; the host's triangle-id image uses the same ids.
    pub fn first_triangle_id(self, first: u32) -> Self {
        Self {
            first_triangle_id: first,
            ..self
        }
    }

    /// The mesh is closed and wound counter-clockwise seen from outside, and neither the
    /// light nor the camera is inside it: triangles facing away from the light all shutter
    /// are skipped.
    pub fn closed(self) -> Self {
        Self {
            closed: true,
            ..self
        }
    }

    /// The host's CPU copy of the geometry (checked against the description when used).
    pub fn cpu(self, geometry: CpuGeometry<'a>) -> Self {
        Self {
            room: Room::Cpu(geometry),
            ..self
        }
    }

    /// A cheap bound for a mesh only the GPU holds.
    pub fn bound(self, bound: MeshBound) -> Self {
        Self {
            room: Room::Bound(bound),
            ..self
        }
    }

    /// Whether the mesh was described as still.
    pub fn is_still(&self) -> bool {
        self.motion == Motion::Still
    }

    /// Whether the mesh was described as closed ([`Self::closed`]).
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// Triangles drawn.
    pub fn triangle_count(&self) -> u32 {
        self.triangle_count
    }

    /// One past the mesh's last triangle id.
    pub(crate) fn id_end(&self) -> u64 {
        u64::from(self.first_triangle_id) + u64::from(self.triangle_count)
    }

    /// The GPU draw, after checking that the description holds together (`which`: the
    /// mesh's place, for the error).
    pub fn draw(&self, which: usize) -> Result<Draw> {
        let fail = |what: String| Err(Error::InvalidArgument(format!("mesh {which}: {what}")));
        let (t0, t1) = self.transforms;
        match self.motion {
            Motion::Still if t0 != t1 => {
                return fail(
                    "described as still (Mesh::still) but its transforms at shutter open and \
                     close differ: describe it with Mesh::moving"
                        .into(),
                );
            }
            Motion::Moving if self.at_open == self.at_close && t0 == t1 => {
                return fail(
                    "described as moving (Mesh::moving) but it names one position stream at \
                     both ends with one transform: describe it with Mesh::still"
                        .into(),
                );
            }
            _ => {}
        }
        if let Room::Cpu(cpu) = &self.room {
            if let Err(e) = self.check_cpu(cpu) {
                return fail(e);
            }
        }
        let mut draw = Draw::new(
            self.at_open,
            self.at_close,
            self.vertex_count,
            self.indices,
            self.triangle_count,
            self.first_triangle_id,
        );
        draw.transform_t0 = t0;
        draw.transform_t1 = t1;
        draw.closed = self.closed;
        Ok(draw)
    }

    /// The CPU geometry says what the GPU description says: as many positions, the same
    /// motion, indices of the same width and count.
    fn check_cpu(&self, cpu: &CpuGeometry) -> std::result::Result<(), String> {
        let n = self.vertex_count as usize;
        match (self.motion, cpu.at_close) {
            (Motion::Still, Some(_)) => {
                return Err("a still mesh with moving CPU geometry (CpuGeometry::moving)".into());
            }
            (Motion::Moving, None) => {
                return Err("a moving mesh with still CPU geometry (CpuGeometry::still)".into());
            }
            _ => {}
        }
        for (end, positions) in [("open", Some(cpu.at_open)), ("close", cpu.at_close)] {
            if let Some(p) = positions.filter(|p| p.len() != n) {
                return Err(format!(
                    "{} CPU positions at shutter {end}, the GPU streams have {n}",
                    p.len()
                ));
            }
        }
        let listed = match (cpu.indices, self.indices) {
            (CpuIndices::None, Indices::None) => None,
            (CpuIndices::U16(i), Indices::U16(_)) => Some(i.len()),
            (CpuIndices::U32(i), Indices::U32(_)) => Some(i.len()),
            (cpu, gpu) => {
                return Err(format!(
                    "CPU indices {} and GPU indices {} differ in width",
                    cpu.width(),
                    match gpu {
                        Indices::None => "none",
                        Indices::U16(_) => "u16",
                        Indices::U32(_) => "u32",
                    }
                ));
            }
        };
        let needed = 3 * self.triangle_count as usize;
        if listed.is_some_and(|l| l != needed) {
            return Err(format!(
                "{} CPU indices for {} triangles (3 each)",
                listed.unwrap_or(0),
                self.triangle_count
            ));
        }
        Ok(())
    }

    /// Each triangle's world-space corners at shutter open and close, from the CPU geometry;
    /// an error names the first index beyond the positions.
    pub(crate) fn cpu_triangles(
        &self,
        cpu: CpuGeometry<'a>,
    ) -> Result<impl Iterator<Item = ([Vec3; 3], [Vec3; 3])> + '_> {
        self.check_cpu(&cpu).map_err(|e| {
            Error::InvalidArgument(format!(
                "the mesh with triangle ids from {}: {e}",
                self.first_triangle_id
            ))
        })?;
        let n = self.vertex_count as usize;
        let index = move |k: usize| -> usize {
            match cpu.indices {
                CpuIndices::None => k,
                CpuIndices::U16(i) => usize::from(i[k]),
                CpuIndices::U32(i) => i[k] as usize,
            }
        };
        let corners = 3 * self.triangle_count as usize;
        if let Some(k) = (0..corners).find(|&k| index(k) >= n) {
            return Err(Error::InvalidArgument(format!(
                "the mesh with triangle ids from {}: index {k} is {}, beyond its {n} positions",
                self.first_triangle_id,
                index(k)
            )));
        }
        let (t0, t1) = self.transforms;
        let (open, close) = (cpu.at_open, cpu.at_close.unwrap_or(cpu.at_open));
        Ok((0..self.triangle_count as usize).map(move |tri| {
            let at =
                |p: &[Vec3], m: Mat4| [0, 1, 2].map(|c| m.transform_point3(p[index(3 * tri + c)]));
            (at(open, t0), at(close, t1))
        }))
    }

    /// The bound's world-space corners at shutter open and close.
    pub(crate) fn bound_corners(&self, bound: &MeshBound) -> ([Vec3; 8], [Vec3; 8]) {
        let (t0, t1) = self.transforms;
        (
            MeshBound::corners(bound.at_open, t0),
            MeshBound::corners(bound.at_close, t1),
        )
    }

    /// The CPU geometry or bound the room is reserved from, or the error saying neither was
    /// given.
    pub(crate) fn room(&self) -> Result<RoomSource<'a>> {
        match self.room {
            Room::Cpu(cpu) => Ok(RoomSource::Cpu(cpu)),
            Room::Bound(bound) => Ok(RoomSource::Bound(bound)),
            Room::Unbounded => Err(Error::InvalidArgument(format!(
                "the mesh with triangle ids from {} has neither CPU geometry (Mesh::cpu) nor a \
                 bound (Mesh::bound): the room for its shadow cannot be reserved",
                self.first_triangle_id
            ))),
        }
    }
}

/// What a mesh's room is reserved from.
pub(crate) enum RoomSource<'a> {
    Cpu(CpuGeometry<'a>),
    Bound(MeshBound),
}

impl CpuIndices<'_> {
    fn width(&self) -> &'static str {
        match self {
            Self::None => "none",
            Self::U16(_) => "u16",
            Self::U32(_) => "u32",
        }
    }
}
