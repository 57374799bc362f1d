//! A light's screen-space chain: the stages each method runs over the screen after its maps
//! (one module and one WGSL file each), and [`ScreenChain`], which holds a light's stages, one
//! variant per method, with how they connect ([`ScreenChain::bind`]) and the order they run in
//! ([`ScreenChain::encode`]) side by side.
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
//! A new stage is three files: its WGSL file in `shaders/` (whose first line names the pieces
//! of `shaders/common/` it is joined after: `build.rs` lists it), its module here (the stage's
//! struct, with `bind` and `encode` for its own inputs and [`ScreenStage`] for its size,
//! parameters and memory), and this file (a `mod` line, and its place in the chains that run
//! it: their variant, [`ScreenChain::new`], `fits`, `stages_of!`, [`ScreenChain::bind`] and
//! [`ScreenChain::encode`]). A stage with settings of its own also adds them to
//! `crate::settings` and `crate::frame::PassParams`.

mod blur;
mod distance_map;
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
pub(crate) use distance_map::{DistanceMapCompute, DistanceMapPass, DistanceMaps};
pub(crate) use pcf::PcfPass;
pub(crate) use pcss::PcssPass;
pub(crate) use resolve::ResolvePass;
pub use shared::VISIBILITY_FORMAT;
pub(crate) use shared::*;
pub(crate) use storage_clear::StorageClear;
pub(crate) use targets::{Cleared, ComputeNeeds, ComputeTargets};
pub(crate) use tile_classify::{ClearedByList, TileListPass, TileListTargets};
pub(crate) use variable_pcf::{VariablePcfCompute, VariablePcfPass};
// What the stages build on besides the helpers above.
pub(crate) use crate::gpu_helpers::{
    Binding, Fullscreen, begin_pass, bind_group, cleared, comparison_sampler, depth_attachment, entry,
    fullscreen_pipeline, fullscreen_pipeline_with, screen_target,
};
pub(crate) use crate::passes::{DepthUse, Tiles, draw_area, draw_fullscreen_into};

use crate::chain::{Chain, FRAME_SIZE, LightMaps, run};
use crate::frame::{DistanceSwitches, PassParams};

/// What a light's screen-space passes read besides their own: the frame uniform, the engine's
/// depth and receiver mask (or a stand-in), the light's maps, and a 1 x 1 stand-in for inputs
/// a chain does not have; and the compute path's intermediates, which every light shares.
pub(crate) struct ScreenInputs<'a> {
    pub frame: &'a wgpu::Buffer,
    pub depth: &'a wgpu::TextureView,
    pub mask: &'a wgpu::TextureView,
    pub maps: &'a LightMaps,
    pub dummy: &'a wgpu::TextureView,
    pub compute: Option<&'a ComputeTargets>,
    /// The light's layer of the visibility array, where the compute passes write it themselves
    /// ([`PassParams::layer_writes`]).
    pub layer: Option<&'a wgpu::TextureView>,
}

/// A light's screen-space passes, one variant per [`Chain`] (one value per light, made when its
/// chain changes: their sizes differ, unboxed). Each chain owns every pass it runs, blur
/// included.
#[allow(clippy::large_enum_variant)]
pub(crate) enum ScreenChain {
    MapOnly,
    /// The distance-map method as compute passes over the distance map's tile list.
    OursCompute {
        distance: DistanceMapCompute,
        pcf: VariablePcfCompute,
        /// Writes the layer; without it the resolve does.
        blur: Option<BlurCompute>,
        resolve: ResolvePass,
        /// The shared intermediates, as bound.
        targets: Option<ComputeTargets>,
    },
    Ours {
        distance: DistanceMapPass,
        pcf: VariablePcfPass,
        /// Its vertical draw writes the layer; none without a blur.
        blur: Option<BlurPass>,
        /// Writes the layer when the chain has no blur.
        resolve: ResolvePass,
    },
    Traditional {
        pcf: PcfPass,
        blur: Option<BlurPass>,
        resolve: ResolvePass,
    },
    /// The baseline as compute passes over the screen (every tile listed); the blur writes the
    /// layer, the resolve only without a blur.
    TraditionalCompute {
        pcf: PcfPass,
        blur: Option<BlurCompute>,
        resolve: ResolvePass,
        /// The shared intermediates, as bound.
        targets: Option<ComputeTargets>,
    },
    Pcss {
        pcss: PcssPass,
        resolve: ResolvePass,
    },
    Hard {
        pcf: PcfPass,
        resolve: ResolvePass,
    },
}

