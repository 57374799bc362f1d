//! Depth prepass of the convenience [`crate::Renderer`]: what an engine's own depth prepass
//! gives [`crate::Shadows`].
//!
//! Input: every instance of a [`GpuScene`] and the frame uniform (camera). Output: the camera
//! depth (Depth32Float, reversed: cleared to 0, `Greater` test; tested `Equal` by the
//! composite) and a receiver mask (R8Unorm: 1 on instances that receive shadows).

use super::gpu_scene::{CameraStreams, GpuScene};
use crate::gpu_helpers::Target;
use crate::gpu_helpers::{begin_pass, cleared, depth_attachment};
use crate::gpu_helpers::{entry, screen_target};
use crate::layouts::SceneLayouts;

pub struct DepthPrepass {
    frame_layout: wgpu::BindGroupLayout,
    /// Instances whose material is not alpha-masked ([`PrepassKind::Opaque`]).
    opaque: wgpu::RenderPipeline,
    /// Alpha-masked instances ([`PrepassKind::Masked`]).
    masked: wgpu::RenderPipeline,
    depth: Target,
    receiver_mask: Target,
    bind_group: Option<wgpu::BindGroup>,
}

impl DepthPrepass {
    pub const DEPTH_FORMAT: wgpu::TextureFormat = super::camera_pipelines::CAMERA_DEPTH_FORMAT;
    pub const RECEIVER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, frame_size: usize) -> Self {
        let frame_layout = prepass_frame_layout(device, "DepthPrepass", frame_size);
        let pipeline = |kind| {
            prepass_pipeline(
                device,
                "DepthPrepass",
                (layouts, &frame_layout),
                Self::RECEIVER_FORMAT,
                kind,
            )
        };
        let (opaque, masked) = (pipeline(PrepassKind::Opaque), pipeline(PrepassKind::Masked));
        Self {
            frame_layout,
            opaque,
            masked,
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
        self.bind_group = Some(crate::gpu_helpers::bind_group(
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
        pass.set_bind_group(0, bind_group, &[]);
        for (pipeline, masked) in [(&self.opaque, false), (&self.masked, true)] {
            pass.set_pipeline(pipeline);
            scene.draw_masked(&mut pass, CameraStreams::PositionUv, masked);
        }
    }
}

/// What a pipeline of `depth_prepass.wgsl` draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PrepassKind {
    /// The prepass for materials that are not alpha-masked: depth written, the receiver mask;
    /// no texture read and no discard (`fs_opaque`), so the rasterizer can test depth before
    /// shading. On lavapipe the teapot's prepass at 1280x1024 took about a third less time than
    /// with `fs_main` for every instance (docs/cost.md); on an NVIDIA H200 it was the same.
    Opaque,
    /// The prepass for alpha-masked materials: the base colour's alpha read, the fragments
    /// under the cutoff discarded (`fs_main`).
    Masked,
    /// Over the prepass's depth (only tested), the reference's triangle normals (`fs_main` with
    /// `NORMALS` 1; [`super::GeometricNormals`]).
    Normals,
}

/// The layout of a `depth_prepass.wgsl` pipeline's group 0: the frame uniform.
pub(super) fn prepass_frame_layout(
    device: &wgpu::Device,
    label: &str,
    frame_size: usize,
) -> wgpu::BindGroupLayout {
    crate::gpu_helpers::layout(
        device,
        &format!("{label}::frame_layout"),
        &[entry::uniform(
            0,
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            frame_size,
            false,
        )],
    )
}

/// A pipeline drawing instances with `depth_prepass.wgsl` into a target of `format`, its group
/// 0 laid out by `frame_layout` ([`prepass_frame_layout`]), as `kind` says.
pub(super) fn prepass_pipeline(
    device: &wgpu::Device,
    label: &str,
    (layouts, frame_layout): (&SceneLayouts, &wgpu::BindGroupLayout),
    format: wgpu::TextureFormat,
    kind: PrepassKind,
) -> wgpu::RenderPipeline {
    let shader = crate::shaders::module(device, "depth_prepass.wgsl", crate::shaders::DEPTH_PREPASS);
    super::camera_pipelines::camera_pipeline(
        device,
        &format!("{label}::pipeline"),
        &shader,
        frame_layout,
        layouts,
        CameraStreams::PositionUv,
        kind != PrepassKind::Normals,
        format.into(),
        match kind {
            PrepassKind::Opaque => ("fs_opaque", &[]),
            PrepassKind::Masked => ("fs_main", &[]),
            PrepassKind::Normals => ("fs_main", &[("NORMALS", 1.0)]),
        },
    )
}
