//! The distance-map method's screen-space chain: the distance map, the variable-spacing PCF,
//! then the blur whose width follows the distance (or a resolve without a blur). As compute
//! passes over the distance map's tile list ([`OursChain`]), or as draws ([`OursDrawChain`]).

use super::screen_chain::{ChainKey, MethodChain, Recorder, ScreenInputs, stage_lists};
use crate::chain::{Chain, FRAME_SIZE};
use crate::frame::{DistanceSwitches, PassParams};
use crate::map_resolution::WidthProbe;
use crate::pipeline_cache::CachedDevice;
use crate::screen::{
    BlurCompute, BlurInput, BlurPass, Cleared, ClearedByList, ComputeTargets, DistanceMapCompute,
    DistanceMapPass, DistanceMaps, ResolvePass, ScreenStage, VariablePcfCompute, VariablePcfPass,
};

/// The distance-map method as compute passes over the distance map's tile list.
pub(crate) struct OursChain {
    /// The variable PCF writes the light's layer ([`Chain::pcf_in_layer`]).
    into_layer: bool,
    distance: DistanceMapCompute,
    pcf: VariablePcfCompute,
    /// Writes the layer; without it the resolve does.
    blur: Option<BlurCompute>,
    resolve: ResolvePass,
    /// The shared intermediates, as bound.
    targets: Option<ComputeTargets>,
    /// Bound as a member of a group of lights ([`crate::screen::LightGroup`]): the chain runs
    /// its tile classification alone, and the group the passes after it.
    grouped: bool,
}

impl OursChain {
    /// What the chain is made for: the distance switches of the compute path, the PCF's, the
    /// blur's and whether it writes the layer, and where the distance is taken.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey {
            distance: DistanceSwitches {
                tiles: params.list_tiles,
                ..params.distance_switches
            },
            distance_in_pcf: params.distance_in_pcf,
            ..ChainKey::bare(chain, kind).pcf(params).blur(params, true)
        }
    }

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        let (kind, in_pcf) = (key.kind, key.distance_in_pcf);
        let blur = key.blur.is_some();
        let half = key.half_floats();
        let into_layer = key.chain.pcf_in_layer();
        Self {
            distance: DistanceMapCompute::new(
                device,
                FRAME_SIZE,
                key.distance,
                kind,
                (blur, half, into_layer),
                (!in_pcf, key.map_arrays),
            ),
            pcf: VariablePcfCompute::new(
                device,
                FRAME_SIZE,
                (key.pcf, in_pcf.then_some(key.distance)),
                kind,
                (half.intermediates, key.map_arrays, false),
            ),
            blur: key
                .blur
                .map(|switches| BlurCompute::new(device, FRAME_SIZE, switches, half, (into_layer, false))),
            resolve: ResolvePass::new(device, FRAME_SIZE),
            targets: None,
            into_layer,
            grouped: false,
        }
    }
}

impl OursChain {
    /// The shared intermediates the chain's passes wrote, as bound: none where grouped (the
    /// group holds the light's, in layers of its own).
    fn own_targets(&self) -> Option<&crate::screen::DistanceMapTargets> {
        self.targets
            .as_ref()
            .filter(|_| !self.grouped)?
            .distance_map
            .as_ref()
    }
}

impl MethodChain for OursChain {
    stage_lists!(distance, pcf, resolve; blur);

