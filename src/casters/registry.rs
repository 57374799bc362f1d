//! [`Casters`]: the meshes and instances that cast shadows, their streams and layers, and what each light sees of them.

use super::desc::{
    AlphaMask, CasterInstance, CasterMeshDesc, InstanceId, MeshGeometry, MeshId, VertexStream,
};
use super::desc::{
    NORMAL_FORMATS, POSITION_FORMATS, check_indices, check_stream, check_transform, index_size,
};
use super::read_back::{decode_vec3, read_indices, read_stream};
use crate::bounds::Aabb;
pub(crate) use crate::casters::normals::OutwardWinding;
use crate::error::{PenumbraError, Result};
use crate::layouts::{InstanceUniform, MaterialUniform, SceneLayouts};
use glam::{Mat3, Mat4, Vec3};

/// Which casters a light-space draw takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Cull {
    /// `Some((view_projection, margin))`: those whose world box, grown by `margin` (how far a
    /// pass pushes vertices out), reaches into the clip volume of `view_projection` (one
    /// cascade or cube face); `None`: wherever they are.
    pub clip: Option<(Mat4, f32)>,
    /// Those with a layer in common with these ([`Casters::set_layers`],
    /// [`crate::Shadows::set_light_layers`]).
    pub layers: u32,
}

impl Cull {
    /// Every caster.
    pub const ALL: Cull = Cull {
        clip: None,
        layers: ALL_LAYERS,
    };

    fn keeps(&self, record: &InstanceRecord) -> bool {
        record.layers & self.layers != 0
            && self.clip.is_none_or(|(view_projection, margin)| {
                crate::light_space::box_reaches_clip(&view_projection, &record.world_bounds, margin)
            })
    }
}

/// Every layer: what an instance and a light are on until set otherwise
/// ([`Casters::set_layers`], [`crate::Shadows::set_light_layers`]).
pub const ALL_LAYERS: u32 = u32::MAX;

/// The boxes of what one light can see ([`Casters::seen_by`]).
#[derive(Default)]
pub(crate) struct SeenBounds {
    /// The casters' union.
    pub casters: Aabb,
    /// Casters' and receivers' union.
    pub all: Aabb,
    /// Each caster's and receiver's box.
    pub parts: Vec<Aabb>,
    /// Each caster's box.
    pub caster_parts: Vec<Aabb>,
}
/// A vertex stream kept by penumbra: buffer and offset, with the layout that pipelines key on.
#[derive(Debug, Clone)]
pub(crate) struct OwnedStream {
    pub buffer: wgpu::Buffer,
    pub offset: u64,
    pub layout: StreamLayout,
}

/// What a pipeline must know of a vertex stream: its stride and format (the offset is given
/// when the buffer is bound).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct StreamLayout {
    pub stride: u64,
    pub format: wgpu::VertexFormat,
}

impl StreamLayout {
    pub(crate) const FLOAT3: StreamLayout = StreamLayout {
        stride: 12,
        format: wgpu::VertexFormat::Float32x3,
    };

    pub(crate) fn attributes(&self, location: u32) -> [wgpu::VertexAttribute; 1] {
        [wgpu::VertexAttribute {
            format: self.format,
            offset: 0,
            shader_location: location,
        }]
    }

    pub(crate) fn buffer_layout<'a>(
        &self,
        attributes: &'a [wgpu::VertexAttribute],
    ) -> wgpu::VertexBufferLayout<'a> {
        wgpu::VertexBufferLayout {
            array_stride: self.stride,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes,
        }
    }
}

/// The vertex layouts of one draw: what a pass's pipeline is made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct DrawLayout {
    pub position: StreamLayout,
    /// Set for alpha-masked instances in the depth passes.
    pub uv: Option<StreamLayout>,
}

/// Which vertex streams a pass draws with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Streams {
    /// Positions of the opaque casters (slot 0).
    OpaqueDepth,
    /// Positions and uvs of the alpha-masked casters (slots 0, 1; material at group 2).
    MaskedDepth,
    /// Positions and smoothed normals of every caster (slots 0, 1).
    Fattened,
}

struct CasterMesh {
    label: String,
    /// GPU memory penumbra allocated for the mesh (its smoothed normals), in bytes.
    own_bytes: u64,
    positions: OwnedStream,
    smoothed_normals: OwnedStream,
    indices: Option<(wgpu::Buffer, u64, wgpu::IndexFormat)>,
    /// Indices, or vertices when not indexed.
    element_count: u32,
    vertex_count: u32,
    bounds: Aabb,
    /// Which way its triangles turn seen from outside ([`crate::casters::normals::outward_winding`]).
    winding: OutwardWinding,
}

