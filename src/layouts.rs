//! The bind group layouts and uniforms of instances and materials, shared by every pass that
//! draws geometry ([`crate::Casters`] and the convenience [`crate::GpuScene`]).

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec4};

use crate::gpu_helpers::entry;

/// Bind group layouts shared by every pass that draws scene geometry. Cloning shares the
/// layouts, so several [`crate::Renderer`]s made with [`crate::Renderer::with_layouts`] can
/// draw one `GpuScene`.
#[derive(Clone)]
pub struct SceneLayouts {
    /// Group with one dynamic-offset uniform: the instance data (model and normal matrices, flags).
    pub instance: wgpu::BindGroupLayout,
    /// Group with the material uniform, its base color texture and sampler.
    pub material: wgpu::BindGroupLayout,
    /// The convenience renderer's lit passes: what an instance adds to its material there,
    /// its lightmap (uniform, atlas, sampler), its material's occlusion texture and sampler, and
    /// its emissive, metallic-roughness and normal textures.
    pub surface: wgpu::BindGroupLayout,
}

impl SceneLayouts {
    /// Creates the three layouts on `device`.
    pub fn new(device: &wgpu::Device) -> Self {
        let instance = crate::gpu_helpers::layout(
            device,
            "SceneLayouts::instance",
            &[entry::uniform(
                0,
                wgpu::ShaderStages::VERTEX_FRAGMENT,
                size_of::<InstanceUniform>(),
                true,
            )],
        );
        let material = crate::gpu_helpers::layout(
            device,
            "SceneLayouts::material",
            &[
                entry::fragment_uniform(0, size_of::<MaterialUniform>()),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(2, wgpu::SamplerBindingType::Filtering),
            ],
        );
        let surface = crate::gpu_helpers::layout(
            device,
            "SceneLayouts::surface",
            &[
                entry::fragment_uniform(0, size_of::<SurfaceUniform>()),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(2, wgpu::SamplerBindingType::Filtering),
                entry::texture_2d(3, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(4, wgpu::SamplerBindingType::Filtering),
                // The material's emissive, metallic-roughness and normal textures, read with its
                // sampler (binding 4).
                entry::texture_2d(5, wgpu::TextureSampleType::Float { filterable: true }),
                entry::texture_2d(6, wgpu::TextureSampleType::Float { filterable: true }),
                entry::texture_2d(7, wgpu::TextureSampleType::Float { filterable: true }),
            ],
        );
        Self {
            instance,
            material,
            surface,
        }
    }
}

/// What the lit shaders add to an instance's material (mirrors `Surface` in
/// `shaders/common/surface.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Default)]
pub struct SurfaceUniform {
    /// The lightmap's atlas rectangle: xy min, zw max (texture space).
    pub rect: [f32; 4],
    /// x: lightmap exposure; y: 0 no lightmap (dynamic lighting or none for the instance),
    /// 1 mixed, 2 baked; z: 1 bicubic lightmap filtering, 0 bilinear.
    pub params: [f32; 4],
    /// x: occlusion strength (0: no occlusion texture); y: its UV set (0 or 1).
    pub occlusion: [f32; 4],
    /// The occlusion UVs' affine transform, two rows: `u' = dot(row0.xyz, (u, v, 1))`.
    pub occlusion_transform: [[f32; 4]; 2],
    /// rgb: the material's emissive light (times the emissive texture, binding 5); w: unused.
    pub emissive: [f32; 4],
    /// x: metallic, y: roughness (times the metallic-roughness texture, binding 6); z: 1 for
    /// the metallic-roughness model, 0 Lambertian; w: the normal map's scale (binding 7; 0:
    /// no normal map).
    pub shading: [f32; 4],
}

/// Per-instance data, as the shaders see it.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct InstanceUniform {
    pub model: [[f32; 4]; 4],
    /// Inverse transpose of the model matrix (upper 3x3 used).
    pub normal: [[f32; 4]; 4],
    /// x: 1 when the instance receives shadows.
    pub flags: [f32; 4],
}

/// Per-material data, as the shaders see it.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct MaterialUniform {
    pub base_color: [f32; 4],
    /// x: alpha cutoff (negative when there is none); y: 1 when the material is blended.
    pub alpha: [f32; 4],
}

/// Linear RGBA from a color, for uniforms.
pub(crate) fn vec4(v: Vec3, w: f32) -> [f32; 4] {
    Vec4::new(v.x, v.y, v.z, w).to_array()
}
