//! # penumbra
//!
//! Real-time soft shadows as wgpu render passes, built to be embedded: penumbra works on an
//! engine's own depth buffer, camera matrices and vertex buffers, hands back one visibility per
//! light for the engine's lit shader, and never owns a window or an event loop.
//!
//! ## Two ways in
//!
//! **An engine** keeps its own renderer and asks penumbra for shadows only (no feature needed;
//! `default-features = false` builds on wgpu, glam, bytemuck and thiserror alone):
//!
//! 1. [`Casters`] registers meshes from the engine's vertex and index buffers
//!    ([`CasterMeshDesc`]) and places instances of them ([`CasterInstance`]); moving one is a
//!    [`Casters::set_transform`].
//! 2. [`Shadows`] holds the lights ([`Shadows::add_light`]; as many as the device's texture
//!    arrays have layers, [`Shadows::max_lights`]), each given a layer of one texture array.
//! 3. Each frame, after its depth prepass, the engine hands over its camera
//!    ([`CameraMatrices`]) and depth ([`ViewInputs`]); [`Shadows::render`] records every
//!    light's passes into the engine's encoder.
//! 4. The engine's lit shader samples [`Shadows::visibility`] (format
//!    [`VISIBILITY_FORMAT`], layer [`LightId::layer`]) and multiplies each light's direct term
//!    by it.
//!
//! ```no_run
//! # fn main() -> penumbra::Result<()> {
//! # let gpu = penumbra::HeadlessGpu::new()?;
//! # let (device, queue) = (&gpu.device, &gpu.queue);
//! # let vertices: wgpu::Buffer = unimplemented!();
//! # let depth: wgpu::Texture = unimplemented!();
//! # let (view, projection) = (glam::Mat4::IDENTITY, glam::Mat4::IDENTITY);
//! // Once: the engine's mesh (positions at offset 0 of a 24-byte vertex) and an instance.
//! let mut casters = penumbra::Casters::new(device);
//! let positions = penumbra::VertexStream::new(&vertices, 0, 24, wgpu::VertexFormat::Float32x3);
//! let mesh = casters.add_mesh(device, queue, &penumbra::CasterMeshDesc::new("crate", positions, 36))?;
//! let instance = casters.add_instance(device, queue, penumbra::CasterInstance::new(mesh, glam::Mat4::IDENTITY))?;
//!
//! let mut shadows = penumbra::Shadows::new(device, penumbra::ShadowSettings::default())?;
//! let sun = shadows.add_light(device, penumbra::Light::Directional(penumbra::DirectionalLight {
//!     direction: glam::Vec3::new(-0.3, -1.0, -0.2),
//!     angular_diameter_deg: 2.0,
//!     color: glam::Vec3::ONE,
//!     intensity: 1.0,
//! }))?;
//!
//! // Every frame, after the engine's depth prepass into `depth`:
//! casters.set_transform(queue, instance, glam::Mat4::from_translation(glam::Vec3::Y))?;
//! let camera = penumbra::CameraMatrices { view, projection, depth: penumbra::DepthConvention::Standard };
//! let mut encoder = device.create_command_encoder(&Default::default());
//! shadows.render(device, queue, &mut encoder, &casters, &penumbra::ViewInputs::new(camera, &depth))?;
//! queue.submit([encoder.finish()]);
//! // The lit shader reads layer `sun.layer()` of this view.
//! let visibility: &wgpu::TextureView = shadows.visibility().expect("made by the first frame");
//! # let _ = (sun, visibility); Ok(()) }
//! ```
//!
//! `examples/engine.rs` in the repository is a whole engine written this way, and
//! `penumbra-bevy` a plugin that does it on Bevy's own data.
//!
//! **A whole frame** (feature `renderer`, on by default): [`Renderer`] draws a lit frame of a
//! [`GpuScene`] on top of [`Shadows`], with its own depth prepass and composite; the scene
//! model ([`Scene`]) comes with loaders for OBJ and glTF 2.0 ([`load_model`]) and a RON scene
//! format ([`SceneFile`], [`load_scene`]). It also renders the ground truth
//! ([`Renderer::render_reference`]) and gives every intermediate texture for inspection
//! ([`Renderer::debug_texture`], [`debug`]).
//!
//! ```no_run
//! # fn main() -> penumbra::Result<()> {
//! let gpu = penumbra::HeadlessGpu::new()?;
//! let scene = penumbra::load_scene(std::path::Path::new("assets/scenes/teapot.ron"))?;
//! let format = wgpu::TextureFormat::Rgba8UnormSrgb;
//! let mut renderer = penumbra::Renderer::new(&gpu.device, format, penumbra::ShadowSettings::default())?;
//! let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
//! let image = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &scene.view(0)?, 640, 480)?;
//! image.save("teapot.png").expect("writable");
//! # Ok(()) }
//! ```
//!
//! ## Methods and settings
//!
//! [`ShadowSettings`] chooses the method and its parameters; [`ShadowSettings::default`] is
//! the distance-map method in physical mode, where only each light's size is set and the
//! filter widths follow from it.
//!
//! * [`ShadowMethod::Ours`]: the distance-map method. A depth shadow map, a fattened shadow
//!   map, a screen-space distance map over the camera depth, PCF whose spacing grows with the
//!   receiver-to-occluder distance, a distance-driven separable blur and indirect-light
//!   attenuation. Each method's chain of passes is written once ([`Chain`]).
//! * Beside it, for comparison: the PCF + Gaussian baseline ([`ShadowMethod::Traditional`]),
//!   PCSS, hard shadows and hardware 2x2 PCF, and the ground truth
//!   ([`ShadowMethod::Reference`], many hard shadow maps averaged).
//!
//! ## Errors
//!
//! Every fallible call returns a [`PenumbraError`] that names the setting, file or argument at
//! fault and why; penumbra does not panic on input a user can influence.

