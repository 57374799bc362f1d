//! PCF pass: screen-space visibility from N x N comparison taps on the real shadow map at a
//! fixed spacing: the baseline's PCF, and screen-space hard shadows with one tap.
//!
//! Input: the frame uniform, the camera depth (world positions are reconstructed from it) and
//! the shadow map. Output: an R16F visibility texture (1 lit, 0 shadowed), or on the compute
//! path an R32F one the lights share, written by a compute pass ([`super::ScreenPipeline`]). The distance-map
//! method takes its distance-driven taps in [`super::DistanceMapPass`], with the same tap code
//! (`shaders/common/pcf_taps.wgsl`).

use super::{LIGHT_KIND, ScreenPipeline, entry};
use super::{ScreenStage, VisibilityPass};
use crate::frame::PassParams;
use crate::frame::{PcfSwitches, PcfUniform};
use crate::gpu_helpers::Target;

pub struct PcfPass {
    layout: wgpu::BindGroupLayout,
    pipeline: ScreenPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    bind_group: Option<wgpu::BindGroup>,
}

impl PcfPass {
    /// The pass for `switches` and one light kind ([`crate::frame::light_kind`]: the other
    /// kinds' code is compiled out), a compute pass with `compute`, which with `layers`
    /// writes the light's layer too (hard shadows, whose visibility is final); other switches,
    /// another kind or the other kind of pass need a new pass.
    pub(crate) fn new(
        device: &wgpu::Device,
        frame_size: usize,
        switches: PcfSwitches,
        light_kind: u32,
        (compute, layers): (bool, bool),
    ) -> Self {
        let shader = crate::shaders::module_for(device, "pcf.wgsl", crate::shaders::PCF, layers);
        let entries = ScreenPipeline::layout_entries(
            entry::shadow_lookup(frame_size, &[entry::fragment_uniform(4, size_of::<PcfUniform>())]),
            (compute, layers),
        );
        let layout = crate::gpu_helpers::layout(device, "PcfPass::layout", &entries);
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let pipeline = ScreenPipeline::new(
            device,
            "PcfPass::pipeline",
            &shader,
            &layout,
            &[
                ("ROTATE_TAPS", flag(switches.rotate_taps)),
                (LIGHT_KIND, light_kind as f64),
            ],
            (compute, layers),
        );
        let params =
            crate::gpu_helpers::uniform_buffer(device, "PcfPass::params", size_of::<PcfUniform>() as u64);
        Self {
            layout,
            pipeline,
            params,
            sampler: super::comparison_sampler(
                device,
                "PcfPass::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            bind_group: None,
        }
    }
}

impl VisibilityPass for PcfPass {
    const NAME: &'static str = "pcf";

    fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        camera_depth: &wgpu::TextureView,
        shadow_map: &wgpu::TextureView,
        shared: Option<&Target>,
        layer: Option<(&wgpu::TextureView, &wgpu::TextureView)>,
    ) {
        self.bind_group = self.pipeline.bind_group(
            device,
            "PcfPass::bind_group",
            &self.layout,
            &[frame, camera_depth, shadow_map, &self.sampler, &self.params],
            shared,
            layer,
        );
    }

    fn writes_layers(&self) -> bool {
        self.pipeline.writes_layers()
    }

    fn visibility(&self) -> Option<&wgpu::TextureView> {
        self.pipeline.output().map(|o| &o.view)
    }

    fn visibility_texture(&self) -> Option<&wgpu::Texture> {
        self.pipeline.output().map(|o| &o.texture)
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(group) = &self.bind_group {
            self.pipeline.encode(encoder, "PcfPass", group);
        }
    }
}

impl ScreenStage for PcfPass {
    fn allocated_bytes(&self) -> u64 {
        self.params.size() + self.pipeline.own_bytes()
    }

    fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.pipeline.resize(device, "PcfPass::visibility", width, height);
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.pcf;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }
}
