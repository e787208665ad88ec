//! Time-dependent shadow maps as an engine builds them (`EngineTsmPass`): N depth maps over
//! the shutter, the static draws' map drawn once and kept, and a mask over the host's
//! G-buffer (drawn here by the library's `GBufferPass` from the receivers alone). Checked
//! against closed forms: a caster translating over a still plane, a plane translating under a
//! still caster, a still square's shadow; and the kept static map against a redrawn one. Each
//! runs with both ways a map starts from the static one (`TsmStart`), one map per dispatch
//! and in batches (`EngineTsmMap::layers`).

mod convergence;
mod declared;
mod rig;
mod static_map;
mod strata;

use motion_shadows::technique::TsmStart;

/// The mask's pixels.
const SIZE: (u32, u32) = (96, 96);
/// The maps' texels on a side.
const SHADOW: u32 = 512;
/// Half the side of the directional light's box around the origin.
const HALF: f32 = 3.0;
/// A texel of the maps, in world units.
const TEXEL: f32 = 2.0 * HALF / SHADOW as f32;
/// How the maps start from the static map, and how many are drawn per dispatch (5: batches
/// of 5, 5, 5, 1 for 16 maps).
const CONFIGS: [(TsmStart, u32); 4] = [
    (TsmStart::Copy, 1),
    (TsmStart::SecondLookup, 1),
    (TsmStart::Copy, 5),
    (TsmStart::SecondLookup, 8),
];
