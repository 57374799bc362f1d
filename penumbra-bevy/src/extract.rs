//! What the render world takes from the app each frame: the penumbra camera, the casters, the
//! lights, and the CPU geometry of meshes it has not seen.

use bevy::camera::visibility::{InheritedVisibility, RenderLayers};
use bevy::core_pipeline::prepass::{DeferredPrepass, DepthPrepass};
use bevy::light::{
    CascadeShadowConfig, DirectionalLightShadowMap, NotShadowCaster, NotShadowReceiver, PointLightShadowMap,
    SunDisk,
};
use bevy::mesh::morph::{MeshMorphWeights, MorphWeights};
use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::mesh::{Indices, PrimitiveTopology, VertexAttributeValues};
use bevy::platform::collections::{HashMap, HashSet};
use bevy::prelude::*;
use bevy::render::Extract;
use bevy::render::storage::ShaderBuffer;
use bevy::render::sync_world::RenderEntity;
use penumbra::{DirectionalLight as Sun, Light, PointLight as Point, RectLight as Rect, SpotLight as Spot};

use crate::material::{PenumbraMaterial, PenumbraTargets};
use crate::{PenumbraCamera, PenumbraLightSize, RectLightShadows, vec3};

/// The sun's angular diameter in radians, for a `DirectionalLight` with no size given.
pub const SUN_ANGULAR_DIAMETER: f32 = 0.0093;

/// A penumbra camera, as the render world sees it.
#[derive(Clone, Debug)]
pub(crate) struct ExtractedPenumbraCamera {
    pub render_entity: Entity,
    /// How messages name it: `camera 12v0 "Main"` (its `Name`, where it has one).
    pub label: String,
    pub settings: penumbra::ShadowSettings,
    /// Why penumbra cannot run on this camera (no depth prepass), logged once.
    pub refused: Option<String>,
}

/// A skinned or morphed caster: its vertices as its joints and morph weights pose them this
/// frame.
#[derive(Clone, Debug)]
pub(crate) struct ExtractedSkinned {
    pub entity: Entity,
    pub mesh: AssetId<Mesh>,
    /// World-space positions and normals, and the mesh's indices.
    pub pose: Geometry,
    pub casts: bool,
    pub receives: bool,
    /// Its render layers as penumbra's mask ([`layer_mask`]).
    pub layers: u32,
}

/// A caster: a mesh entity and where it is.
#[derive(Clone, Debug)]
pub(crate) struct ExtractedCaster {
    pub entity: Entity,
    pub mesh: AssetId<Mesh>,
    pub transform: Mat4,
    /// False for `NotShadowCaster` (and for a masked material whose alpha is below its
    /// cutoff everywhere): still a receiver, which the lights' maps are fitted to.
    pub casts: bool,
    pub receives: bool,
    /// Its `StandardMaterial`'s alpha test (`AlphaMode::Mask`), where a texture gives the alpha.
    pub mask: Option<ExtractedMask>,
    /// Its render layers as penumbra's mask ([`layer_mask`]): it casts for the lights it
    /// shares a layer with.
    pub layers: u32,
}

/// A `StandardMaterial`'s alpha test: texels whose alpha (the base-colour texture's times the
/// base colour's) is below the cutoff cast no shadow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ExtractedMask {
    pub texture: AssetId<Image>,
    pub alpha_factor: f32,
    pub cutoff: f32,
}

/// A light penumbra shades.
#[derive(Clone, Debug)]
pub(crate) struct ExtractedLight {
    pub entity: Entity,
    /// How messages name it: `DirectionalLight 7v0 "Sun"` (its `Name`, where it has one).
    pub label: String,
    pub render_entity: Entity,
    pub light: Light,
    /// Its render layers as penumbra's mask ([`layer_mask`]): it shadows the casters it shares
    /// a layer with.
    pub mask: u32,
}

/// A mesh's triangles on the CPU: what penumbra computes its bounds and smoothed normals from.
#[derive(Clone, Debug)]
pub(crate) struct Geometry {
    pub positions: Vec<glam::Vec3>,
    pub normals: Option<Vec<glam::Vec3>>,
    pub indices: Option<Vec<u32>>,
}

