//! A material of the app's own with penumbra's shadows: the examples' scene with its floor in
//! `Tinted` (`common/tinted.rs` and `common/tinted.wesl`), an `ExtendedMaterial` whose WESL
//! shader imports `penumbra_bevy::shaders::shadows`. The floor is lit by Bevy's PBR with
//! penumbra's shadows (`apply_shadows`), or, with `--unlit`, unlit and darkened by the sun's
//! visibility alone (`directional_visibility`).
//!
//! ```sh
//! cargo +nightly run --release -p penumbra-bevy --example custom_material --ignore-rust-version
//! cargo +nightly run --release -p penumbra-bevy --example custom_material --ignore-rust-version -- --unlit --out floor.png
//! ```

mod common;

use bevy::pbr::ExtendedMaterial;
use bevy::prelude::*;
use common::tinted::{Tint, Tinted, TintedPlugin};
use common::{Floor, move_box, spawn_scene};
use penumbra_bevy::{PenumbraCamera, PenumbraPlugin};

/// The floor's look.
#[derive(Resource, Clone, Copy)]
struct Unlit(bool);

fn main() {
    let args = common::ExampleArgs::parse("custom_material", &["--unlit"]);
    let unlit = Unlit(args.has("--unlit"));
    match args.out {
        Some(path) => {
            let mut headless = common::Headless::new(UVec2::new(960, 640), |app| {
                app.add_plugins((PenumbraPlugin, TintedPlugin))
                    .add_systems(Update, move_box);
            });
            let camera = headless.camera(Vec3::new(-6.0, 7.0, 9.0), Vec3::new(0.0, 0.5, 0.0));
            let world = headless.app.world_mut();
            world.insert_resource(unlit);
            world.run_system_cached(spawn_scene).expect("the scene spawns");
            world
                .run_system_cached(tinted_floor)
                .expect("the floor is tinted");
            world.spawn((camera, PenumbraCamera::default()));
            let frame = headless.render(16);
            if let Err(e) = frame.save(&path) {
                fail(&format!("cannot write {path}: {e}"));
            }
            println!("wrote {path}");
        }
        None => {
            App::new()
                .add_plugins((common::default_plugins(true), PenumbraPlugin, TintedPlugin))
                .insert_resource(unlit)
                .add_systems(Startup, (spawn_scene, tinted_floor, spawn_camera).chain())
                .add_systems(Update, move_box)
                .run();
        }
    }
}

fn fail(message: &str) -> ! {
    eprintln!("custom_material: {message}");
    std::process::exit(2)
}

/// The floor switched to a bluish `Tinted` made from its `StandardMaterial`.
fn tinted_floor(
    mut commands: Commands,
    floor: Query<(Entity, &MeshMaterial3d<StandardMaterial>), With<Floor>>,
    standard: Res<Assets<StandardMaterial>>,
    mut tinted: ResMut<Assets<Tinted>>,
    unlit: Res<Unlit>,
) {
    for (floor, material) in &floor {
        let base = standard.get(&material.0).cloned().unwrap_or_default();
        let handle = tinted.add(ExtendedMaterial {
            base,
            extension: Tint::new(Vec3::new(0.75, 0.85, 1.0), unlit.0),
        });
        commands
            .entity(floor)
            .remove::<MeshMaterial3d<StandardMaterial>>()
            .insert(MeshMaterial3d(handle));
    }
}

fn spawn_camera(mut commands: Commands) {
    commands.spawn((
        Camera3d::default(),
        PenumbraCamera::default(),
        Transform::from_xyz(-6.0, 7.0, 9.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
}
