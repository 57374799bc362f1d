//! Fattened shadow map pass: the casters from the light, each vertex pushed outward along its
//! smoothed normal by `fatten_distance` world units.
//!
//! Input: the [`GpuScene`]'s casters (positions and smoothed normals), the [`LightView`] and the
//! fatten distance. Output: a depth texture like the shadow map's (same projection, resolution
//! and format). Because every vertex at one position shares one smoothed normal, meshes with
//! hard edges fatten into closed shapes. Alpha-masked casters are fattened whole (a superset of
//! their real shadow, so the mask stays conservative).

use bytemuck::{Pod, Zeroable};

use super::shadow_map::{begin_depth_pass, depth_state, light_depth_target};
use super::{POSITION, entry, stream, vertex_layout};
use crate::gpu_scene::{GpuScene, SceneLayouts};
use crate::light_space::LightView;
use crate::settings::ShadowMapSettings;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FattenUniform {
    view_proj: [[f32; 4]; 4],
    params: [f32; 4],
}

pub struct FattenedShadowMapPass {
    settings: ShadowMapSettings,
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    uniform: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    pipeline: wgpu::RenderPipeline,
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
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("FattenedShadowMapPass::pipeline_layout"),
            bind_group_layouts: &[Some(&bind_layout), Some(&layouts.instance)],
            immediate_size: 0,
        });
        const SMOOTHED_NORMAL: [wgpu::VertexAttribute; 1] = stream(1, wgpu::VertexFormat::Float32x3);
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("FattenedShadowMapPass::pipeline"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[
                    Some(vertex_layout(&POSITION)),
                    Some(vertex_layout(&SMOOTHED_NORMAL)),
                ],
            },
            // Fattened shapes are drawn from both sides: inflating can turn thin parts inside out.
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(depth_state(settings)),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        let (texture, view) = light_depth_target(device, settings, "FattenedShadowMapPass::fattened_map");
        Self {
            settings: *settings,
            texture,
            view,
            uniform,
            bind_group,
            pipeline,
        }
    }

    pub fn settings(&self) -> &ShadowMapSettings {
        &self.settings
    }

    /// The fattened depth map.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    pub fn texture(&self) -> &wgpu::Texture {
        &self.texture
    }

    /// Records the pass: every caster, inflated by `fatten_distance` world units.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        light: &LightView,
        fatten_distance: f32,
    ) {
        let uniform = FattenUniform {
            view_proj: light.view_projection.to_cols_array_2d(),
            params: [fatten_distance, 0.0, 0.0, 0.0],
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let mut pass = begin_depth_pass(encoder, "FattenedShadowMapPass", &self.view);
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        for inst in scene.instances.iter().filter(|i| i.caster) {
            let mesh = &scene.meshes[inst.mesh];
            if mesh.index_count == 0 {
                continue;
            }
            pass.set_bind_group(1, &scene.instance_bind_group, &[inst.uniform_offset]);
            pass.set_vertex_buffer(0, mesh.positions.slice(..));
            pass.set_vertex_buffer(1, mesh.smoothed_normals.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }
}