/// Every stage of `$chain` (a `&ScreenChain` or a `&mut ScreenChain`), each once, its blur
/// last: the one list behind `ScreenChain::stages` and `stages_mut`. `$option` takes the
/// optional blur as a reference of the same kind (`as_ref` or `as_mut`).
macro_rules! stages_of {
    ($chain:expr, $option:ident) => {
        match $chain {
            ScreenChain::MapOnly => vec![],
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                ..
            } => with_blur(vec![distance, pcf, resolve], blur.$option().map(|b| b as _)),
            ScreenChain::Ours {
                distance,
                pcf,
                blur,
                resolve,
            } => with_blur(vec![distance, pcf, resolve], blur.$option().map(|b| b as _)),
            ScreenChain::Traditional { pcf, blur, resolve } => {
                with_blur(vec![pcf, resolve], blur.$option().map(|b| b as _))
            }
            ScreenChain::TraditionalCompute {
                pcf, blur, resolve, ..
            } => with_blur(vec![pcf, resolve], blur.$option().map(|b| b as _)),
            ScreenChain::Pcss { pcss, resolve } => vec![pcss, resolve],
            ScreenChain::Hard { pcf, resolve } => vec![pcf, resolve],
        }
    };
}

impl ScreenChain {
    /// The chain's stages, each once: what `allocated_bytes`, `resize` and `prepare` go over.
    fn stages(&self) -> Vec<&dyn ScreenStage> {
        stages_of!(self, as_ref)
    }