/// This frame's extraction.
#[derive(Resource, Default)]
pub(crate) struct Extracted {
    /// The active cameras with an enabled `PenumbraCamera`, in Bevy's rendering order
    /// (`Camera::order`): each gets its own shadows; the first one's lights set the layers of
    /// the visibility the materials read.
    pub cameras: Vec<ExtractedPenumbraCamera>,
    pub casters: Vec<ExtractedCaster>,
    pub lights: Vec<ExtractedLight>,
    /// The lights whose shadows the app asked for (`shadow_maps_enabled`, `RectLightShadows`).
    pub lights_shadowed: usize,
    /// Shadow-mapped lights past penumbra's limit (they keep Bevy's shadows).
    pub lights_over_limit: usize,
    /// The names of the cameras that have one (for messages about a camera without a
    /// `PenumbraCamera`).
    pub camera_names: HashMap<Entity, String>,
    /// The render entities of the lights whose Bevy shadow maps the app asked for.
    pub bevy_shadowed: Vec<Entity>,
    /// Geometry of meshes new or changed since the last frame (or why it cannot be read).
    pub geometry: Vec<(AssetId<Mesh>, Result<Geometry, String>)>,
    /// Meshes removed or changed: their registration is dropped.
    pub stale_meshes: Vec<AssetId<Mesh>>,
    pub visibility: Handle<Image>,
    pub lights_buffer: Handle<ShaderBuffer>,
    /// Skinned and morphed casters, posed.
    pub skinned: Vec<ExtractedSkinned>,
    /// Skinned or morphed casters that could not be posed, with why.
    pub not_posed: Vec<(Entity, String)>,
    /// Entities on render layers past 31, which penumbra's masks do not hold.
    pub high_layers: Vec<Entity>,
}

/// Render layers as penumbra's 32-bit mask (layer n is bit n; no component is layer 0), and
/// whether a layer past 31 was left out.
pub(crate) fn layer_mask(layers: Option<&RenderLayers>) -> (u32, bool) {
    let Some(layers) = layers else { return (1, false) };
    let mut mask = 0u32;
    let mut high = false;
    for layer in layers.iter() {
        if layer < 32 {
            mask |= 1 << layer;
        } else {
            high = true;
        }
    }
    (mask, high)
}

/// How a message names an entity: its kind, its id and its `Name` where it has one.
pub(crate) fn label(kind: &str, entity: Entity, name: Option<&Name>) -> String {
    match name {
        Some(name) => format!("{kind} {entity} \"{name}\""),
        None => format!("{kind} {entity}"),
    }
}

/// Meshes whose geometry the render world holds (so it is not copied again).
#[derive(Resource, Default)]
pub(crate) struct KnownGeometry(pub HashSet<AssetId<Mesh>>);

type CasterQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        &'static Mesh3d,
        &'static GlobalTransform,
        Option<&'static InheritedVisibility>,
        Has<NotShadowCaster>,
        Has<NotShadowReceiver>,
        Option<&'static SkinnedMesh>,
        Option<&'static MeshMorphWeights>,
        Option<&'static MorphWeights>,
        Option<&'static MeshMaterial3d<StandardMaterial>>,
        Option<&'static MeshMaterial3d<PenumbraMaterial>>,
        Option<&'static RenderLayers>,
    ),
>;

/// The suns, with what penumbra takes from them.
type SunQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        RenderEntity,
        &'static DirectionalLight,
        &'static GlobalTransform,
        Option<&'static SunDisk>,
        Option<&'static PenumbraLightSize>,
        Option<&'static CascadeShadowConfig>,
        Option<&'static RenderLayers>,
        Option<&'static Name>,
    ),
>;

/// The cameras penumbra may shade, with what decides whether it can.
type CameraQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        RenderEntity,
        &'static Camera,
        &'static PenumbraCamera,
        Has<DepthPrepass>,
        Has<DeferredPrepass>,
        Option<&'static Name>,
    ),
>;

