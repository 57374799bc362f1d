//! The convenience layer (feature `renderer`): a [`Renderer`](render::Renderer) that owns a
//! [`crate::Shadows`] for a scene's lights and draws the scene around it (its depth prepass,
//! the lit composite or forward pass), the scene on the GPU ([`gpu_scene`]), the ground truth
//! ([`ground_truth`] and its pass, [`reference`]), a headless GPU and texture read-back
//! ([`gpu`]), the debug views ([`debug`]) and the error metrics ([`metrics`]).

mod camera_pipelines;
mod composite;
pub mod debug;
mod depth_prepass;
mod forward;
pub mod gpu;
pub(crate) mod gpu_scene;
pub(crate) mod ground_truth;
pub mod metrics;
mod reference;
pub(crate) mod render;
