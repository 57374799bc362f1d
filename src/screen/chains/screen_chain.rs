//! [`ScreenChain`]: a light's screen-space passes, one [`MethodChain`] per method, made from a
//! [`ChainKey`] and made again only when the key changes.

use super::ours::{OursChain, OursDrawChain};
use super::single_pass::{HardChain, PcssChain};
use super::traditional::{TraditionalChain, TraditionalDrawChain};
use crate::chain::Chain;
use crate::frame::FrameSlot;
use crate::frame::{BlurSwitches, DistanceSwitches, PassParams, PcfSwitches};
use crate::light_maps::{LightMaps, MapViews};
use crate::map_resolution::WidthProbe;
use crate::pipeline_cache::CachedDevice;
use crate::screen::{ComputeTargets, PassPath, ScreenStage};
use crate::shaders::HalfFloats;

/// What a light's screen-space passes read besides their own: the frame uniform, the engine's
/// depth and receiver mask (or a stand-in), the light's maps, and a 1 x 1 stand-in for inputs
/// a chain does not have; and the compute path's intermediates, which every light shares.
pub(crate) struct ScreenInputs<'a> {
    pub frame: &'a FrameSlot,
    pub depth: &'a wgpu::TextureView,
    pub mask: &'a wgpu::TextureView,
    pub maps: &'a LightMaps,
    /// The light's maps as the chain's passes bind them ([`ScreenChain::map_arrays`]).
    pub views: &'a MapViews,
    pub dummy: &'a wgpu::TextureView,
    pub compute: Option<&'a ComputeTargets>,
    /// The light's layer of the visibility array, where the compute passes write it themselves
    /// ([`PassParams::layer_writes`]).
    pub layer: Option<&'a wgpu::TextureView>,
    /// The light runs in a group ([`crate::screen::LightGroup`]), which records its screen
    /// passes: its chain records none.
    pub grouped: bool,
}

impl<'a> ScreenInputs<'a> {
    /// What most passes read: the frame uniform, and the camera's depth, the receiver mask and
    /// the stand-in.
    pub fn common(&self) -> (&'a FrameSlot, [&'a wgpu::TextureView; 3]) {
        (self.frame, [self.depth, self.mask, self.dummy])
    }
}

/// What a light's screen-space passes are made for: its chain, its light's kind
/// ([`crate::frame::light_kind`]) and the compile-time switches of the stages that chain runs.
/// Each method's chain fills in only what it reads (the rest stays at its default), so a
/// switch it does not read never makes it again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ChainKey {
    pub chain: Chain,
    pub kind: u32,
    pub pcf: PcfSwitches,
    pub distance: DistanceSwitches,
    /// The blur's switches, where the chain blurs.
    pub blur: Option<BlurSwitches>,
    /// A compute pass writes the light's layer ([`PassParams::layer_writes`]).
    pub layer_writes: bool,
    /// The compute path's variable PCF takes the distance itself
    /// ([`crate::ExecutionSettings::distance_in_pcf`]).
    pub distance_in_pcf: bool,
    /// The compute passes store the intermediates in half floats
    /// ([`PassParams::half_intermediates`]).
    pub half_intermediates: bool,
    /// The compute passes bind the light's maps as arrays ([`PassParams::map_arrays`]).
    pub map_arrays: bool,
}

impl ChainKey {
    /// The key of `chain` for a light of `kind` with nothing else set.
    pub fn bare(chain: Chain, kind: u32) -> Self {
        Self {
            chain,
            kind,
            pcf: PcfSwitches::default(),
            distance: DistanceSwitches::default(),
            blur: None,
            layer_writes: false,
            distance_in_pcf: false,
            half_intermediates: false,
            map_arrays: false,
        }
    }

    /// How the chain's compute passes store what they write: the layer where they write it,
    /// the intermediates as [`PassParams::half_intermediates`] says.
    pub fn half_floats(&self) -> HalfFloats {
        HalfFloats {
            layers: self.layer_writes,
            intermediates: self.half_intermediates,
        }
    }

    /// How the chain's passes run: compute or draws, storing as [`Self::half_floats`] says.
    pub fn path(&self) -> PassPath {
        if self.chain.compute() {
            PassPath::compute(self.half_floats(), self.map_arrays)
        } else {
            PassPath::DRAW
        }
    }

    /// This key with the PCF's switches of `params`.
    pub fn pcf(self, params: &PassParams) -> Self {
        Self {
            pcf: params.pcf_switches,
            ..self
        }
    }

