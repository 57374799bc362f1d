//! Fattened shadow map pass: the casters from the light, each vertex pushed outward along its
//! smoothed normal by `fatten_distance` world units.
//!
//! Input: the casters ([`crate::Casters`]) (positions and smoothed normals), the [`LightView`] and the
//! fatten distance. Output: a depth texture like the shadow map's (same projection, resolution
//! and format). Because every vertex at one position shares one smoothed normal, meshes with
//! hard edges fatten into closed shapes. Alpha-masked casters are fattened whole (a superset of
//! their real shadow, so the mask stays conservative).

use bytemuck::{Pod, Zeroable};

use super::shadow_map::{begin_depth_pass, depth_state, light_depth_target};
use super::{CasterPipelines, SecondStream, entry};
use crate::casters::{Casters, Streams};
use crate::layouts::SceneLayouts;
use crate::light_space::LightView;
use crate::settings::ShadowMapSettings;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FattenUniform {
    view_proj: [[f32; 4]; 4],
    params: [f32; 4],
}

pub struct FattenedShadowMapPass {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    pipelines: CasterPipelines,
}

impl FattenedShadowMapPass {
    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, settings: &ShadowMapSettings) -> Self {
        let shader = crate::shaders::module(
            device,
            "fattened_shadow_map.wgsl",
            crate::shaders::FATTENED_SHADOW_MAP,
        );
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("FattenedShadowMapPass::layout"),
            entries: &[entry::uniform(
                0,
                wgpu::ShaderStages::VERTEX,
                size_of::<FattenUniform>(),
                false,
            )],
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("FattenedShadowMapPass::uniform"),
            size: size_of::<FattenUniform>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("FattenedShadowMapPass::bind_group"),
            layout: &bind_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let pipelines = CasterPipelines::new(
            device,
            "FattenedShadowMapPass::pipeline",
            &shader,
            &[Some(&bind_layout), Some(&layouts.instance)],
            "vs_main",
            None,
            SecondStream::SmoothedNormals,
            // Fattened shapes are drawn from both sides: inflating can turn thin parts inside out.
            wgpu::PrimitiveState::default(),
            depth_state(settings),
        );
        let (texture, view) = light_depth_target(device, settings, "FattenedShadowMapPass::fattened_map");
        Self {
            texture,
            view,
            uniform,
            bind_group,
            pipelines,
        }
    }

    /// The fattened depth map.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// Makes the pipelines for the vertex layouts of `casters` and uploads the light's view and
    /// the fatten distance (world units).
    pub(crate) fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        casters: &Casters,
        light: &LightView,
        fatten_distance: f32,
    ) {
        self.pipelines
            .prepare(device, &casters.draw_layouts(Streams::Fattened));
        let uniform = FattenUniform {
            view_proj: light.view_projection.to_cols_array_2d(),
            params: [fatten_distance, 0.0, 0.0, 0.0],
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
    }

    /// Records the pass: every caster, inflated ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder, casters: &Casters) {
        let mut pass = begin_depth_pass(encoder, "FattenedShadowMapPass", &self.view);
        pass.set_bind_group(0, &self.bind_group, &[]);
        casters.draw(&mut pass, Streams::Fattened, |l| self.pipelines.get(l));
    }
}
