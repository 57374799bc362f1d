//! Depth prepass of the convenience [`crate::Renderer`]: what an engine's own depth prepass
//! gives [`crate::Shadows`].
//!
//! Input: every instance of a [`GpuScene`] and the frame uniform (camera). Output: the camera
//! depth (Depth32Float, reversed: cleared to 0, `Greater` test; tested `Equal` by the
//! composite) and a receiver mask (R8Unorm: 1 on instances that receive shadows).

use super::{begin_pass, cleared, depth_attachment};
use super::{entry, screen_target};
use crate::gpu_helpers::Target;
use crate::gpu_scene::{CameraStreams, GpuScene};
use crate::layouts::SceneLayouts;

pub struct DepthPrepass {
    frame_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    depth: Target,
    receiver_mask: Target,
    bind_group: Option<wgpu::BindGroup>,
}

impl DepthPrepass {
    pub const DEPTH_FORMAT: wgpu::TextureFormat = super::CAMERA_DEPTH_FORMAT;
    pub const RECEIVER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, frame_size: usize) -> Self {
        let (frame_layout, pipeline) = prepass_pipeline(
            device,
            "DepthPrepass",
            layouts,
            frame_size,
            Self::RECEIVER_FORMAT,
            false,
        );
        Self {
            frame_layout,
            pipeline,
            depth: screen_target(device, "DepthPrepass::camera_depth", 1, 1, Self::DEPTH_FORMAT),
            receiver_mask: screen_target(device, "DepthPrepass::receiver_mask", 1, 1, Self::RECEIVER_FORMAT),
            bind_group: None,
        }
    }

    /// Recreates the screen-sized targets.
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.depth = screen_target(
            device,
            "DepthPrepass::camera_depth",
            width,
            height,
            Self::DEPTH_FORMAT,
        );
        self.receiver_mask = screen_target(
            device,
            "DepthPrepass::receiver_mask",
            width,
            height,
            Self::RECEIVER_FORMAT,
        );
    }

    /// Points the pass at the frame uniform.
    pub fn bind(&mut self, device: &wgpu::Device, frame: &wgpu::Buffer) {
        self.bind_group = Some(super::bind_group(
            device,
            "DepthPrepass::bind_group",
            &self.frame_layout,
            &[frame],
        ));
    }

    /// Camera depth (Depth32Float).
    pub fn depth(&self) -> &wgpu::TextureView {
        &self.depth.view
    }

    pub fn depth_texture(&self) -> &wgpu::Texture {
        &self.depth.texture
    }

    pub fn receiver_mask_texture(&self) -> &wgpu::Texture {
        &self.receiver_mask.texture
    }

    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, scene: &GpuScene) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        let mut pass = begin_pass(
            encoder,
            "DepthPrepass",
            &[cleared(&self.receiver_mask.view, wgpu::Color::TRANSPARENT)],
            depth_attachment(&self.depth.view, Some(wgpu::LoadOp::Clear(0.0))),
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        scene.draw(&mut pass, CameraStreams::PositionUv);
    }
}

/// The layout of group 0 (the frame uniform) and a pipeline drawing every instance with
/// `depth_prepass.wgsl` into a target of `format`: the prepass itself (`normals` false: depth
/// written, the receiver mask) or, over its depth, the reference's triangle normals (`normals`
/// true: `NORMALS` 1, depth only tested; [`super::GeometricNormals`]).
pub(super) fn prepass_pipeline(
    device: &wgpu::Device,
    label: &str,
    layouts: &SceneLayouts,
    frame_size: usize,
    format: wgpu::TextureFormat,
    normals: bool,
) -> (wgpu::BindGroupLayout, wgpu::RenderPipeline) {
    let shader = crate::shaders::module(device, "depth_prepass.wgsl", crate::shaders::DEPTH_PREPASS);
    let frame_layout = crate::gpu_helpers::layout(
        device,
        &format!("{label}::frame_layout"),
        &[entry::uniform(
            0,
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            frame_size,
            false,
        )],
    );
    let pipeline = super::camera_pipeline(
        device,
        &format!("{label}::pipeline"),
        &shader,
        &frame_layout,
        layouts,
        CameraStreams::PositionUv,
        !normals,
        format.into(),
        if normals { &[("NORMALS", 1.0)] } else { &[] },
    );
    (frame_layout, pipeline)
}
