//! The render world's side: penumbra's `Casters` and `Shadows` kept in step with the app, and
//! penumbra's passes between Bevy's depth prepass and its main pass.

use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::{Core3d, Core3dSystems};
use bevy::pbr::{ExtractedDirectionalLight, ExtractedPointLight, GlobalClusterableObjectMeta};
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::mesh::RenderMesh;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::render_asset::RenderAssets;
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::storage::GpuShaderBuffer;
use bevy::render::texture::GpuImage;
use bevy::render::view::ExtractedView;
use bevy::render::{ExtractSchedule, Render, RenderSystems};
use penumbra::{
    AlphaMask, CameraMatrices, CasterInstance, CasterMeshDesc, Casters, DepthConvention, IndexStream,
    InstanceId, Light, LightId, MeshGeometry, MeshId, Shadows, VertexStream, ViewInputs,
};

use crate::depth_resolve::DepthResolve;
use crate::extract::{Extracted, ExtractedLight, ExtractedMask, Geometry, KnownGeometry, extract_penumbra};
use crate::material::{GpuLight, GpuLights, KIND_DIRECTIONAL, KIND_POINT, KIND_SPOT};
use crate::{PenumbraDiagnostics, mat4};

/// A mesh registered with penumbra, and where its data was in Bevy's buffers then.
struct RegisteredMesh {
    id: MeshId,
    at: MeshPlace,
}

/// Where a mesh lies in the mesh allocator's slabs.
#[derive(Clone, Debug, PartialEq, Eq)]
struct MeshPlace {
    vertex_buffer: bevy::render::render_resource::BufferId,
    first_vertex: u32,
    index_buffer: Option<(bevy::render::render_resource::BufferId, u32)>,
}

/// A skinned caster's mesh and instance, and the buffers its pose is written to.
struct SkinnedCaster {
    mesh: MeshId,
    instance: InstanceId,
    vertices: wgpu::Buffer,
    /// The mesh's indices (kept alive for penumbra's draws).
    _indices: Option<wgpu::Buffer>,
    /// The pose last given (a pose that does not change redraws nothing).
    pose: Geometry,
    flags: (bool, bool),
}

struct Instance {
    id: InstanceId,
    mesh: AssetId<Mesh>,
    transform: Mat4,
    flags: (bool, bool),
    /// The alpha test it was placed with.
    mask: Option<ExtractedMask>,
}

/// penumbra's state in the render world.
#[derive(Resource, Default)]
pub(crate) struct PenumbraState {
    gpu: Option<(Casters, Shadows)>,
    geometry: HashMap<AssetId<Mesh>, Geometry>,
    meshes: HashMap<AssetId<Mesh>, RegisteredMesh>,
    instances: HashMap<Entity, Instance>,
    /// Main-world light entity -> its light id and the light as last given.
    lights: HashMap<Entity, (LightId, Light)>,
    table: GpuLights,
    /// The light table's GPU buffer (the material's binding 101).
    table_buffer: Option<wgpu::Buffer>,
    /// Whether this frame's passes may run (the camera is usable and the table was written).
    active: bool,
    /// Messages already logged (each once), shared with the app.
    diagnostics: PenumbraDiagnostics,
    /// The single-sampled copy of a multisampled depth prepass (MSAA on the camera).
    resolve: Option<DepthResolve>,
    /// Skinned casters: drawn from buffers of the plugin's own that hold their posed vertices.
    skinned: HashMap<Entity, SkinnedCaster>,
    /// `Shadows::prepare` ran for this frame's camera (the graph's step may record).
    prepared: bool,
}

impl PenumbraState {
    fn log_once(&mut self, message: String) {
        if self.diagnostics.push(message.clone()) {
            error!("{message}");
        }
    }

    fn warn_once(&mut self, message: String) {
        if self.diagnostics.push(message.clone()) {
            warn!("{message}");
        }
    }
}

