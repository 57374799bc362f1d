//! The render world's side: penumbra's `Casters` and `Shadows` kept in step with the app, and
//! penumbra's passes between Bevy's depth prepass and its main pass.

use bevy::core_pipeline::prepass::ViewPrepassTextures;
use bevy::core_pipeline::{Core3d, Core3dSystems};
use bevy::pbr::{ExtractedDirectionalLight, ExtractedPointLight, GlobalClusterableObjectMeta};
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::camera::ExtractedCamera;
use bevy::render::diagnostic::RecordDiagnostics;
use bevy::render::mesh::RenderMesh;
use bevy::render::mesh::allocator::MeshAllocator;
use bevy::render::render_asset::RenderAssets;
use bevy::render::renderer::{RenderContext, RenderDevice, RenderQueue, ViewQuery};
use bevy::render::storage::GpuShaderBuffer;
use bevy::render::sync_world::MainEntity;
use bevy::render::texture::GpuImage;
use bevy::render::view::ExtractedView;
use bevy::render::{ExtractSchedule, Render, RenderSystems};
use penumbra::{
    AlphaMask, CameraMatrices, CasterInstance, CasterMeshDesc, Casters, DepthConvention, IndexStream,
    InstanceId, Light, LightId, MeshGeometry, MeshId, Shadows, VertexStream, ViewInputs,
};

use crate::depth_resolve::DepthResolve;
use crate::extract::{Extracted, ExtractedLight, ExtractedMask, Geometry, KnownGeometry, extract_penumbra};
use crate::material::{GpuLight, GpuLights, KIND_DIRECTIONAL, KIND_POINT, KIND_RECT, KIND_SPOT};
use crate::{PenumbraDiagnostics, mat4};

mod casters;
mod lights;

use casters::{Instance, RegisteredMesh, SkinnedCaster, sync_casters, take_geometry};
use lights::sync_lights;

/// One penumbra camera's shadows: a `Shadows` of its own (the lights' fits to its view, their
/// maps, the screen-space passes) over the casters every camera shares.
struct ViewShadows {
    /// How messages name the camera (its `Name` where it has one).
    label: String,
    shadows: Shadows,
    /// Main-world light entity -> its light id in this camera's `Shadows`, the light and its
    /// layer mask as last given. Only the lights sharing a render layer with the camera.
    lights: HashMap<Entity, (LightId, Light, u32)>,
    /// The light table this camera's main pass reads (which of Bevy's lights each visibility
    /// layer belongs to), and its GPU copy, copied into the material's before that pass.
    table: GpuLights,
    table_buffer: wgpu::Buffer,
    /// The visibility layers the table names (those copied when `copied`).
    layers: Vec<u32>,
    /// The single-sampled copy of a multisampled depth prepass (MSAA on the camera).
    resolve: Option<DepthResolve>,
    /// `None`: the passes write straight into the material's visibility. `Some(size)`: this
    /// camera's target is smaller than the largest penumbra camera's: the passes write into
    /// penumbra's own texture, whose layers are then copied into the material's, before this
    /// camera's main pass.
    copied: Option<(u32, u32)>,
    /// `Shadows::prepare` ran for this frame (the graph's step may record).
    prepared: bool,
}

