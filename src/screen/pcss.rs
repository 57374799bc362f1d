//! PCSS pass (Fernando 2005): screen-space visibility from a blocker search and a PCF disk
//! sized by the light.
//!
//! Input: the frame uniform, the camera depth and the shadow map. Output: an R16F visibility
//! texture, or on the compute path an R32F one the lights share ([`super::ScreenPipeline`]). Blocker and PCF tap counts come from [`crate::PcssSettings`].

use super::{LIGHT_KIND, ScreenPipeline, entry};
use super::{ScreenStage, VisibilityPass};
use crate::frame::PassParams;
use crate::frame::PcssUniform;
use crate::gpu_helpers::Target;

pub struct PcssPass {
    layout: wgpu::BindGroupLayout,
    pipeline: ScreenPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    bind_group: Option<wgpu::BindGroup>,
}

impl PcssPass {
    /// The pass for one light kind ([`crate::frame::light_kind`]: the other kinds' code is
    /// compiled out, as in the distance-map method's passes), a compute pass with `compute`,
    /// which with `layers` writes the light's layer too; another kind or the other kind of
    /// pass needs a new pass.
    pub fn new(
        device: &wgpu::Device,
        frame_size: usize,
        light_kind: u32,
        (compute, layers): (bool, bool),
    ) -> Self {
        let shader = crate::shaders::module_for(device, "pcss.wgsl", crate::shaders::PCSS, layers);
        let entries = ScreenPipeline::layout_entries(
            entry::shadow_lookup(
                frame_size,
                &[
                    entry::unfilterable(4),
                    entry::fragment_uniform(5, size_of::<PcssUniform>()),
                ],
            ),
            (compute, layers),
        );
        let layout = crate::gpu_helpers::layout(device, "PcssPass::layout", &entries);
        let pipeline = ScreenPipeline::new(
            device,
            "PcssPass::pipeline",
            &shader,
            &layout,
            &[(LIGHT_KIND, light_kind as f64)],
            (compute, layers),
        );
        let params =
            crate::gpu_helpers::uniform_buffer(device, "PcssPass::params", size_of::<PcssUniform>() as u64);
        Self {
            layout,
            pipeline,
            params,
            sampler: super::comparison_sampler(
                device,
                "PcssPass::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            bind_group: None,
        }
    }
}

impl VisibilityPass for PcssPass {
    const NAME: &'static str = "pcss";

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
            "PcssPass::bind_group",
            &self.layout,
            &[
                frame,
                camera_depth,
                shadow_map,
                &self.sampler,
                shadow_map,
                &self.params,
            ],
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
            self.pipeline.encode(encoder, "PcssPass", group);
        }
    }
}

impl ScreenStage for PcssPass {
    fn allocated_bytes(&self) -> u64 {
        self.params.size() + self.pipeline.own_bytes()
    }

    fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.pipeline
            .resize(device, "PcssPass::visibility", width, height);
    }

    fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        let params = &params.pcss;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }
}
