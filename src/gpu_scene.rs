//! A [`Scene`] uploaded to the GPU: one vertex buffer per attribute stream (so the depth-only
//! passes read positions alone), instance transforms in a dynamic-offset uniform buffer, and one
//! bind group per material.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};
use wgpu::util::DeviceExt;

use crate::error::{PenumbraError, Result};
use crate::passes::entry;
use crate::scene::{Aabb, AlphaMode, Light, Scene};

/// Bind group layouts shared by every pass that draws scene geometry. Cloning shares the
/// layouts, so several [`crate::Renderer`]s made with [`crate::Renderer::with_layouts`] can
/// draw one [`GpuScene`].
#[derive(Clone)]
pub struct SceneLayouts {
    /// Group with one dynamic-offset uniform: [`InstanceUniform`].
    pub instance: wgpu::BindGroupLayout,
    /// Group with the material uniform, its base color texture and sampler.
    pub material: wgpu::BindGroupLayout,
}

impl SceneLayouts {
    pub fn new(device: &wgpu::Device) -> Self {
        let instance = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("SceneLayouts::instance"),
            entries: &[entry::uniform(
                0,
                wgpu::ShaderStages::VERTEX_FRAGMENT,
                size_of::<InstanceUniform>(),
                true,
            )],
        });
        let material = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("SceneLayouts::material"),
            entries: &[
                entry::uniform(
                    0,
                    wgpu::ShaderStages::FRAGMENT,
                    size_of::<MaterialUniform>(),
                    false,
                ),
                entry::texture_2d(1, wgpu::TextureSampleType::Float { filterable: true }),
                entry::sampler(2, wgpu::SamplerBindingType::Filtering),
            ],
        });
        Self { instance, material }
    }
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
    /// x: alpha cutoff (negative when the material is opaque).
    pub alpha: [f32; 4],
}