/// Bevy's spot (`L` = `SpotLight`) or point lights (`PointLight`).
type LampQuery<'w, 's, L> = Query<
    'w,
    's,
    (
        Entity,
        RenderEntity,
        &'static L,
        &'static GlobalTransform,
        Option<&'static PenumbraLightSize>,
        Option<&'static RenderLayers>,
        Option<&'static Name>,
    ),
>;

/// Bevy's rectangle lights, with whether they ask for penumbra's shadows.
type RectQuery<'w, 's> = Query<
    'w,
    's,
    (
        Entity,
        RenderEntity,
        &'static RectLight,
        &'static GlobalTransform,
        Has<RectLightShadows>,
        Option<&'static RenderLayers>,
        Option<&'static Name>,
    ),
>;

/// The materials a caster's alpha test is read from: a `StandardMaterial`, or the
/// `PenumbraMaterial` the plugin switched it to.
type MaterialAssets<'w> = (
    Res<'w, Assets<StandardMaterial>>,
    Res<'w, Assets<PenumbraMaterial>>,
);

#[allow(clippy::too_many_arguments)]
pub(crate) fn extract_penumbra(
    mut extracted: ResMut<Extracted>,
    mut known: ResMut<KnownGeometry>,
    cameras: Extract<CameraQuery>,
    named_cameras: Extract<Query<(Entity, &Name), With<Camera>>>,
    bevy_maps: Extract<(Res<DirectionalLightShadowMap>, Res<PointLightShadowMap>)>,
    casters: Extract<CasterQuery>,
    suns: Extract<SunQuery>,
    spots: Extract<LampQuery<SpotLight>>,
    points: Extract<LampQuery<PointLight>>,
    rects: Extract<RectQuery>,
    meshes: Extract<Res<Assets<Mesh>>>,
    skins: Extract<(Query<&GlobalTransform>, Res<Assets<SkinnedMeshInverseBindposes>>)>,
    morph_weights: Extract<Query<&MorphWeights>>,
    materials: Extract<MaterialAssets>,
    mut mesh_events: Extract<MessageReader<AssetEvent<Mesh>>>,
    targets: Extract<Res<PenumbraTargets>>,
) {
    let extracted = &mut *extracted;
    let mut shaded: Vec<_> = cameras
        .iter()
        .filter(|(_, _, camera, penumbra, ..)| camera.is_active && penumbra.enabled)
        .collect();
    shaded.sort_by_key(|(main_entity, _, camera, ..)| (camera.order, *main_entity));
    extracted.cameras = shaded
        .into_iter()
        .map(
            |(main_entity, render_entity, _, penumbra, depth_prepass, _deferred, name)| {
                let label = label("camera", main_entity, name);
                // MSAA is served: the render world resolves the multisampled depth prepass. With
                // `DeferredPrepass` the plugin's materials still draw in the forward pass (they
                // are made `OpaqueRendererMethod::Forward`), on the same depth prepass.
                let refused = (!depth_prepass).then(|| {
                    format!(
                        "penumbra: {label} has no DepthPrepass; penumbra's passes read it. \
                         Bevy's own shadows are used meanwhile."
                    )
                });
                let mut settings = penumbra.settings;
                if penumbra.bevy_shadow_settings {
                    take_bevy_shadow_settings(&mut settings, &bevy_maps, &suns);
                }
                ExtractedPenumbraCamera {
                    render_entity,
                    label,
                    settings,
                    refused,
                }
            },
        )
        .collect();
    extracted.camera_names = named_cameras
        .iter()
        .map(|(entity, name)| (entity, name.to_string()))
        .collect();
    extracted.visibility = targets.visibility.clone();
    extracted.lights_buffer = targets.lights.clone();

    extracted.stale_meshes.clear();
    for event in mesh_events.read() {
        match event {
            AssetEvent::Modified { id } | AssetEvent::Removed { id } | AssetEvent::Unused { id }
                if known.0.remove(id) =>
            {
                extracted.stale_meshes.push(*id);
            }
            _ => {}
        }
    }

    extracted.casters.clear();
    extracted.geometry.clear();
    extracted.skinned.clear();
    extracted.not_posed.clear();
    extracted.high_layers.clear();
    let (standard, converted) = &*materials;
    for (
        entity,
        mesh,
        transform,
        visibility,
        not_caster,
        not_receiver,
        skinned,
        mesh_morph,
        own_morph,
        material,
        penumbra,
        render_layers,
    ) in &casters
    {
        if visibility.is_some_and(|v| !v.get()) || (not_caster && not_receiver) {
            continue;
        }
        let (layers, high) = layer_mask(render_layers);
        if high {
            extracted.high_layers.push(entity);
        }
        // A skinned or morphed mesh: its vertices as Bevy's morph weights and joints pose them
        // this frame, in world space.
        let weights = match (mesh_morph, own_morph) {
            (Some(MeshMorphWeights::Value { weights }), _) => Some(Ok(weights.as_slice())),
            (Some(MeshMorphWeights::Reference(owner)), _) => {
                Some(morph_weights.get(*owner).map(|w| w.weights()).map_err(|_| {
                    format!("its MeshMorphWeights names entity {owner}, which has no MorphWeights")
                }))
            }
            (None, Some(own)) => Some(Ok(own.weights())),
            (None, None) => None,
        };
        if skinned.is_some() || weights.is_some() {
            let Some(asset) = meshes.get(mesh.id()) else {
                continue;
            };
            let pose = weights
                .unwrap_or(Ok(&[]))
                .and_then(|weights| morphed(geometry(asset)?, asset, weights))
                .and_then(|rest| match skinned {
                    Some(skin) => posed(rest, asset, skin, &skins),
                    None => Ok(placed(rest, &transform.to_matrix())),
                });
            match pose {
                Ok(pose) => extracted.skinned.push(ExtractedSkinned {
                    entity,
                    mesh: mesh.id(),
                    pose,
                    casts: !not_caster,
                    receives: !not_receiver,
                    layers,
                }),
                Err(why) => extracted.not_posed.push((entity, why)),
            }
            continue;
        }
        let id = mesh.id();
        if !known.0.contains(&id) {
            let Some(mesh) = meshes.get(id) else { continue };
            extracted.geometry.push((id, geometry(mesh)));
            known.0.insert(id);
        }
        // An alpha-masked material: its texture's alpha is tested as the shadow is drawn; without
        // a texture its base colour's alpha passes everywhere or nowhere.
        let (mut casts, mut mask) = (!not_caster, None);
        // The plugin switches a `StandardMaterial` to a `PenumbraMaterial` built on it.
        let material = material
            .and_then(|m| standard.get(&m.0))
            .or_else(|| penumbra.and_then(|m| converted.get(&m.0)).map(|m| &m.base));
        if let Some(material) = material
            && let AlphaMode::Mask(cutoff) = material.alpha_mode
        {
            let alpha_factor = material.base_color.alpha();
            match &material.base_color_texture {
                Some(texture) => {
                    mask = Some(ExtractedMask {
                        texture: texture.id(),
                        alpha_factor,
                        cutoff,
                    })
                }
                None => casts &= alpha_factor >= cutoff,
            }
        }
        extracted.casters.push(ExtractedCaster {
            entity,
            mesh: id,
            transform: transform.to_matrix(),
            casts,
            receives: !not_receiver,
            mask,
            layers,
        });
    }

    let mut lights: Vec<ExtractedLight> = Vec::new();
    extracted.bevy_shadowed.clear();
    let mut add = |entity: Entity,
                   render_entity: Entity,
                   shadow_maps_enabled: bool,
                   light: Light,
                   layers: Option<&RenderLayers>,
                   label: String| {
        if shadow_maps_enabled {
            extracted.bevy_shadowed.push(render_entity);
            let (mask, high) = layer_mask(layers);
            if high {
                extracted.high_layers.push(entity);
            }
            lights.push(ExtractedLight {
                entity,
                label,
                render_entity,
                light,
                mask,
            });
        }
    };
    for (entity, render_entity, sun, transform, disk, size, _, layers, name) in &suns {
        let diameter = size
            .map(|s| s.0)
            .or(disk.map(|d| d.angular_size))
            .unwrap_or(SUN_ANGULAR_DIAMETER);
        let light = Light::Directional(Sun {
            direction: vec3(transform.forward().as_vec3()),
            angular_diameter_deg: diameter.max(0.0).to_degrees(),
            color: linear(sun.color),
            intensity: sun.illuminance,
        });
        let label = label("DirectionalLight", entity, name);
        add(
            entity,
            render_entity,
            sun.shadow_maps_enabled,
            light,
            layers,
            label,
        );
    }
    for (entity, render_entity, spot, transform, size, layers, name) in &spots {
        let light = Light::Spot(Spot {
            position: vec3(transform.translation()),
            direction: vec3(transform.forward().as_vec3()),
            cone_angle_deg: spot.outer_angle.to_degrees().clamp(0.5, 89.0),
            radius: size.map_or(spot.radius, |s| s.0).max(0.0),
            color: linear(spot.color),
            intensity: spot.intensity,
            // Shadows' visibility is unitless: the units are Bevy's to shade. The range ends the
            // light's maps, as it ends Bevy's own: past it the light gives nothing.
            range: shadow_range(spot.range),
        });
        let label = label("SpotLight", entity, name);
        add(
            entity,
            render_entity,
            spot.shadow_maps_enabled,
            light,
            layers,
            label,
        );
    }
    for (entity, render_entity, point, transform, size, layers, name) in &points {
        let light = Light::Point(Point {
            position: vec3(transform.translation()),
            radius: size.map_or(point.radius, |s| s.0).max(0.0),
            color: linear(point.color),
            intensity: point.intensity,
            range: shadow_range(point.range),
        });
        let label = label("PointLight", entity, name);
        add(
            entity,
            render_entity,
            point.shadow_maps_enabled,
            light,
            layers,
            label,
        );
    }
    for (entity, render_entity, rect, transform, shadows, layers, name) in &rects {
        // Bevy's frame: the rectangle in the local xy plane, facing local -z; its sides scaled
        // by the transform as Bevy scales them.
        let affine = transform.affine();
        let (width, height) = (
            rect.width * affine.matrix3.x_axis.length(),
            rect.height * affine.matrix3.y_axis.length(),
        );
        let light = Light::Rect(Rect {
            position: vec3(transform.translation()),
            direction: vec3(transform.forward().as_vec3()),
            up: vec3(transform.up().as_vec3()),
            width,
            height,
            color: linear(rect.color),
            // Lumens over π times the area: the luminance (Bevy's own conversion).
            intensity: rect.intensity / (std::f32::consts::PI * width * height).max(1e-12),
            range: shadow_range(rect.range),
        });
        let label = label("RectLight", entity, name);
        add(entity, render_entity, shadows, light, layers, label);
    }
    // A stable order: the same lights keep the same layers while they live.
    lights.sort_by_key(|l| l.entity);
    extracted.lights_shadowed = lights.len();
    extracted.lights_over_limit = lights.len().saturating_sub(crate::MAX_SHADOWED_LIGHTS);
    lights.truncate(crate::MAX_SHADOWED_LIGHTS);
    extracted.lights = lights;
}

