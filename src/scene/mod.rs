//! The scene model: meshes, materials, instances, a light and named viewpoints.
//!
//! Everything here is plain CPU data; [`crate::GpuScene`] uploads it.

mod camera;
pub mod character;
#[cfg(feature = "renderer")]
pub mod file;
mod light;
mod lightmap;
#[cfg(feature = "renderer")]
pub mod loaders;
mod material;
pub(crate) mod mesh;
mod model;
pub mod primitives;
pub mod teapot;
mod teapot_data;

pub use crate::bounds::Aabb;
pub use crate::camera::Camera;
pub use crate::lights::{
    AreaLight, AreaShape, DirectionalLight, DiskLight, Exposure, Light, MAX_LIGHTS, PointLight, RectLight,
    SpotLight, light_axes,
};
pub use camera::OrbitCamera;
#[cfg(feature = "renderer")]
pub use file::{LightsFrom, MeshSource, SceneFile, TextureSource};
pub use light::{
    MODEL_SPOT_RADIUS_PER_DISTANCE, MODEL_SUN_DIAMETER_DEG, ModelLight, ModelLightKind, ModelLightSizes,
    lights_from_model,
};
pub use lightmap::{LightingMode, LightmapFilter, LightmapImage, LightmapRect, Lightmaps, rg11b10, rgb9e5};
pub use material::{AlphaMode, FilterMode, Material, Shading, TextureImage, TextureSampler, WrapMode};
pub use mesh::{Mesh, MeshRepairs};
pub use model::*;