pub(crate) fn build(render_app: &mut SubApp, diagnostics: PenumbraDiagnostics) {
    render_app
        .init_resource::<Extracted>()
        .init_resource::<KnownGeometry>()
        .insert_resource(PenumbraState {
            diagnostics,
            ..default()
        })
        .add_systems(ExtractSchedule, extract_penumbra)
        .add_systems(
            Render,
            (
                hand_over_shadow_maps
                    .after(RenderSystems::ExtractCommands)
                    .before(RenderSystems::CreateViews),
                prepare_penumbra.in_set(RenderSystems::PrepareResources),
                prepare_shadows.in_set(RenderSystems::PrepareBindGroups),
            ),
        );
}

pub(crate) fn finish(render_app: &mut SubApp) {
    render_app.add_systems(
        Core3d,
        penumbra_pass
            .after(Core3dSystems::Prepass)
            .before(Core3dSystems::MainPass),
    );
}

/// Bevy renders no shadow map for the lights penumbra shades (every frame: Bevy re-extracts a
/// light only when it changed, and a light penumbra lets go of gets its map back).
fn hand_over_shadow_maps(
    extracted: Res<Extracted>,
    mut suns: Query<(Entity, &mut ExtractedDirectionalLight)>,
    mut others: Query<(Entity, &mut ExtractedPointLight)>,
) {
    let usable = extracted.camera.as_ref().is_some_and(|c| c.refused.is_none());
    let penumbra: HashSet<Entity> = if usable {
        extracted.lights.iter().map(|l| l.render_entity).collect()
    } else {
        HashSet::default()
    };
    let wanted = |entity: Entity| extracted.bevy_shadowed.contains(&entity) && !penumbra.contains(&entity);
    for (entity, mut light) in &mut suns {
        let on = wanted(entity);
        if light.shadow_maps_enabled != on {
            light.shadow_maps_enabled = on;
        }
    }
    for (entity, mut light) in &mut others {
        let on = wanted(entity);
        if light.shadow_maps_enabled != on {
            light.shadow_maps_enabled = on;
        }
    }
}

/// Brings penumbra's casters and lights in step with this frame's extraction and writes the
/// light table the material reads.
#[allow(clippy::too_many_arguments)]
fn prepare_penumbra(
    extracted: Res<Extracted>,
    mut state: ResMut<PenumbraState>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    allocator: Res<MeshAllocator>,
    render_meshes: Res<RenderAssets<RenderMesh>>,
    buffers: Res<RenderAssets<GpuShaderBuffer>>,
    images: Res<RenderAssets<GpuImage>>,
    clustered: Option<Res<GlobalClusterableObjectMeta>>,
) {
    let state = &mut *state;
    state.active = false;
    let device = device.wgpu_device();
    let queue: &wgpu::Queue = &queue;
    let Some(table_buffer) = buffers.get(&extracted.lights_buffer) else {
        return;
    };
    state.table_buffer = Some((*table_buffer.buffer).clone());
    // An empty table unless penumbra's passes run this frame: they write the full one.
    queue.write_buffer(&table_buffer.buffer, 0, bytemuck::bytes_of(&GpuLights::default()));

    let camera = match &extracted.camera {
        Some(camera) => camera,
        None => return,
    };
    if let Some(reason) = &camera.refused {
        state.log_once(reason.clone());
        return;
    }
    for other in &extracted.unshaded_cameras {
        state.log_once(format!(
            "penumbra: camera {other} also has an enabled PenumbraCamera; penumbra shades one camera \
             ({}), and {other}'s materials read that camera's visibility: its shadows from penumbra's \
             lights are wrong. Disable the PenumbraCamera on all cameras but one.",
            camera.main_entity
        ));
    }
    if extracted.lights_over_limit > 0 {
        state.warn_once(format!(
            "penumbra: {} shadow-mapped lights are past penumbra's limit of {}; they keep Bevy's own shadows",
            extracted.lights_over_limit,
            penumbra::MAX_LIGHTS
        ));
    }
    for (entity, why) in &extracted.left_out {
        state.warn_once(format!(
            "penumbra: entity {entity} casts no penumbra shadow: its mesh is {why} (penumbra draws meshes in their rest pose)"
        ));
    }

    if state.gpu.is_none() {
        match Shadows::new(device, camera.settings) {
            Ok(shadows) => state.gpu = Some((Casters::new(device), shadows)),
            Err(e) => {
                state.log_once(format!("penumbra: the camera's settings are refused: {e}"));
                return;
            }
        }
    }
    if let Err(e) = state.gpu.as_mut().map_or(Ok(()), |(_, shadows)| {
        if shadows.settings() != &camera.settings {
            shadows.set_settings(device, camera.settings)
        } else {
            Ok(())
        }
    }) {
        state.log_once(format!("penumbra: the camera's settings are refused: {e}"));
        return;
    }
    state.diagnostics.set_settings(camera.settings);

    sync_casters(
        state,
        &extracted,
        device,
        queue,
        (&allocator, &render_meshes, &images),
    );
    sync_lights(state, &extracted.lights, device, clustered.as_deref());

    let Some(image) = images.get(&extracted.visibility) else {
        return;
    };
    let (_, shadows) = state.gpu.as_mut().expect("made above");
    if let Err(e) = shadows.set_visibility_target(Some((*image.texture).clone())) {
        let message = format!("penumbra: {e}");
        state.log_once(message);
        return;
    }
    state.active = true;
}