// Without the convenience layer (feature `renderer`) some crate-private helpers it shares with
// the core go unused.
#![cfg_attr(not(feature = "renderer"), allow(dead_code))]
#![warn(missing_docs)]

mod bounds;
mod camera;
pub mod casters;
mod chain;
pub mod device;
pub mod error;
mod frame;
mod gpu_helpers;
mod layouts;
mod light_maps;
pub mod light_samples;
pub mod light_space;
mod lights;
pub mod map_resolution;
mod pipeline_cache;
pub mod scene;
mod screen;
pub mod settings;
pub mod shaders;
pub mod shadows;
pub mod timing;
pub mod view;

// The convenience layer: the renderer, its scene on the GPU, the ground truth, the loaders and
// the tools around them (`src/renderer/`, `src/scene/loaders/`, `src/scene/file.rs`).
#[cfg(feature = "renderer")]
mod renderer;
#[cfg(feature = "renderer")]
pub use renderer::{
    debug, gpu,
    gpu::{
        HeadlessGpu, read_texture_bytes, read_texture_f32, read_texture_layer_bytes, read_texture_layer_f32,
        read_texture_rgba8,
    },
    gpu_scene::GpuScene,
    ground_truth::ReferenceProgress,
    metrics,
    render::{
        FrameReport, PassPlan, Renderer, WARMUP_MIN_MS, render_to_image, render_to_image_with_progress,
    },
};
#[cfg(feature = "renderer")]
pub use scene::{SceneFile, file::load_scene, loaders, loaders::load_model};

pub use bounds::Aabb;
pub use camera::Camera;
pub use casters::{
    ALL_LAYERS, AlphaMask, CasterInstance, CasterMeshDesc, Casters, IndexStream, InstanceId, MeshGeometry,
    MeshId, VertexStream,
};
pub use device::{DeviceLoss, device_descriptor, instance_flags};
pub use error::{PenumbraError, Result};
pub use frame::DerivedSpreads;
pub use layouts::SceneLayouts;
pub use light_space::{Cascade, LightView, MAX_CASCADES, UnheldCaster};
pub use lights::{
    AreaLight, AreaShape, DirectionalLight, DiskLight, Exposure, Light, MAX_LIGHTS, PointLight, RectLight,
    SpotLight,
};
pub use map_resolution::PenumbraWidths;
pub use scene::{
    AlphaMode, Instance, LightingMode, LightmapFilter, LightmapImage, LightmapRect, Lightmaps, Material,
    Mesh, Model, OrbitCamera, Scene, Shading, TextureImage, Viewpoint,
};
pub use screen::VISIBILITY_FORMAT;
pub use settings::{
    CascadeSettings, CullMode, DepthFormat, DevicePath, ExecutionSettings, ExitFaces, ExitMapDraw, Fattening,
    LightFit, MapResolution, PcfKernel, PcssSettings, PenumbraSettings, Quality, ShadowMapSettings,
    ShadowMethod, ShadowSettings, SpreadMode, TileClassification, TilePixels, TraditionalSettings,
};
pub use shadows::{Chain, LightId, LightReport, LightTexture, Shadows, ViewInputs};
pub use view::{CameraMatrices, DepthConvention};

/// The README's Rust code, compiled by `cargo test --doc` so that the front page's embedding
/// glue stays true to the API.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