struct InstanceAlpha {
    uvs: OwnedStream,
    bind_group: wgpu::BindGroup,
}

struct InstanceRecord {
    instance: CasterInstance,
    offset: u32,
    world_bounds: Aabb,
    alpha: Option<InstanceAlpha>,
    /// The layers it casts on ([`Casters::set_layers`]).
    layers: u32,
}

/// How many changes the log keeps; a light that last looked further back re-renders.
const CHANGE_LOG: usize = 4096;

/// The shadow casters (and receivers) of a scene, drawn from the engine's buffers. Shared by
/// every light: pass it to [`crate::Shadows::prepare`] each frame.
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use glam::{Mat4, Vec3};
/// use penumbra::{CasterInstance, CasterMeshDesc, Casters, IndexStream, VertexStream};
/// use wgpu::util::DeviceExt;
///
/// let gpu = penumbra::HeadlessGpu::new()?;
/// let (device, queue) = (&gpu.device, &gpu.queue);
/// // The engine's own buffers: a 2 x 2 quad, positions tightly packed (12-byte stride).
/// let positions = [
///     Vec3::new(-1.0, 0.0, -1.0),
///     Vec3::new(1.0, 0.0, -1.0),
///     Vec3::new(1.0, 0.0, 1.0),
///     Vec3::new(-1.0, 0.0, 1.0),
/// ];
/// let indices: [u32; 6] = [0, 2, 1, 0, 3, 2];
/// let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
///     label: Some("quad vertices"),
///     contents: bytemuck::cast_slice(&positions),
///     usage: wgpu::BufferUsages::VERTEX,
/// });
/// let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
///     label: Some("quad indices"),
///     contents: bytemuck::cast_slice(&indices),
///     usage: wgpu::BufferUsages::INDEX,
/// });
///
/// let mut casters = Casters::new(device);
/// // Registered once. The CPU copy of the same data spares a read-back (and `COPY_SRC`).
/// let desc = CasterMeshDesc::new(
///     "quad",
///     VertexStream::new(&vertex_buffer, 0, 12, wgpu::VertexFormat::Float32x3),
///     positions.len() as u32,
/// )
/// .indices(IndexStream::u32(&index_buffer, indices.len() as u32))
/// .cpu(&positions, None, Some(&indices));
/// let mesh = casters.add_mesh(device, queue, &desc)?;
///
/// // Placed one unit up, casting and receiving shadows.
/// let instance = casters.add_instance(
///     device,
///     queue,
///     CasterInstance::new(mesh, Mat4::from_translation(Vec3::Y)),
/// )?;
/// // Moved in a later frame: only this instance's data is uploaded.
/// casters.set_transform(queue, instance, Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)))?;
/// assert_eq!(casters.instance(instance)?.transform.w_axis.y, 2.0);
/// assert!(casters.caster_bounds().max.y > 1.9);
/// # Ok(()) }
/// ```
pub struct Casters {
    id: u64,
    layouts: SceneLayouts,
    meshes: Vec<Option<CasterMesh>>,
    instances: Vec<Option<InstanceRecord>>,
    free_slots: Vec<u32>,
    stride: u32,
    capacity: u32,
    buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    sampler: wgpu::Sampler,
    revision: u64,
    /// (revision, world box touched), oldest first.
    changes: std::collections::VecDeque<(u64, Aabb)>,
}

static NEXT_ID: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);

impl Casters {
    /// An empty set of casters with bind group layouts of its own.
    pub fn new(device: &wgpu::Device) -> Self {
        Self::with_layouts(device, SceneLayouts::new(device))
    }

