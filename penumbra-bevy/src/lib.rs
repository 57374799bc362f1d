//! penumbra's soft shadows in a Bevy 0.20 app, on Bevy's own data.
//!
//! ```no_run
//! use bevy::prelude::*;
//! use penumbra_bevy::{PenumbraCamera, PenumbraPlugin};
//!
//! App::new()
//!     .add_plugins((DefaultPlugins, PenumbraPlugin))
//!     .add_systems(Startup, |mut commands: Commands| {
//!         commands.spawn((Camera3d::default(), PenumbraCamera::default()));
//!     })
//!     .run();
//! ```
//!
//! What the plugin does each frame:
//! - **Casters** are the app's `Mesh3d` entities, drawn from the vertex and index buffers Bevy's
//!   mesh allocator already holds, at their `GlobalTransform`s. `NotShadowCaster` and hidden
//!   entities cast no penumbra shadow; skinned and morphed meshes are posed on the CPU with their
//!   morph weights and joints each frame. A mesh casts for the lights it shares a `RenderLayers`
//!   layer with.
//! - **Lights** are the `DirectionalLight`s, `SpotLight`s and `PointLight`s with
//!   `shadow_maps_enabled`, and the `RectLight`s with [`RectLightShadows`] (Bevy gives them no
//!   shadows), up to [`MAX_SHADOWED_LIGHTS`] (256). Their size comes from Bevy's fields:
//!   `SpotLight::radius`, `PointLight::radius`, a sun's `SunDisk::angular_size` (or
//!   [`PenumbraLightSize`] to set it), a `RectLight`'s width and height. Bevy renders no shadow
//!   map for these lights; lights past the limit keep Bevy's own shadows.
//! - **The views**: penumbra's passes run on each penumbra camera's depth prepass, after
//!   Bevy's prepass and before its main pass, and write one visibility layer per light.
//! - **Shading**: each `StandardMaterial` mesh is switched to [`PenumbraMaterial`] (Bevy's
//!   PBR, with each penumbra light's direct term scaled by its visibility). Entities with
//!   [`KeepStandardMaterial`] are left alone; they then get no shadow from penumbra's lights.
//!
//! See `docs/bevy.md` in the repository for what is supported and what it costs.

mod depth_resolve;
mod extract;
mod material;
mod render;

use std::sync::{Arc, Mutex};

use bevy::asset::embedded_asset;
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::pbr::MaterialPlugin;
use bevy::prelude::*;
use bevy::render::RenderApp;

pub use material::{
    KeepStandardMaterial, MAX_SHADOWED_LIGHTS, PenumbraBindings, PenumbraMaterial, PenumbraMaterialPlugin,
    PenumbraShading, PenumbraTargets,
};
pub use penumbra::{Quality, ShadowMethod, ShadowSettings};

/// Adds penumbra's soft shadows to every camera with a [`PenumbraCamera`].
pub struct PenumbraPlugin;

/// Turns penumbra on for a 3D camera, with or without MSAA (with it, penumbra reads the
/// nearest sample of each pixel of the depth prepass), forward or deferred (penumbra's
/// materials draw in the forward pass either way). Several cameras may have one (split
/// screen with `Camera::viewport`, a view rendered to a texture beside the window's): each gets
/// shadows of its own, fitted to its view and drawn before its main pass. A 3D camera without
/// one sees penumbra's lights unshadowed (a warning names it).
#[derive(Component, Clone, Debug)]
#[require(DepthPrepass)]
pub struct PenumbraCamera {
    /// penumbra's method, quality and map settings.
    pub settings: ShadowSettings,
    /// False: Bevy's own shadow maps and filtering for every light, as without the plugin.
    pub enabled: bool,
    /// True (the default): Bevy's shadow settings replace these where they mean the same:
    /// `DirectionalLightShadowMap::size` the map resolution (with no sun shaded, twice
    /// `PointLightShadowMap::size`: penumbra's cube faces are half its resolution); the first
    /// shaded sun's `CascadeShadowConfig`: its number of bounds the number of cascades (at most
    /// 4), its maximum distance the shadow distance (the maps cover the view up to it, whatever
    /// the scene's extent: a 500,000-unit ground under a small character keeps its shadow),
    /// its first cascade's far bound the first cascade's end (the others split the rest
    /// geometrically, as Bevy's) and its overlap the blend band; and its `shadow_normal_bias`
    /// the normal offset (texels of the map in both). Bevy's depth biases are not taken (world
    /// units along the light; penumbra's are in units of the depth format), nor spot and point
    /// lights' normal biases (penumbra has one normal offset for every light). Off, penumbra's
    /// own settings fit a sun's maps up to Bevy's infinite far plane, that is to the farthest
    /// corner of the scene: over a huge ground a message names the sun whose map loses a
    /// caster's shadow.
    pub bevy_shadow_settings: bool,
}

