//! The room a mesh's shadow needs, from the same description as its draw.

use super::mesh::{Mesh, RoomSource};
use crate::error::Result;
use crate::technique::{Bounded, RangeCeiling};

impl Bounded for Mesh<'_> {
    fn is_still(&self) -> bool {
        Mesh::is_still(self)
    }

    fn ranges_at_most(&self, ceiling: &RangeCeiling) -> Result<u64> {
        Ok(match self.room()? {
            RoomSource::Cpu(cpu) => self
                .cpu_triangles(cpu)?
                .map(|(t0, t1)| ceiling.triangle(&t0, &t1, self.is_closed()))
                .sum(),
            RoomSource::Bound(bound) => {
                let (open, close) = self.bound_corners(&bound);
                let each = ceiling.triangle_within(&open, &close, !self.is_still());
                each.saturating_mul(u64::from(self.triangle_count()))
            }
        })
    }
}
