//! The forward frame's passes, each made by the first frame that records it. A renderer
//! renders one method or two (every `motion-shadows` run makes one), and on lavapipe making a
//! pass's pipelines costs more CPU than a small frame: a temporal frame never needs the
//! coverage or plain passes, a plain, TSM or reference frame never the collection's.

use super::Method;
use motion_shadows::Result;
use motion_shadows::gpu::Context;
use motion_shadows::technique::{
    CollectionPass, CoveragePass, GenerationPass, LightingPass, PlainShadowPass,
};

#[derive(Default)]
pub(super) struct Passes {
    collection: Option<CollectionPass>,
    generation: Option<GenerationPass>,
    coverage: Option<CoveragePass>,
    lighting: Option<LightingPass>,
    plain: Option<PlainShadowPass>,
}

/// The pass in `slot`, made there first if it is empty.
fn made<T>(slot: &mut Option<T>, make: impl FnOnce() -> Result<T>) -> Result<&mut T> {
    if slot.is_none() {
        *slot = Some(make()?);
    }
    Ok(slot.as_mut().expect("filled above"))
}

impl Passes {
    pub fn collection(&mut self, ctx: &Context) -> Result<&mut CollectionPass> {
        made(&mut self.collection, || CollectionPass::new(ctx))
    }

    pub fn generation(&mut self, ctx: &Context) -> Result<&mut GenerationPass> {
        made(&mut self.generation, || GenerationPass::new(ctx))
    }

    pub fn coverage(&mut self, ctx: &Context) -> Result<&mut CoveragePass> {
        made(&mut self.coverage, || CoveragePass::new(ctx))
    }

    pub fn lighting(&mut self, ctx: &Context) -> Result<&mut LightingPass> {
        made(&mut self.lighting, || LightingPass::new(ctx))
    }

    pub fn plain(&mut self, ctx: &Context) -> Result<&mut PlainShadowPass> {
        made(&mut self.plain, || PlainShadowPass::new(ctx))
    }

    /// Makes the passes a forward frame of `method` records, before its clock starts (the
    /// ray tracer records none).
    pub fn make_for(&mut self, ctx: &Context, method: Method) -> Result<()> {
        match method {
            Method::Temporal => {
                self.collection(ctx)?;
                self.generation(ctx)?;
            }
            Method::Coverage => {
                self.collection(ctx)?;
                self.generation(ctx)?;
                self.coverage(ctx)?;
            }
            Method::Tsm | Method::Reference { .. } | Method::Plain { .. } => {
                self.plain(ctx)?;
            }
            Method::Raytrace => return Ok(()),
        }
        self.lighting(ctx).map(|_| ())
    }
}
