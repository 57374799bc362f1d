//! `Tinted`: a material of the app's own (an `ExtendedMaterial` of Bevy's `StandardMaterial`)
//! whose shader reads penumbra's shadows, for the `custom_material` example and the tests.

use bevy::pbr::{ExtendedMaterial, MaterialExtension, MaterialPlugin};
use bevy::prelude::*;
use bevy::render::render_resource::AsBindGroup;
use bevy::render::storage::ShaderBuffer;
use bevy::shader::{Shader, ShaderRef};
use penumbra_bevy::{PenumbraBindings, PenumbraMaterialPlugin};

/// `StandardMaterial` tinted, shaded lit (with penumbra's shadows) or unlit (darkened in the
/// first sun's penumbra shadow).
pub type Tinted = ExtendedMaterial<StandardMaterial, Tint>;

/// The extension: penumbra's two bindings and the material's own uniform.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
pub struct Tint {
    #[texture(100, dimension = "2d_array", sample_type = "float", filterable = false)]
    visibility: Handle<Image>,
    #[storage(101, read_only)]
    lights: Handle<ShaderBuffer>,
    /// rgb: the tint; w: 1 for the unlit look.
    #[uniform(102)]
    pub tint: Vec4,
}

impl Tint {
    /// `color` (linear), lit or unlit.
    pub fn new(color: Vec3, unlit: bool) -> Self {
        Self {
            tint: color.extend(if unlit { 1.0 } else { 0.0 }),
            ..default()
        }
    }
}

impl PenumbraBindings for Tint {
    fn penumbra_visibility(&self) -> &Handle<Image> {
        &self.visibility
    }

    fn set_penumbra_bindings(&mut self, visibility: Handle<Image>, lights: Handle<ShaderBuffer>) {
        self.visibility = visibility;
        self.lights = lights;
    }
}

const SHADER: Handle<Shader> = bevy::asset::uuid_handle!("5b0f6f8e-2a43-4d52-9a57-3f1e7c2d9b10");

impl MaterialExtension for Tint {
    fn fragment_shader() -> ShaderRef {
        SHADER.into()
    }
}

/// The material, its shader and penumbra's bindings kept on it: what an app adds for a
/// material of its own (beside `PenumbraPlugin`).
pub struct TintedPlugin;

impl Plugin for TintedPlugin {
    fn build(&self, app: &mut App) {
        app.world_mut()
            .resource_mut::<Assets<Shader>>()
            .insert(
                &SHADER,
                Shader::from_wesl(include_str!("tinted.wesl"), "tinted.wesl"),
            )
            .expect("a handle of its own");
        app.add_plugins((
            MaterialPlugin::<Tinted>::default(),
            PenumbraMaterialPlugin::<Tinted>::default(),
        ));
    }
}