/// Bevy's shadow settings where they mean what penumbra's do
/// ([`PenumbraCamera::bevy_shadow_settings`]).
fn take_bevy_shadow_settings(
    settings: &mut penumbra::ShadowSettings,
    (directional, point): &(Res<DirectionalLightShadowMap>, Res<PointLightShadowMap>),
    suns: &SunQuery,
) {
    let sun = suns
        .iter()
        .filter(|(_, _, sun, ..)| sun.shadow_maps_enabled)
        .min_by_key(|(entity, ..)| *entity);
    let power_of_two = |size: usize| {
        let size = size.clamp(64, penumbra::settings::MAX_CASCADE_RESOLUTION as usize) as u32;
        1u32 << (31 - size.leading_zeros())
    };
    let sm = &mut settings.shadow_map;
    match sun {
        Some((_, _, light, _, _, _, cascades, _, _)) => {
            sm.resolution = power_of_two(directional.size);
            if let Some(cascades) = cascades {
                take_cascades(sm, cascades);
            }
            sm.normal_offset = light.shadow_normal_bias.clamp(0.0, 8.0);
        }
        None => sm.resolution = power_of_two(2 * point.size),
    }
}

/// A sun's `CascadeShadowConfig` as penumbra's: its maximum distance is the shadow distance
/// (the maps cover the view up to it, whatever the scene's extent: a 500,000-unit ground under
/// a small character), its first cascade's far bound the first cascade's end (the others split
/// the rest geometrically, as Bevy's do), its overlap the blend band, and its number of bounds
/// the number of cascades (at most penumbra's 4).
fn take_cascades(sm: &mut penumbra::ShadowMapSettings, config: &CascadeShadowConfig) {
    let count = (config.bounds.len() as u32).clamp(1, penumbra::MAX_CASCADES as u32);
    sm.cascades.count = count;
    if let Some(&last) = config.bounds.last()
        && last > 0.0
        && last.is_finite()
    {
        sm.fit = penumbra::LightFit::CameraFrustum { max_distance: last };
    }
    if count > 1
        && let Some(&first) = config.bounds.first()
        && first > 0.0
        && first.is_finite()
    {
        sm.cascades.first_end = first;
        sm.cascades.split = 1.0;
    }
    sm.cascades.blend = config.overlap_proportion.clamp(0.0, 0.5);
}

