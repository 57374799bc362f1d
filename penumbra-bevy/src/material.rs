//! The material that shades with penumbra's visibility, and the switch of a scene's
//! `StandardMaterial`s to it.

use bevy::asset::RenderAssetUsages;
use bevy::material::OpaqueRendererMethod;
use bevy::pbr::{ExtendedMaterial, Material, MaterialExtension};
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, Extent3d, TextureDimension, TextureFormat, TextureUsages, TextureViewDescriptor,
    TextureViewDimension,
};
use bevy::render::renderer::RenderDevice;
use bevy::render::storage::ShaderBuffer;
use bevy::shader::ShaderRef;

use crate::{PenumbraCamera, RectLightShadows};

/// Bevy's `StandardMaterial` with penumbra's shadows: the same PBR shading, with the direct
/// term of each light penumbra shades scaled by that light's visibility at the pixel.
///
/// The plugin switches every `MeshMaterial3d<StandardMaterial>` to one of these (one per
/// `StandardMaterial` asset; later changes to that asset are followed). To make one yourself,
/// take [`PenumbraShading`] from [`PenumbraTargets::shading`].
pub type PenumbraMaterial = ExtendedMaterial<StandardMaterial, PenumbraShading>;

/// The part of [`PenumbraMaterial`] that is penumbra's: the visibility of the penumbra camera's
/// lights and which of Bevy's lights each layer belongs to. Managed by the plugin.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
pub struct PenumbraShading {
    #[texture(100, dimension = "2d_array", sample_type = "float", filterable = false)]
    pub(crate) visibility: Handle<Image>,
    #[storage(101, read_only)]
    pub(crate) lights: Handle<ShaderBuffer>,
}

impl MaterialExtension for PenumbraShading {
    fn fragment_shader() -> ShaderRef {
        "embedded://penumbra_bevy/shaders/penumbra_material.wesl".into()
    }
}

/// One light's row of the table the material reads (`PenumbraLight` in the shader).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuLight {
    pub kind: u32,
    pub index: u32,
    pub layer: u32,
    pub _pad: u32,
    pub direction_to_light: [f32; 4],
}

/// The table of penumbra's lights (`PenumbraLights` in the shader): [`MAX_SHADOWED_LIGHTS`]
/// rows, 8 KiB.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuLights {
    pub count: u32,
    pub _pad: [u32; 3],
    pub lights: [GpuLight; MAX_SHADOWED_LIGHTS],
}

impl Default for GpuLights {
    fn default() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

/// The most lights the plugin shadows (each camera's lights, together): 256, the texture
/// array layers of Bevy's default render device (wgpu's default limits), which hold each
/// light's visibility and its maps ([`penumbra::Shadows::max_lights`]). Lights past it keep
/// Bevy's own shadows, and a warning says how many.
pub const MAX_SHADOWED_LIGHTS: usize = 256;

pub(crate) const KIND_DIRECTIONAL: u32 = 0;
pub(crate) const KIND_SPOT: u32 = 1;
pub(crate) const KIND_POINT: u32 = 2;
pub(crate) const KIND_RECT: u32 = 3;

/// A material of the app's own whose fragment shader reads penumbra's shadows, through the
/// WESL module `penumbra_bevy::shaders::shadows` (`apply_shadows`, `directional_visibility`,
/// `clustered_visibility`; see `docs/bevy.md`, "Custom materials"). The material declares the
/// two bindings that module reads, and [`PenumbraMaterialPlugin`] keeps them pointed at
/// penumbra's textures:
///
/// ```ignore
/// #[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
/// struct MyExtension {
///     // penumbra's (the module's bindings 100 and 101):
///     #[texture(100, dimension = "2d_array", sample_type = "float", filterable = false)]
///     visibility: Handle<Image>,
///     #[storage(101, read_only)]
///     lights: Handle<ShaderBuffer>,
///     // the material's own, from 102 on.
/// }
/// ```
///
/// For an `ExtendedMaterial<B, E>`, implement it for the extension `E`.
pub trait PenumbraBindings: Asset {
    /// The visibility array the material's binding 100 holds now.
    fn penumbra_visibility(&self) -> &Handle<Image>;
    /// Points bindings 100 (the visibility array) and 101 (the light table) at penumbra's.
    fn set_penumbra_bindings(&mut self, visibility: Handle<Image>, lights: Handle<ShaderBuffer>);
}

impl<B: Material, E: MaterialExtension + PenumbraBindings> PenumbraBindings for ExtendedMaterial<B, E> {
    fn penumbra_visibility(&self) -> &Handle<Image> {
        self.extension.penumbra_visibility()
    }

