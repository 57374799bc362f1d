//! PCF pass: screen-space visibility from N x N comparison taps on the real shadow map at a
//! fixed spacing: the baseline's PCF, and screen-space hard shadows with one tap.
//!
//! Input: the frame uniform, the camera depth (world positions are reconstructed from it) and
//! the shadow map. Output: an R16F visibility texture (1 lit, 0 shadowed). The distance-map
//! method takes its distance-driven taps in [`super::DistanceMapPass`], with the same tap code
//! (`shaders/common/pcf_taps.wgsl`).

use super::{LIGHT_KIND, VISIBILITY_FORMAT, draw_fullscreen, entry, fullscreen_pipeline_with, screen_target};
use crate::frame::{PcfSwitches, PcfUniform};
use crate::gpu_helpers::texture_bytes;

pub struct PcfPass {
    switches: PcfSwitches,
    light_kind: u32,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    sampler: wgpu::Sampler,
    output: (wgpu::Texture, wgpu::TextureView),
    bind_group: Option<wgpu::BindGroup>,
}

impl PcfPass {
    /// GPU memory this pass allocated: its textures and buffers, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.params.size() + texture_bytes(&self.output.0)
    }

    /// The pass for `switches` and one light kind ([`crate::frame::light_kind`]: the other
    /// kinds' code is compiled out); other switches or another kind need a new pass.
    pub(crate) fn new(
        device: &wgpu::Device,
        frame_size: usize,
        switches: PcfSwitches,
        light_kind: u32,
    ) -> Self {
        let shader = crate::shaders::module(device, "pcf.wgsl", crate::shaders::PCF);
        let layout = crate::gpu_helpers::shadow_lookup_layout(
            device,
            "PcfPass::layout",
            frame_size,
            &[entry::fragment_uniform(4, size_of::<PcfUniform>())],
        );
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let pipeline = fullscreen_pipeline_with(
            device,
            "PcfPass::pipeline",
            &shader,
            &[Some(&layout)],
            VISIBILITY_FORMAT,
            &[
                ("ROTATE_TAPS", flag(switches.rotate_taps)),
                (LIGHT_KIND, light_kind as f64),
            ],
        );
        let params =
            crate::gpu_helpers::uniform_buffer(device, "PcfPass::params", size_of::<PcfUniform>() as u64);
        Self {
            switches,
            light_kind,
            layout,
            pipeline,
            params,
            sampler: super::comparison_sampler(
                device,
                "PcfPass::comparison_sampler",
                wgpu::FilterMode::Linear,
            ),
            output: screen_target(device, "PcfPass::visibility", 1, 1, VISIBILITY_FORMAT),
            bind_group: None,
        }
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.output = screen_target(device, "PcfPass::visibility", width, height, VISIBILITY_FORMAT);
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
            "PcfPass::bind_group",
            &self.layout,
            &[frame, camera_depth, shadow_map, &self.sampler, &self.params],
        ));
    }

    /// The switches the pipeline was made with.
    pub(crate) fn switches(&self) -> PcfSwitches {
        self.switches
    }

    /// The light kind the pipeline was made for ([`crate::frame::light_kind`]).
    pub(crate) fn light_kind(&self) -> u32 {
        self.light_kind
    }

    /// Uploads the frame's tap count and spacing.
    pub(crate) fn prepare(&self, queue: &wgpu::Queue, params: &PcfUniform) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
    }

    /// The raw PCF visibility.
    pub fn visibility(&self) -> &wgpu::TextureView {
        &self.output.1
    }

    pub fn visibility_texture(&self) -> &wgpu::Texture {
        &self.output.0
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some(group) = &self.bind_group {
            draw_fullscreen(encoder, "PcfPass", &self.pipeline, &[group], &self.output.1);
        }
    }
}
