//! Forward lit pass: draws every instance from the camera with Lambert diffuse plus ambient,
//! shadowing the direct light with one comparison lookup into the shadow map.
//!
//! Inputs: the [`GpuScene`], the camera's matrices, the [`LightView`] and the shadow map. Output: the
//! lit color in the caller's target (any color format given at creation) and the pass's own
//! camera depth buffer. [`ShadowMethod::Hard`] binds a nearest-filtering comparison sampler (one
//! tap), [`ShadowMethod::Hardware2x2`] a linear one (the hardware's 2x2 PCF); the pipeline is
//! the same.

use crate::gpu_helpers::{begin_pass, cleared, depth_attachment};
use bytemuck::{Pod, Zeroable};

use super::gpu_scene::{CameraStreams, GpuScene};
use crate::gpu_helpers::{entry, screen_target};
use crate::layouts::SceneLayouts;
use crate::layouts::vec4;
use crate::light_space::{LightView, MAX_TILES, tile_matrix};
use crate::settings::ShadowMethod;
use crate::view::CameraMatrices;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    /// Each cascade's view-projection into its tile of the map atlas.
    light_view_proj: [[[f32; 4]; 4]; MAX_TILES],
    /// The view distance where each cascade ends.
    cascade_end: [f32; 4],
    /// Each cascade's normal offset, world units (orthographic) or world units per unit of
    /// distance from the light (spot).
    cascade_offset: [f32; 4],
    /// x: cascades in use.
    cascade_count: [u32; 4],
    camera_position: [f32; 4],
    light_direction: [f32; 4],
    light_position: [f32; 4],
    light_radiance: [f32; 4],
    ambient: [f32; 4],
    /// An area light's half-axes and shape (`FrameUniform`'s `area_u` and `area_v`).
    area_u: [f32; 4],
    area_v: [f32; 4],
}

/// The color behind the scene (linear RGB), shared by the lit passes.
pub(crate) const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.55,
    g: 0.62,
    b: 0.72,
    a: 1.0,
};

pub struct ForwardPass {
    frame_layout: wgpu::BindGroupLayout,
    frame_buffer: wgpu::Buffer,
    hard_sampler: wgpu::Sampler,
    pcf_sampler: wgpu::Sampler,
    hard_bind_group: wgpu::BindGroup,
    pcf_bind_group: wgpu::BindGroup,
    /// Opaque, then blended instances (drawn after the opaque ones).
    pipelines: super::camera_pipelines::LitPipelines,
    depth: wgpu::TextureView,
    size: (u32, u32),
}

impl ForwardPass {
    /// Camera depth buffer format.
    pub const DEPTH_FORMAT: wgpu::TextureFormat = super::camera_pipelines::CAMERA_DEPTH_FORMAT;

    pub fn new(
        device: &wgpu::Device,
        layouts: &SceneLayouts,
        color_format: wgpu::TextureFormat,
        shadow_map: &wgpu::TextureView,
    ) -> Self {
        let shader = crate::shaders::module(device, "forward.wgsl", crate::shaders::FORWARD);
        let frame_layout = crate::gpu_helpers::layout(
            device,
            "ForwardPass::frame_layout",
            &[
                entry::uniform(
                    0,
                    wgpu::ShaderStages::VERTEX_FRAGMENT,
                    size_of::<FrameUniform>(),
                    false,
                ),
                entry::texture_2d(1, wgpu::TextureSampleType::Depth),
                entry::sampler(2, wgpu::SamplerBindingType::Comparison),
            ],
        );
        let frame_buffer = crate::gpu_helpers::uniform_buffer(
            device,
            "ForwardPass::frame",
            size_of::<FrameUniform>() as u64,
        );
        let hard_sampler = crate::gpu_helpers::comparison_sampler(
            device,
            "ForwardPass::hard_sampler",
            wgpu::FilterMode::Nearest,
        );
        let pcf_sampler = crate::gpu_helpers::comparison_sampler(
            device,
            "ForwardPass::pcf_sampler",
            wgpu::FilterMode::Linear,
        );
        // Opaque surfaces write depth; blended ones over them are depth tested, not written.
        let pipelines = super::camera_pipelines::LitPipelines::new(
            device,
            "ForwardPass::pipeline",
            &shader,
            &frame_layout,
            layouts,
            true,
            color_format,
        );
        let make_bind_group = |sampler: &wgpu::Sampler, label| {
            frame_bind_group(device, &frame_layout, &frame_buffer, shadow_map, sampler, label)
        };
        let hard_bind_group = make_bind_group(&hard_sampler, "ForwardPass::frame_hard");
        let pcf_bind_group = make_bind_group(&pcf_sampler, "ForwardPass::frame_pcf");
        let depth = screen_target(device, "ForwardPass::camera_depth", 1, 1, Self::DEPTH_FORMAT).view;
        Self {
            frame_layout,
            frame_buffer,
            hard_sampler,
            pcf_sampler,
            hard_bind_group,
            pcf_bind_group,
            pipelines,
            depth,
            size: (1, 1),
        }
    }

