//! Soft shadows inside an engine's frame: [`Shadows`] takes the engine's camera matrices, its
//! depth buffer, its casters ([`Casters`](crate::Casters)) and a list of lights, and writes one visibility per
//! light into a texture array the engine samples in its own lit shader.
//!
//! Per light and frame: the shadow map and the fattened map (only when the light, its fit or a
//! caster it sees changed), then full-screen passes over the engine's depth. The distance-map
//! method runs the distance map, then its PCF and blur only where the distance map says a
//! shadow can fall; the blur writes the light's layer. The other methods run PCF or PCSS, the
//! blur, and a resolve into the layer. Each light's chain owns every pass it runs. No camera
//! geometry is drawn.

mod api;
mod inputs;
mod light_state;
mod plan;
mod report;

pub use api::*;
pub use inputs::ViewInputs;
#[cfg(feature = "renderer")]
pub(crate) use light_state::spreads;
pub use report::{LightId, LightReport, LightTexture};