/// One mesh's vertex streams.
pub struct GpuMesh {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    pub smoothed_normals: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

/// A drawable instance: which mesh and material, its dynamic offset, and its flags.
#[derive(Debug, Clone, Copy)]
pub struct GpuInstance {
    pub mesh: usize,
    pub material: usize,
    pub uniform_offset: u32,
    pub caster: bool,
    pub receiver: bool,
    pub masked: bool,
}

/// A scene on the GPU. Made once per scene; the light can be changed with [`GpuScene::set_light`].
pub struct GpuScene {
    /// Unique per scene, and bumped when the light changes: what shadow-map caching keys on.
    revision: (u64, u64),
    pub meshes: Vec<GpuMesh>,
    pub materials: Vec<wgpu::BindGroup>,
    pub instances: Vec<GpuInstance>,
    pub instance_bind_group: wgpu::BindGroup,
    light: Light,
    ambient: Vec3,
    /// Union of caster and receiver bounds: what the light's projection must cover.
    shadow_bounds: Aabb,
    /// World bounds of each instance that casts or receives shadows.
    shadow_parts: Vec<Aabb>,
    bounds: Aabb,
    caster_bounds: Aabb,
    triangle_count: usize,
}

impl GpuScene {
    /// Validates and uploads `scene`.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &SceneLayouts,
        scene: &Scene,
    ) -> Result<Self> {
        scene.validate()?;
        let meshes = scene
            .meshes
            .iter()
            .map(|mesh| {
                let make = |label: &str, contents: &[u8], usage| {
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(label),
                        contents,
                        usage,
                    })
                };
                let vertex = wgpu::BufferUsages::VERTEX;
                // wgpu rejects zero-sized vertex buffers being bound; pad empty meshes.
                let pad = |bytes: &[u8]| {
                    if bytes.is_empty() {
                        vec![0u8; 16]
                    } else {
                        bytes.to_vec()
                    }
                };
                GpuMesh {
                    positions: make(
                        "GpuMesh::positions",
                        &pad(bytemuck::cast_slice(&mesh.positions)),
                        vertex,
                    ),
                    normals: make(
                        "GpuMesh::normals",
                        &pad(bytemuck::cast_slice(&mesh.normals)),
                        vertex,
                    ),
                    uvs: make("GpuMesh::uvs", &pad(bytemuck::cast_slice(&mesh.uvs)), vertex),
                    smoothed_normals: make(
                        "GpuMesh::smoothed_normals",
                        &pad(bytemuck::cast_slice(&mesh.smoothed_normals)),
                        vertex,
                    ),
                    indices: make(
                        "GpuMesh::indices",
                        &pad(bytemuck::cast_slice(&mesh.indices)),
                        wgpu::BufferUsages::INDEX,
                    ),
                    index_count: mesh.indices.len() as u32,
                }
            })
            .collect();

        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("GpuScene::base_color_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let max_side = device.limits().max_texture_dimension_2d;
        let textures: Vec<wgpu::TextureView> = scene
            .textures
            .iter()
            .map(|t| {
                if t.width > max_side || t.height > max_side {
                    return Err(PenumbraError::Texture {
                        name: t.name.clone(),
                        reason: format!("{}x{} exceeds the device limit of {max_side}", t.width, t.height),
                    });
                }
                Ok(upload_texture(
                    device, queue, &t.name, t.width, t.height, &t.rgba8,
                ))
            })
            .collect::<Result<_>>()?;
        let white = upload_texture(device, queue, "white", 1, 1, &[255; 4]);
        let materials = scene
            .materials
            .iter()
            .map(|m| {
                let uniform = MaterialUniform {
                    base_color: m.base_color.to_array(),
                    alpha: [
                        match m.alpha_mode {
                            AlphaMode::Opaque => -1.0,
                            AlphaMode::Mask { cutoff } => cutoff,
                        },
                        0.0,
                        0.0,
                        0.0,
                    ],
                };
                let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("GpuScene::material"),
                    contents: bytemuck::bytes_of(&uniform),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let view = m.base_color_texture.map_or(&white, |t| &textures[t]);
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("GpuScene::material"),
                    layout: &layouts.material,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: buffer.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Sampler(&sampler),
                        },
                    ],
                })
            })
            .collect();

        let stride = (size_of::<InstanceUniform>() as u32)
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment);
        let mut instance_bytes = vec![0u8; (stride as usize) * scene.instances.len().max(1)];
        let mut instances = Vec::with_capacity(scene.instances.len());
        for (k, inst) in scene.instances.iter().enumerate() {
            let uniform = InstanceUniform {
                model: inst.transform.to_cols_array_2d(),
                normal: normal_matrix(&inst.transform).to_cols_array_2d(),
                flags: [if inst.receiver { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
            };
            let offset = k * stride as usize;
            instance_bytes[offset..offset + size_of::<InstanceUniform>()]
                .copy_from_slice(bytemuck::bytes_of(&uniform));
            instances.push(GpuInstance {
                mesh: inst.mesh,
                material: inst.material,
                uniform_offset: offset as u32,
                caster: inst.caster,
                receiver: inst.receiver,
                masked: scene.materials[inst.material].is_masked(),
            });
        }
        let instance_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("GpuScene::instances"),
            contents: &instance_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let instance_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("GpuScene::instances"),
            layout: &layouts.instance,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &instance_buffer,
                    offset: 0,
                    size: wgpu::BufferSize::new(size_of::<InstanceUniform>() as u64),
                }),
            }],
        });
        let caster_bounds = scene.caster_bounds();
        static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        let id = NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Ok(Self {
            revision: (id, 0),
            meshes,
            materials,
            instances,
            instance_bind_group,
            light: scene.light,
            ambient: scene.ambient,
            shadow_bounds: caster_bounds.union(&scene.receiver_bounds()),
            shadow_parts: scene
                .instances
                .iter()
                .filter(|i| i.caster || i.receiver)
                .map(|i| scene.meshes[i.mesh].bounds.transformed(&i.transform))
                .filter(|b| !b.is_empty())
                .collect(),
            bounds: scene.bounds(),
            caster_bounds,
            triangle_count: scene
                .instances
                .iter()
                .map(|i| scene.meshes[i.mesh].triangle_count())
                .sum(),
        })
    }

    pub fn light(&self) -> &Light {
        &self.light
    }

    /// Replaces the light (validated).
    pub fn set_light(&mut self, light: Light) -> Result<()> {
        light.validate()?;
        if light != self.light {
            self.light = light;
            self.revision.1 += 1;
        }
        Ok(())
    }

    /// (scene id, revision): changes whenever anything the shadow maps depend on changes.
    pub fn revision(&self) -> (u64, u64) {
        self.revision
    }

    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// What the light's projection is fitted around: casters and receivers.
    pub fn shadow_bounds(&self) -> Aabb {
        self.shadow_bounds
    }

    /// World bounds of each instance that casts or receives shadows: the light's near and far
    /// planes enclose the parts of these inside its frustum.
    pub fn shadow_parts(&self) -> &[Aabb] {
        &self.shadow_parts
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn caster_bounds(&self) -> Aabb {
        self.caster_bounds
    }

    /// Triangles drawn per camera pass.
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }
}

fn normal_matrix(m: &Mat4) -> Mat4 {
    let n = glam::Mat3::from_mat4(*m).inverse().transpose();
    if n.is_finite() {
        Mat4::from_mat3(n)
    } else {
        Mat4::IDENTITY
    }
}

/// Uploads an sRGB RGBA8 image with a full mip chain (box-filtered on the CPU).
fn upload_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    name: &str,
    width: u32,
    height: u32,
    rgba8: &[u8],
) -> wgpu::TextureView {
    let levels = 32 - width.max(height).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8UnormSrgb,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let mut level_image = image::RgbaImage::from_raw(width, height, rgba8.to_vec()).expect("validated size");
    for level in 0..levels {
        let (w, h) = level_image.dimensions();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            level_image.as_raw(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 4),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        if level + 1 < levels {
            level_image = image::imageops::resize(
                &level_image,
                (w / 2).max(1),
                (h / 2).max(1),
                image::imageops::FilterType::Triangle,
            );
        }
    }
    texture.create_view(&Default::default())
}

/// Linear RGBA from a color, for uniforms.
pub(crate) fn vec4(v: Vec3, w: f32) -> [f32; 4] {
    Vec4::new(v.x, v.y, v.z, w).to_array()
}