    /// This key with the blur's switches of `params` where the chain blurs, and whether the
    /// blur writes the layer where `compute` (its compute form does, on a device that stores
    /// half floats).
    pub fn blur(self, params: &PassParams, compute: bool) -> Self {
        let blur = self.chain.blur();
        Self {
            blur: blur.then_some(params.blur_switches),
            layer_writes: blur && compute && params.layer_writes,
            ..self
        }
    }

    /// The key of `chain` for a light of `kind` under `params`, as its method's chain reads it.
    pub fn new(chain: &Chain, params: &PassParams, kind: u32) -> Self {
        let chain = *chain;
        let key = match chain {
            Chain::MapOnly { .. } => Self::bare(chain, 0),
            Chain::Ours { compute: true, .. } => OursChain::key(chain, params, kind),
            Chain::Ours { .. } => OursDrawChain::key(chain, params, kind),
            Chain::Traditional { compute: true, .. } => TraditionalChain::key(chain, params, kind),
            Chain::Traditional { .. } => TraditionalDrawChain::key(chain, params, kind),
            Chain::Pcss { .. } => PcssChain::key(chain, params, kind),
            Chain::Hard { .. } => HardChain::key(chain, params, kind),
        };
        // Every compute chain writes the intermediates the lights share, in one format.
        Self {
            half_intermediates: chain.compute() && params.half_intermediates,
            map_arrays: chain.compute() && params.map_arrays,
            ..key
        }
    }
}

/// How a chain marks the end of each pass it records (`mark(encoder, pass)`).
pub(crate) type Mark<'a> = &'a mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str);

/// What a chain records its passes into: the frame's encoder, the light's layer of the
/// visibility array, whether the light's maps were drawn this frame, and the mark each pass
/// ends with, which names it (the frame's list of passes and their timings come from these).
pub(crate) struct Recorder<'a> {
    encoder: &'a mut wgpu::CommandEncoder,
    /// The light's layer, which the chain's last pass writes.
    pub layer: &'a wgpu::TextureView,
    /// The light's maps were drawn this frame.
    pub maps_drawn: bool,
    mark: Mark<'a>,
}

impl Recorder<'_> {
    /// Records one pass, `name`, in a debug group of its name, then marks its end.
    pub fn pass(&mut self, name: &'static str, pass: impl FnOnce(&mut wgpu::CommandEncoder)) {
        crate::chain::run(self.encoder, &mut *self.mark, name, pass);
    }
}

/// A chain's `stages` and `stages_mut`: its stages (fields) each once, its optional blur last.
macro_rules! stage_lists {
    ($($stage:ident),+ ; $blur:ident) => {
        fn stages(&self) -> Vec<&dyn ScreenStage> {
            let mut stages: Vec<&dyn ScreenStage> = vec![$(&self.$stage),+];
            stages.extend(self.$blur.as_ref().map(|b| b as &dyn ScreenStage));
            stages
        }

        fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
            let mut stages: Vec<&mut dyn ScreenStage> = vec![$(&mut self.$stage),+];
            stages.extend(self.$blur.as_mut().map(|b| b as &mut dyn ScreenStage));
            stages
        }
    };
    ($($stage:ident),+) => {
        fn stages(&self) -> Vec<&dyn ScreenStage> {
            vec![$(&self.$stage),+]
        }

        fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
            vec![$(&mut self.$stage),+]
        }
    };
}
pub(super) use stage_lists;

/// One method's screen-space chain: it owns every pass it runs, blur included, connects them
/// ([`MethodChain::bind`]) and records them in order ([`MethodChain::encode`]).
pub(crate) trait MethodChain: wgpu::WasmNotSendSync {
    /// The chain's stages, each once: what sizing, preparing and counting memory go over.
    fn stages(&self) -> Vec<&dyn ScreenStage>;

    /// [`Self::stages`], to resize.
    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage>;

    /// Forgets the shared intermediates it was bound to (they are remade at a new size).
    fn unbind(&mut self) {}

    /// Points each pass at its inputs: the chain's wiring, pass by pass.
    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs);

    /// Records the passes in order, each through `recorder`.
    fn encode(&self, recorder: &mut Recorder);

    /// The penumbra widths the compute path's PCF counts ([`crate::map_resolution`]).
    fn width_probe_mut(&mut self) -> Option<&mut WidthProbe> {
        None
    }

    /// The distance map (R distance, G mask; the compute path's one value, distance or code,
    /// [`crate::LightTexture::DistanceMap`]).
    fn distance_texture(&self) -> Option<&wgpu::Texture> {
        None
    }

    /// The tile classification's classes, where the chain draws only the tiles it keeps or
    /// lists them.
    fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        None
    }

    /// The raw visibility (PCF or PCSS), before any blur.
    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        None
    }

    /// The fixed blur's own output (the compute paths' blurs write the layer).
    fn blurred_visibility(&self) -> Option<&wgpu::Texture> {
        None
    }
}

