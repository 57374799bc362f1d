//! The light's view and projection.
//!
//! Directional lights get an orthographic projection. Its sides enclose where shadows can fall
//! (the casters, seen along the light) and, with [`LightFit::CameraFrustum`](crate::LightFit::CameraFrustum), only the part the
//! camera sees. With texel snapping its texel size stays fixed while the camera moves and its
//! window moves in whole texels, so a static shadow samples the same texels every frame. Spot
//! lights get a perspective projection covering their cone.
//!
//! Either way the near and far planes come from clipping the scene's bounds against the four
//! side planes of the light's frustum: only geometry that can land in the map counts.

mod atlas;
mod clip;
mod fit;
mod view;
pub use atlas::{AtlasGrid, atlas_grid, tile_matrix, tile_resolution, tile_viewport};
pub(crate) use clip::box_reaches_clip;
#[cfg(test)]
pub(crate) use clip::frustum_corners;
pub use fit::{CASCADE_RATIO, FitInputs, UnheldCaster};

pub use view::*;
