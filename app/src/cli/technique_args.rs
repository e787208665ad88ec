//! The values of the options that choose how shadows are made and read (`--method`,
//! `--truth`, `--static-layer`, `--prisms`, `--lookup`, `--range-storage`, `--pruning`,
//! `--shadow-filter`, `--receiver`, `--shadow-estimator`), with what each maps to in the
//! library or the renderer.

use clap::ValueEnum;

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// The depth-time ranges shadow map.
    Temporal,
    /// The temporal shadow map with the coverage map (2017 paper's extension).
    Coverage,
    /// Time-dependent shadow maps: one depth map per time stratum (as many as spp).
    Tsm,
    /// Brute-force accumulation over --slices times with ordinary shadow maps (the papers'
    /// ground truth).
    Reference,
    /// An ordinary shadow map of the scene frozen at mid-shutter (t = 0.5).
    Plain,
    /// The same samples ray traced on the CPU (motion BVH, watertight triangle test, no
    /// shadow map): the exact truth. Needs no Vulkan device.
    Raytrace,
}

/// `compare --truth`: the image every other method's error is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TruthArg {
    /// The brute-force reference (`--slices` shadow maps).
    Reference,
    /// The ray-traced reference (`--spp` samples, no shadow map).
    Raytrace,
}

/// `--static-layer`: where static triangles go in the temporal map, and whether the timed
/// pass keeps a layer drawn before it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum StaticLayerArg {
    On,
    Off,
    Kept,
}

impl StaticLayerArg {
    /// `RenderSettings::static_layer` and `keep_static_layer`.
    pub fn settings(self) -> (bool, bool) {
        match self {
            Self::On => (true, false),
            Self::Off => (false, false),
            Self::Kept => (true, true),
        }
    }
}

/// `--prisms`: how the temporal shadow map's collection pass builds each moving triangle's
/// fragments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PrismsArg {
    /// Covered times solved in closed form per texel: exact for any linear vertex motion.
    Exact,
    /// The papers' prism (caps and sides triangulated around their centres): exact only for
    /// translation.
    Paper,
}

/// `--lookup`: how the temporal map is read (the forward frame's samples, the deferred
/// frame's mask).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum LookupArg {
    /// The papers' depth-line test per texel.
    Depth,
    /// The exact test against the triangles the map names.
    Exact,
}

impl LookupArg {
    pub fn lookup(self) -> motion_shadows::technique::Lookup {
        match self {
            Self::Depth => motion_shadows::technique::Lookup::DepthLine,
            Self::Exact => motion_shadows::technique::Lookup::Exact,
        }
    }

    /// As typed, and in the JSON's `lookup`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Depth => "depth",
            Self::Exact => "exact",
        }
    }
}

/// `--range-storage`: how the temporal map keeps the ranges its collection stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RangeStorageArg {
    /// Each texel's ranges contiguous, in order of start time.
    Sorted,
    /// Per-texel linked lists in the order the collection appended them.
    Lists,
}

/// `--pruning`: which ranges the sort of sorted ranges leaves out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PruningArg {
    /// Ranges behind the static layer (where receivers are tested at their plane's depth).
    StaticLayer,
    /// Also ranges that nearer ranges of two other triangles cover all along.
    Cover,
    /// The coverage map in one pass: where one triangle covers the texel all frame, nearest
    /// at every time, only its range (receivers on it are then lit there).
    Coverage,
}

impl PruningArg {
    pub fn pruning(self) -> motion_shadows::technique::Pruning {
        match self {
            Self::StaticLayer => motion_shadows::technique::Pruning::StaticLayer,
            Self::Cover => motion_shadows::technique::Pruning::Cover,
            Self::Coverage => motion_shadows::technique::Pruning::Coverage,
        }
    }
}

impl RangeStorageArg {
    pub fn storage(self) -> motion_shadows::technique::RangeStorage {
        match self {
            Self::Sorted => motion_shadows::technique::RangeStorage::Sorted,
            Self::Lists => motion_shadows::technique::RangeStorage::Lists,
        }
    }
}

impl PrismsArg {
    pub fn construction(self) -> motion_shadows::technique::PrismConstruction {
        match self {
            Self::Exact => motion_shadows::technique::PrismConstruction::Exact,
            Self::Paper => motion_shadows::technique::PrismConstruction::Paper,
        }
    }
}

/// `--shadow-filter`: how a shadow map is read around a receiver.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FilterArg {
    /// The receiver's own texel.
    None,
    /// The 2x2 texels around the receiver's projection, bilinear weights (PCF).
    Bilinear,
    /// Bilinear lookups averaged over the pixel's footprint on the receiver's plane.
    Footprint,
}

impl FilterArg {
    pub fn filter(self) -> motion_shadows::technique::ShadowFilter {
        match self {
            Self::None => motion_shadows::technique::ShadowFilter::None,
            Self::Bilinear => motion_shadows::technique::ShadowFilter::Bilinear,
            Self::Footprint => motion_shadows::technique::ShadowFilter::Footprint,
        }
    }
}

/// `--receiver`: how a receiver is tested against the shadow maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ReceiverArg {
    /// `plane` where the maps hold triangle ids (temporal, coverage, reference, plain),
    /// `offset` for TSM.
    Auto,
    /// The receiver's tangent plane's depth at the texel centre, no normal offset.
    Plane,
    /// The receiver moved one shadow texel along its normal (the papers').
    Offset,
}

impl ReceiverArg {
    /// The setting, with the older `--receiver-plane` flag folded in.
    pub fn test(self, receiver_plane_flag: bool) -> crate::render::ReceiverTest {
        use crate::render::ReceiverTest;
        match self {
            _ if receiver_plane_flag => ReceiverTest::Plane,
            Self::Auto => ReceiverTest::Auto,
            Self::Plane => ReceiverTest::Plane,
            Self::Offset => ReceiverTest::Offset,
        }
    }
}

/// `--shadow-estimator`: how the temporal shadow map's shadow term is estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EstimatorArg {
    /// The papers' test at each sample's time (noisy over time).
    Sampled,
    /// Static receivers take the exact lit fraction of the shutter (no time noise); samples
    /// on moving triangles keep the per-sample test.
    Analytic,
}

impl EstimatorArg {
    pub fn estimator(self) -> motion_shadows::technique::ShadowEstimator {
        match self {
            Self::Sampled => motion_shadows::technique::ShadowEstimator::Sampled,
            Self::Analytic => motion_shadows::technique::ShadowEstimator::Analytic,
        }
    }
}
