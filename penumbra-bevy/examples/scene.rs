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

use bevy::light::ShadowFilteringMethod;
use bevy::prelude::*;
use penumbra_bevy::{PenumbraCamera, PenumbraLightSize, PenumbraPlugin};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args.iter().position(|a| a == "--out").map(|i| {
        args.get(i + 1)
            .cloned()
            .unwrap_or_else(|| fail("--out needs a file name, e.g. --out scene.png"))
    });
    let bevy_shadows = args.iter().any(|a| a == "--bevy");
    if let Some(bad) = args
        .iter()
        .find(|a| a.starts_with("--") && !["--out", "--bevy"].contains(&a.as_str()))
    {
        fail(&format!(
            "unknown argument `{bad}` (expected --out FILE.png, --bevy)"
        ));
    }
    match out {
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

/// The box that moves.
#[derive(Component)]
struct Moving;

fn spawn_scene(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    let matte = |color: Color| StandardMaterial {
        base_color: color,
        perceptual_roughness: 0.9,
        ..default()
    };
    commands.insert_resource(GlobalAmbientLight {
        brightness: 120.0,
        ..default()
    });
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(20.0, 20.0))),
        MeshMaterial3d(materials.add(matte(Color::srgb(0.75, 0.74, 0.70)))),
    ));
    commands.spawn((
        Mesh3d(meshes.add(Cylinder::new(0.35, 3.0))),
        MeshMaterial3d(materials.add(matte(Color::srgb(0.55, 0.6, 0.75)))),
        Transform::from_xyz(-1.5, 1.5, -1.0),
    ));
    let stone = materials.add(matte(Color::srgb(0.8, 0.55, 0.4)));
    let pillar = meshes.add(Cuboid::new(0.4, 2.0, 0.4));
    for x in [1.0, 2.6] {
        commands.spawn((
            Mesh3d(pillar.clone()),
            MeshMaterial3d(stone.clone()),
            Transform::from_xyz(x, 1.0, 1.0),
        ));
    }
    commands.spawn((
        Mesh3d(meshes.add(Cuboid::new(2.2, 0.3, 0.5))),
        MeshMaterial3d(stone),
        Transform::from_xyz(1.8, 2.15, 1.0),
    ));
    commands.spawn((
        Mesh3d(meshes.add(Sphere::new(0.5).mesh().uv(32, 18))),
        MeshMaterial3d(materials.add(matte(Color::srgb(0.3, 0.7, 0.4)))),
        Transform::from_xyz(0.0, 0.5, 2.8),
    ));
    commands.spawn((
        Mesh3d(meshes.add(Cuboid::new(0.8, 0.8, 0.8))),
        MeshMaterial3d(materials.add(matte(Color::srgb(0.85, 0.2, 0.2)))),
        Transform::from_xyz(0.0, 1.6, -0.2),
        Moving,
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 3000.0,
            shadow_maps_enabled: true,
            ..default()
        },
        // A sun six times the real one's size, for soft shadows that read in a small window.
        PenumbraLightSize(3.0_f32.to_radians()),
        Transform::default().looking_to(Vec3::new(0.5, -1.0, -0.35), Vec3::Y),
    ));
    commands.spawn((
        SpotLight {
            intensity: 1_200_000.0,
            radius: 0.25,
            range: 30.0,
            outer_angle: 0.6,
            inner_angle: 0.45,
            shadow_maps_enabled: true,
            color: Color::srgb(1.0, 0.85, 0.6),
            ..default()
        },
        Transform::from_xyz(-4.0, 5.0, 3.0).looking_at(Vec3::new(0.0, 0.0, 0.5), Vec3::Y),
    ));
    commands.spawn((
        PointLight {
            intensity: 600_000.0,
            radius: 0.2,
            range: 20.0,
            shadow_maps_enabled: true,
            color: Color::srgb(0.6, 0.75, 1.0),
            ..default()
        },
        Transform::from_xyz(3.5, 3.2, -2.0),
    ));
}

fn spawn_window_camera(mut commands: Commands) {
    commands.spawn((
        Camera3d::default(),
        Msaa::Off,
        PenumbraCamera::default(),
        ShadowFilteringMethod::Gaussian,
        Transform::from_xyz(-6.0, 7.0, 9.0).looking_at(Vec3::new(0.0, 0.5, 0.0), Vec3::Y),
    ));
}

fn move_box(time: Res<Time>, mut boxes: Query<&mut Transform, With<Moving>>) {
    let t = time.elapsed_secs();
    for mut transform in &mut boxes {
        transform.translation.x = 1.2 * (0.8 * t).sin();
        transform.rotation = Quat::from_rotation_y(0.5 * t);
    }
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
