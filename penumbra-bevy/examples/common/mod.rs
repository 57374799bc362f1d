//! Shared by the examples and the tests: a Bevy app rendering headless into an image, read
//! back to the CPU.

#![allow(dead_code)]

pub mod tinted;

use std::sync::{Arc, Mutex};

use bevy::app::PluginsState;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::prelude::*;
use bevy::render::RenderPlugin;
use bevy::render::gpu_readback::{Readback, ReadbackComplete};
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::settings::{Backends, RenderCreation, WgpuSettings};
use bevy::window::ExitCondition;
use bevy::winit::WinitPlugin;
use penumbra_bevy::PenumbraLightSize;

/// Bevy's default plugins set up for this machine: Vulkan (Mesa's lavapipe where there is no
/// GPU) without wgpu's debug labels, which lavapipe crashes on; pipelines compiled at once.
pub fn default_plugins(window: bool) -> bevy::app::PluginGroupBuilder {
    let render = RenderPlugin {
        render_creation: RenderCreation::Automatic(Box::new(WgpuSettings {
            backends: Some(Backends::VULKAN),
            instance_flags: penumbra::instance_flags(),
            ..default()
        })),
        synchronous_pipeline_compilation: !window,
        ..default()
    };
    // Assets (a glTF scene in the tests) from the repository's `assets/`.
    let assets = bevy::asset::AssetPlugin {
        file_path: concat!(env!("CARGO_MANIFEST_DIR"), "/../assets").into(),
        ..default()
    };
    let plugins = DefaultPlugins.set(render).set(assets);
    if window {
        plugins
    } else {
        // Headless: extraction and rendering in each update, so a frame is done when it returns.
        plugins
            .disable::<bevy::render::pipelined_rendering::PipelinedRenderingPlugin>()
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                close_when_requested: false,
                ..default()
            })
            .disable::<WinitPlugin>()
    }
}

/// An example's command line: `--out FILE.png` (render headless into that file) and on/off
/// `switches`. Exits with a message naming the argument on anything else, or on `--out`
/// without a file name.
pub struct ExampleArgs {
    pub out: Option<String>,
    args: Vec<String>,
}

impl ExampleArgs {
    pub fn parse(example: &str, switches: &[&str]) -> Self {
        let fail = |message: String| -> ! {
            eprintln!("{example}: {message}");
            std::process::exit(2)
        };
        let args: Vec<String> = std::env::args().skip(1).collect();
        let out = args.iter().position(|a| a == "--out").map(|i| {
            args.get(i + 1)
                .cloned()
                .unwrap_or_else(|| fail(format!("--out needs a file name, e.g. --out {example}.png")))
        });
        if let Some(bad) = args
            .iter()
            .find(|a| a.starts_with("--") && *a != "--out" && !switches.contains(&a.as_str()))
        {
            fail(format!(
                "unknown argument `{bad}` (expected --out FILE.png{})",
                switches.iter().map(|s| format!(", {s}")).collect::<String>()
            ));
        }
        Self { out, args }
    }

    /// Whether switch `name` was given.
    pub fn has(&self, name: &str) -> bool {
        self.args.iter().any(|a| a == name)
    }
}

/// The last frame read back from the render target, as RGBA8 rows.
#[derive(Resource, Clone, Default)]
pub struct Captured(pub Arc<Mutex<Option<Vec<u8>>>>);

/// Another render target with a read-back of its own (a second camera's).
pub struct Target {
    pub image: Handle<Image>,
    pub size: UVec2,
    captured: Captured,
}

/// A target image of `size` that is read back every frame into `captured`.
fn readback_target(app: &mut App, size: UVec2) -> (Handle<Image>, Captured) {
    assert!(
        size.x.is_multiple_of(64),
        "rows are read back padded to 256 bytes: use a width that is a multiple of 64"
    );
    let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
    let captured = Captured::default();
    let sink = captured.clone();
    app.world_mut()
        .spawn(Readback::texture(target.clone()))
        .observe(move |event: On<ReadbackComplete>| {
            *sink.0.lock().unwrap() = Some(event.data.clone());
        });
    (target, captured)
}

/// A headless app: everything the caller adds renders through a camera into `target`.
pub struct Headless {
    pub app: App,
    pub target: Handle<Image>,
    pub size: UVec2,
    captured: Captured,
}