/// penumbra's state in the render world.
#[derive(Resource, Default)]
pub(crate) struct PenumbraState {
    /// The casters every penumbra camera's shadows draw.
    casters: Option<Casters>,
    /// Each penumbra camera's shadows, by its render-world view entity.
    views: HashMap<Entity, ViewShadows>,
    geometry: HashMap<AssetId<Mesh>, Geometry>,
    meshes: HashMap<AssetId<Mesh>, RegisteredMesh>,
    instances: HashMap<Entity, Instance>,
    /// The light table's GPU buffer (the material's binding 101).
    table_buffer: Option<wgpu::Buffer>,
    /// An empty light table, copied into the table buffer before the main pass of a 3D camera
    /// whose penumbra passes did not run (so no camera reads another's visibility); a penumbra
    /// camera's own table is copied before its main pass.
    empty_table: Option<wgpu::Buffer>,
    /// Whether this frame's passes may run (every penumbra camera is usable).
    active: bool,
    /// Messages already logged (each once), shared with the app.
    diagnostics: PenumbraDiagnostics,
    /// Skinned casters: drawn from buffers of the plugin's own that hold their posed vertices.
    skinned: HashMap<Entity, SkinnedCaster>,
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
    let usable = usable(&extracted);
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

/// Whether penumbra shades this frame: there is a penumbra camera and none is refused (one
/// refused camera gives every camera Bevy's own shadows: a camera left with neither would be
/// silently wrong).
fn usable(extracted: &Extracted) -> bool {
    !extracted.cameras.is_empty() && extracted.cameras.iter().all(|c| c.refused.is_none())
}

/// Brings penumbra's casters, cameras and lights in step with this frame's extraction and
/// writes the light table the material reads.
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
    // Before any return: the extraction sends each mesh's geometry once.
    take_geometry(state, &extracted);
    let device = device.wgpu_device();
    let queue: &wgpu::Queue = &queue;
    let Some(table_buffer) = buffers.get(&extracted.lights_buffer) else {
        return;
    };
    state.table_buffer = Some((*table_buffer.buffer).clone());
    // An empty table unless penumbra's passes run this frame: each camera's step copies the
    // table its main pass reads.
    queue.write_buffer(&table_buffer.buffer, 0, bytemuck::bytes_of(&GpuLights::default()));

    // Cameras gone or turned off: their shadows are dropped.
    let current: HashSet<Entity> = extracted.cameras.iter().map(|c| c.render_entity).collect();
    state.views.retain(|entity, _| current.contains(entity));
    if extracted.cameras.is_empty() {
        return;
    }
    let mut refused = false;
    for camera in &extracted.cameras {
        if let Some(reason) = &camera.refused {
            state.log_once(reason.clone());
            refused = true;
        }
    }
    if refused {
        return;
    }
    if extracted.lights_over_limit > 0 {
        state.warn_once(format!(
            "penumbra: {} shadowed lights: penumbra shadows {}, the other {} keep Bevy's own shadows \
             (penumbra's limit is {} lights)",
            extracted.lights_shadowed,
            extracted.lights_shadowed - extracted.lights_over_limit,
            extracted.lights_over_limit,
            crate::MAX_SHADOWED_LIGHTS
        ));
    }
    for entity in &extracted.high_layers {
        state.warn_once(format!(
            "penumbra: entity {entity} is on render layers past 31, which penumbra does not follow: it \
             casts and lights as on its layers 0 to 31 alone"
        ));
    }

    state.casters.get_or_insert_with(|| Casters::new(device));
    let mut messages = Vec::new();
    for camera in &extracted.cameras {
        match state.views.get_mut(&camera.render_entity) {
            Some(view) => {
                view.label.clone_from(&camera.label);
                if view.shadows.settings() != &camera.settings
                    && let Err(e) = view.shadows.set_settings(device, camera.settings)
                {
                    messages.push(format!("penumbra: {}'s settings are refused: {e}", camera.label));
                    state.views.remove(&camera.render_entity);
                }
            }
            None => match Shadows::new(device, camera.settings) {
                Ok(mut shadows) => {
                    // The cameras' passes share their pipelines: a second view compiles none
                    // that the first has. Every view's `Shadows` is made on this device.
                    let shared = state
                        .views
                        .values()
                        .next()
                        .map(|v| shadows.share_pipelines_with(&v.shadows));
                    if let Some(Err(e)) = shared {
                        state.warn_once(format!(
                            "penumbra: {} compiles its own pipelines: {e}",
                            camera.label
                        ));
                    }
                    state.views.insert(
                        camera.render_entity,
                        ViewShadows {
                            label: camera.label.clone(),
                            shadows,
                            lights: HashMap::default(),
                            table: GpuLights::default(),
                            table_buffer: new_table(device, "penumbra-bevy light table"),
                            layers: Vec::new(),
                            resolve: None,
                            copied: None,
                            prepared: false,
                        },
                    );
                }
                Err(e) => messages.push(format!("penumbra: {}'s settings are refused: {e}", camera.label)),
            },
        }
    }
    let refused_settings = !messages.is_empty();
    for message in messages {
        state.log_once(message);
    }
    if refused_settings {
        // A penumbra camera without shadows would read another camera's.
        return;
    }
    state.diagnostics.set_settings(extracted.cameras[0].settings);

