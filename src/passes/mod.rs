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
pub(crate) const fn stream(location: u32, format: wgpu::VertexFormat) -> [wgpu::VertexAttribute; 1] {
    [wgpu::VertexAttribute {
        format,
        offset: 0,
        shader_location: location,
    }]
}

pub(crate) const POSITION: [wgpu::VertexAttribute; 1] = stream(0, wgpu::VertexFormat::Float32x3);

pub(crate) fn layout(attributes: &[wgpu::VertexAttribute]) -> wgpu::VertexBufferLayout<'_> {
    wgpu::VertexBufferLayout {
        array_stride: attributes[0].format.size(),
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes,
    }
}