impl Headless {
    /// An app with the default plugins (no window) and `plugins`, ready to update.
    pub fn new(size: UVec2, add: impl FnOnce(&mut App)) -> Self {
        let mut app = App::new();
        app.add_plugins(default_plugins(false));
        add(&mut app);
        while app.plugins_state() == PluginsState::Adding {
            bevy::tasks::tick_global_task_pools_on_main_thread();
        }
        app.finish();
        app.cleanup();
        let (target, captured) = readback_target(&mut app, size);
        Self {
            app,
            target,
            size,
            captured,
        }
    }

    /// A camera rendering into the target from `eye` toward `at` (looking straight down, world
    /// +x is the image's right), without tone mapping and without MSAA.
    pub fn camera(&self, eye: Vec3, at: Vec3) -> impl Bundle {
        (
            Camera3d::default(),
            Camera::default(),
            bevy::camera::RenderTarget::Image(self.target.clone().into()),
            Tonemapping::None,
            Msaa::Off,
            Transform::from_translation(eye).looking_at(
                at,
                if (at - eye).normalize().y.abs() > 0.99 {
                    Vec3::NEG_Z
                } else {
                    Vec3::Y
                },
            ),
        )
    }

    /// Runs one update and waits until the GPU has finished its work.
    pub fn frame(&mut self) {
        self.app.update();
        let device = self
            .app
            .sub_app(bevy::render::RenderApp)
            .world()
            .resource::<bevy::render::renderer::RenderDevice>();
        let _ = device.wgpu_device().poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        });
    }

    /// Runs `frames` updates and returns the last frame read back.
    pub fn render(&mut self, frames: u32) -> image::RgbaImage {
        self.render_all(frames, &[]).0
    }

    /// Another target of `size`, for a camera of the caller's, read back by [`Headless::render_all`].
    pub fn add_target(&mut self, size: UVec2) -> Target {
        let (image, captured) = readback_target(&mut self.app, size);
        Target {
            image,
            size,
            captured,
        }
    }

    /// Runs `frames` updates and returns the last frame read back from the main target and
    /// from each of `others`.
    pub fn render_all(
        &mut self,
        frames: u32,
        others: &[&Target],
    ) -> (image::RgbaImage, Vec<image::RgbaImage>) {
        let all: Vec<(&Captured, UVec2)> = std::iter::once((&self.captured, self.size))
            .chain(others.iter().map(|t| (&t.captured, t.size)))
            .collect();
        for (captured, _) in &all {
            *captured.0.lock().unwrap() = None;
        }
        for _ in 0..frames {
            self.app.update();
        }
        // The read-backs arrive a frame or two later.
        for _ in 0..8 {
            if all.iter().all(|(c, _)| c.0.lock().unwrap().is_some()) {
                break;
            }
            self.app.update();
        }
        let mut images = all.iter().map(|(captured, size)| {
            let data = captured.0.lock().unwrap().take().expect("no frame was read back");
            image::RgbaImage::from_raw(size.x, size.y, data).expect("a frame of the target's size")
        });
        let main = images.next().expect("the main target");
        (main, images.collect())
    }
}

/// The box that moves.
#[derive(Component)]
pub struct Moving;

/// The examples' scene's floor.
#[derive(Component)]
pub struct Floor;

/// The examples' scene: a floor, a column, an arch, a sphere and a moving box under a sun
/// (3 degrees), a spot (radius 0.25) and a point light (radius 0.2).
pub fn spawn_scene(
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
        Floor,
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

/// Holds the [`Moving`] box at the pose it has at this time (seconds), for pictures of
/// several modes from one view.
#[derive(Resource, Clone, Copy)]
pub struct BoxPoseAt(pub f32);

/// Moves and turns the [`Moving`] box with time.
pub fn move_box(time: Res<Time>, at: Option<Res<BoxPoseAt>>, mut boxes: Query<&mut Transform, With<Moving>>) {
    let t = at.map_or(time.elapsed_secs(), |at| at.0);
    for mut transform in &mut boxes {
        transform.translation.x = 1.2 * (0.8 * t).sin();
        transform.rotation = Quat::from_rotation_y(0.5 * t);
    }
}