    sync_casters(
        state,
        &extracted,
        device,
        queue,
        (&allocator, &render_meshes, &images),
    );
    sync_lights(state, &extracted, device, clustered.as_deref());

    if images.get(&extracted.visibility).is_none() {
        return;
    }
    state
        .empty_table
        .get_or_insert_with(|| new_table(device, "penumbra-bevy empty light table"));
    for view in state.views.values() {
        queue.write_buffer(&view.table_buffer, 0, bytemuck::bytes_of(&view.table));
    }
    state.active = true;
}

/// A light table to copy into the material's, empty until written.
fn new_table(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::bytes_of(&GpuLights::default()),
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
    })
}

/// penumbra's [`Shadows::prepare`] on each penumbra camera's depth prepass, once Bevy has made
/// the views' prepass textures: the lights' fits and uniforms and the passes' bind groups (with
/// MSAA, on the single-sampled depth the graph's step resolves into before it records).
fn prepare_shadows(
    views: Query<(&ExtractedView, &ViewPrepassTextures)>,
    extracted: Res<Extracted>,
    mut state: ResMut<PenumbraState>,
    device: Res<RenderDevice>,
    queue: Res<RenderQueue>,
    images: Res<RenderAssets<GpuImage>>,
) {
    let state = &mut *state;
    for view in state.views.values_mut() {
        view.prepared = false;
    }
    if !state.active {
        return;
    }
    let (Some(casters), Some(shared)) = (state.casters.as_ref(), images.get(&extracted.visibility)) else {
        return;
    };
    let device = device.wgpu_device();
    let queue: &wgpu::Queue = &queue;
    let mut messages = Vec::new();
    for (entity, view) in &mut state.views {
        let Ok((extracted_view, prepass)) = views.get(*entity) else {
            continue;
        };
        let Some(depth) = prepass.depth.as_ref() else {
            messages.push(format!(
                "penumbra: {} has no depth prepass texture; add DepthPrepass to it",
                view.label
            ));
            continue;
        };
        let source = &depth.texture.texture;
        // With MSAA, the nearest sample of each pixel, single-sampled.
        let depth: wgpu::Texture = if source.sample_count() > 1 {
            view.resolve
                .get_or_insert_with(|| DepthResolve::new(device))
                .target(device, (source.width(), source.height()))
        } else {
            (**source).clone()
        };
        let size = (depth.width(), depth.height());
        // Straight into the material's visibility where it fits, its size and a layer for each
        // of this camera's light slots (every light its shadows hold); otherwise copied into it.
        let layers = shared.texture.depth_or_array_layers();
        let direct = (shared.texture.width(), shared.texture.height()) == size
            && view.lights.values().all(|(id, ..)| id.layer() < layers);
        if let Err(e) = view
            .shadows
            .set_visibility_target(direct.then(|| (*shared.texture).clone()))
        {
            messages.push(format!("penumbra: {}: {e}", view.label));
            continue;
        }
        view.copied = (!direct).then_some(size);
        if !direct {
            // Copied in table order: the table names other layers than the one written before.
            let shadowed = view.layers.len();
            if view.copy_in_table_order(layers) {
                messages.push(format!(
                    "penumbra: {}: {shadowed} shadowed lights this frame, but the visibility array has \
                     {layers} layers; the others are shaded unshadowed until it grows",
                    view.label,
                ));
            }
            queue.write_buffer(&view.table_buffer, 0, bytemuck::bytes_of(&view.table));
        }
        let camera_matrices = CameraMatrices {
            view: mat4(extracted_view.world_from_view.to_matrix().inverse()),
            projection: mat4(whole_target(
                extracted_view.clip_from_view,
                extracted_view.viewport,
                size,
            )),
            depth: DepthConvention::Reversed,
        };
        match view
            .shadows
            .prepare(device, queue, casters, &ViewInputs::new(camera_matrices, &depth))
        {
            Ok(()) => {
                view.prepared = true;
                view.map_messages(&extracted, &mut messages);
            }
            Err(e) => messages.push(format!("penumbra: {}: {e}", view.label)),
        }
    }
    for message in messages {
        state.log_once(message);
    }
}