    fn unbind(&mut self) {
        self.targets = None;
        self.grouped = false;
    }

    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        let (frame, [depth, mask, _]) = inputs.common();
        let (Some(maps), Some(all)) = (distance_maps(inputs), inputs.compute) else {
            return;
        };
        self.grouped = false;
        if inputs.grouped {
            // The group classifies and runs the passes (`LightGroup`).
            self.targets = Some(all.clone());
            self.grouped = true;
            return;
        }
        let Some(shared) = &all.distance_map else {
            return;
        };
        // The PCF's visibility: the light's layer where it writes there, else the targets'.
        let visibility = if self.into_layer {
            inputs.layer
        } else {
            all.visibility.as_ref().map(|v| &v.view)
        };
        let Some(visibility) = visibility else {
            return;
        };
        self.targets = Some(all.clone());
        let distance_map = &shared.distance.view;
        let sigma = &shared.sigma.view;
        let cleared = ClearedByList {
            distance: distance_map,
            visibility,
            blurred: all.blurred.as_ref().map(|b| &b.view),
        };
        self.distance
            .bind(device, (&shared.tiles, &cleared), frame, &maps, (depth, mask));
        let distance = (distance_map, inputs.dummy);
        self.pcf
            .bind(device, (visibility, sigma), frame, (depth, mask), distance, &maps);
        match (&mut self.blur, &all.blurred) {
            (Some(blur), Some(blurred)) => {
                let read = (visibility, sigma, distance_map);
                blur.bind(device, &blurred.view, frame, (depth, mask), read, inputs.layer)
            }
            _ => self
                .resolve
                .bind(device, frame, [depth, distance_map, visibility, mask]),
        }
    }

    fn encode(&self, recorder: &mut Recorder) {
        let (Some(listed), Some(targets)) = (self.distance.listed(), &self.targets) else {
            return;
        };
        let maps_drawn = recorder.maps_drawn;
        if self.grouped {
            // The group records the light's classification and passes (`LightGroup::encode`).
            return;
        }
        // The tile classification sets the intermediates where it tests pixels by workgroups
        // (a GPU): their clear values, and 0 over the tiles turned away from the light.
        // Otherwise each is cleared before the pass that fills it, and the passes write the 0
        // over the tiles turned away, without taps.
        let by_list = self.distance.clears();
        let clear = |e: &mut wgpu::CommandEncoder, which| {
            if !by_list {
                targets.clear(e, which);
            }
        };
        // Where the variable PCF takes the distance itself (the default), the mark "distance
        // map" times the tile list, and "pcf" the distance map with PCF.
        recorder.pass("distance map", |e| {
            clear(e, Cleared::Distance);
            self.distance.encode(e, maps_drawn)
        });
        let away = self.distance.away().filter(|_| {
            let switches = self.distance.switches();
            switches.facing_away || switches.umbra
        });
        let away_passes = away.filter(|_| !by_list);
        let layer = recorder.layer;
        recorder.pass("pcf", |e| match &self.blur {
            // The PCF writes the layer: set first as it must end where nothing writes it (by
            // the tile list's clears where they run).
            Some(blur) if self.into_layer => {
                if !by_list {
                    blur.encode_layer_init(e, layer, away);
                }
                self.pcf.encode(e, listed, None)
            }
            _ => {
                clear(e, Cleared::Visibility);
                self.pcf.encode(e, listed, away_passes)
            }
        });
        match &self.blur {
            Some(blur) => recorder.pass("blur", |e| {
                clear(e, Cleared::Blurred);
                blur.encode(e, listed, (away, by_list), layer)
            }),
            None => recorder.pass("resolve", |e| self.resolve.encode(e, layer)),
        }
    }

    fn width_probe_mut(&mut self) -> Option<&mut WidthProbe> {
        Some(self.pcf.probe_mut())
    }

    fn distance_texture(&self) -> Option<&wgpu::Texture> {
        Some(&self.own_targets()?.distance.texture)
    }

    fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        Some(self.own_targets()?.tiles.classes_texture())
    }

    /// None where the PCF writes the light's layer: the blur overwrites it there.
    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        if self.into_layer {
            return None;
        }
        self.targets.as_ref()?.visibility.as_ref().map(|v| &v.texture)
    }
}

/// The distance-map method as draws (a device without compute shaders, or PCF at half
/// resolution).
pub(crate) struct OursDrawChain {
    distance: DistanceMapPass,
    pcf: VariablePcfPass,
    /// Its vertical draw writes the layer; none without a blur.
    blur: Option<BlurPass>,
    /// Writes the layer when the chain has no blur.
    resolve: ResolvePass,
}

impl OursDrawChain {
    /// What the chain is made for: the distance map's, the PCF's and the blur's switches.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey {
            distance: params.distance_switches,
            ..ChainKey::bare(chain, kind).pcf(params).blur(params, false)
        }
    }

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        Self {
            distance: DistanceMapPass::new(device, FRAME_SIZE, key.distance, key.kind),
            pcf: VariablePcfPass::new(device, FRAME_SIZE, key.pcf, key.kind),
            blur: key
                .blur
                .map(|switches| BlurPass::new(device, FRAME_SIZE, switches)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl MethodChain for OursDrawChain {
    stage_lists!(distance, pcf, resolve; blur);

    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        let (frame, [depth, mask, _]) = inputs.common();
        let Some(maps) = distance_maps(inputs) else {
            return;
        };
        self.distance.bind(device, frame, &maps, (depth, mask));
        let distance_map = self.distance.distance_map();
        self.pcf
            .bind(device, frame, [depth, distance_map, maps.shadow_map]);
        let visibility = self.pcf.visibility();
        if let Some(blur) = &mut self.blur {
            let blur_sigma = self.pcf.blur_sigma();
            let input = BlurInput {
                visibility,
                distance_map,
                blur_sigma,
            };
            blur.bind(device, frame, (depth, mask), &input);
        }
        self.resolve
            .bind(device, frame, [depth, distance_map, visibility, mask]);
    }

    fn encode(&self, recorder: &mut Recorder) {
        let maps_drawn = recorder.maps_drawn;
        recorder.pass("distance map", |e| self.distance.encode(e, maps_drawn));
        let classification = self.distance.classification();
        recorder.pass("pcf", |e| self.pcf.encode(e, classification));
        let layer = recorder.layer;
        match &self.blur {
            Some(blur) => recorder.pass("blur", |e| blur.encode(e, Some(classification), layer)),
            None => recorder.pass("resolve", |e| self.resolve.encode(e, layer)),
        }
    }

    fn distance_texture(&self) -> Option<&wgpu::Texture> {
        Some(self.distance.distance_texture())
    }

    fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        self.distance.tile_classes_texture()
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        Some(self.pcf.visibility_texture())
    }
}

/// The light's maps the distance map reads, as its chain binds them (none without a fattened
/// map).
fn distance_maps<'a>(inputs: &ScreenInputs<'a>) -> Option<DistanceMaps<'a>> {
    DistanceMaps::of(inputs.maps, inputs.views)
}