    /// As [`Casters::new`], with shared layouts (a [`crate::GpuScene`]'s).
    pub fn with_layouts(device: &wgpu::Device, layouts: SceneLayouts) -> Self {
        let stride = (size_of::<InstanceUniform>() as u32)
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment);
        let capacity = 16;
        let (buffer, bind_group) = instance_buffer(device, &layouts, stride, capacity);
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("Casters::alpha_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        Self {
            id: NEXT_ID.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            layouts,
            meshes: Vec::new(),
            instances: Vec::new(),
            free_slots: Vec::new(),
            stride,
            capacity,
            buffer,
            bind_group,
            sampler,
            revision: 0,
            changes: std::collections::VecDeque::new(),
        }
    }

    /// Registers a mesh that lives in the engine's buffers (see [`CasterMeshDesc`]). Its
    /// smoothed normals are computed here, once.
    pub fn add_mesh(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        desc: &CasterMeshDesc,
    ) -> Result<MeshId> {
        PenumbraError::scoped(
            device,
            || format!("adding caster mesh `{}`", desc.label),
            || self.add_mesh_now(device, queue, desc),
        )
    }

    fn add_mesh_now(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        desc: &CasterMeshDesc,
    ) -> Result<MeshId> {
        let what = || format!("caster mesh `{}`", desc.label);
        check_stream(
            &what(),
            "positions",
            &desc.positions,
            desc.vertex_count,
            POSITION_FORMATS,
        )?;
        if let Some(n) = &desc.normals {
            check_stream(&what(), "normals", n, desc.vertex_count, NORMAL_FORMATS)?;
        }
        if let Some(ix) = &desc.indices {
            check_indices(&what(), ix)?;
        } else if !desc.vertex_count.is_multiple_of(3) {
            return Err(PenumbraError::input(
                what(),
                format!(
                    "{} vertices without indices is not a triangle list",
                    desc.vertex_count
                ),
            ));
        }
        let (positions, normals, indices) = match desc.geometry {
            MeshGeometry::Cpu {
                positions,
                normals,
                indices,
            } => (
                positions.to_vec(),
                normals.map(<[Vec3]>::to_vec),
                indices.map(<[u32]>::to_vec),
            ),
            MeshGeometry::ReadBack => {
                let positions = decode_vec3(
                    &read_stream(
                        device,
                        queue,
                        &what(),
                        "positions",
                        &desc.positions,
                        desc.vertex_count,
                    )?,
                    &desc.positions,
                );
                let normals = match &desc.normals {
                    Some(n) => Some(decode_vec3(
                        &read_stream(device, queue, &what(), "normals", n, desc.vertex_count)?,
                        n,
                    )),
                    None => None,
                };
                let indices = match &desc.indices {
                    Some(ix) => Some(read_indices(device, queue, &what(), ix)?),
                    None => None,
                };
                (positions, normals, indices)
            }
        };
        if positions.len() != desc.vertex_count as usize {
            return Err(PenumbraError::input(
                what(),
                format!(
                    "{} CPU positions for vertex_count {}",
                    positions.len(),
                    desc.vertex_count
                ),
            ));
        }
        if let Some(n) = &normals
            && n.len() != positions.len()
        {
            return Err(PenumbraError::input(
                what(),
                format!("{} normals for {} positions", n.len(), positions.len()),
            ));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(PenumbraError::input(
                what(),
                format!("position {i} is not finite"),
            ));
        }
        let indices = match indices {
            Some(ix) => {
                if desc.indices.is_none_or(|gpu| gpu.count as usize != ix.len()) {
                    return Err(PenumbraError::input(
                        what(),
                        format!(
                            "{} CPU indices for {:?} in the index buffer",
                            ix.len(),
                            desc.indices.map(|gpu| gpu.count)
                        ),
                    ));
                }
                if let Some(bad) = ix.iter().find(|&&i| i >= desc.vertex_count) {
                    return Err(PenumbraError::input(
                        what(),
                        format!("index {bad} is out of range (vertex_count {})", desc.vertex_count),
                    ));
                }
                ix
            }
            None if desc.indices.is_some() => {
                return Err(PenumbraError::input(
                    what(),
                    "the mesh is indexed but its CPU geometry has no indices",
                ));
            }
            None => (0..desc.vertex_count).collect(),
        };
        let bounds = Aabb::from_points(positions.iter());
        let smoothed =
            crate::casters::normals::smoothed_normals(&positions, &indices, bounds, normals.as_deref());
        let winding = crate::casters::normals::outward_winding(&positions, &indices, &smoothed);
        let smoothed_buffer = vertex_buffer(
            device,
            "Casters::smoothed_normals",
            bytemuck::cast_slice(&smoothed),
        );
        Ok(self.push_mesh(CasterMesh {
            label: desc.label.to_string(),
            positions: owned(&desc.positions),
            own_bytes: smoothed_buffer.size(),
            smoothed_normals: OwnedStream {
                buffer: smoothed_buffer,
                offset: 0,
                layout: StreamLayout::FLOAT3,
            },
            indices: desc.indices.map(|ix| (ix.buffer.clone(), ix.offset, ix.format)),
            element_count: desc.indices.map_or(desc.vertex_count, |ix| ix.count),
            vertex_count: desc.vertex_count,
            bounds,
            winding,
        }))
    }

    /// A mesh whose smoothed normals are already on the GPU (tightly packed `Float32x3`), and
    /// which way its triangles turn.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_prepared_mesh(
        &mut self,
        label: &str,
        positions: &wgpu::Buffer,
        smoothed_normals: &wgpu::Buffer,
        indices: &wgpu::Buffer,
        (index_count, vertex_count): (u32, u32),
        bounds: Aabb,
        winding: OutwardWinding,
    ) -> MeshId {
        self.push_mesh(CasterMesh {
            label: label.to_string(),
            positions: OwnedStream {
                buffer: positions.clone(),
                offset: 0,
                layout: StreamLayout::FLOAT3,
            },
            smoothed_normals: OwnedStream {
                buffer: smoothed_normals.clone(),
                offset: 0,
                layout: StreamLayout::FLOAT3,
            },
            indices: Some((indices.clone(), 0, wgpu::IndexFormat::Uint32)),
            // The buffers are the scene's.
            own_bytes: 0,
            element_count: index_count,
            vertex_count,
            bounds,
            winding,
        })
    }

    /// The GPU memory these casters allocated, in bytes: the instances' uniform buffer and the
    /// smoothed normals of the meshes added with [`Casters::add_mesh`] (the engine's own
    /// buffers are not counted).
    pub fn allocated_bytes(&self) -> u64 {
        self.buffer.size() + self.meshes.iter().flatten().map(|m| m.own_bytes).sum::<u64>()
    }

    fn push_mesh(&mut self, mesh: CasterMesh) -> MeshId {
        self.meshes.push(Some(mesh));
        MeshId(self.meshes.len() as u32 - 1)
    }

    /// Forgets a mesh. Errors while an instance still uses it.
    pub fn remove_mesh(&mut self, id: MeshId) -> Result<()> {
        self.mesh(id)?;
        if self.instances.iter().flatten().any(|r| r.instance.mesh == id) {
            return Err(PenumbraError::input(
                format!("mesh {}", id.0),
                "instances still use it; remove them first",
            ));
        }
        self.meshes[id.0 as usize] = None;
        Ok(())
    }

    /// A deforming mesh's new pose (a skinned or morphed character): the engine has written
    /// its new vertex positions into the buffer the mesh was registered with ([`Casters::add_mesh`]),
    /// and `positions` (and `normals`) are their CPU copy, `indices` the mesh's CPU indices
    /// (`None` for a mesh that is not indexed). Its bounds and smoothed normals are computed
    /// again, and every light redraws what its instances covered before and cover now.
    pub fn set_mesh_pose(
        &mut self,
        queue: &wgpu::Queue,
        id: MeshId,
        positions: &[Vec3],
        normals: Option<&[Vec3]>,
        indices: Option<&[u32]>,
    ) -> Result<()> {
        let what = || format!("mesh {}", id.0);
        let mesh = self.mesh(id)?;
        if mesh.own_bytes == 0 {
            return Err(PenumbraError::input(
                what(),
                "its smoothed normals are shared; it cannot be posed",
            ));
        }
        if positions.len() != mesh.vertex_count as usize
            || normals.is_some_and(|n| n.len() != positions.len())
        {
            return Err(PenumbraError::input(
                what(),
                format!(
                    "{} positions and {:?} normals for {} vertices",
                    positions.len(),
                    normals.map(<[Vec3]>::len),
                    mesh.vertex_count
                ),
            ));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(PenumbraError::input(
                what(),
                format!("position {i} is not finite"),
            ));
        }
        let all: Vec<u32>;
        let indices = match (indices, mesh.indices.is_some()) {
            (Some(ix), true) if ix.len() == mesh.element_count as usize => {
                if let Some(bad) = ix.iter().find(|&&i| i >= mesh.vertex_count) {
                    return Err(PenumbraError::input(
                        what(),
                        format!("index {bad} is out of range"),
                    ));
                }
                ix
            }
            (None, false) => {
                all = (0..mesh.vertex_count).collect();
                &all
            }
            _ => {
                return Err(PenumbraError::input(
                    what(),
                    "its CPU indices do not match the index buffer it was registered with",
                ));
            }
        };
        let bounds = Aabb::from_points(positions.iter());
        let smoothed = crate::casters::normals::smoothed_normals(positions, indices, bounds, normals);
        queue.write_buffer(&mesh.smoothed_normals.buffer, 0, bytemuck::cast_slice(&smoothed));
        let winding = crate::casters::normals::outward_winding(positions, indices, &smoothed);
        if let Some(mesh) = self.meshes.get_mut(id.0 as usize).and_then(Option::as_mut) {
            mesh.bounds = bounds;
            mesh.winding = winding;
        }
        let placed: Vec<u32> = self
            .instances
            .iter()
            .enumerate()
            .filter(|(_, r)| r.as_ref().is_some_and(|r| r.instance.mesh == id))
            .map(|(slot, _)| slot as u32)
            .collect();
        for slot in placed {
            let Some(record) = self.instances[slot as usize].as_mut() else {
                continue;
            };
            let old = record.world_bounds;
            record.world_bounds = bounds.transformed(&record.instance.transform);
            let changed = old.union(&record.world_bounds);
            self.log_change(changed);
        }
        Ok(())
    }

    /// Places a mesh.
    pub fn add_instance(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        instance: CasterInstance,
    ) -> Result<InstanceId> {
        PenumbraError::scoped(
            device,
            || "adding a caster instance".into(),
            || self.insert(device, queue, instance, None),
        )
    }

    /// Places a mesh whose shadow is alpha-tested (foliage, fences).
    pub fn add_masked_instance(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        instance: CasterInstance,
        mask: &AlphaMask,
    ) -> Result<InstanceId> {
        let vertex_count = self.mesh(instance.mesh)?.vertex_count;
        check_stream(
            "alpha mask",
            "uvs",
            &mask.uvs,
            vertex_count,
            &[wgpu::VertexFormat::Float32x2],
        )?;
        if !(mask.cutoff.is_finite() && mask.alpha_factor.is_finite()) {
            return Err(PenumbraError::input(
                "alpha mask",
                "cutoff and alpha_factor must be finite",
            ));
        }
        let uniform = MaterialUniform {
            base_color: [1.0, 1.0, 1.0, mask.alpha_factor],
            alpha: [mask.cutoff, 0.0, 0.0, 0.0],
        };
        let buffer = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("Casters::alpha_mask"),
                contents: bytemuck::bytes_of(&uniform),
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let bind_group = crate::gpu_helpers::bind_group(
            device,
            "Casters::alpha_mask",
            &self.layouts.material,
            &[&buffer, mask.texture, &self.sampler],
        );
        let alpha = InstanceAlpha {
            uvs: owned(&mask.uvs),
            bind_group,
        };
        PenumbraError::scoped(
            device,
            || "adding a caster instance".into(),
            || self.insert(device, queue, instance, Some(alpha)),
        )
    }

    /// Adds an instance (inside wgpu's error scopes).
    fn insert(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        instance: CasterInstance,
        alpha: Option<InstanceAlpha>,
    ) -> Result<InstanceId> {
        let local = self.mesh(instance.mesh)?.bounds;
        check_transform(&instance.transform, "new instance")?;
        let slot = match self.free_slots.pop() {
            Some(slot) => slot,
            None => {
                self.instances.push(None);
                self.instances.len() as u32 - 1
            }
        };
        if slot >= self.capacity {
            self.grow(device, queue, slot + 1);
        }
        let record = InstanceRecord {
            instance,
            offset: slot * self.stride,
            world_bounds: local.transformed(&instance.transform),
            alpha,
            layers: ALL_LAYERS,
        };
        self.log_change(record.world_bounds);
        self.write(queue, &record);
        self.instances[slot as usize] = Some(record);
        Ok(InstanceId(slot))
    }

    /// Moves an instance: uploads its instance data alone.
    pub fn set_transform(&mut self, queue: &wgpu::Queue, id: InstanceId, transform: Mat4) -> Result<()> {
        check_transform(&transform, &format!("instance {}", id.0))?;
        let record = self.record_mut(id)?;
        if record.instance.transform == transform {
            return Ok(());
        }
        let old = record.world_bounds;
        record.instance.transform = transform;
        let local = self.mesh(self.record(id)?.instance.mesh)?.bounds;
        let record = self.record_mut(id)?;
        record.world_bounds = local.transformed(&transform);
        let new = record.world_bounds;
        self.log_change(old.union(&new));
        let record = self.record(id)?;
        self.write(queue, record);
        Ok(())
    }

    /// Changes whether an instance casts and receives shadows.
    pub fn set_flags(
        &mut self,
        queue: &wgpu::Queue,
        id: InstanceId,
        caster: bool,
        receiver: bool,
    ) -> Result<()> {
        let record = self.record_mut(id)?;
        if (record.instance.caster, record.instance.receiver) == (caster, receiver) {
            return Ok(());
        }
        record.instance.caster = caster;
        record.instance.receiver = receiver;
        let bounds = record.world_bounds;
        self.log_change(bounds);
        self.write(queue, self.record(id)?);
        Ok(())
    }

    /// Puts an instance on `layers` (a bit mask; [`ALL_LAYERS`] when added): it casts shadows
    /// only from the lights with a layer in common ([`crate::Shadows::set_light_layers`]),
    /// as render layers (Bevy's `RenderLayers`) keep a light's shadows to some meshes. 0 casts
    /// for no light. The lights whose maps it reaches draw them again.
    pub fn set_layers(&mut self, id: InstanceId, layers: u32) -> Result<()> {
        let record = self.record_mut(id)?;
        if record.layers == layers {
            return Ok(());
        }
        record.layers = layers;
        let bounds = record.world_bounds;
        self.log_change(bounds);
        Ok(())
    }

    /// The layers an instance casts on ([`Casters::set_layers`]).
    pub fn layers(&self, id: InstanceId) -> Result<u32> {
        self.record(id).map(|r| r.layers)
    }

    /// Removes an instance.
    pub fn remove_instance(&mut self, id: InstanceId) -> Result<()> {
        let bounds = self.record(id)?.world_bounds;
        self.instances[id.0 as usize] = None;
        self.free_slots.push(id.0);
        self.log_change(bounds);
        Ok(())
    }

    /// An instance as it is now.
    pub fn instance(&self, id: InstanceId) -> Result<CasterInstance> {
        self.record(id).map(|r| r.instance)
    }

    /// Unique per `Casters`.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// Bumped by every change to instances.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// True when a change after `revision` touched a world box for which `inside` holds (or
    /// when the log no longer reaches back that far).
    pub fn changed_inside(&self, revision: u64, inside: impl Fn(&Aabb) -> bool) -> bool {
        if revision >= self.revision {
            return false;
        }
        match self.changes.front() {
            Some(&(oldest, _)) if oldest <= revision + 1 => self
                .changes
                .iter()
                .filter(|(r, _)| *r > revision)
                .any(|(_, b)| inside(b)),
            _ => true,
        }
    }

    /// World bounds of every caster.
    pub fn caster_bounds(&self) -> Aabb {
        self.records()
            .filter(|r| r.instance.caster)
            .fold(Aabb::EMPTY, |a, r| a.union(&r.world_bounds))
    }

    /// World bounds of each instance that casts.
    pub(crate) fn caster_parts(&self) -> Vec<Aabb> {
        self.records()
            .filter(|r| r.instance.caster && !r.world_bounds.is_empty())
            .map(|r| r.world_bounds)
            .collect()
    }

    /// World bounds of everything that casts or receives.
    pub fn shadow_bounds(&self) -> Aabb {
        self.shadow_parts().iter().fold(Aabb::EMPTY, |a, b| a.union(b))
    }

    /// World bounds of each instance that casts or receives.
    pub fn shadow_parts(&self) -> Vec<Aabb> {
        self.records()
            .filter(|r| r.instance.caster || r.instance.receiver)
            .map(|r| r.world_bounds)
            .filter(|b| !b.is_empty())
            .collect()
    }

    /// As [`Casters::caster_bounds`], [`Casters::shadow_bounds`], [`Casters::shadow_parts`] and
    /// [`Casters::caster_parts`], over the instances whose world box `inside` keeps (what one
    /// light can see).
    pub(crate) fn seen_by(&self, inside: impl Fn(&Aabb) -> bool) -> SeenBounds {
        let mut seen = SeenBounds::default();
        for r in self.records() {
            if (r.instance.caster || r.instance.receiver)
                && !r.world_bounds.is_empty()
                && inside(&r.world_bounds)
            {
                if r.instance.caster {
                    seen.casters = seen.casters.union(&r.world_bounds);
                    seen.caster_parts.push(r.world_bounds);
                }
                seen.parts.push(r.world_bounds);
            }
        }
        seen.all = seen.parts.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
        seen
    }

    /// Triangles drawn per shadow-map pass.
    pub fn caster_triangle_count(&self) -> usize {
        self.records()
            .filter(|r| r.instance.caster)
            .filter_map(|r| self.meshes[r.instance.mesh.0 as usize].as_ref())
            .map(|m| m.element_count as usize / 3)
            .sum()
    }

    pub(crate) fn layouts(&self) -> &SceneLayouts {
        &self.layouts
    }

    /// The instance-data bind group (dynamic offset [`Casters::offset`]).
    pub(crate) fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind_group
    }

    /// The dynamic offset of an instance's data.
    pub(crate) fn offset(&self, id: InstanceId) -> Option<u32> {
        self.record(id).ok().map(|r| r.offset)
    }

    /// The layouts the draws of `streams` use: a pass makes a pipeline for each before drawing.
    pub(crate) fn draw_layouts(&self, streams: Streams) -> Vec<DrawLayout> {
        let mut out: Vec<DrawLayout> = Vec::new();
        for (mesh, record) in self.draws(streams) {
            let layout = draw_layout(mesh, record, streams);
            if !out.contains(&layout) {
                out.push(layout);
            }
        }
        out
    }

    /// Draws every caster of `streams` that `cull` keeps into `pass`, whose group 0 is set.
    /// `pipeline` gives the pass's pipeline for a draw layout (made beforehand from
    /// [`Casters::draw_layouts`]) and for which way the draw's triangles turn in the pass's
    /// target seen from outside their caster (`outward_in_target`).
    pub(crate) fn draw<'p>(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        streams: Streams,
        cull: Cull,
        pipeline: impl Fn(DrawLayout, OutwardWinding) -> Option<&'p wgpu::RenderPipeline>,
    ) {
        let mut current: Option<(DrawLayout, OutwardWinding)> = None;
        // A projection that mirrors turns every triangle the other way in the target.
        let mirrors = cull
            .clip
            .map(|(view_projection, _)| view_projection.determinant() > 0.0);
        for (mesh, record) in self.draws(streams).filter(|(_, r)| cull.keeps(r)) {
            let key = (
                draw_layout(mesh, record, streams),
                outward_in_target(mesh.winding, &record.instance.transform, mirrors),
            );
            if current != Some(key) {
                let Some(p) = pipeline(key.0, key.1) else { continue };
                pass.set_pipeline(p);
                current = Some(key);
            }
            pass.set_bind_group(1, &self.bind_group, &[record.offset]);
            bind_stream(pass, 0, &mesh.positions, mesh.vertex_count);
            match streams {
                Streams::Fattened => bind_stream(pass, 1, &mesh.smoothed_normals, mesh.vertex_count),
                Streams::MaskedDepth => {
                    if let Some(alpha) = &record.alpha {
                        bind_stream(pass, 1, &alpha.uvs, mesh.vertex_count);
                        pass.set_bind_group(2, &alpha.bind_group, &[]);
                    }
                }
                Streams::OpaqueDepth => {}
            }
            match &mesh.indices {
                Some((buffer, offset, format)) => {
                    let end = offset + mesh.element_count as u64 * index_size(*format);
                    pass.set_index_buffer(buffer.slice(*offset..end), *format);
                    pass.draw_indexed(0..mesh.element_count, 0, 0..1);
                }
                None => pass.draw(0..mesh.element_count, 0..1),
            }
        }
    }

    fn draws(&self, streams: Streams) -> impl Iterator<Item = (&CasterMesh, &InstanceRecord)> {
        self.records()
            .filter(move |r| {
                r.instance.caster
                    && match streams {
                        Streams::OpaqueDepth => r.alpha.is_none(),
                        Streams::MaskedDepth => r.alpha.is_some(),
                        Streams::Fattened => true,
                    }
            })
            .filter_map(|r| {
                self.meshes[r.instance.mesh.0 as usize]
                    .as_ref()
                    .filter(|m| m.element_count > 0)
                    .map(|m| (m, r))
            })
    }

    fn records(&self) -> impl Iterator<Item = &InstanceRecord> {
        self.instances.iter().flatten()
    }

    fn mesh(&self, id: MeshId) -> Result<&CasterMesh> {
        crate::error::slot(&self.meshes, "mesh", id.0)
    }

    /// The name a mesh was registered with.
    pub fn mesh_label(&self, id: MeshId) -> Result<&str> {
        self.mesh(id).map(|m| m.label.as_str())
    }

    fn record(&self, id: InstanceId) -> Result<&InstanceRecord> {
        crate::error::slot(&self.instances, "instance", id.0)
    }

    fn record_mut(&mut self, id: InstanceId) -> Result<&mut InstanceRecord> {
        crate::error::slot_mut(&mut self.instances, "instance", id.0)
    }

    fn log_change(&mut self, bounds: Aabb) {
        self.revision += 1;
        self.changes.push_back((self.revision, bounds));
        while self.changes.len() > CHANGE_LOG {
            self.changes.pop_front();
        }
    }

    fn write(&self, queue: &wgpu::Queue, record: &InstanceRecord) {
        queue.write_buffer(
            &self.buffer,
            record.offset as u64,
            bytemuck::bytes_of(&instance_uniform(&record.instance)),
        );
    }

    /// Makes room for `needed` instances: a larger buffer, every instance written again.
    fn grow(&mut self, device: &wgpu::Device, queue: &wgpu::Queue, needed: u32) {
        self.capacity = needed.next_power_of_two().max(self.capacity * 2);
        (self.buffer, self.bind_group) = instance_buffer(device, &self.layouts, self.stride, self.capacity);
        for record in self.instances.iter().flatten() {
            self.write(queue, record);
        }
    }
}

