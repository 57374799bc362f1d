//! The screen-space stages each method runs after its light's maps, one module and one WGSL
//! file each, and in [`chains`] each method's chain of them.
//!
//! | stage | shader | inputs | output |
//! |---|---|---|---|
//! | [`DistanceMapPass`] | `shaders/distance_map.wgsl` | camera depth, receiver mask, fattened map and occluder offset, exit map, shadow map | distance + mask (RG16F) and where a shadow can fall (depth), full screen |
//! | [`VariablePcfPass`] | `shaders/variable_pcf.wgsl` | camera depth, distance map and its classification, shadow map | visibility (R16F) and the blur's standard deviations (RG16F), where a shadow can fall |
//! | [`PcfPass`] | `shaders/pcf.wgsl` | camera depth, shadow map | fixed-spacing visibility (R16F): the baseline and hard shadows |
//! | [`PcssPass`] | `shaders/pcss.wgsl` | camera depth, shadow map | visibility (R16F) |
//! | [`BlurPass`] | `shaders/blur.wgsl` | visibility, distance map, camera depth | blurred visibility (R16F), or the light's output layer with the indirect attenuation applied |
//! | [`ResolvePass`] | `shaders/resolve.wgsl` | visibility, distance map, camera depth, receiver mask | one layer of the visibility array, indirect attenuation applied |
//!
//! The compute path (the default where the device has compute shaders,
//! [`crate::PenumbraSettings::fragment_passes`]): `TileListPass` (`cs_classify` in
//! `shaders/tile_classify.wgsl`) lists the 16 x 16 tiles the distance-map method's shadows can
//! reach and writes indirect arguments; `VariablePcfCompute` (`cs_distance_pcf`: each pixel's
//! distance, the work of `shaders/common/distance.wgsl`, written into the distance map, then
//! its taps) and both axes of `BlurCompute` (`cs_main`) run over that list
//! (`shaders/common/tile_list.wgsl`). Where the device stores half floats the blur's vertical
//! axis (`cs_layer`) writes the light's layer itself, after a clear of the layer; elsewhere a
//! draw of the listed tiles' quads copies the blurred result into it (one load a pixel).
//! `DistanceMapCompute` owns the list, and
//! runs the distance map as a pass of its own (`cs_main` in its shader) only with
//! [`crate::ExecutionSettings::distance_in_pcf`] off. [`PcfPass`] and [`PcssPass`] run `cs_main`
//! over the screen ([`ScreenPipeline`]), and where the device stores half floats `cs_layer`,
//! which writes the light's layer as [`ResolvePass`] would (no resolve is drawn). Their
//! screen-sized outputs are the lights' shared [`ComputeTargets`].
//!
//! Each method's chain of stages is one struct in [`chains`], built from a key of what it was
//! made for; a light holds its chain as a [`ScreenChain`].
//!
//! A new stage is four files: its WGSL file in `shaders/` (whose first line names the pieces of
//! `shaders/common/` it is joined after: `build.rs` lists it), its module here (the stage's
//! struct, with `new`, `bind` and `encode` for its own inputs and [`ScreenStage`] for its size,
//! parameters and memory), a `mod` line here, and its place in the chain of each method that
//! runs it (`chains/<method>.rs`: a field, made in `new`, listed in `stages`, connected in
//! `bind`, recorded in `encode`). A stage with settings of its own also adds them to
//! `crate::settings` and `crate::frame::PassParams`.

mod blur;
mod chains;
mod distance_map;
mod light_group;
mod pcf;
mod pcss;
mod resolve;
mod shared;
mod storage_clear;
mod targets;
mod tile_classify;
mod variable_pcf;

#[cfg(test)]
pub(crate) use blur::BlurUniform;
pub(crate) use blur::{BlurCompute, BlurInput, BlurPass};
pub(crate) use chains::{ChainKey, Mark, ScreenChain, ScreenInputs};
pub(crate) use distance_map::{DistanceMapCompute, DistanceMapPass, DistanceMaps};
pub(crate) use light_group::{LightGroup, MAX_MEMBERS as MAX_GROUP_MEMBERS};
pub(crate) use pcf::PcfPass;
pub(crate) use pcss::PcssPass;
pub(crate) use resolve::ResolvePass;
pub use shared::VISIBILITY_FORMAT;
pub(crate) use shared::*;
pub(crate) use storage_clear::StorageClear;
pub(crate) use targets::{Cleared, ComputeNeeds, ComputeTargets, DistanceMapTargets};
pub(crate) use tile_classify::{ClearedByList, TileListPass, TileListTargets};
pub(crate) use variable_pcf::{VariablePcfCompute, VariablePcfPass};