    fn set_penumbra_bindings(&mut self, visibility: Handle<Image>, lights: Handle<ShaderBuffer>) {
        self.extension.set_penumbra_bindings(visibility, lights);
    }
}

/// Keeps every material of type `M` pointed at penumbra's visibility and light table (set on
/// each new material, and again when the visibility array is made anew for a new target
/// size). Add it beside `MaterialPlugin::<M>` and [`crate::PenumbraPlugin`].
pub struct PenumbraMaterialPlugin<M>(std::marker::PhantomData<M>);

impl<M> Default for PenumbraMaterialPlugin<M> {
    fn default() -> Self {
        Self(std::marker::PhantomData)
    }
}

impl<M: PenumbraBindings> Plugin for PenumbraMaterialPlugin<M> {
    fn build(&self, app: &mut App) {
        app.add_systems(PostUpdate, bind_targets::<M>.after(fit_targets));
    }
}

/// Points the materials of type `M` whose visibility binding is not penumbra's current one at
/// penumbra's textures.
fn bind_targets<M: PenumbraBindings>(
    targets: Option<Res<PenumbraTargets>>,
    mut materials: ResMut<Assets<M>>,
) {
    let Some(targets) = targets else { return };
    let stale: Vec<AssetId<M>> = materials
        .iter()
        .filter(|(_, material)| material.penumbra_visibility() != &targets.visibility)
        .map(|(id, _)| id)
        .collect();
    for id in stale {
        if let Some(mut material) = materials.get_mut(id) {
            material.set_penumbra_bindings(targets.visibility.clone(), targets.lights.clone());
        }
    }
}

/// An entity whose `StandardMaterial` the plugin leaves as it is (it then gets Bevy's own
/// shadows for the lights penumbra does not shade, and none from those it does).
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct KeepStandardMaterial;

/// The textures and buffers penumbra's shading reads: the visibility array (a layer per
/// shadowed light, the largest penumbra camera's target size) and the light table.
#[derive(Resource)]
pub struct PenumbraTargets {
    pub(crate) visibility: Handle<Image>,
    pub(crate) lights: Handle<ShaderBuffer>,
    pub(crate) size: UVec2,
    /// The visibility array's layers ([`visibility_layers`]).
    pub(crate) layers: u32,
    /// The array takes `STORAGE_BINDING` too, so penumbra's compute passes write its layers
    /// themselves ([`penumbra::Shadows::visibility_usages`]); decided once the render device
    /// is known.
    storage: Option<bool>,
    converted: HashMap<AssetId<StandardMaterial>, Handle<PenumbraMaterial>>,
}

impl FromWorld for PenumbraTargets {
    fn from_world(world: &mut World) -> Self {
        let visibility = world.resource_mut::<Assets<Image>>().add(visibility_image(
            UVec2::ONE,
            visibility_layers(0),
            false,
        ));
        let lights = world
            .resource_mut::<Assets<ShaderBuffer>>()
            .add(ShaderBuffer::new(
                vec![GpuLights::default()],
                RenderAssetUsages::RENDER_WORLD,
            ));
        Self {
            visibility,
            lights,
            size: UVec2::ONE,
            layers: visibility_layers(0),
            storage: None,
            converted: HashMap::default(),
        }
    }
}

impl PenumbraTargets {
    /// The visibility array penumbra's passes write and the materials read (`R16Float`, a
    /// layer per shadowed light: [`visibility_layers`] of them). Where the render device lets a compute pass store half floats
    /// ([`penumbra::Shadows::visibility_usages`]) it has `STORAGE_BINDING` too, and penumbra's
    /// compute passes write its layers themselves.
    pub fn visibility(&self) -> &Handle<Image> {
        &self.visibility
    }

    /// The extension a hand-made [`PenumbraMaterial`] needs.
    pub fn shading(&self) -> PenumbraShading {
        PenumbraShading {
            visibility: self.visibility.clone(),
            lights: self.lights.clone(),
        }
    }
}

/// The visibility array's layers for `lights` shadowed lights: at least that many, at most
/// [`MAX_SHADOWED_LIGHTS`], in powers of two from 2 (a light more or less does not make a
/// new array each time; a single layer would be a plain 2D texture on WebGL2). Each layer is
/// 2 bytes a pixel, so an app with one light keeps 4 a pixel, one with 17 lights 64.
pub(crate) fn visibility_layers(lights: usize) -> u32 {
    lights
        .clamp(2, MAX_SHADOWED_LIGHTS)
        .next_power_of_two()
        .min(MAX_SHADOWED_LIGHTS) as u32
}

/// The visibility array: `R16Float`, `layers` layers, written by penumbra's passes (its content
/// before the first frame is never read: the light table is empty). With `storage`,
/// penumbra's compute passes can write it (the device stores half floats).
fn visibility_image(size: UVec2, layers: u32, storage: bool) -> Image {
    let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::R16Float, None);
    image.data = None;
    image.texture_descriptor.label = Some("penumbra visibility");
    image.texture_descriptor.size = Extent3d {
        width: size.x,
        height: size.y,
        depth_or_array_layers: layers,
    };
    image.texture_descriptor.dimension = TextureDimension::D2;
    image.texture_descriptor.usage = TextureUsages::TEXTURE_BINDING
        | TextureUsages::RENDER_ATTACHMENT
        | TextureUsages::COPY_SRC
        | TextureUsages::COPY_DST;
    if storage {
        image.texture_descriptor.usage |= TextureUsages::STORAGE_BINDING;
    }
    image.texture_view_descriptor = Some(TextureViewDescriptor {
        dimension: Some(TextureViewDimension::D2Array),
        ..Default::default()
    });
    image.asset_usage = RenderAssetUsages::RENDER_WORLD;
    image.copy_on_resize = false;
    image
}