/// Which way a draw's triangles turn in a light-space pass's target, seen from outside their
/// caster: the mesh's own `winding`, turned the other way by an instance `transform` that
/// mirrors and by a projection that does (`mirrors`; `None`, not known: [`OutwardWinding::Mixed`]).
/// wgpu's projections (right-handed views into a left-handed clip space) have a negative
/// determinant and do not count as mirroring: a mesh wound counter-clockwise seen from outside
/// shows its light-facing triangles counter-clockwise.
fn outward_in_target(winding: OutwardWinding, transform: &Mat4, mirrors: Option<bool>) -> OutwardWinding {
    let Some(projection_mirrors) = mirrors else {
        return OutwardWinding::Mixed;
    };
    let ccw = match winding {
        OutwardWinding::Ccw => true,
        OutwardWinding::Cw => false,
        OutwardWinding::Mixed => return OutwardWinding::Mixed,
    };
    let instance_mirrors = Mat3::from_mat4(*transform).determinant() < 0.0;
    if ccw ^ instance_mirrors ^ projection_mirrors {
        OutwardWinding::Ccw
    } else {
        OutwardWinding::Cw
    }
}

fn draw_layout(mesh: &CasterMesh, record: &InstanceRecord, streams: Streams) -> DrawLayout {
    DrawLayout {
        position: mesh.positions.layout,
        uv: match streams {
            Streams::MaskedDepth => record.alpha.as_ref().map(|a| a.uvs.layout),
            _ => None,
        },
    }
}