/// Registers new meshes and places, moves and removes instances.
fn sync_casters(
    state: &mut PenumbraState,
    extracted: &Extracted,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (allocator, render_meshes, images): (&MeshAllocator, &RenderAssets<RenderMesh>, &RenderAssets<GpuImage>),
) {
    for id in &extracted.stale_meshes {
        state.geometry.remove(id);
        drop_mesh(state, *id);
    }
    let mut messages = Vec::new();
    for (id, geometry) in &extracted.geometry {
        match geometry {
            Ok(g) => {
                state.geometry.insert(*id, g.clone());
            }
            Err(why) => messages.push(format!("penumbra: mesh {id} casts no shadow: {why}")),
        }
    }
    let mut seen = HashSet::new();
    for caster in &extracted.casters {
        seen.insert(caster.entity);
        // The mesh: registered, and where Bevy has it now.
        let Some(place) = place_of(allocator, render_meshes, caster.mesh) else {
            continue; // Not on the GPU yet.
        };
        if state.meshes.get(&caster.mesh).is_some_and(|m| m.at != place) {
            drop_mesh(state, caster.mesh);
        }
        if !state.meshes.contains_key(&caster.mesh) {
            let Some(geometry) = state.geometry.get(&caster.mesh) else {
                continue;
            };
            let (casters, _) = state.gpu.as_mut().expect("made");
            match register(
                casters,
                device,
                queue,
                allocator,
                render_meshes,
                caster.mesh,
                geometry,
            ) {
                Ok(id) => {
                    state.meshes.insert(caster.mesh, RegisteredMesh { id, at: place });
                }
                Err(why) => {
                    messages.push(format!("penumbra: mesh {} casts no shadow: {why}", caster.mesh));
                    state.geometry.remove(&caster.mesh);
                    continue;
                }
            }
        }
        // A masked caster's texture, once Bevy has it on the GPU.
        let mask_texture = match &caster.mask {
            Some(mask) => match images.get(mask.texture) {
                Some(image) => Some(&image.texture_view),
                None => continue,
            },
            None => None,
        };
        let mesh_id = state.meshes[&caster.mesh].id;
        let (casters, _) = state.gpu.as_mut().expect("made");
        let transform = mat4(caster.transform);
        match state.instances.get_mut(&caster.entity) {
            Some(instance) if instance.mesh == caster.mesh && instance.mask == caster.mask => {
                if instance.transform != caster.transform {
                    if let Err(e) = casters.set_transform(queue, instance.id, transform) {
                        messages.push(format!("penumbra: entity {}: {e}", caster.entity));
                    }
                    instance.transform = caster.transform;
                }
                let flags = (caster.casts, caster.receives);
                if instance.flags != flags {
                    if let Err(e) = casters.set_flags(queue, instance.id, flags.0, flags.1) {
                        messages.push(format!("penumbra: entity {}: {e}", caster.entity));
                    }
                    instance.flags = flags;
                }
            }
            other => {
                if let Some(old) = other {
                    let _ = casters.remove_instance(old.id);
                }
                let mut instance = CasterInstance::new(mesh_id, transform);
                instance.caster = caster.casts;
                instance.receiver = caster.receives;
                let added = match (&caster.mask, mask_texture) {
                    (Some(mask), Some(texture)) => match uv_stream(allocator, render_meshes, caster.mesh) {
                        Ok(uvs) => casters
                            .add_masked_instance(
                                device,
                                queue,
                                instance,
                                &AlphaMask {
                                    uvs,
                                    texture,
                                    alpha_factor: mask.alpha_factor,
                                    cutoff: mask.cutoff,
                                },
                            )
                            .map_err(|e| e.to_string()),
                        Err(why) => {
                            messages.push(format!(
                                "penumbra: entity {}: its material is alpha-masked but {why}; its shadow is not masked",
                                caster.entity
                            ));
                            casters
                                .add_instance(device, queue, instance)
                                .map_err(|e| e.to_string())
                        }
                    },
                    _ => casters
                        .add_instance(device, queue, instance)
                        .map_err(|e| e.to_string()),
                };
                match added {
                    Ok(id) => {
                        state.instances.insert(
                            caster.entity,
                            Instance {
                                id,
                                mesh: caster.mesh,
                                transform: caster.transform,
                                flags: (caster.casts, caster.receives),
                                mask: caster.mask,
                            },
                        );
                    }
                    Err(e) => messages.push(format!("penumbra: entity {}: {e}", caster.entity)),
                }
            }
        }
    }
    sync_skinned(state, extracted, device, queue, &mut messages);
    // Despawned, hidden or no longer casting.
    let gone: Vec<Entity> = state
        .instances
        .keys()
        .filter(|e| !seen.contains(*e))
        .copied()
        .collect();
    for entity in gone {
        if let Some(instance) = state.instances.remove(&entity)
            && let Some((casters, _)) = state.gpu.as_mut()
        {
            let _ = casters.remove_instance(instance.id);
        }
    }
    for message in messages {
        state.log_once(message);
    }
}