impl ViewShadows {
    /// What this camera's lights' maps lose, after a prepare: a sun whose maps cannot hold a
    /// caster in view, a spot or point light whose maps end before the scene does. Said once
    /// each: the texts hold no figure that changes as the camera moves (the light's report has
    /// them).
    fn map_messages(&self, extracted: &Extracted, messages: &mut Vec<String>) {
        for (entity, (id, ..)) in &self.lights {
            let Some(report) = self.shadows.report(*id) else {
                continue;
            };
            let light = || {
                extracted
                    .lights
                    .iter()
                    .find(|l| l.entity == *entity)
                    .map_or_else(|| format!("light {entity}"), |l| l.label.clone())
            };
            // Spread over a ground far wider than the view, with no shadow distance.
            if report.unheld_caster.is_some() {
                messages.push(format!(
                    "penumbra: in {}, {}'s shadow map cannot hold a caster in view: one is \
                     narrower than a texel of the map (spread over a scene far wider than the \
                     view), and its shadow is lost. Give the light a CascadeShadowConfig whose \
                     maximum_distance covers what needs shadows \
                     (PenumbraCamera::bevy_shadow_settings), or set the camera's \
                     settings.shadow_map.fit max_distance",
                    self.label,
                    light()
                ));
            }
            // A caster near the light, the scene and the range thousands of times deeper.
            if report.light_view.shadow_reach.is_some() {
                messages.push(format!(
                    "penumbra: in {}, {}'s shadow maps end before its range and the scene's \
                     farthest part: a caster lies so near the light that the maps' depths keep \
                     only a thousand times its distance (LightView::shadow_reach), and receivers \
                     beyond get no shadow. Lower the light's range to what needs shadows",
                    self.label,
                    light()
                ));
            }
        }
    }

    /// Where this camera's visibility is copied into the material's array: each light's row of
    /// the table names the layer at its own index, so the copies fill layers 0, 1, ... whatever
    /// the slots (a light's slot can lie past the array's layers, which grow with the lights'
    /// count: after lights are removed the others keep theirs). Rows past the array's `layers`
    /// are left out (the array grows the next frame); returns whether any was.
    fn copy_in_table_order(&mut self, layers: u32) -> bool {
        let rows = (self.table.count).min(layers);
        let cut = rows < self.table.count;
        self.table.count = rows;
        self.layers.truncate(rows as usize);
        for (row, light) in self.table.lights[..rows as usize].iter_mut().enumerate() {
            light.layer = row as u32;
        }
        cut
    }
}

/// A camera's projection onto its viewport (`x, y, width, height` in pixels of its target, of
/// `size`) as a projection onto the whole target, which its depth prepass texture covers: the
/// viewport's clip space scaled and moved within the target's.
fn whole_target(clip_from_view: Mat4, viewport: UVec4, size: (u32, u32)) -> Mat4 {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    let v = viewport.as_vec4();
    if v.z <= 0.0 || v.w <= 0.0 || (viewport == UVec4::new(0, 0, size.0, size.1)) {
        return clip_from_view;
    }
    // NDC x from the viewport's [-1, 1] to the target's; y likewise, pixel rows running down.
    let (sx, sy) = (v.z / w, v.w / h);
    let tx = (2.0 * v.x + v.z) / w - 1.0;
    let ty = 1.0 - (2.0 * v.y + v.w) / h;
    let to_target = Mat4::from_cols(
        Vec4::new(sx, 0.0, 0.0, 0.0),
        Vec4::new(0.0, sy, 0.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0, 0.0),
        Vec4::new(tx, ty, 0.0, 1.0),
    );
    to_target * clip_from_view
}