impl Default for PenumbraCamera {
    /// penumbra's own method (distance-map PCF and blur) at medium quality.
    fn default() -> Self {
        Self::new(ShadowMethod::Ours, Quality::Medium)
    }
}

impl PenumbraCamera {
    /// One of penumbra's methods at one of its quality presets.
    pub fn new(method: ShadowMethod, quality: Quality) -> Self {
        Self {
            settings: ShadowSettings::preset(method, quality),
            enabled: true,
            bevy_shadow_settings: true,
        }
    }
}

/// A light's physical size for penumbra, overriding what Bevy's fields say: for a
/// `DirectionalLight`, the angular diameter of the sun's disk in radians (otherwise its
/// `SunDisk::angular_size`, otherwise the sun's 0.0093); for a `SpotLight` or `PointLight`, the
/// radius of its emitting disk or sphere in world units (otherwise its `radius`). 0 gives hard
/// shadows.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct PenumbraLightSize(pub f32);

/// Casts penumbra's soft shadows from a `RectLight`, which Bevy 0.20 shades (with its
/// `area_light_luts` feature) but gives no shadow and no shadow switch: put this beside it. Its
/// penumbrae are as wide along each of the rectangle's sides as that side is long.
///
/// Bevy shades rectangle lights from its clustered lights, which need storage buffers: where
/// there are none (WebGL2) the light is not shadowed, and a warning says so.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq)]
pub struct RectLightShadows;

impl Plugin for PenumbraPlugin {
    fn build(&self, app: &mut App) {
        // The shadows' WESL module, which `PenumbraMaterial` and an app's own materials import.
        bevy::shader::load_shader_library!(app, "shaders/shadows.wesl");
        embedded_asset!(app, "shaders/penumbra_material.wesl");
        let diagnostics = PenumbraDiagnostics::default();
        app.insert_resource(diagnostics.clone());
        app.add_plugins(MaterialPlugin::<PenumbraMaterial>::default())
            .init_resource::<material::PenumbraTargets>()
            .add_systems(
                PostUpdate,
                (material::convert_standard_materials, material::fit_targets).chain(),
            );
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render::build(render_app, diagnostics);
        }
    }

    fn finish(&self, app: &mut App) {
        if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
            render::finish(render_app);
        }
    }
}

/// The errors and warnings the plugin logged (each once), for an app or a test to show or
/// check: a camera penumbra cannot run on, a mesh it cannot cast, lights past its limit.
#[derive(Resource, Clone, Default, Debug)]
pub struct PenumbraDiagnostics(Arc<Mutex<Vec<String>>>, Arc<Mutex<Option<ShadowSettings>>>);

impl PenumbraDiagnostics {
    /// The settings penumbra's passes ran with last: the camera's, with Bevy's shadow settings
    /// taken in ([`PenumbraCamera::bevy_shadow_settings`]).
    pub fn settings(&self) -> Option<ShadowSettings> {
        self.1.lock().ok().and_then(|s| *s)
    }

    pub(crate) fn set_settings(&self, settings: ShadowSettings) {
        if let Ok(mut s) = self.1.lock() {
            *s = Some(settings);
        }
    }

    /// Every message so far, oldest first.
    pub fn messages(&self) -> Vec<String> {
        self.0.lock().map(|m| m.clone()).unwrap_or_default()
    }

    /// Adds a message; false if it was already there.
    pub(crate) fn push(&self, message: String) -> bool {
        let Ok(mut messages) = self.0.lock() else {
            return false;
        };
        if messages.contains(&message) {
            return false;
        }
        messages.push(message);
        true
    }
}

/// glam 0.33 (Bevy's) to glam 0.34 (penumbra's).
pub(crate) fn mat4(m: Mat4) -> glam::Mat4 {
    glam::Mat4::from_cols_array(&m.to_cols_array())
}

pub(crate) fn vec3(v: Vec3) -> glam::Vec3 {
    glam::Vec3::from_array(v.to_array())
}