/// Places, poses and removes the skinned casters: each a mesh of penumbra's drawn from the
/// plugin's own buffers, which hold its vertices as Bevy's joints pose them this frame (in world
/// space: the instance is not moved).
fn sync_skinned(
    state: &mut PenumbraState,
    extracted: &Extracted,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    messages: &mut Vec<String>,
) {
    for (entity, why) in &extracted.not_posed {
        messages.push(format!(
            "penumbra: skinned entity {entity} casts no penumbra shadow: {why}"
        ));
    }
    let Some((casters, _)) = state.gpu.as_mut() else {
        return;
    };
    let mut seen = HashSet::new();
    for skinned in &extracted.skinned {
        seen.insert(skinned.entity);
        let pose = &skinned.pose;
        let flags = (skinned.casts, skinned.receives);
        if let Some(caster) = state.skinned.get_mut(&skinned.entity)
            && caster.pose.positions.len() == pose.positions.len()
            && caster.pose.indices == pose.indices
        {
            if caster.pose.positions != pose.positions {
                queue.write_buffer(&caster.vertices, 0, bytemuck::cast_slice(&pose.positions));
                if let Err(e) = casters.set_mesh_pose(
                    queue,
                    caster.mesh,
                    &pose.positions,
                    pose.normals.as_deref(),
                    pose.indices.as_deref(),
                ) {
                    messages.push(format!("penumbra: skinned entity {}: {e}", skinned.entity));
                }
                caster.pose = pose.clone();
            }
            if caster.flags != flags {
                if let Err(e) = casters.set_flags(queue, caster.instance, flags.0, flags.1) {
                    messages.push(format!("penumbra: skinned entity {}: {e}", skinned.entity));
                }
                caster.flags = flags;
            }
            continue;
        }
        // New, or its mesh changed: registered again.
        if let Some(old) = state.skinned.remove(&skinned.entity) {
            let _ = casters.remove_instance(old.instance);
            let _ = casters.remove_mesh(old.mesh);
        }
        use wgpu::util::DeviceExt;
        let vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("penumbra-bevy posed vertices"),
            contents: bytemuck::cast_slice(&pose.positions),
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        });
        let indices = pose.indices.as_ref().map(|ix| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("penumbra-bevy posed indices"),
                contents: bytemuck::cast_slice(ix),
                usage: wgpu::BufferUsages::INDEX,
            })
        });
        let label = format!("bevy skinned mesh {} of entity {}", skinned.mesh, skinned.entity);
        let mut desc = CasterMeshDesc::new(
            &label,
            VertexStream::new(&vertices, 0, 12, wgpu::VertexFormat::Float32x3),
            pose.positions.len() as u32,
        );
        if let (Some(buffer), Some(ix)) = (&indices, &pose.indices) {
            desc = desc.indices(IndexStream::u32(buffer, ix.len() as u32));
        }
        desc = desc.cpu(&pose.positions, pose.normals.as_deref(), pose.indices.as_deref());
        let placed = casters.add_mesh(device, queue, &desc).and_then(|mesh| {
            let mut instance = CasterInstance::new(mesh, glam::Mat4::IDENTITY);
            instance.caster = flags.0;
            instance.receiver = flags.1;
            casters.add_instance(device, queue, instance).map(|id| (mesh, id))
        });
        match placed {
            Ok((mesh, instance)) => {
                state.skinned.insert(
                    skinned.entity,
                    SkinnedCaster {
                        mesh,
                        instance,
                        vertices,
                        _indices: indices,
                        pose: pose.clone(),
                        flags,
                    },
                );
            }
            Err(e) => messages.push(format!("penumbra: skinned entity {}: {e}", skinned.entity)),
        }
    }
    // Despawned, hidden, or no longer skinned.
    state.skinned.retain(|entity, caster| {
        let keep = seen.contains(entity);
        if !keep {
            let _ = casters.remove_instance(caster.instance);
            let _ = casters.remove_mesh(caster.mesh);
        }
        keep
    });
}

