//! A light's maps, drawn from the light: the shadow map, and for the distance-map method the
//! fattened map (drawn, or derived from the shadow map) and the exit map, one module and one WGSL file each, each drawn into an atlas
//! of tiles (one per cascade or cube face, [`atlas`]); [`LightMaps`] owns a light's set. The
//! light's fit (its view and the atlas's layout) is `crate::light_space`'s; the screen-space
//! stages that read the maps are `crate::screen`'s.
//!
//! | pass | shader | inputs | output |
//! |---|---|---|---|
//! | [`ShadowMapPass`] | `shaders/shadow_map.wgsl` | casters, light view | depth shadow map |
//! | [`fattened_shadow_map::FattenedShadowMapPass`] | `shaders/fattened_shadow_map.wgsl` | casters, smoothed normals, light view | fattened depth map |
//! | [`dilated_map::DilatedMapPass`] | `shaders/dilated_map.wgsl` | the shadow map, light view, fatten distance | the fattened map derived in compute (no geometry): the least depth within the fatten distance |
//! | [`exit_map::ExitMapPass`] | `shaders/exit_map.wgsl` | casters, smoothed normals, light view | depth of the casters' back faces (where rays leave the first occluder) |
//! | [`exit_in_shadow_pass::ExitInShadowPass`] | `shaders/shadow_map.wgsl` (`fs_exit_*`, with `shaders/common/exit_faces.wgsl`) | the shadow map pass's draws | the same exit map, kept by the shadow map's pass (a buffer the fragments' atomics fill, copied into an R32F map): no drawing of its own |

mod atlas;
mod dilated_map;
mod exit_in_shadow_pass;
mod exit_map;
mod fattened_shadow_map;
mod maps;
mod pipelines;
mod pool;
mod shadow_map;
mod tile_clear;

pub(crate) use atlas::{FarPlaneFill, MapUpload};
pub(crate) use exit_in_shadow_pass::supported as exit_in_shadow_pass_supported;
pub(crate) use maps::{LightMaps, MapViews};
pub(crate) use pool::{MapPools, Moved};
#[cfg(feature = "renderer")]
pub use shadow_map::ShadowMapPass;
