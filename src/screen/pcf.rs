//! PCF pass: screen-space visibility from N x N comparison taps on the real shadow map at a
//! fixed spacing: the baseline's PCF, and screen-space hard shadows with one tap.
//!
//! Input: the frame uniform, the camera depth (world positions are reconstructed from it) and
//! the shadow map. Output: an R16F visibility texture (1 lit, 0 shadowed), or on the compute
//! path one the lights share (R16F where the device stores half floats, else R32F), written by a compute pass ([`super::ScreenPipeline`]). The distance-map
//! method takes its distance-driven taps in [`super::DistanceMapPass`], with the same tap code
//! (`shaders/common/pcf_taps.wgsl`).

use super::{LIGHT_KIND, ScreenStage, ShadowLookup, VisibilityPass};
use crate::frame::{PassParams, PcfSwitches, PcfUniform};
use crate::pipeline_cache::CachedDevice;

pub struct PcfPass(ShadowLookup);

impl PcfPass {
    /// The pass for `switches` and one light kind ([`crate::frame::light_kind`]: the other
    /// kinds' code is compiled out), run and stored as `path` says (a compute pass writing the
    /// light's layer too with layers: hard shadows, whose visibility is final); other switches,
    /// another kind or the other kind of pass need a new pass.
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        frame_size: usize,
        switches: PcfSwitches,
        light_kind: u32,
        path: super::PassPath,
    ) -> Self {
        let shader = crate::shaders::module_for(device, "pcf.wgsl", crate::shaders::PCF, path.module());
        let rotate = if switches.rotate_taps { 1.0 } else { 0.0 };
        let constants = [("ROTATE_TAPS", rotate), (LIGHT_KIND, light_kind as f64)];
        let sizes = (frame_size, size_of::<PcfUniform>(), false);
        Self(ShadowLookup::new(
            device,
            "PcfPass",
            (&shader, &constants),
            sizes,
            path,
        ))
    }
}

impl VisibilityPass for PcfPass {
    const NAME: &'static str = "pcf";

    fn lookup(&self) -> &ShadowLookup {
        &self.0
    }

    fn lookup_mut(&mut self) -> &mut ShadowLookup {
        &mut self.0
    }
}

impl ScreenStage for PcfPass {
    fn allocated_bytes(&self) -> u64 {
        self.0.allocated_bytes()
    }

    fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        self.0.resize(device, width, height);
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        self.0.write_params(queue, bytemuck::bytes_of(&params.pcf));
    }
}