/// Where a mesh's vertices and indices lie now, `None` while it is not on the GPU.
fn place_of(
    allocator: &MeshAllocator,
    render_meshes: &RenderAssets<RenderMesh>,
    mesh: AssetId<Mesh>,
) -> Option<MeshPlace> {
    render_meshes.get(mesh)?;
    let vertices = allocator.mesh_vertex_slice(&mesh)?;
    let indices = allocator.mesh_index_slice(&mesh);
    Some(MeshPlace {
        vertex_buffer: vertices.buffer.id(),
        first_vertex: vertices.range.start,
        index_buffer: indices.map(|i| (i.buffer.id(), i.range.start)),
    })
}

/// A mesh's first texture coordinates where Bevy has them on the GPU, for an alpha test, or
/// why there are none.
fn uv_stream<'a>(
    allocator: &'a MeshAllocator,
    render_meshes: &RenderAssets<RenderMesh>,
    mesh: AssetId<Mesh>,
) -> Result<VertexStream<'a>, String> {
    let render_mesh = render_meshes.get(mesh).ok_or("it is not on the GPU")?;
    let vertices = allocator.mesh_vertex_slice(&mesh).ok_or("it is not on the GPU")?;
    let layout = render_mesh.layout.0.layout();
    let uv = render_mesh
        .layout
        .0
        .attribute_ids()
        .iter()
        .position(|id| *id == Mesh::ATTRIBUTE_UV_0.id)
        .ok_or("its mesh has no UV_0")?;
    let attribute = layout.attributes[uv];
    if attribute.format != wgpu::VertexFormat::Float32x2 {
        return Err(format!(
            "its GPU UVs are {:?}; penumbra reads Float32x2",
            attribute.format
        ));
    }
    let stride = layout.array_stride;
    Ok(VertexStream::new(
        vertices.buffer,
        vertices.range.start as u64 * stride + attribute.offset,
        stride,
        attribute.format,
    ))
}