/// `rest` (`mesh`'s vertices, morphed) as `weights` morph it, as Bevy's morphing does: each
/// vertex plus each target's displacement of it times that target's weight (the targets laid
/// out one after another, each a displacement per vertex).
fn morphed(mut rest: Geometry, mesh: &Mesh, weights: &[f32]) -> Result<Geometry, String> {
    if weights.iter().all(|w| *w == 0.0) {
        return Ok(rest);
    }
    let targets = mesh
        .try_morph_targets()
        .map_err(|e| format!("its morph targets are not on the CPU ({e})"))?;
    let count = rest.positions.len();
    if count == 0 || targets.len() % count != 0 {
        return Err(format!(
            "its {} morph displacements are not a whole number of targets of {count} vertices",
            targets.len()
        ));
    }
    for (target, weight) in targets.chunks(count).zip(weights) {
        if *weight == 0.0 {
            continue;
        }
        for (v, d) in target.iter().enumerate() {
            rest.positions[v] += vec3(d.position) * *weight;
            if let Some(normals) = &mut rest.normals {
                normals[v] += vec3(d.normal) * *weight;
            }
        }
    }
    if let Some(normals) = &mut rest.normals {
        for n in normals {
            *n = n.normalize_or_zero();
        }
    }
    Ok(rest)
}