/// What [`penumbra_pass`] reads of its view: its prepass textures, its main-world entity and
/// whether it is a camera.
type PassView = (
    Entity,
    Option<&'static ViewPrepassTextures>,
    Option<&'static MainEntity>,
    Has<ExtractedCamera>,
);

/// penumbra's passes, recorded for each 3D camera between Bevy's depth prepass and its main
/// pass (prepared in [`prepare_shadows`]), and the light table that camera's main pass reads:
/// a penumbra camera's own, an empty one for any other camera.
#[allow(clippy::too_many_arguments)]
fn penumbra_pass(
    view: ViewQuery<PassView>,
    extracted: Res<Extracted>,
    mut state: ResMut<PenumbraState>,
    device: Res<RenderDevice>,
    images: Res<RenderAssets<GpuImage>>,
    mut ctx: RenderContext,
) {
    let (entity, prepass, main_entity, is_camera) = view.into_inner();
    let state = &mut *state;
    let (Some(empty), Some(table)) = (state.empty_table.clone(), state.table_buffer.clone()) else {
        return;
    };
    let size = std::mem::size_of::<GpuLights>() as u64;
    let shaded = state.active && state.views.get(&entity).is_some_and(|v| v.prepared);
    if !shaded {
        if state.active && is_camera && !state.views.contains_key(&entity) {
            let main = main_entity.map_or(entity, |m| m.id());
            let name = extracted.camera_names.get(&main).map(|n| Name::new(n.clone()));
            state.warn_once(format!(
                "penumbra: {} has no enabled PenumbraCamera; penumbra's lights cast no shadow in it \
                 (Bevy's shadow maps are off for them). Add PenumbraCamera to it.",
                crate::extract::label("camera", main, name.as_ref())
            ));
        }
        ctx.command_encoder()
            .copy_buffer_to_buffer(&empty, 0, &table, 0, size);
        return;
    }
    let casters = state.casters.as_ref().expect("made with the views");
    let view = state.views.get_mut(&entity).expect("checked above");
    // A span of Bevy's render diagnostics (`RenderDiagnosticsPlugin`: GPU time where the device
    // has timestamp queries): `render/penumbra/elapsed_gpu`.
    let recorder = ctx.diagnostic_recorder();
    let span = recorder
        .as_deref()
        .map(|r| r.time_span(ctx.command_encoder(), "penumbra"));
    if let (Some(depth), Some(resolve)) = (prepass.and_then(|p| p.depth.as_ref()), view.resolve.as_mut())
        && depth.texture.texture.sample_count() > 1
    {
        resolve.encode(
            device.wgpu_device(),
            ctx.command_encoder(),
            &depth.texture.texture,
        );
    }
    let encoded = view.shadows.encode(ctx.command_encoder(), casters);
    if encoded.is_ok()
        && let (Some(size), Some(own), Some(shared)) = (
            view.copied,
            view.shadows.visibility_texture(),
            images.get(&extracted.visibility),
        )
    {
        let extent = wgpu::Extent3d {
            width: size.0.min(shared.texture.width()),
            height: size.1.min(shared.texture.height()),
            depth_or_array_layers: 1,
        };
        // Each light's slot into the layer its table row names (`copy_in_table_order`).
        for (row, slot) in view.layers.iter().enumerate() {
            let at = |texture, z| wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z },
                aspect: wgpu::TextureAspect::All,
            };
            ctx.command_encoder().copy_texture_to_texture(
                at(own, *slot),
                at(&shared.texture, row as u32),
                extent,
            );
        }
    }
    if let Some(span) = span {
        span.end(ctx.command_encoder());
    }
    match encoded {
        // This camera's main pass reads the visibility just written.
        Ok(_) => ctx
            .command_encoder()
            .copy_buffer_to_buffer(&view.table_buffer, 0, &table, 0, size),
        // The lights are shaded unshadowed in this camera this frame.
        Err(e) => {
            let message = format!("penumbra: {}: {e}", view.label);
            view.prepared = false;
            ctx.command_encoder()
                .copy_buffer_to_buffer(&empty, 0, &table, 0, size);
            state.log_once(message);
        }
    }
}
