//! Clearing the compute path's storage textures with a compute pass.
//!
//! A render pass that only clears (`LoadOp::Clear`) a texture the compute passes write took,
//! on an NVIDIA H100, 0.09 ms for a 1280x1024 `R32Float` texture and 0.19 ms for an
//! `Rgba16Float` one: more than the compute passes that fill them over the tile list
//! (`docs/bench/archive/passes-h100.md`). A compute pass that stores one value a texel costs about what
//! the texels' bytes do. Input: the texture (its view and size); output: every texel set to
//! the value.

use crate::pipeline_cache::CachedDevice;
/// A compute clear of one storage texture to one value: its pipeline and bind group.
#[derive(Clone)]
pub(crate) struct StorageClear {
    pipeline: std::sync::Arc<wgpu::ComputePipeline>,
    group: wgpu::BindGroup,
    size: (u32, u32),
}

impl StorageClear {
    /// A clear of `view` (a 2D storage texture of `format` and `size`) to `value`.
    pub(crate) fn new(
        device: &CachedDevice<'_>,
        label: &str,
        (view, format, size): (&wgpu::TextureView, wgpu::TextureFormat, (u32, u32)),
        value: [f64; 4],
    ) -> Self {
        let name = match format {
            wgpu::TextureFormat::R32Float => "r32float",
            wgpu::TextureFormat::R16Float => "r16float",
            wgpu::TextureFormat::Rgba16Float => "rgba16float",
            wgpu::TextureFormat::Rg32Float => "rg32float",
            wgpu::TextureFormat::Rg16Float => "rg16float",
            other => unreachable!("no compute clear for {other:?}: add its WGSL name"),
        };
        let source = format!(
            "override R: f32 = 0.0;\n\
             override G: f32 = 0.0;\n\
             override B: f32 = 0.0;\n\
             override A: f32 = 0.0;\n\
             @group(0) @binding(0) var target_texture: texture_storage_2d<{name}, write>;\n\
             @compute @workgroup_size(16, 16)\n\
             fn cs_clear(@builtin(global_invocation_id) id: vec3<u32>) {{\n\
             \x20   let size = textureDimensions(target_texture);\n\
             \x20   if id.x < size.x && id.y < size.y {{\n\
             \x20       textureStore(target_texture, id.xy, vec4<f32>(R, G, B, A));\n\
             \x20   }}\n\
             }}\n"
        );
        let shader = device.module(label, &source);
        let layout =
            device.bind_group_layout(label, &[crate::gpu_helpers::entry::storage_texture(0, format)]);
        let pipeline = device.compute_pipeline(
            label,
            &shader,
            &[Some(&layout)],
            "cs_clear",
            &[("R", value[0]), ("G", value[1]), ("B", value[2]), ("A", value[3])],
        );
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(view),
            }],
        });
        Self {
            pipeline,
            group,
            size,
        }
    }

    /// Records the clear.
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("StorageClear"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.size.0.div_ceil(16), self.size.1.div_ceil(16), 1);
    }
}
