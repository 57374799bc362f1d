//! The render passes, one module and one WGSL file each.
//!
//! | pass | shader | inputs | output |
//! |---|---|---|---|
//! | [`ShadowMapPass`] | `shaders/shadow_map.wgsl` | casters, light view | depth shadow map |
//! | [`ForwardPass`] | `shaders/forward.wgsl` | all instances, camera, shadow map | lit color + camera depth |

mod forward;
mod shadow_map;

pub use forward::ForwardPass;
pub use shadow_map::ShadowMapPass;

/// Vertex buffer layout of one tightly packed attribute stream.
pub(crate) const fn stream(
    location: u32,
    format: wgpu::VertexFormat,
) -> [wgpu::VertexAttribute; 1] {
    [wgpu::VertexAttribute {
        format,
        offset: 0,
        shader_location: location,
    }]
}

pub(crate) const POSITION: [wgpu::VertexAttribute; 1] = stream(0, wgpu::VertexFormat::Float32x3);

/// Bind group layout entries, so each pass states only what differs.
pub(crate) mod entry {
    /// A uniform buffer of at least `size` bytes (dynamic offset when `dynamic`).
    pub(crate) fn uniform(
        binding: u32,
        visibility: wgpu::ShaderStages,
        size: usize,
        dynamic: bool,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: dynamic,
                min_binding_size: wgpu::BufferSize::new(size as u64),
            },
            count: None,
        }
    }

    /// A 2D texture read in the fragment stage.
    pub(crate) fn texture_2d(
        binding: u32,
        sample_type: wgpu::TextureSampleType,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        }
    }

    /// A sampler used in the fragment stage.
    pub(crate) fn sampler(
        binding: u32,
        kind: wgpu::SamplerBindingType,
    ) -> wgpu::BindGroupLayoutEntry {
        wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Sampler(kind),
            count: None,
        }
    }
}

pub(crate) fn layout(attributes: &[wgpu::VertexAttribute]) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: attributes[0].format.size(),
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    }
}
