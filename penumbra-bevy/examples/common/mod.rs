//! Shared by the examples and the tests: a Bevy app rendering headless into an image, read
//! back to the CPU.

#![allow(dead_code)]

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
    let plugins = DefaultPlugins.set(render);
    if window {
        plugins
    } else {
        plugins
            .set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                close_when_requested: false,
                ..default()
            })
            .disable::<WinitPlugin>()
    }
}

/// The last frame read back from the render target, as RGBA8 rows.
#[derive(Resource, Clone, Default)]
pub struct Captured(pub Arc<Mutex<Option<Vec<u8>>>>);

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
        assert!(
            size.x % 64 == 0,
            "rows are read back padded to 256 bytes: use a width that is a multiple of 64"
        );
        let mut app = App::new();
        app.add_plugins(default_plugins(false));
        add(&mut app);
        while app.plugins_state() == PluginsState::Adding {
            bevy::tasks::tick_global_task_pools_on_main_thread();
        }
        app.finish();
        app.cleanup();
        let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::Rgba8UnormSrgb, None);
        image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        let target = app.world_mut().resource_mut::<Assets<Image>>().add(image);
        let captured = Captured::default();
        let sink = captured.clone();
        app.world_mut().spawn(Readback::texture(target.clone())).observe(
            move |event: On<ReadbackComplete>| {
                *sink.0.lock().unwrap() = Some(event.data.clone());
            },
        );
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

    /// Runs `frames` updates and returns the last frame read back.
    pub fn render(&mut self, frames: u32) -> image::RgbaImage {
        *self.captured.0.lock().unwrap() = None;
        for _ in 0..frames {
            self.app.update();
        }
        // The read-back arrives a frame or two later.
        for _ in 0..8 {
            if self.captured.0.lock().unwrap().is_some() {
                break;
            }
            self.app.update();
        }
        let data = self
            .captured
            .0
            .lock()
            .unwrap()
            .take()
            .expect("no frame was read back");
        image::RgbaImage::from_raw(self.size.x, self.size.y, data).expect("a frame of the target's size")
    }
}
