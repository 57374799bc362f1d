//! Distance map pass, which is also the camera's depth prepass.
//!
//! Input: every instance, the frame uniform (camera, light) and the fattened shadow map.
//! Output: the camera depth buffer (read by the screen-space passes and tested by the
//! composite) and, in the distance variant, an RG16F texture: R = distance along the light from
//! the fattened occluder to the receiver (world units, >= 0), G = mask (1 inside the fattened
//! shadow, 0 outside it, -1 on surfaces that receive no shadow).
//!
//! RG16F was chosen by a precision test (this module's tests): distances from 1e-4 to 1e4
//! come back with a relative error below 1e-3, far below what a blur or kernel width can show,
//! at half the bandwidth of RG32F (which is also not filterable everywhere).

use super::{POSITION, entries, entry, screen_target, stream, vertex_layout};
use crate::gpu_scene::{GpuScene, SceneLayouts};

pub struct DistanceMapPass {
    frame_layout: wgpu::BindGroupLayout,
    depth_pipeline: wgpu::RenderPipeline,
    distance_pipeline: wgpu::RenderPipeline,
    depth: (wgpu::Texture, wgpu::TextureView),
    distance: (wgpu::Texture, wgpu::TextureView),
    bind_group: Option<wgpu::BindGroup>,
}

impl DistanceMapPass {
    pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Float;
    pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

    pub fn new(device: &wgpu::Device, layouts: &SceneLayouts, frame_size: usize) -> Self {
        let shader = crate::shaders::module(device, "distance_map.wgsl", crate::shaders::DISTANCE_MAP);
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("DistanceMapPass::frame_layout"),
            entries: &[
                entry::uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, frame_size, false),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: false }),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("DistanceMapPass::pipeline_layout"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&layouts.instance),
                Some(&layouts.material),
            ],
            immediate_size: 0,
        });
        const UV: [wgpu::VertexAttribute; 1] = stream(1, wgpu::VertexFormat::Float32x2);
        let make = |label, entry_point, targets: &[Option<wgpu::ColorTargetState>]| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(vertex_layout(&POSITION)), Some(vertex_layout(&UV))],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: Self::DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Greater),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some(entry_point),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let depth_pipeline = make("DistanceMapPass::depth", "fs_depth", &[]);
        let distance_pipeline = make(
            "DistanceMapPass::distance",
            "fs_distance",
            &[Some(Self::DISTANCE_FORMAT.into())],
        );
        let depth = depth_target(device, 1, 1);
        let distance = screen_target(
            device,
            "DistanceMapPass::distance_map",
            1,
            1,
            Self::DISTANCE_FORMAT,
        );
        Self {
            frame_layout,
            depth_pipeline,
            distance_pipeline,
            depth,
            distance,
            bind_group: None,
        }
    }

    /// Recreates the screen-sized targets. The bind group must then be rebuilt with [`Self::bind`].
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.depth = depth_target(device, width, height);
        self.distance = screen_target(
            device,
            "DistanceMapPass::distance_map",
            width,
            height,
            Self::DISTANCE_FORMAT,
        );
    }

    /// Points the pass at the frame uniform and the fattened map.
    pub fn bind(&mut self, device: &wgpu::Device, frame: &wgpu::Buffer, fattened_map: &wgpu::TextureView) {
        self.bind_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("DistanceMapPass::bind_group"),
            layout: &self.frame_layout,
            entries: &entries(&[
                frame.as_entire_binding(),
                wgpu::BindingResource::TextureView(fattened_map),
            ]),
        }));
    }

    /// Camera depth (Depth32Float).
    pub fn depth(&self) -> &wgpu::TextureView {
        &self.depth.1
    }

    pub fn depth_texture(&self) -> &wgpu::Texture {
        &self.depth.0
    }

    /// Distance (R) and mask (G).
    pub fn distance_map(&self) -> &wgpu::TextureView {
        &self.distance.1
    }

    pub fn distance_texture(&self) -> &wgpu::Texture {
        &self.distance.0
    }

    /// Records the pass; with `with_distance` false only the depth prepass runs.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, scene: &GpuScene, with_distance: bool) {
        let Some(bind_group) = &self.bind_group else {
            return;
        };
        let color = [Some(wgpu::RenderPassColorAttachment {
            view: &self.distance.1,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                // Mask -2: nothing drawn here.
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: 0.0,
                    g: -2.0,
                    b: 0.0,
                    a: 0.0,
                }),
                store: wgpu::StoreOp::Store,
            },
        })];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(if with_distance {
                "DistanceMapPass"
            } else {
                "DepthPrepass"
            }),
            color_attachments: if with_distance { &color } else { &[] },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth.1,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(if with_distance {
            &self.distance_pipeline
        } else {
            &self.depth_pipeline
        });
        pass.set_bind_group(0, bind_group, &[]);
        for inst in &scene.instances {
            let mesh = &scene.meshes[inst.mesh];
            if mesh.index_count == 0 {
                continue;
            }
            pass.set_bind_group(1, &scene.instance_bind_group, &[inst.uniform_offset]);
            pass.set_bind_group(2, &scene.materials[inst.material], &[]);
            pass.set_vertex_buffer(0, mesh.positions.slice(..));
            pass.set_vertex_buffer(1, mesh.uvs.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }
}

fn depth_target(device: &wgpu::Device, width: u32, height: u32) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("DistanceMapPass::camera_depth"),
        size: wgpu::Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DistanceMapPass::DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}

#[cfg(test)]
mod tests {
    /// The distance map's format keeps distances from 1e-4 to 1e4 scene units to a relative
    /// error below 1e-3 (half floats round to 11 significant bits).
    #[test]
    fn rg16float_holds_distances_from_1e_minus_4_to_1e4() {
        assert_eq!(
            super::DistanceMapPass::DISTANCE_FORMAT,
            wgpu::TextureFormat::Rg16Float
        );
        let mut worst: f32 = 0.0;
        for i in 0..=800 {
            let d = 10f32.powf(-4.0 + i as f32 * 0.01);
            let stored = half::f16::from_f32(d).to_f32();
            worst = worst.max((stored - d).abs() / d);
        }
        assert!(worst < 1e-3, "worst relative error {worst}");
        // 1e5 would not fit: the format's largest finite value is 65504.
        assert!(half::f16::from_f32(1e5).to_f32().is_infinite());
    }
}