fn bind_stream(pass: &mut wgpu::RenderPass<'_>, slot: u32, stream: &OwnedStream, vertex_count: u32) {
    let end = stream.offset
        + stream.layout.stride * vertex_count.saturating_sub(1) as u64
        + stream.layout.format.size();
    let end = end.min(stream.buffer.size());
    pass.set_vertex_buffer(
        slot,
        stream
            .buffer
            .slice(stream.offset..end.max(stream.offset + 1).min(stream.buffer.size())),
    );
}

pub(crate) fn instance_uniform(instance: &CasterInstance) -> InstanceUniform {
    InstanceUniform {
        model: instance.transform.to_cols_array_2d(),
        normal: normal_matrix(&instance.transform).to_cols_array_2d(),
        flags: [if instance.receiver { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
    }
}

pub(crate) fn normal_matrix(m: &Mat4) -> Mat4 {
    let n = Mat3::from_mat4(*m).inverse().transpose();
    if n.is_finite() {
        Mat4::from_mat3(n)
    } else {
        Mat4::IDENTITY
    }
}

fn instance_buffer(
    device: &wgpu::Device,
    layouts: &SceneLayouts,
    stride: u32,
    capacity: u32,
) -> (wgpu::Buffer, wgpu::BindGroup) {
    let buffer =
        crate::gpu_helpers::uniform_buffer(device, "Casters::instances", stride as u64 * capacity as u64);
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("Casters::instances"),
        layout: &layouts.instance,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &buffer,
                offset: 0,
                size: wgpu::BufferSize::new(size_of::<InstanceUniform>() as u64),
            }),
        }],
    });
    (buffer, bind_group)
}

