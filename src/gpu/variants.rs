//! A compute shader with many specializations, each pipeline made the first time it is asked
//! for. Making a pipeline is slow on some drivers (lavapipe: about 0.1 s for a large shader),
//! so a pass whose shader has dozens of variants makes only those its frames use.

use super::context::{Context, Shared};
use super::pipeline::{Pipeline, ShaderModule, Spirv, compute_of_module};
use crate::error::Result;
use std::sync::{Arc, Mutex};

/// The pipelines of one compute shader, one per set of specialization constants (see
/// [`super::specialized_compute_pipeline`]), made on first use and kept until drop. Shareable
/// between threads: a variant is made once, whoever asks first.
pub struct ComputeVariants {
    shared: Arc<Shared>,
    module: ShaderModule,
    push_bytes: u32,
    made: Mutex<Vec<(Vec<u32>, Arc<Pipeline>)>>,
}

impl ComputeVariants {
    /// Variants of the compute shader `spirv` (`name` for error messages) whose layout has
    /// `push_bytes` of push constants and no descriptor sets. Makes no pipeline yet.
    pub fn new(ctx: &Context, push_bytes: u32, name: &str, spirv: Spirv<'_>) -> Result<Self> {
        Ok(Self {
            shared: ctx.shared.clone(),
            module: ShaderModule::new(ctx, name, spirv)?,
            push_bytes,
            made: Mutex::new(Vec::new()),
        })
    }

    /// The pipeline whose constant `constant_id = i` is `constants[i]`, made now if it was
    /// not made before.
    pub fn get(&self, constants: &[u32]) -> Result<Arc<Pipeline>> {
        // A panic elsewhere while the lock was held cannot have left the list half-changed
        // (a variant is pushed whole, once made), so a poisoned lock is taken as it is.
        let mut made = self
            .made
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((_, pipeline)) = made.iter().find(|(key, _)| key == constants) {
            return Ok(pipeline.clone());
        }
        let pipeline = Arc::new(compute_of_module(
            &self.shared,
            &[],
            self.push_bytes,
            &self.module,
            constants,
        )?);
        made.push((constants.to_vec(), pipeline.clone()));
        Ok(pipeline)
    }

    /// How many variants have been made so far.
    pub fn made(&self) -> usize {
        self.made
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
            .len()
    }
}
