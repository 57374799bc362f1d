//! The casters: Bevy's meshes registered with penumbra's `Casters` from the mesh allocator's
//! buffers, their instances placed and moved, skinned and morphed meshes posed on the CPU.

use super::*;

/// A mesh registered with penumbra, and where its data was in Bevy's buffers then.
pub(super) struct RegisteredMesh {
    id: MeshId,
    at: MeshPlace,
}

/// Where a mesh lies in the mesh allocator's slabs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct MeshPlace {
    vertex_buffer: bevy::render::render_resource::BufferId,
    first_vertex: u32,
    index_buffer: Option<(bevy::render::render_resource::BufferId, u32)>,
}

/// A skinned caster's mesh and instance, and the buffers its pose is written to.
pub(super) struct SkinnedCaster {
    mesh: MeshId,
    instance: InstanceId,
    vertices: wgpu::Buffer,
    /// The mesh's indices (kept alive for penumbra's draws).
    _indices: Option<wgpu::Buffer>,
    /// The pose last given (a pose that does not change redraws nothing).
    pose: Geometry,
    flags: (bool, bool),
    layers: u32,
}

pub(super) struct Instance {
    id: InstanceId,
    mesh: AssetId<Mesh>,
    transform: Mat4,
    flags: (bool, bool),
    /// The alpha test it was placed with.
    mask: Option<ExtractedMask>,
    /// Its render layers as penumbra's mask.
    layers: u32,
}

/// Keeps the geometry of the meshes extracted this frame and forgets the stale ones: every
/// frame, whether penumbra shades it or not. The extraction sends a mesh's geometry once
/// ([`KnownGeometry`]), so a frame that dropped it (a camera refused for want of a depth
/// prepass, settings refused) left its casters without geometry, and without shadows, once
/// penumbra shaded again.
pub(super) fn take_geometry(state: &mut PenumbraState, extracted: &Extracted) {
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
    for message in messages {
        state.log_once(message);
    }
}

/// Registers new meshes and places, moves and removes instances (the meshes' geometry taken
/// by [`take_geometry`] first).
pub(super) fn sync_casters(
    state: &mut PenumbraState,
    extracted: &Extracted,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    (allocator, render_meshes, images): (&MeshAllocator, &RenderAssets<RenderMesh>, &RenderAssets<GpuImage>),
) {
    let mut messages = Vec::new();
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
            let casters = state.casters.as_mut().expect("made");
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
        let casters = state.casters.as_mut().expect("made");
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
                if instance.layers != caster.layers {
                    if let Err(e) = casters.set_layers(instance.id, caster.layers) {
                        messages.push(format!("penumbra: entity {}: {e}", caster.entity));
                    }
                    instance.layers = caster.layers;
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
                match added.and_then(|id| {
                    casters
                        .set_layers(id, caster.layers)
                        .map(|()| id)
                        .map_err(|e| e.to_string())
                }) {
                    Ok(id) => {
                        state.instances.insert(
                            caster.entity,
                            Instance {
                                id,
                                mesh: caster.mesh,
                                transform: caster.transform,
                                flags: (caster.casts, caster.receives),
                                mask: caster.mask,
                                layers: caster.layers,
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
            && let Some(casters) = state.casters.as_mut()
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
pub(super) fn sync_skinned(
    state: &mut PenumbraState,
    extracted: &Extracted,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    messages: &mut Vec<String>,
) {
    for (entity, why) in &extracted.not_posed {
        messages.push(format!(
            "penumbra: entity {entity} (skinned or morphed) casts no penumbra shadow: {why}"
        ));
    }
    let Some(casters) = state.casters.as_mut() else {
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
            if caster.layers != skinned.layers {
                if let Err(e) = casters.set_layers(caster.instance, skinned.layers) {
                    messages.push(format!("penumbra: skinned entity {}: {e}", skinned.entity));
                }
                caster.layers = skinned.layers;
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
            let id = casters.add_instance(device, queue, instance)?;
            casters.set_layers(id, skinned.layers)?;
            Ok((mesh, id))
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
                        layers: skinned.layers,
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
pub(super) fn place_of(
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
pub(super) fn uv_stream<'a>(
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
pub(super) fn register(
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
        vertices.buffer,
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
            buffer: index_slice.buffer,
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
pub(super) fn drop_mesh(state: &mut PenumbraState, mesh: AssetId<Mesh>) {
    let Some(registered) = state.meshes.remove(&mesh) else {
        return;
    };
    let Some(casters) = state.casters.as_mut() else {
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
