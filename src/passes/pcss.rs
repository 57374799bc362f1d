//! PCSS pass (Fernando 2005): screen-space visibility from a blocker search and a PCF disk
//! sized by the light.
//!
//! Input: the frame uniform, the camera depth and the shadow map. Output: an R16F visibility
//! texture. Blocker and PCF tap counts come from [`crate::PcssSettings`].

use super::{LIGHT_KIND, VISIBILITY_FORMAT, draw_fullscreen, entry, fullscreen_pipeline_with, screen_target};
use crate::frame::PcssUniform;
use crate::gpu_helpers::texture_bytes;

pub struct PcssPass {
    light_kind: u32,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    output: (wgpu::Texture, wgpu::TextureView),
    bind_group: Option<wgpu::BindGroup>,
}

impl PcssPass {
    /// GPU memory this pass allocated: its textures and buffers, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.params.size() + texture_bytes(&self.output.0)
    }

    /// The pass for one light kind ([`crate::frame::light_kind`]: the other kinds' code is
    /// compiled out, as in the distance-map method's passes); another kind needs a new pass.
    pub fn new(device: &wgpu::Device, frame_size: usize, light_kind: u32) -> Self {
        let shader = crate::shaders::module(device, "pcss.wgsl", crate::shaders::PCSS);
        let layout = crate::gpu_helpers::shadow_lookup_layout(
            device,
            "PcssPass::layout",
            frame_size,
            &[
                entry::unfilterable(4),
                entry::fragment_uniform(5, size_of::<PcssUniform>()),
            ],
        );
        let pipeline = fullscreen_pipeline_with(
            device,
            "PcssPass::pipeline",
            &shader,
            &[Some(&layout)],
            VISIBILITY_FORMAT,
            &[(LIGHT_KIND, light_kind as f64)],
        );
        let params =
            crate::gpu_helpers::uniform_buffer(device, "PcssPass::params", size_of::<PcssUniform>() as u64);
        Self {
            light_kind,
            layout,
            pipeline,
            params,
            sampler: super::comparison_sampler(
                device,
                "PcssPass::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            output: screen_target(device, "PcssPass::visibility", 1, 1, VISIBILITY_FORMAT),
            bind_group: None,
        }
    }

    /// The light kind the pipeline was made for.
    pub(crate) fn light_kind(&self) -> u32 {
        self.light_kind
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.output = screen_target(device, "PcssPass::visibility", width, height, VISIBILITY_FORMAT);
    }

    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        camera_depth: &wgpu::TextureView,
        shadow_map: &wgpu::TextureView,
    ) {
        self.bind_group = Some(super::bind_group(
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
        ));
    }

    pub fn visibility(&self) -> &wgpu::TextureView {
        &self.output.1
    }

    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.output.0
    }

    /// Uploads the frame's sample counts.
    pub(crate) fn prepare(&self, queue: &wgpu::Queue, params: &PcssUniform) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(group) = &self.bind_group {
            draw_fullscreen(encoder, "PcssPass", &self.pipeline, &[group], &self.output.1);
        }
    }
}
