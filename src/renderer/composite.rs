//! Composite pass of the convenience [`crate::Renderer`]: the lit scene from the camera, its
//! direct light multiplied by a screen-space visibility (an engine does this in its own lit
//! shader).
//!
//! Input: every instance, the frame uniform, the lights and the resolved visibility array (one
//! layer per light, indirect attenuation already applied; or the reference's mean) and the
//! prepass's camera depth (tested, not written). Output: the lit color in the caller's target.

use super::gpu_scene::{CameraStreams, GpuScene};
use crate::gpu_helpers::entry;
use crate::gpu_helpers::{begin_pass, cleared, depth_attachment};
use crate::layouts::SceneLayouts;

use crate::frame::ShadedLights;
use crate::lights::Light;

pub struct CompositePass {
    lights: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    /// Opaque, then blended instances (drawn after the opaque ones).
    pipelines: super::camera_pipelines::LitPipelines,
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
        let layout = crate::gpu_helpers::layout(
            device,
            "CompositePass::layout",
            &[
                entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
                // Not filterable: the reference's mean is R32F.
                entry::texture(
                    1,
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2Array,
                ),
                entry::fragment_uniform(2, size_of::<ShadedLights>()),
            ],
        );
        let lights = crate::gpu_helpers::uniform_buffer(
            device,
            "CompositePass::lights",
            size_of::<ShadedLights>() as u64,
        );
        // Depth tested against the prepass, not written; blended surfaces over the opaque ones.
        let pipelines = super::camera_pipelines::LitPipelines::new(
            device,
            "CompositePass::pipeline",
            &shader,
            &layout,
            layouts,
            false,
            color_format,
        );
        Self {
            lights,
            layout,
            pipelines,
            bind_group: None,
        }
    }

    /// Sets the lights to shade, each with its layer of the visibility array (at most
    /// [`crate::MAX_LIGHTS`]; the caller checked), and the pipelines for them (the area lights'
    /// shading only where one has an area).
    /// `exposure` is the camera's ([`crate::Exposure::scale`]).
    pub fn set_lights(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        lights: &[(Light, u32)],
        exposure: f32,
    ) {
        self.pipelines
            .shade_area_lights(device, lights.iter().any(|(l, _)| l.area().is_some()));
        queue.write_buffer(
            &self.lights,
            0,
            bytemuck::bytes_of(&ShadedLights::new(lights, exposure)),
        );
    }

    /// Binds the frame uniform and the visibility array (a 2D-array view).
    pub fn bind(&mut self, device: &wgpu::Device, frame: &wgpu::Buffer, visibility: &wgpu::TextureView) {
        self.bind_group = Some(crate::gpu_helpers::bind_group(
            device,
            "CompositePass::bind_group",
            &self.layout,
            &[frame, visibility, &self.lights],
        ));
    }

    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        eye: glam::Vec3,
        camera_depth: &wgpu::TextureView,
        target: &wgpu::TextureView,
    ) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        let mut pass = begin_pass(
            encoder,
            "CompositePass",
            &[cleared(target, super::forward::BACKGROUND)],
            depth_attachment(camera_depth, Some(wgpu::LoadOp::Load)),
        );
        pass.set_pipeline(self.pipelines.opaque(scene));
        pass.set_bind_group(0, bind_group, &[]);
        scene.draw(&mut pass, CameraStreams::Lit);
        if scene.has_blended() {
            pass.set_pipeline(self.pipelines.blended(scene));
            scene.draw_blended(&mut pass, eye);
        }
    }
}
