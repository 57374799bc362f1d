//! PCSS pass (Fernando 2005): screen-space visibility from a blocker search and a PCF disk
//! sized by the light.
//!
//! Input: the frame uniform, the camera depth and the shadow map. Output: an R16F visibility
//! texture, or on the compute path one the lights share (R16F where the device stores half floats, else R32F) ([`super::ScreenPipeline`]). Blocker and PCF tap counts come from [`crate::PcssSettings`].

use super::{LIGHT_KIND, ScreenStage, ShadowLookup, VisibilityPass};
use crate::frame::{PassParams, PcssUniform};
use crate::pipeline_cache::CachedDevice;

pub struct PcssPass(ShadowLookup);

impl PcssPass {
    /// The pass for one light kind ([`crate::frame::light_kind`]: the other kinds' code is
    /// compiled out, as in the distance-map method's passes), run and stored as `path` says
    /// (a compute pass writing the light's layer too with layers); another kind or the other kind of
    /// pass needs a new pass. The blocker search reads the shadow map unfiltered, a second
    /// binding beside the comparison sampler's.
    pub fn new(device: &CachedDevice<'_>, frame_size: usize, light_kind: u32, path: super::PassPath) -> Self {
        let shader = crate::shaders::module_for(device, "pcss.wgsl", crate::shaders::PCSS, path.module());
        let constants = [(LIGHT_KIND, light_kind as f64)];
        let sizes = (frame_size, size_of::<PcssUniform>(), true);
        Self(ShadowLookup::new(
            device,
            "PcssPass",
            (&shader, &constants),
            sizes,
            path,
        ))
    }
}

impl VisibilityPass for PcssPass {
    const NAME: &'static str = "pcss";

    fn lookup(&self) -> &ShadowLookup {
        &self.0
    }

    fn lookup_mut(&mut self) -> &mut ShadowLookup {
        &mut self.0
    }
}

impl ScreenStage for PcssPass {
    fn allocated_bytes(&self) -> u64 {
        self.0.allocated_bytes()
    }

    fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.0.resize(device, width, height);
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        self.0.write_params(queue, bytemuck::bytes_of(&params.pcss));
    }
}