/// Switches each `StandardMaterial` mesh to the [`PenumbraMaterial`] made from its material,
/// and carries later edits of the `StandardMaterial` over.
pub(crate) fn convert_standard_materials(
    mut commands: Commands,
    meshes: Query<(Entity, &MeshMaterial3d<StandardMaterial>), Without<KeepStandardMaterial>>,
    standard: Res<Assets<StandardMaterial>>,
    mut penumbra: ResMut<Assets<PenumbraMaterial>>,
    mut targets: ResMut<PenumbraTargets>,
    mut edits: MessageReader<AssetEvent<StandardMaterial>>,
) {
    for edit in edits.read() {
        if let AssetEvent::Modified { id } = edit
            && let (Some(handle), Some(base)) = (targets.converted.get(id), standard.get(*id))
            && let Some(mut material) = penumbra.get_mut(handle)
        {
            material.base = forward(base);
        }
    }
    for (entity, material) in &meshes {
        let id = material.id();
        let handle = match targets.converted.get(&id) {
            Some(handle) => handle.clone(),
            None => {
                // Not loaded yet: switched once it is.
                let Some(base) = standard.get(id) else { continue };
                let handle = penumbra.add(ExtendedMaterial {
                    base: forward(base),
                    extension: targets.shading(),
                });
                targets.converted.insert(id, handle.clone());
                handle
            }
        };
        commands
            .entity(entity)
            .remove::<MeshMaterial3d<StandardMaterial>>()
            .insert(MeshMaterial3d(handle));
    }
}

/// A copy of `base` for a [`PenumbraMaterial`], drawn in the forward pass, where penumbra's
/// shading runs, whatever `DefaultOpaqueRendererMethod` says: Bevy decides an `Auto` material's
/// method only when it prepares the material, and the copy is prepared a frame after the app
/// switches its default (its edits are followed a frame late), so an app switching a camera
/// from deferred to forward + prepass found a copy still deferred and Bevy's prepass queue
/// panicked. A material the app made `Deferred` itself stays deferred (Bevy's deferred
/// lighting, without penumbra's shadows).
fn forward(base: &StandardMaterial) -> StandardMaterial {
    let mut base = base.clone();
    if base.opaque_render_method == OpaqueRendererMethod::Auto {
        base.opaque_render_method = OpaqueRendererMethod::Forward;
    }
    base
}

/// The lights that ask for shadows (`shadow_maps_enabled`, [`RectLightShadows`]): the most
/// penumbra may shade.
#[derive(bevy::ecs::system::SystemParam)]
pub(crate) struct ShadowedLights<'w, 's> {
    suns: Query<'w, 's, &'static DirectionalLight>,
    spots: Query<'w, 's, &'static SpotLight>,
    points: Query<'w, 's, &'static PointLight>,
    rects: Query<'w, 's, (), (With<RectLight>, With<RectLightShadows>)>,
}

impl ShadowedLights<'_, '_> {
    fn count(&self) -> usize {
        self.suns.iter().filter(|l| l.shadow_maps_enabled).count()
            + self.spots.iter().filter(|l| l.shadow_maps_enabled).count()
            + self.points.iter().filter(|l| l.shadow_maps_enabled).count()
            + self.rects.iter().count()
    }
}

/// Keeps the visibility array the size of the largest penumbra camera's target (each camera's
/// passes write their visibility into its top-left corner before that camera's main pass),
/// with a layer for each light that asks for shadows ([`visibility_layers`]). A new size or
/// layer count makes a new image, which every [`PenumbraMaterial`] is pointed at.
pub(crate) fn fit_targets(
    cameras: Query<(&Camera, &PenumbraCamera)>,
    lights: ShadowedLights,
    mut images: ResMut<Assets<Image>>,
    mut materials: ResMut<Assets<PenumbraMaterial>>,
    mut targets: ResMut<PenumbraTargets>,
    device: Option<Res<RenderDevice>>,
) {
    let Some(size) = cameras
        .iter()
        .filter(|(camera, penumbra)| camera.is_active && penumbra.enabled)
        .filter_map(|(camera, _)| camera.physical_target_size())
        .reduce(UVec2::max)
    else {
        return;
    };
    let layers = visibility_layers(lights.count());
    if (size == targets.size && layers == targets.layers) || size.x == 0 || size.y == 0 {
        return;
    }
    if targets.storage.is_none()
        && let Some(device) = &device
    {
        let usages = penumbra::Shadows::visibility_usages(device.wgpu_device());
        targets.storage = Some(usages.contains(TextureUsages::STORAGE_BINDING));
    }
    let storage = targets.storage.unwrap_or(false);
    let old = std::mem::replace(
        &mut targets.visibility,
        images.add(visibility_image(size, layers, storage)),
    );
    images.remove(&old);
    targets.size = size;
    targets.layers = layers;
    for (_, material) in materials.iter_mut() {
        material.extension.visibility = targets.visibility.clone();
    }
}
