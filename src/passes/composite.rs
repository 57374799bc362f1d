//! Composite pass of the convenience [`crate::Renderer`]: the lit scene from the camera, its
//! direct light multiplied by a screen-space visibility (an engine does this in its own lit
//! shader).
//!
//! Input: every instance, the frame uniform, the resolved visibility (indirect attenuation
//! already applied; or the reference's mean) and the prepass's camera depth (tested, not
//! written). Output: the lit color in the caller's target.

use super::{entries, entry};
use crate::gpu_scene::{CameraStreams, GpuScene};
use crate::layouts::SceneLayouts;

pub struct CompositePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    bind_group: Option<wgpu::BindGroup>,
}

impl CompositePass {
    pub fn new(
        device: &wgpu::Device,
        layouts: &SceneLayouts,
        color_format: wgpu::TextureFormat,
        frame_size: usize,
    ) -> Self {
        let shader = crate::shaders::module(device, "composite.wgsl", crate::shaders::COMPOSITE);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("CompositePass::layout"),
            entries: &[
                entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: false }),
            ],
        });
        let pipeline = super::camera_pipeline(
            device,
            "CompositePass::pipeline",
            &shader,
            &layout,
            layouts,
            CameraStreams::PositionNormalUv,
            false,
            color_format.into(),
        );
        Self {
            layout,
            pipeline,
            bind_group: None,
        }
    }

    pub fn bind(&mut self, device: &wgpu::Device, frame: &wgpu::Buffer, visibility: &wgpu::TextureView) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("CompositePass::bind_group"),
            layout: &self.layout,
            entries: &entries(&[
                frame.as_entire_binding(),
                wgpu::BindingResource::TextureView(visibility),
            ]),
        }));
    }

    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera_depth: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("CompositePass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(super::forward::BACKGROUND),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: camera_depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        scene.draw(&mut pass, CameraStreams::PositionNormalUv);
    }
}
