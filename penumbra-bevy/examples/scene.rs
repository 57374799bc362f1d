//! A small scene with penumbra's soft shadows in Bevy: a sun, a spot and a point light over a
//! floor, a column, an arch and a box that moves.
//!
//! ```sh
//! cargo +nightly run --release -p penumbra-bevy --example scene --ignore-rust-version
//! cargo +nightly run --release -p penumbra-bevy --example scene --ignore-rust-version -- --out scene.png
//! ```
//!
//! In the window, Space switches between penumbra's shadows and Bevy's own (its
//! `ShadowFilteringMethod::Gaussian` filtering of its shadow maps). `--out FILE.png` renders
//! headless (no window) after a few frames, writes the frame and exits; add `--bevy` for Bevy's
//! own shadows.

mod common;

use common::{move_box, spawn_scene};

use bevy::light::ShadowFilteringMethod;
use bevy::prelude::*;
use penumbra_bevy::{PenumbraCamera, PenumbraPlugin};

fn main() {
    let args = common::ExampleArgs::parse("scene", &["--bevy"]);
    let bevy_shadows = args.has("--bevy");
    match args.out {
        Some(path) => headless(&path, !bevy_shadows),
        None => {
            App::new()
                .add_plugins((common::default_plugins(true), PenumbraPlugin))
                .add_systems(Startup, (spawn_scene, spawn_window_camera))
                .add_systems(Update, (move_box, toggle))
                .run();
        }
    }
}

fn fail(message: &str) -> ! {
    eprintln!("scene: {message}");
    std::process::exit(2)
}

fn headless(path: &str, penumbra: bool) {
    let mut headless = common::Headless::new(UVec2::new(960, 640), |app| {
        app.add_plugins(PenumbraPlugin).add_systems(Update, move_box);
    });
    let camera = headless.camera(Vec3::new(-6.0, 7.0, 9.0), Vec3::new(0.0, 0.5, 0.0));
    let world = headless.app.world_mut();
    world.run_system_cached(spawn_scene).expect("the scene spawns");
    world.spawn((
        camera,
        PenumbraCamera {
            enabled: penumbra,
            ..default()
        },
        ShadowFilteringMethod::Gaussian,
    ));
    let frame = headless.render(16);
    if let Err(e) = frame.save(path) {
        fail(&format!("cannot write {path}: {e}"));
    }
    println!("wrote {path}");
}

fn spawn_window_camera(mut commands: Commands) {
    commands.spawn((
        Camera3d::default(),
        PenumbraCamera::default(),
        ShadowFilteringMethod::Gaussian,
        Transform::from_xyz(-6.0, 7.0, 9.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
}

/// Space: penumbra's shadows or Bevy's own.
fn toggle(keys: Res<ButtonInput<KeyCode>>, mut cameras: Query<&mut PenumbraCamera>) {
    if keys.just_pressed(KeyCode::Space) {
        for mut camera in &mut cameras {
            camera.enabled = !camera.enabled;
            info!(
                "shadows: {}",
                if camera.enabled {
                    "penumbra"
                } else {
                    "Bevy's own (Gaussian)"
                }
            );
        }
    }
}