fn vertex_buffer(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    // wgpu rejects zero-sized vertex buffers being bound; pad empty ones.
    let padded;
    let contents = if bytes.is_empty() {
        padded = [0u8; 16];
        &padded[..]
    } else {
        bytes
    };
    wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            // COPY_DST: a deforming mesh's smoothed normals are rewritten (`set_mesh_pose`).
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        },
    )
}

fn owned(stream: &VertexStream) -> OwnedStream {
    OwnedStream {
        buffer: stream.buffer.clone(),
        offset: stream.offset,
        layout: StreamLayout {
            stride: stream.stride,
            format: stream.format,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mirror_in_the_instance_or_the_projection_turns_the_winding() {
        use OutwardWinding::{Ccw, Cw, Mixed};
        let mirror = Mat4::from_scale(Vec3::new(-1.0, 2.0, 1.0));
        let turned = Mat4::from_rotation_y(2.0) * Mat4::from_scale(Vec3::new(3.0, 0.5, 1.0));
        assert_eq!(outward_in_target(Ccw, &turned, Some(false)), Ccw);
        assert_eq!(outward_in_target(Cw, &turned, Some(false)), Cw);
        assert_eq!(outward_in_target(Ccw, &mirror, Some(false)), Cw);
        assert_eq!(outward_in_target(Ccw, &Mat4::IDENTITY, Some(true)), Cw);
        assert_eq!(outward_in_target(Ccw, &mirror, Some(true)), Ccw);
        assert_eq!(outward_in_target(Cw, &mirror, Some(false)), Ccw);
        // Not known: each fragment tests its side.
        assert_eq!(outward_in_target(Ccw, &Mat4::IDENTITY, None), Mixed);
        assert_eq!(outward_in_target(Mixed, &Mat4::IDENTITY, Some(false)), Mixed);
    }
}