/// Registers a mesh at its place in Bevy's buffers.
fn register(
    casters: &mut Casters,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    allocator: &MeshAllocator,
    render_meshes: &RenderAssets<RenderMesh>,
    mesh: AssetId<Mesh>,
    geometry: &Geometry,
) -> Result<MeshId, String> {
    let render_mesh = render_meshes.get(mesh).ok_or("it is not on the GPU")?;
    let vertices = allocator.mesh_vertex_slice(&mesh).ok_or("it is not on the GPU")?;
    let layout = render_mesh.layout.0.layout();
    let position = render_mesh
        .layout
        .0
        .attribute_ids()
        .iter()
        .position(|id| *id == Mesh::ATTRIBUTE_POSITION.id)
        .ok_or("it has no positions")?;
    let attribute = layout.attributes[position];
    if attribute.format != wgpu::VertexFormat::Float32x3 {
        return Err(format!(
            "its GPU positions are {:?} (compressed?); penumbra reads Float32x3",
            attribute.format
        ));
    }
    let stride = layout.array_stride;
    let positions = VertexStream::new(
        &vertices.buffer,
        vertices.range.start as u64 * stride + attribute.offset,
        stride,
        attribute.format,
    );
    let label = format!("bevy mesh {mesh}");
    let mut desc = CasterMeshDesc::new(&label, positions, render_mesh.vertex_count);
    let index_slice;
    if let bevy::render::mesh::RenderMeshBufferInfo::Indexed { count, index_format } = render_mesh.buffer_info
    {
        index_slice = allocator
            .mesh_index_slice(&mesh)
            .ok_or("its indices are not on the GPU")?;
        let size = match index_format {
            wgpu::IndexFormat::Uint16 => 2,
            wgpu::IndexFormat::Uint32 => 4,
        };
        desc = desc.indices(IndexStream {
            buffer: &index_slice.buffer,
            offset: index_slice.range.start as u64 * size,
            format: index_format,
            count,
        });
    }
    desc.geometry = MeshGeometry::Cpu {
        positions: &geometry.positions,
        normals: geometry.normals.as_deref(),
        indices: geometry.indices.as_deref(),
    };
    casters.add_mesh(device, queue, &desc).map_err(|e| e.to_string())
}

/// Forgets a mesh and its instances (placed again when next seen).
fn drop_mesh(state: &mut PenumbraState, mesh: AssetId<Mesh>) {
    let Some(registered) = state.meshes.remove(&mesh) else {
        return;
    };
    let Some((casters, _)) = state.gpu.as_mut() else {
        return;
    };
    state.instances.retain(|_, instance| {
        if instance.mesh == mesh {
            let _ = casters.remove_instance(instance.id);
            false
        } else {
            true
        }
    });
    let _ = casters.remove_mesh(registered.id);
}

/// Adds, changes and removes penumbra's lights, and fills the light table.
fn sync_lights(
    state: &mut PenumbraState,
    lights: &[ExtractedLight],
    device: &wgpu::Device,
    clustered: Option<&GlobalClusterableObjectMeta>,
) {
    let mut messages = Vec::new();
    let (_, shadows) = state.gpu.as_mut().expect("made");
    let alive: HashSet<Entity> = lights.iter().map(|l| l.entity).collect();
    state.lights.retain(|entity, (id, _)| {
        let keep = alive.contains(entity);
        if !keep {
            let _ = shadows.remove_light(*id);
        }
        keep
    });
    let mut table = GpuLights::default();
    for extracted in lights {
        let id = match state.lights.get_mut(&extracted.entity) {
            Some((id, light)) => {
                if *light != extracted.light {
                    if let Err(e) = shadows.set_light(*id, extracted.light) {
                        messages.push(format!("penumbra: light {}: {e}", extracted.entity));
                        continue;
                    }
                    *light = extracted.light;
                }
                *id
            }
            None => match shadows.add_light(device, extracted.light) {
                Ok(id) => {
                    state.lights.insert(extracted.entity, (id, extracted.light));
                    id
                }
                Err(e) => {
                    messages.push(format!("penumbra: light {}: {e}", extracted.entity));
                    continue;
                }
            },
        };
        let (kind, index, direction) = match extracted.light {
            Light::Directional(sun) => (KIND_DIRECTIONAL, 0, -sun.direction.normalize()),
            Light::Spot(_) | Light::Point(_) => {
                let Some(index) = clustered.and_then(|c| c.entity_to_index.get(&extracted.render_entity))
                else {
                    continue; // Not in Bevy's light list this frame.
                };
                let kind = if matches!(extracted.light, Light::Spot(_)) {
                    KIND_SPOT
                } else {
                    KIND_POINT
                };
                (kind, *index as u32, glam::Vec3::ZERO)
            }
        };
        let row = &mut table.lights[table.count as usize];
        *row = GpuLight {
            kind,
            index,
            layer: id.layer(),
            _pad: 0,
            direction_to_light: direction.extend(0.0).to_array(),
        };
        table.count += 1;
    }
    state.table = table;
    for message in messages {
        state.log_once(message);
    }
}