/// A light's screen-space passes: the chain its key names (none for the shadow map alone),
/// one value per light, made again when the key changes.
pub(crate) struct ScreenChain {
    key: ChainKey,
    passes: Option<Box<dyn MethodChain>>,
}

impl ScreenChain {
    /// No screen-space passes: the light's shadow map alone.
    pub fn map_only() -> Self {
        Self {
            key: ChainKey::bare(
                Chain::MapOnly {
                    method: crate::settings::ShadowMethod::Reference,
                },
                0,
            ),
            passes: None,
        }
    }

    /// The passes of `chain` for a light of `kind` ([`crate::frame::light_kind`]), made with
    /// `params`' compile-time switches and sized `width` x `height`.
    pub fn new(
        device: &CachedDevice<'_>,
        chain: &Chain,
        params: &PassParams,
        kind: u32,
        (w, h): (u32, u32),
    ) -> Self {
        let key = ChainKey::new(chain, params, kind);
        let passes: Option<Box<dyn MethodChain>> = match key.chain {
            Chain::MapOnly { .. } => None,
            Chain::Ours { compute: true, .. } => Some(Box::new(OursChain::new(device, &key))),
            Chain::Ours { .. } => Some(Box::new(OursDrawChain::new(device, &key))),
            Chain::Traditional { compute: true, .. } => Some(Box::new(TraditionalChain::new(device, &key))),
            Chain::Traditional { .. } => Some(Box::new(TraditionalDrawChain::new(device, &key))),
            Chain::Pcss { .. } => Some(Box::new(PcssChain::new(device, &key))),
            Chain::Hard { .. } => Some(Box::new(HardChain::new(device, &key))),
        };
        let mut made = Self { key, passes };
        made.resize(device, w, h);
        made
    }

    /// These passes serve `chain` for a light of `kind` with `params`' switches (otherwise
    /// they must be made again): their keys are equal.
    pub fn fits(&self, chain: &Chain, params: &PassParams, kind: u32) -> bool {
        self.key == ChainKey::new(chain, params, kind)
    }

    /// GPU memory the chain's passes allocated, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.passes
            .iter()
            .flat_map(|p| p.stages())
            .map(|s| s.allocated_bytes())
            .sum()
    }

    /// Sizes the screen-sized targets; the passes must then be bound again.
    pub fn resize(&mut self, device: &CachedDevice<'_>, w: u32, h: u32) {
        if let Some(passes) = &mut self.passes {
            for stage in passes.stages_mut() {
                stage.resize(device, w, h);
            }
            passes.unbind();
        }
    }

    /// Uploads the frame's parameters of each pass.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        for stage in self.passes.iter().flat_map(|p| p.stages()) {
            stage.prepare(queue, params);
        }
    }

    /// What the passes were made for.
    pub fn key(&self) -> &ChainKey {
        &self.key
    }

    /// The compute passes bind the light's maps as the arrays they are layers of
    /// ([`crate::light_maps::LightMaps::screen_views`]).
    pub fn map_arrays(&self) -> bool {
        self.key.map_arrays
    }

    /// Points each pass at its inputs.
    pub fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        if let Some(passes) = &mut self.passes {
            passes.bind(device, inputs);
        }
    }

    /// Records the passes in order into the light's `layer` (`maps_drawn`: the light's maps
    /// were drawn this frame), calling `mark(encoder, pass)` after each.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        maps_drawn: bool,
        layer: &wgpu::TextureView,
        mark: Mark,
    ) {
        if let Some(passes) = &self.passes {
            passes.encode(&mut Recorder {
                encoder,
                layer,
                maps_drawn,
                mark,
            });
        }
    }

    pub fn width_probe_mut(&mut self) -> Option<&mut WidthProbe> {
        self.passes.as_mut()?.width_probe_mut()
    }

    pub fn distance_texture(&self) -> Option<&wgpu::Texture> {
        self.passes.as_ref()?.distance_texture()
    }

    pub fn tile_classes_texture(&self) -> Option<&wgpu::Texture> {
        self.passes.as_ref()?.tile_classes_texture()
    }

    pub fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.passes.as_ref()?.raw_visibility()
    }

    pub fn blurred_visibility(&self) -> Option<&wgpu::Texture> {
        self.passes.as_ref()?.blurred_visibility()
    }
}