/// `rest` moved by `transform` into world space (a morphed mesh that is not skinned).
fn placed(mut rest: Geometry, transform: &Mat4) -> Geometry {
    let transform = crate::mat4(*transform);
    let normal_matrix = transform.inverse().transpose();
    for p in &mut rest.positions {
        *p = transform.transform_point3(*p);
    }
    if let Some(normals) = &mut rest.normals {
        for n in normals {
            *n = normal_matrix.transform_vector3(*n).normalize_or_zero();
        }
    }
    rest
}

/// `rest` (`mesh`'s vertices, morphed) posed by `skin`'s joints as Bevy's skinning does (each
/// vertex the weighted sum of its joints' `global x inverse bind pose` applied to it), in world
/// space.
fn posed(
    rest: Geometry,
    mesh: &Mesh,
    skin: &SkinnedMesh,
    (joints, bindposes): &(Query<&GlobalTransform>, Res<Assets<SkinnedMeshInverseBindposes>>),
) -> Result<Geometry, String> {
    let bindposes = bindposes
        .get(&skin.inverse_bindposes)
        .ok_or("its inverse bind poses are not loaded")?;
    let matrices: Vec<Mat4> = skin
        .joints
        .iter()
        .zip(bindposes.iter())
        .map(|(joint, inverse)| {
            joints
                .get(*joint)
                .map(|global| global.to_matrix() * *inverse)
                .map_err(|_| format!("its joint {joint} has no GlobalTransform"))
        })
        .collect::<Result<_, _>>()?;
    let indices = match mesh.try_attribute(Mesh::ATTRIBUTE_JOINT_INDEX) {
        Ok(VertexAttributeValues::Uint16x4(v)) => v.iter().map(|j| j.map(u32::from)).collect::<Vec<_>>(),
        _ => return Err("its joint indices are not Uint16x4 on the CPU".into()),
    };
    let weights = match mesh.try_attribute(Mesh::ATTRIBUTE_JOINT_WEIGHT) {
        Ok(VertexAttributeValues::Float32x4(v)) => v.clone(),
        _ => return Err("its joint weights are not Float32x4 on the CPU".into()),
    };
    if indices.len() != rest.positions.len() || weights.len() != rest.positions.len() {
        return Err("its joint attributes do not cover its vertices".into());
    }
    let skin_matrix = |v: usize| -> Result<Mat4, String> {
        let mut m = Mat4::ZERO;
        for k in 0..4 {
            let joint = matrices
                .get(indices[v][k] as usize)
                .ok_or_else(|| format!("vertex {v} names joint {} of {}", indices[v][k], matrices.len()))?;
            m += *joint * weights[v][k];
        }
        Ok(m)
    };
    let mut positions = Vec::with_capacity(rest.positions.len());
    let mut normals = rest.normals.as_ref().map(|n| Vec::with_capacity(n.len()));
    for (v, p) in rest.positions.iter().enumerate() {
        let m = skin_matrix(v)?;
        positions.push(vec3(m.transform_point3(Vec3::from_array(p.to_array()))));
        if let (Some(out), Some(rest_normals)) = (&mut normals, &rest.normals) {
            let n = m.transform_vector3(Vec3::from_array(rest_normals[v].to_array()));
            out.push(vec3(n.normalize_or_zero()));
        }
    }
    Ok(Geometry {
        positions,
        normals,
        indices: rest.indices,
    })
}