/// penumbra's [`Shadows::prepare`] on the penumbra camera's depth prepass, once Bevy has made
/// the view's prepass textures: the lights' fits and uniforms and the passes' bind groups (with
/// MSAA, on the single-sampled depth the graph's step resolves into before it records).
fn prepare_shadows(
    views: Query<(&ExtractedView, &ViewPrepassTextures)>,
    extracted: Res<Extracted>,
    mut state: ResMut<PenumbraState>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
) {
    let state = &mut *state;
    state.prepared = false;
    let Some(camera) = &extracted.camera else { return };
    if !state.active {
        return;
    }
    let Ok((view, prepass)) = views.get(camera.render_entity) else {
        return;
    };
    let Some(depth) = prepass.depth.as_ref() else {
        state.log_once(format!(
            "penumbra: camera {} has no depth prepass texture; add DepthPrepass to it",
            camera.main_entity
        ));
        state.active = false;
        return;
    };
    let device = device.wgpu_device();
    let queue: &wgpu::Queue = &queue;
    let source = &depth.texture.texture;
    // With MSAA, the nearest sample of each pixel, single-sampled.
    let depth: wgpu::Texture = if source.sample_count() > 1 {
        state
            .resolve
            .get_or_insert_with(|| DepthResolve::new(device))
            .target(device, (source.width(), source.height()))
    } else {
        (**source).clone()
    };
    let camera_matrices = CameraMatrices {
        view: mat4(view.world_from_view.to_matrix().inverse()),
        projection: mat4(view.clip_from_view),
        depth: DepthConvention::Reversed,
    };
    let Some((casters, shadows)) = state.gpu.as_mut() else {
        return;
    };
    match shadows.prepare(device, queue, casters, &ViewInputs::new(camera_matrices, &depth)) {
        Ok(()) => state.prepared = true,
        Err(e) => {
            state.active = false;
            state.log_once(format!("penumbra: {e}"));
        }
    }
}

/// penumbra's passes, recorded between Bevy's depth prepass and its main pass (prepared in
/// [`prepare_shadows`]).
fn penumbra_pass(
    view: ViewQuery<(Entity, &ViewPrepassTextures)>,
    extracted: Res<Extracted>,
    mut state: ResMut<PenumbraState>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    mut ctx: RenderContext,
) {
    let (entity, prepass) = view.into_inner();
    let Some(camera) = &extracted.camera else { return };
    if camera.render_entity != entity || !state.active || !state.prepared {
        return;
    }
    let state = &mut *state;
    // A span of Bevy's render diagnostics (`RenderDiagnosticsPlugin`: GPU time where the device
    // has timestamp queries): `render/penumbra/elapsed_gpu`.
    let recorder = ctx.diagnostic_recorder();
    let span = recorder
        .as_deref()
        .map(|r| r.time_span(ctx.command_encoder(), "penumbra"));
    if let (Some(depth), Some(resolve)) = (prepass.depth.as_ref(), state.resolve.as_mut())
        && depth.texture.texture.sample_count() > 1
    {
        resolve.encode(
            device.wgpu_device(),
            ctx.command_encoder(),
            &depth.texture.texture,
        );
    }
    let encoded = state
        .gpu
        .as_mut()
        .map(|(casters, shadows)| shadows.encode(ctx.command_encoder(), casters));
    if let Some(span) = span {
        span.end(ctx.command_encoder());
    }
    let Some(encoded) = encoded else {
        return;
    };
    match encoded {
        // The material reads the visibility from now on (the write lands before the main pass).
        Ok(_) => {
            if let Some(buffer) = &state.table_buffer {
                queue.write_buffer(buffer, 0, bytemuck::bytes_of(&state.table));
            }
        }
        // The lights are shaded unshadowed this frame (the table stays empty).
        Err(e) => {
            state.active = false;
            let message = format!("penumbra: {e}");
            state.log_once(message);
        }
    }
}
