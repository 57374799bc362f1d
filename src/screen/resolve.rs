//! Resolve pass: one light's final visibility, as an engine samples it.
//!
//! Input: the frame uniform, the camera depth, the distance map (when the method has one), the
//! raw or blurred visibility and the receiver mask (when given). Output: one layer of the
//! visibility array ([`crate::Shadows::visibility`], R16F), in [0, 1], with the indirect-light
//! attenuation already applied and 1 where nothing was drawn or the pixel receives no shadow.

use super::ScreenStage;
use super::{VISIBILITY_FORMAT, draw_fullscreen};
use crate::frame::FrameSlot;
use crate::gpu_helpers::entry;
use crate::pipeline_cache::CachedDevice;
use crate::pipeline_cache::fullscreen_pipeline;

pub struct ResolvePass {
    layout: wgpu::BindGroupLayout,
    pipeline: std::sync::Arc<wgpu::RenderPipeline>,
    bind_group: Option<wgpu::BindGroup>,
}

impl ResolvePass {
    pub fn new(device: &CachedDevice<'_>, frame_size: usize) -> Self {
        let shader = device.module("resolve.wgsl", crate::shaders::RESOLVE);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.bind_group_layout(
            "ResolvePass::layout",
            &[
                entry::fragment_uniform(0, frame_size),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::texture_2d(3, unfilterable),
                entry::texture_2d(4, unfilterable),
            ],
        );
        let pipeline = fullscreen_pipeline(
            device,
            "ResolvePass::pipeline",
            &shader,
            &[Some(&layout)],
            VISIBILITY_FORMAT,
        );
        Self {
            layout,
            pipeline,
            bind_group: None,
        }
    }

    /// Points the pass at its inputs: `views` are the camera depth, the distance map, the
    /// visibility and the receiver mask, in that order (the distance map and the mask are read
    /// only where the frame uniform says they are real).
    pub fn bind(&mut self, device: &CachedDevice<'_>, frame: &FrameSlot, views: [&wgpu::TextureView; 4]) {
        let [camera_depth, distance_map, visibility, receiver_mask] = views;
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "ResolvePass::bind_group",
            &self.layout,
            &[frame, camera_depth, distance_map, visibility, receiver_mask],
        ));
    }

    /// Writes the visibility into `output` (a single-layer view of the visibility array).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, output: &wgpu::TextureView) {
        if let Some(group) = &self.bind_group {
            draw_fullscreen(encoder, "ResolvePass", &self.pipeline, &[group], output);
        }
    }
}

impl ScreenStage for ResolvePass {}