    /// Points the pass at a new shadow map (after the shadow map was recreated).
    pub fn set_shadow_map(&mut self, device: &wgpu::Device, shadow_map: &wgpu::TextureView) {
        self.hard_bind_group = frame_bind_group(
            device,
            &self.frame_layout,
            &self.frame_buffer,
            shadow_map,
            &self.hard_sampler,
            "ForwardPass::frame_hard",
        );
        self.pcf_bind_group = frame_bind_group(
            device,
            &self.frame_layout,
            &self.frame_buffer,
            shadow_map,
            &self.pcf_sampler,
            "ForwardPass::frame_pcf",
        );
    }

    /// Recreates the camera depth buffer for a new target size (both sides >= 1).
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        let (width, height) = (width.max(1), height.max(1));
        if self.size != (width, height) {
            self.depth = screen_target(
                device,
                "ForwardPass::camera_depth",
                width,
                height,
                Self::DEPTH_FORMAT,
            )
            .view;
            self.size = (width, height);
        }
    }

    /// Makes ready the pipelines for `light` (the area lights' shading only where it has an
    /// area).
    pub fn shade(&mut self, device: &wgpu::Device, light: &crate::lights::Light) {
        self.pipelines.shade_area_lights(device, light.area().is_some());
    }

    /// Records the pass into `target`, which must match the size given to [`ForwardPass::resize`].
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &CameraMatrices,
        light_view: &LightView,
        method: ShadowMethod,
        shadow_map: &crate::ShadowMapSettings,
        target: &wgpu::TextureView,
    ) {
        let light = scene.light();
        let direction = light.direction();
        let kind = crate::frame::light_kind(light) as f32;
        let (position, cos_outer, cos_inner) = light.cone();
        let mut light_view_proj = [[[0.0; 4]; 4]; MAX_TILES];
        let mut cascade_end = [f32::MAX; 4];
        let mut cascade_offset = [0.0; 4];
        let cascades = light_view.cascades();
        for (i, c) in cascades.iter().enumerate() {
            light_view_proj[i] =
                (tile_matrix(light_view.grid, i as u32) * c.view_projection).to_cols_array_2d();
            // A sun's cascades (a point light's faces share the first's offset).
            if i < 4 {
                cascade_end[i] = c.end;
                cascade_offset[i] = normal_offset_scale(light_view, c.extent.x, shadow_map);
            }
        }
        let frame = FrameUniform {
            view_proj: camera.view_projection().to_cols_array_2d(),
            light_view_proj,
            cascade_end,
            cascade_offset,
            cascade_count: [
                cascades.len() as u32,
                light_view.grid.cols.max(1),
                light_view.grid.rows.max(1),
                0,
            ],
            camera_position: vec4(camera.eye(), 0.0),
            light_direction: vec4(direction, kind),
            light_position: vec4(position, cos_outer),
            light_radiance: vec4(light.radiance() * scene.exposure().scale(), cos_inner),
            ambient: vec4(scene.ambient(), light.range().unwrap_or(0.0)),
            area_u: crate::frame::area_axes(light).0,
            area_v: crate::frame::area_axes(light).1,
        };
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&frame));
        let mut pass = begin_pass(
            encoder,
            "ForwardPass",
            &[cleared(target, BACKGROUND)],
            depth_attachment(&self.depth, Some(wgpu::LoadOp::Clear(0.0))),
        );
        pass.set_pipeline(self.pipelines.opaque(scene));
        let frame_group = match method {
            ShadowMethod::Hard => &self.hard_bind_group,
            _ => &self.pcf_bind_group,
        };
        pass.set_bind_group(0, frame_group, &[]);
        scene.draw(&mut pass, CameraStreams::Lit);
        if scene.has_blended() {
            pass.set_pipeline(self.pipelines.blended(scene));
            scene.draw_blended(&mut pass, camera.eye());
        }
    }
}

fn frame_bind_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    frame: &wgpu::Buffer,
    shadow_map: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
    label: &str,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: frame.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(shadow_map),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

/// The normal offset in world units for an orthographic light view, or in world units per unit
/// of distance from the light for a perspective one (one texel's footprint grows with it).
fn normal_offset_scale(light_view: &LightView, extent: f32, shadow_map: &crate::ShadowMapSettings) -> f32 {
    let texel = extent / light_view.tile.max(1) as f32;
    let per_texel = match light_view.kind {
        crate::light_space::ProjectionKind::Orthographic => texel,
        crate::light_space::ProjectionKind::Perspective => texel / light_view.near.max(1e-12),
    };
    shadow_map.normal_offset * per_texel
}