    /// [`Self::stages`], to resize.
    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
        stages_of!(self, as_mut)
    }

    /// GPU memory the chain's passes allocated, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.stages().iter().map(|s| s.allocated_bytes()).sum()
    }

    /// The passes of `chain` for a light of `kind` ([`crate::frame::light_kind`]), made with
    /// `params`' compile-time switches and sized `width` x `height`.
    pub fn new(
        device: &wgpu::Device,
        chain: &Chain,
        params: &PassParams,
        kind: u32,
        (w, h): (u32, u32),
    ) -> Self {
        let resolve = || ResolvePass::new(device, FRAME_SIZE);
        let layers = params.layer_writes;
        let mut passes = match chain {
            Chain::MapOnly { .. } => ScreenChain::MapOnly,
            Chain::Ours {
                compute: true, blur, ..
            } => ScreenChain::OursCompute {
                distance: DistanceMapCompute::new(
                    device,
                    FRAME_SIZE,
                    compute_distance_switches(params),
                    kind,
                    *blur,
                    !params.distance_in_pcf,
                ),
                pcf: VariablePcfCompute::new(
                    device,
                    FRAME_SIZE,
                    params.pcf_switches,
                    params.distance_in_pcf.then(|| compute_distance_switches(params)),
                    kind,
                ),
                blur: blur.then(|| BlurCompute::new(device, FRAME_SIZE, params.blur_switches, layers)),
                resolve: resolve(),
                targets: None,
            },
            Chain::Ours { blur, .. } => ScreenChain::Ours {
                distance: DistanceMapPass::new(device, FRAME_SIZE, params.distance_switches, kind),
                pcf: VariablePcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind),
                blur: blur.then(|| BlurPass::new(device, FRAME_SIZE, params.blur_switches)),
                resolve: resolve(),
            },
            Chain::Traditional { blur, compute: true } => ScreenChain::TraditionalCompute {
                pcf: PcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind, (true, false)),
                blur: blur.then(|| BlurCompute::new(device, FRAME_SIZE, params.blur_switches, layers)),
                resolve: resolve(),
                targets: None,
            },
            Chain::Traditional { blur, .. } => ScreenChain::Traditional {
                pcf: PcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind, (false, false)),
                blur: blur.then(|| BlurPass::new(device, FRAME_SIZE, params.blur_switches)),
                resolve: resolve(),
            },
            Chain::Pcss { compute, .. } => ScreenChain::Pcss {
                pcss: PcssPass::new(device, FRAME_SIZE, kind, (*compute, *compute && layers)),
                resolve: resolve(),
            },
            Chain::Hard { compute, .. } => ScreenChain::Hard {
                pcf: PcfPass::new(
                    device,
                    FRAME_SIZE,
                    params.pcf_switches,
                    kind,
                    (*compute, *compute && layers),
                ),
                resolve: resolve(),
            },
        };
        passes.resize(device, w, h);
        passes
    }

    /// These passes serve `chain` for a light of `kind` with `params`' switches (otherwise
    /// they must be made again).
    pub fn fits(&self, chain: &Chain, params: &PassParams, kind: u32) -> bool {
        let pcf_fits = |p: &PcfPass| p.switches() == params.pcf_switches && p.light_kind() == kind;
        match (self, chain) {
            (ScreenChain::MapOnly, Chain::MapOnly { .. }) => true,
            (
                ScreenChain::OursCompute {
                    distance, pcf, blur, ..
                },
                Chain::Ours {
                    compute: true,
                    blur: wanted,
                    ..
                },
            ) => {
                distance.switches() == compute_distance_switches(params)
                    && distance.light_kind() == kind
                    && distance.own_pass() != params.distance_in_pcf
                    && pcf.distance_switches()
                        == params.distance_in_pcf.then(|| compute_distance_switches(params))
                    && pcf.switches() == params.pcf_switches
                    && pcf.light_kind() == kind
                    && blur.is_some() == *wanted
                    && blur.as_ref().is_none_or(|b| b.switches() == params.blur_switches)
                    && blur
                        .as_ref()
                        .is_none_or(|b| b.writes_layers() == params.layer_writes)
            }
            (
                ScreenChain::Ours {
                    distance, pcf, blur, ..
                },
                Chain::Ours {
                    compute: false,
                    blur: wanted,
                    ..
                },
            ) => {
                distance.switches() == params.distance_switches
                    && distance.light_kind() == kind
                    && pcf.switches() == params.pcf_switches
                    && pcf.light_kind() == kind
                    && blur.is_some() == *wanted
                    && blur.as_ref().is_none_or(|b| b.switches() == params.blur_switches)
            }
            (
                ScreenChain::Traditional { pcf, blur, .. },
                Chain::Traditional {
                    blur: wanted,
                    compute: false,
                },
            ) => {
                pcf_fits(pcf)
                    && !pcf.is_compute()
                    && blur.is_some() == *wanted
                    && blur.as_ref().is_none_or(|b| b.switches() == params.blur_switches)
            }
            (
                ScreenChain::TraditionalCompute { pcf, blur, .. },
                Chain::Traditional {
                    blur: wanted,
                    compute: true,
                },
            ) => {
                pcf_fits(pcf)
                    && pcf.is_compute()
                    && blur.is_some() == *wanted
                    && blur.as_ref().is_none_or(|b| b.switches() == params.blur_switches)
                    && blur
                        .as_ref()
                        .is_none_or(|b| b.writes_layers() == params.layer_writes)
            }
            (ScreenChain::Pcss { pcss, .. }, Chain::Pcss { compute, .. }) => {
                pcss.light_kind() == kind
                    && pcss.is_compute() == *compute
                    && pcss.writes_layers() == (*compute && params.layer_writes)
            }
            (ScreenChain::Hard { pcf, .. }, Chain::Hard { compute, .. }) => {
                pcf_fits(pcf)
                    && pcf.is_compute() == *compute
                    && pcf.writes_layers() == (*compute && params.layer_writes)
            }
            _ => false,
        }
    }

    /// Sizes the screen-sized targets; the passes must then be bound again.
    pub fn resize(&mut self, device: &wgpu::Device, w: u32, h: u32) {
        for stage in self.stages_mut() {
            stage.resize(device, w, h);
        }
        // The compute path's shared intermediates are the screen's size (`Shadows` makes them).
        if let ScreenChain::OursCompute { targets, .. } | ScreenChain::TraditionalCompute { targets, .. } =
            self
        {
            *targets = None;
        }
    }

    /// Uploads the frame's parameters of each pass.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        for stage in self.stages() {
            stage.prepare(queue, params);
        }
    }

    /// Points each pass at its inputs: the chain's wiring, pass by pass.
    pub fn bind(&mut self, device: &wgpu::Device, inputs: &ScreenInputs) {
        let ScreenInputs {
            frame,
            depth,
            mask,
            maps,
            dummy,
            compute,
            layer,
        } = *inputs;
        let shadow_map = maps.shadow.atlas.view();
        match self {
            ScreenChain::MapOnly => {}
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                targets,
            } => {
                let (Some(maps), Some(all)) = (distance_maps(maps), compute) else {
                    return;
                };
                let Some(shared) = &all.distance_map else {
                    return;
                };
                *targets = Some(all.clone());
                let distance_map = &shared.distance.view;
                let cleared = ClearedByList {
                    distance: distance_map,
                    visibility: &all.visibility.view,
                    blurred: all.blurred.as_ref().map(|b| &b.view),
                };
                distance.bind(device, (&shared.tiles, &cleared), frame, &maps, (depth, mask));
                let (visibility, sigma) = (&all.visibility.view, &shared.sigma.view);
                pcf.bind(
                    device,
                    (visibility, sigma),
                    frame,
                    (depth, mask),
                    (distance_map, dummy),
                    &maps,
                );
                match blur {
                    Some(blur) => blur.bind(
                        device,
                        &all.blurred.as_ref().expect("made for a blurring chain").view,
                        frame,
                        (depth, mask),
                        (visibility, sigma, distance_map),
                        layer,
                    ),
                    None => resolve.bind(device, frame, depth, distance_map, visibility, mask),
                }
            }
            ScreenChain::Ours {
                distance,
                pcf,
                blur,
                resolve,
            } => {
                let Some(maps) = distance_maps(maps) else {
                    return;
                };
                distance.bind(device, frame, &maps, (depth, mask));
                pcf.bind(device, frame, depth, distance.distance_map(), shadow_map);
                if let Some(blur) = blur {
                    let input = BlurInput {
                        visibility: pcf.visibility(),
                        distance_map: distance.distance_map(),
                        blur_sigma: pcf.blur_sigma(),
                    };
                    blur.bind(device, frame, (depth, mask), &input);
                }
                resolve.bind(
                    device,
                    frame,
                    depth,
                    distance.distance_map(),
                    pcf.visibility(),
                    mask,
                );
            }
            ScreenChain::Traditional { pcf, blur, resolve } => {
                pcf.bind(device, frame, depth, shadow_map, None, None);
                let Some(mut visibility) = pcf.visibility() else {
                    return;
                };
                if let Some(blur) = blur {
                    let input = BlurInput {
                        visibility,
                        distance_map: dummy,
                        blur_sigma: dummy,
                    };
                    blur.bind(device, frame, (depth, mask), &input);
                    visibility = blur.blurred().unwrap_or(visibility);
                }
                resolve.bind(device, frame, depth, dummy, visibility, mask);
            }
            ScreenChain::TraditionalCompute {
                pcf,
                blur,
                resolve,
                targets,
            } => {
                let Some(all) = compute else {
                    return;
                };
                *targets = Some(all.clone());
                pcf.bind(device, frame, depth, shadow_map, Some(&all.visibility), None);
                let visibility = &all.visibility.view;
                match (blur, &all.blurred) {
                    (Some(blur), Some(blurred)) => blur.bind(
                        device,
                        &blurred.view,
                        frame,
                        (depth, mask),
                        (visibility, dummy, dummy),
                        layer,
                    ),
                    _ => resolve.bind(device, frame, depth, dummy, visibility, mask),
                }
            }
            ScreenChain::Pcss { pcss, resolve } => {
                let shared = compute.map(|c| &c.visibility);
                pcss.bind(device, frame, depth, shadow_map, shared, layer.map(|l| (l, mask)));
                if let Some(visibility) = pcss.visibility() {
                    resolve.bind(device, frame, depth, dummy, visibility, mask);
                }
            }
            ScreenChain::Hard { pcf, resolve } => {
                let shared = compute.map(|c| &c.visibility);
                pcf.bind(device, frame, depth, shadow_map, shared, layer.map(|l| (l, mask)));
                if let Some(visibility) = pcf.visibility() {
                    resolve.bind(device, frame, depth, dummy, visibility, mask);
                }
            }
        }
    }

    /// Records `chain`'s passes in order into the light's `layer` (`maps_drawn`: the light's
    /// maps were drawn this frame), calling `mark(encoder, pass)` after each.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        chain: &Chain,
        maps_drawn: bool,
        layer: &wgpu::TextureView,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    ) {
        match self {
            ScreenChain::MapOnly => {}
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                targets,
            } => {
                let (Some(listed), Some(targets)) = (distance.listed(), targets) else {
                    return;
                };
                // The tile classification sets the intermediates where it tests pixels by
                // workgroups (a GPU): their clear values, and 0 over the tiles turned away from
                // the light. Otherwise each is cleared before the pass that fills it, and the
                // passes write the 0 over the tiles turned away, without taps.
                let by_list = distance.clears();
                let clear = |e: &mut wgpu::CommandEncoder, which| {
                    if !by_list {
                        targets.clear(e, which);
                    }
                };
                // Where the variable PCF takes the distance itself (the default), the mark
                // "distance map" times the tile list, and "pcf" the distance map with PCF.
                run(encoder, mark, "distance map", &|e| {
                    clear(e, Cleared::Distance);
                    distance.encode(e, maps_drawn)
                });
                let away = distance.away().filter(|_| distance.switches().facing_away);
                let away_passes = away.filter(|_| !by_list);
                run(encoder, mark, "pcf", &|e| {
                    clear(e, Cleared::Visibility);
                    pcf.encode(e, listed, away_passes)
                });
                match blur {
                    Some(blur) => run(encoder, mark, "blur", &|e| {
                        clear(e, Cleared::Blurred);
                        blur.encode(e, listed, (away, by_list), layer)
                    }),
                    None => run(encoder, mark, "resolve", &|e| resolve.encode(e, layer)),
                }
            }
            ScreenChain::Ours {
                distance,
                pcf,
                blur,
                resolve,
            } => {
                run(encoder, mark, "distance map", &|e| distance.encode(e, maps_drawn));
                let classification = distance.classification();
                run(encoder, mark, "pcf", &|e| pcf.encode(e, classification));
                if let Some(blur) = blur {
                    run(encoder, mark, "blur", &|e| {
                        blur.encode(e, Some(classification), layer)
                    });
                }
                if chain.resolve() {
                    run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
                }
            }
            ScreenChain::Traditional { pcf, blur, resolve } => {
                run(encoder, mark, "pcf", &|e| pcf.encode(e));
                if let Some(blur) = blur {
                    run(encoder, mark, "blur", &|e| blur.encode(e, None, layer));
                }
                run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
            }
            ScreenChain::TraditionalCompute {
                pcf,
                blur,
                resolve,
                targets,
            } => {
                run(encoder, mark, "pcf", &|e| pcf.encode(e));
                let listed = targets
                    .as_ref()
                    .and_then(|t| t.every_tile.as_ref())
                    .map(TileListTargets::listed);
                match (blur, listed, targets) {
                    (Some(blur), Some(listed), Some(targets)) => run(encoder, mark, "blur", &|e| {
                        targets.clear(e, Cleared::Blurred);
                        blur.encode(e, listed, (None, false), layer)
                    }),
                    _ => run(encoder, mark, "resolve", &|e| resolve.encode(e, layer)),
                }
            }
            // Where the compute pass writes the layer itself, no resolve is drawn.
            ScreenChain::Pcss { pcss, resolve } => {
                run(encoder, mark, "pcss", &|e| pcss.encode(e));
                if !pcss.writes_layers() {
                    run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
                }
            }
            ScreenChain::Hard { pcf, resolve } => {
                run(encoder, mark, "pcf", &|e| pcf.encode(e));
                if !pcf.writes_layers() {
                    run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
                }
            }
        }
    }

    /// The penumbra widths the compute path's PCF counts ([`crate::map_resolution`]).
    pub(crate) fn width_probe_mut(&mut self) -> Option<&mut crate::map_resolution::WidthProbe> {
        match self {
            ScreenChain::OursCompute { pcf, .. } => Some(pcf.probe_mut()),
            _ => None,
        }
    }

    /// The distance map (R distance, G mask; the compute path's B its classification).
    pub fn distance_texture(&self) -> Option<&wgpu::Texture> {
        match self {
            ScreenChain::Ours { distance, .. } => Some(distance.distance_texture()),
            ScreenChain::OursCompute { targets, .. } => targets
                .as_ref()
                .and_then(|t| t.distance_map.as_ref())
                .map(|d| &d.distance.texture),
            _ => None,
        }
    }

    /// The tile classification's classes, where the chain draws only the tiles it keeps or
    /// lists them.
    pub fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        match self {
            ScreenChain::Ours { distance, .. } => distance.tile_classes_texture(),
            ScreenChain::OursCompute { targets, .. } => targets
                .as_ref()
                .and_then(|t| t.distance_map.as_ref())
                .map(|d| d.tiles.classes_texture()),
            _ => None,
        }
    }

    /// The raw visibility (PCF or PCSS), before any blur.
    pub fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        match self {
            ScreenChain::MapOnly => None,
            ScreenChain::OursCompute { targets, .. } => targets.as_ref().map(|t| &t.visibility.texture),
            ScreenChain::Ours { pcf, .. } => Some(pcf.visibility_texture()),
            ScreenChain::Traditional { pcf, .. }
            | ScreenChain::TraditionalCompute { pcf, .. }
            | ScreenChain::Hard { pcf, .. } => pcf.visibility_texture(),
            ScreenChain::Pcss { pcss, .. } => pcss.visibility_texture(),
        }
    }

    /// The fixed blur's own output (the distance-map method's blur writes the layer).
    pub fn blurred_visibility(&self) -> Option<&wgpu::Texture> {
        match self {
            ScreenChain::Traditional { blur: Some(blur), .. } => blur.blurred_texture(),
            _ => None,
        }
    }
}

/// A chain's stages, its blur last when it has one.
fn with_blur<T>(mut stages: Vec<T>, blur: Option<T>) -> Vec<T> {
    stages.extend(blur);
    stages
}

/// The compute path's distance-map switches: its tile list follows the classification setting
/// with `Auto` on (see [`PassParams::list_tiles`]).
fn compute_distance_switches(params: &PassParams) -> DistanceSwitches {
    DistanceSwitches {
        tiles: params.list_tiles,
        ..params.distance_switches
    }
}

/// The maps of `maps` the distance map reads (none without a fattened map).
fn distance_maps(maps: &LightMaps) -> Option<DistanceMaps<'_>> {
    let (fattened, exit) = maps.fattened.as_ref()?;
    let texture = fattened.atlas.texture();
    Some(DistanceMaps {
        shadow_map: maps.shadow.atlas.view(),
        fattened_map: fattened.atlas.view(),
        fattened_size: (texture.width(), texture.height()),
        occluder_offset: fattened.occluder_offset(),
        exit_map: exit.atlas.view(),
    })
}