/// A spot, point or rectangle light's range for its maps' far plane: Bevy's, where it is a length (a
/// range of 0 or one not finite leaves the maps to the scene's extent).
fn shadow_range(range: f32) -> Option<f32> {
    (range > 0.0 && range.is_finite()).then_some(range)
}

/// A Bevy colour as penumbra's linear RGB.
fn linear(color: Color) -> glam::Vec3 {
    glam::Vec3::from_array(color.to_linear().to_f32_array_no_alpha())
}

/// A mesh's positions, normals and indices, or why penumbra cannot use it.
fn geometry(mesh: &Mesh) -> Result<Geometry, String> {
    if mesh.primitive_topology() != PrimitiveTopology::TriangleList {
        return Err(format!(
            "its topology is {:?}; penumbra casts triangle lists",
            mesh.primitive_topology()
        ));
    }
    let positions = match mesh.try_attribute(Mesh::ATTRIBUTE_POSITION) {
        Ok(VertexAttributeValues::Float32x3(p)) => p.iter().map(|p| glam::Vec3::from_array(*p)).collect(),
        Ok(_) => return Err("its positions are not Float32x3".to_string()),
        Err(e) => {
            return Err(format!(
                "its positions are not on the CPU ({e}); keep RenderAssetUsages::MAIN_WORLD on meshes that cast"
            ));
        }
    };
    let normals = match mesh.try_attribute(Mesh::ATTRIBUTE_NORMAL) {
        Ok(VertexAttributeValues::Float32x3(n)) => {
            Some(n.iter().map(|n| glam::Vec3::from_array(*n)).collect())
        }
        _ => None,
    };
    let indices = mesh.try_indices_option().ok().flatten().map(|ix| match ix {
        Indices::U16(v) => v.iter().map(|&i| i as u32).collect(),
        Indices::U32(v) => v.clone(),
    });
    Ok(Geometry {
        positions,
        normals,
        indices,
    })
}
