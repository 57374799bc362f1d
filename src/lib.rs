//! # penumbra
//!
//! Real-time soft shadows as wgpu render passes, built to be embedded: penumbra works on an
//! engine's own depth buffer, camera matrices and vertex buffers, hands back one visibility per
//! light for the engine's lit shader, and never owns a window or an event loop.
//!
//! * **Embedding** (no feature needed): [`Casters`] registers meshes from the engine's buffers
//!   and places instances; [`Shadows`] takes up to [`MAX_LIGHTS`] lights and, each frame, the
//!   engine's [`CameraMatrices`] and depth ([`ViewInputs`]), and writes each light's
//!   visibility into a layer of [`Shadows::visibility`]. `examples/engine.rs` is a worked engine.
//! * [`ShadowMethod::Ours`]: the distance-map method. A depth shadow map, a fattened shadow
//!   map, a full-screen distance map over the camera depth, PCF whose spacing grows with the
//!   receiver-to-occluder distance, a distance-driven separable blur and indirect-light
//!   attenuation; each method's chain of passes is written once in [`Chain::new`].
//! * Beside it: the PCF + Gaussian baseline ([`ShadowMethod::Traditional`]), PCSS, hard shadows
//!   and hardware 2x2 PCF, configured by [`ShadowSettings`] (physical mode by default: only the
//!   light's size is set).
//! * The convenience layer (feature `renderer`, on by default): [`Renderer`] draws a whole lit
//!   frame of a [`GpuScene`] on top of [`Shadows`]; the scene model ([`Scene`]) with loaders
//!   for OBJ and glTF 2.0 ([`load_model`]) and a RON scene format ([`SceneFile`],
//!   [`load_scene`]); the ground truth; debug access to every intermediate texture
//!   ([`Renderer::debug_texture`], [`debug`]).
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

// Without the convenience layer (feature `renderer`) some crate-private helpers it shares with
// the core go unused.
#![cfg_attr(not(feature = "renderer"), allow(dead_code))]

pub mod casters;
mod chain;
#[cfg(feature = "renderer")]
pub mod debug;
pub mod device;
pub mod error;
mod frame;
#[cfg(feature = "renderer")]
pub mod gpu;
mod gpu_helpers;
#[cfg(feature = "renderer")]
mod gpu_scene;
#[cfg(feature = "renderer")]
mod ground_truth;
mod layouts;
pub mod light_samples;
pub mod light_space;
#[cfg(feature = "renderer")]
pub use scene::loaders;
#[cfg(feature = "renderer")]
pub mod metrics;
pub(crate) mod passes;
#[cfg(feature = "renderer")]
mod renderer;
pub mod scene;
pub mod settings;
pub mod shaders;
pub mod shadows;
pub mod timing;
pub mod view;

pub use casters::{
    AlphaMask, CasterInstance, CasterMeshDesc, Casters, IndexStream, InstanceId, MeshGeometry, MeshId,
    VertexStream,
};
pub use device::{device_descriptor, instance_flags};
pub use error::{PenumbraError, Result};
pub use frame::DerivedSpreads;
#[cfg(feature = "renderer")]
pub use gpu::{HeadlessGpu, read_texture_bytes, read_texture_f32, read_texture_rgba8};
#[cfg(feature = "renderer")]
pub use gpu_scene::GpuScene;
#[cfg(feature = "renderer")]
pub use ground_truth::ReferenceProgress;
pub use layouts::SceneLayouts;
pub use light_space::{Cascade, LightView, MAX_CASCADES};
#[cfg(feature = "renderer")]
pub use loaders::load_model;
pub use passes::VISIBILITY_FORMAT;
#[cfg(feature = "renderer")]
pub use renderer::{
    DebugTexture, FrameReport, PassPlan, Renderer, render_to_image, render_to_image_with_progress,
};
#[cfg(feature = "renderer")]
pub use scene::SceneFile;
#[cfg(feature = "renderer")]
pub use scene::file::load_scene;
pub use scene::{
    Aabb, AlphaMode, Camera, DirectionalLight, Exposure, Instance, Light, LightingMode, LightmapFilter,
    LightmapImage, LightmapRect, Lightmaps, MAX_LIGHTS, Material, Mesh, Model, OrbitCamera, PointLight,
    Scene, Shading, SpotLight, TextureImage, Viewpoint,
};
pub use settings::{
    CascadeSettings, CullMode, DepthFormat, LightFit, PcfKernel, PcssSettings, PenumbraSettings, Quality,
    ShadowMapSettings, ShadowMethod, ShadowSettings, SpreadMode, TileClassification, TraditionalSettings,
};
pub use shadows::{Chain, LightId, LightReport, LightTexture, Shadows, ViewInputs};
pub use view::{CameraMatrices, DepthConvention};
