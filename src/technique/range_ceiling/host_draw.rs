//! The host's copy of a draw: what the bound reads on the CPU, mirroring the GPU's `Draw`.

use glam::{Mat4, Vec3};

use crate::error::{Error, Result};

/// A draw as the host holds it: the same positions, indices and transforms as the
/// [`crate::technique::Draw`] it mirrors, read on the CPU. Give the same slice twice (and equal
/// transforms) for a draw that does not move, exactly as its `Draw` names one stream twice.
#[derive(Debug, Clone, Copy)]
pub struct HostDraw<'a> {
    /// Object-space positions at shutter open.
    pub positions_t0: &'a [Vec3],
    /// Object-space positions at shutter close (as many).
    pub positions_t1: &'a [Vec3],
    /// Three per triangle, or None: the positions taken three at a time.
    pub indices: Option<&'a [u32]>,
    /// Object to world at shutter open.
    pub transform_t0: Mat4,
    /// Object to world at shutter close.
    pub transform_t1: Mat4,
    /// As [`crate::technique::Draw::closed`].
    pub closed: bool,
}

impl<'a> HostDraw<'a> {
    /// Both transforms the identity, not closed, as [`crate::technique::Draw::new`].
    pub fn new(
        positions_t0: &'a [Vec3],
        positions_t1: &'a [Vec3],
        indices: Option<&'a [u32]>,
    ) -> Self {
        Self {
            positions_t0,
            positions_t1,
            indices,
            transform_t0: Mat4::IDENTITY,
            transform_t1: Mat4::IDENTITY,
            closed: false,
        }
    }

    /// As [`crate::technique::Draw::is_static`]: one slice named twice and one transform.
    pub fn is_static(&self) -> bool {
        std::ptr::eq(self.positions_t0, self.positions_t1) && self.transform_t0 == self.transform_t1
    }

    /// Its triangles' world-space corners at t = 0 and t = 1, in draw order; an error names
    /// the first index beyond the positions, streams of different lengths, or corners that
    /// are not whole triangles (none is left out unsaid).
    pub fn triangles(&self) -> Result<impl Iterator<Item = ([Vec3; 3], [Vec3; 3])> + '_> {
        let n = self.positions_t0.len();
        if self.positions_t1.len() != n {
            return Err(Error::InvalidArgument(format!(
                "a host draw's positions: {n} at shutter open, {} at shutter close",
                self.positions_t1.len()
            )));
        }
        let listed = self.indices.map_or(n, <[u32]>::len);
        if listed % 3 != 0 {
            return Err(Error::InvalidArgument(format!(
                "a host draw lists {listed} corners ({}), not whole triangles",
                if self.indices.is_some() {
                    "indices"
                } else {
                    "positions"
                }
            )));
        }
        let count = match self.indices {
            Some(indices) => {
                if let Some((at, &i)) = indices.iter().enumerate().find(|(_, i)| **i as usize >= n)
                {
                    return Err(Error::InvalidArgument(format!(
                        "a host draw's index {at} is {i}, beyond its {n} positions"
                    )));
                }
                indices.len() / 3
            }
            None => n / 3,
        };
        let vertex = move |k: usize| self.indices.map_or(k, |i| i[k] as usize);
        Ok((0..count).map(move |tri| {
            let at = |positions: &[Vec3], transform: Mat4| {
                [0, 1, 2].map(|c| transform.transform_point3(positions[vertex(3 * tri + c)]))
            };
            (
                at(self.positions_t0, self.transform_t0),
                at(self.positions_t1, self.transform_t1),
            )
        }))
    }
}
