//! Each method's chain of passes, written once: [`Chain`] names what a light's frame runs, and
//! the crate-internal [`LightMaps`] and [`ScreenChain`] hold the passes of that chain, one
//! variant per method, with how they connect ([`ScreenChain::bind`]) and the order they run in
//! ([`ScreenChain::encode`]) side by side.

use crate::casters::Casters;
use crate::frame::DistanceSwitches;
use crate::frame::{FrameUniform, PassParams, has_no_size};
use crate::gpu_helpers::Target;
use crate::light_space::LightView;
use crate::passes::{
    BlurCompute, BlurInput, BlurPass, DistanceMapCompute, DistanceMapPass, ExitMapPass,
    FattenedShadowMapPass, PackedVisibility, PcfPass, PcssPass, ResolvePass, ScreenStage, ShadowMapPass,
    StorageClear, TileListTargets, VariablePcfCompute, VariablePcfPass,
};
use crate::scene::Light;
use crate::settings::{ShadowMapSettings, ShadowMethod, ShadowSettings};

/// The size of the frame uniform every screen-space pass reads.
pub(crate) const FRAME_SIZE: usize = size_of::<FrameUniform>();

/// Which passes one light's frame runs: each method's chain ([`Chain::new`]). Every chain
/// starts with the light's shadow map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Chain {
    /// The distance-map method ([`ShadowMethod::Ours`], [`ShadowMethod::OursFast`]): from the
    /// light the fattened map and the exit map (the casters' back faces) besides the shadow
    /// map; on the screen the distance map, the variable-spacing PCF, then the blur, whose
    /// vertical draw writes the light's layer (or a resolve, with `blur` false: a blur of one
    /// tap).
    Ours {
        /// [`ShadowMethod::Ours`] or [`ShadowMethod::OursFast`].
        method: ShadowMethod,
        /// The blur has more than one tap.
        blur: bool,
        /// The screen-space passes run as compute passes over a list of the screen tiles a
        /// shadow can reach (the copy of the blurred result into the light's layer, which is
        /// a render target, as a draw of those tiles); otherwise as draws
        /// ([`crate::PenumbraSettings::fragment_passes`]).
        compute: bool,
    },
    /// The baseline ([`ShadowMethod::Traditional`]): fixed-spacing PCF, a fixed Gaussian
    /// blur (`blur`: it has more than one tap), a resolve.
    Traditional {
        /// The blur has more than one tap.
        blur: bool,
        /// PCF and both axes of the blur are compute passes over the screen, and a draw copies
        /// the result into the light's layer (else draws).
        compute: bool,
    },
    /// [`ShadowMethod::Pcss`]: PCSS, a resolve.
    Pcss {
        /// PCSS is a compute pass over the screen (else a draw).
        compute: bool,
    },
    /// Screen-space hard shadows ([`ShadowMethod::Hard`], [`ShadowMethod::Hardware2x2`], and a
    /// method that needs a light size under a light without one): one PCF tap (a bilinear
    /// 2 x 2 comparison), a resolve.
    Hard {
        /// The method drawn.
        method: ShadowMethod,
        /// The tap is a compute pass over the screen (else a draw).
        compute: bool,
    },
    /// The shadow map alone: the convenience renderer shades with it in its forward pass (or
    /// renders the reference).
    MapOnly {
        /// The method the frame draws with the map.
        method: ShadowMethod,
    },
}

impl Chain {
    /// The chain `settings.method` runs for `light`.
    pub fn new(settings: &ShadowSettings, light: &Light) -> Self {
        let compute = !settings.penumbra.fragment_passes;
        match settings.method {
            // A light with no size casts hard shadows: these methods give way to them.
            ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Pcss if has_no_size(light) => {
                Chain::Hard {
                    method: ShadowMethod::Hard,
                    compute,
                }
            }
            method @ (ShadowMethod::Ours | ShadowMethod::OursFast) => Chain::Ours {
                method,
                blur: settings.penumbra.blur_taps > 1,
                // Batched blurs and PCF at half resolution are draws only.
                compute: compute && !settings.penumbra.batch_lights && !settings.penumbra.reduced_resolution,
            },
            ShadowMethod::Traditional => Chain::Traditional {
                blur: settings.traditional.blur_taps > 1,
                compute,
            },
            ShadowMethod::Pcss => Chain::Pcss { compute },
            method @ (ShadowMethod::Hard | ShadowMethod::Hardware2x2) => Chain::Hard { method, compute },
            ShadowMethod::Reference => Chain::MapOnly {
                method: ShadowMethod::Reference,
            },
        }
    }

    /// This chain without its screen-space passes (the light's shadow map only).
    pub(crate) fn map_only(self) -> Self {
        Chain::MapOnly {
            method: self.method(),
        }
    }

    /// This chain with its screen-space passes as draws (a device without compute shaders).
    pub(crate) fn without_compute(self) -> Self {
        match self {
            Chain::Ours { method, blur, .. } => Chain::Ours {
                method,
                blur,
                compute: false,
            },
            Chain::Traditional { blur, .. } => Chain::Traditional { blur, compute: false },
            Chain::Pcss { .. } => Chain::Pcss { compute: false },
            Chain::Hard { method, .. } => Chain::Hard {
                method,
                compute: false,
            },
            other => other,
        }
    }

    /// The screen-space passes run as compute passes (the distance-map method's over a tile
    /// list, the others' over the screen); the writes into the light's layer (the resolve, the
    /// blur's copy of its result) stay draws.
    pub fn compute(&self) -> bool {
        matches!(
            self,
            Chain::Ours { compute: true, .. }
                | Chain::Traditional { compute: true, .. }
                | Chain::Pcss { compute: true }
                | Chain::Hard { compute: true, .. }
        )
    }

    /// The method drawn: a method that needs a light size falls back to
    /// [`ShadowMethod::Hard`] when the light has none.
    pub fn method(&self) -> ShadowMethod {
        match *self {
            Chain::Ours { method, .. } | Chain::Hard { method, .. } | Chain::MapOnly { method } => method,
            Chain::Traditional { .. } => ShadowMethod::Traditional,
            Chain::Pcss { .. } => ShadowMethod::Pcss,
        }
    }

    /// The fattened map and the exit map are drawn from the light (the distance-map method).
    pub fn fattened_map(&self) -> bool {
        matches!(self, Chain::Ours { .. })
    }

    /// The casters' back faces from the light: how near the receiver an occluder ends, for
    /// the distance inside thick occluders' shadows (the distance-map method).
    pub fn exit_map(&self) -> bool {
        self.fattened_map()
    }

    /// The screen-space distance map runs.
    pub fn distance_map(&self) -> bool {
        matches!(self, Chain::Ours { .. })
    }

    /// PCF runs: after the distance map its spacing follows the distance (variable-spacing
    /// PCF), otherwise it is fixed (the baseline, hard shadows).
    pub fn pcf(&self) -> bool {
        matches!(
            self,
            Chain::Ours { .. } | Chain::Traditional { .. } | Chain::Hard { .. }
        )
    }

    /// PCSS runs (its blocker search and filter in one pass).
    pub fn pcss(&self) -> bool {
        matches!(self, Chain::Pcss { .. })
    }

    /// A separable blur runs over the PCF visibility (width following the distance after
    /// the distance map, fixed for the baseline).
    pub fn blur(&self) -> bool {
        matches!(
            self,
            Chain::Ours { blur: true, .. } | Chain::Traditional { blur: true, .. }
        )
    }

    /// A resolve pass writes the light's layer (otherwise the blur's vertical draw does).
    pub fn resolve(&self) -> bool {
        match self {
            Chain::Ours { blur, .. } => !blur,
            Chain::Traditional { blur, compute } => !(*blur && *compute),
            Chain::MapOnly { .. } => false,
            _ => true,
        }
    }

    /// How many maps are drawn from the light when they are redrawn.
    pub fn light_maps(&self) -> u32 {
        if self.fattened_map() { 3 } else { 1 }
    }

    /// The names of the passes, in the order they run.
    pub fn names(&self) -> Vec<&'static str> {
        let mut names = vec!["shadow map"];
        names.extend(match self {
            Chain::Ours { blur, .. } => vec![
                "fattened shadow map",
                "exit map",
                "distance map",
                "pcf",
                if *blur { "blur" } else { "resolve" },
            ],
            // The compute path's blur writes the layer.
            Chain::Traditional {
                blur: true,
                compute: true,
            } => vec!["pcf", "blur"],
            Chain::Traditional { blur: true, .. } => vec!["pcf", "blur", "resolve"],
            Chain::Traditional { blur: false, .. } | Chain::Hard { .. } => vec!["pcf", "resolve"],
            Chain::Pcss { .. } => vec!["pcss", "resolve"],
            Chain::MapOnly { .. } => vec![],
        });
        names
    }
}

/// A light's maps drawn from the light: the shadow map, and for the distance-map method the
/// fattened map and the exit map, all made with one set of casters' vertex layouts and one
/// atlas layout.
pub(crate) struct LightMaps {
    pub shadow: ShadowMapPass,
    pub fattened: Option<(FattenedShadowMapPass, ExitMapPass)>,
    /// The casters (id) the passes were made for.
    casters: u64,
}

impl LightMaps {
    /// GPU memory the maps take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.shadow.allocated_bytes()
            + self.fattened.as_ref().map_or(0, |(fattened, exit)| {
                fattened.allocated_bytes() + exit.allocated_bytes()
            })
    }

    /// Makes or keeps the maps `chain` needs for a light fitted as `light_view` (its atlas's
    /// tiles and their size); true when any was made (they must then be drawn and bound again).
    pub fn allocate(
        maps: &mut Option<LightMaps>,
        device: &wgpu::Device,
        casters: &Casters,
        settings: &ShadowMapSettings,
        light_view: &LightView,
        chain: &Chain,
    ) -> bool {
        let (grid, tile) = (light_view.grid, light_view.tile);
        let layouts = casters.layouts();
        let mut made = false;
        let maps = match maps {
            Some(m) if m.casters == casters.id() => {
                // Another layout (the cascades in use) or resolution
                // (`crate::MapResolution::FromPenumbra`): new textures, the same pipelines.
                if (m.shadow.grid(), m.shadow.tile()) != (grid, tile) {
                    m.shadow.resize(device, settings, grid, tile);
                    if let Some((fattened, exit)) = &mut m.fattened {
                        fattened.resize(device, settings, grid, tile);
                        exit.resize(device, settings, grid, tile);
                    }
                    made = true;
                }
                m
            }
            _ => {
                made = true;
                maps.insert(LightMaps {
                    shadow: ShadowMapPass::new(device, layouts, settings, grid, tile),
                    fattened: None,
                    casters: casters.id(),
                })
            }
        };
        if chain.fattened_map() != maps.fattened.is_some() {
            maps.fattened = chain.fattened_map().then(|| {
                (
                    FattenedShadowMapPass::new(device, layouts, settings, grid, tile),
                    ExitMapPass::new(device, layouts, settings, grid, tile),
                )
            });
            made = true;
        }
        made
    }

    /// Uploads the light's fit (and fatten distance) for the next draw, which redraws only the
    /// tiles (cascades, cube faces) whose bit is set in `tiles` and draws only the casters on
    /// `layers`.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        casters: &Casters,
        light_view: &LightView,
        fatten_distance: f32,
        tiles: u32,
        layers: u32,
    ) {
        self.shadow.prepare(device, queue, casters, light_view, layers);
        self.shadow.redraw_only(tiles);
        if let Some((fattened, exit)) = &mut self.fattened {
            fattened.prepare(device, queue, casters, light_view, fatten_distance, layers);
            fattened.redraw_only(tiles);
            exit.prepare(device, queue, casters, light_view, layers);
            exit.redraw_only(tiles);
        }
    }

    /// Draws the maps, calling `mark(encoder, pass)` after each.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    ) {
        run(encoder, mark, "shadow map", &|e| self.shadow.encode(e, casters));
        if let Some((fattened, exit)) = &self.fattened {
            run(encoder, mark, "fattened shadow map", &|e| {
                fattened.encode(e, casters)
            });
            run(encoder, mark, "exit map", &|e| exit.encode(e, casters));
        }
    }
}

/// Records one pass in a debug group of its name, then `mark`s it.
fn run(
    encoder: &mut wgpu::CommandEncoder,
    mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    name: &'static str,
    pass: &dyn Fn(&mut wgpu::CommandEncoder),
) {
    encoder.push_debug_group(name);
    pass(encoder);
    encoder.pop_debug_group();
    mark(encoder, name);
}

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
}

/// The compute path's screen-sized intermediates. Each light's chain runs whole, blur
/// included, before the next light's starts, so one set serves every light: a light adds only
/// its layer of the visibility array to the screen-space memory. After a frame they hold the
/// last light's values (see `Shadows::inspect`).
#[derive(Clone)]
pub(crate) struct ComputeTargets {
    /// The visibility before any blur (PCF, PCSS).
    pub visibility: Target,
    /// The blur's horizontal axis, where a chain blurs.
    pub blurred: Option<Target>,
    /// The distance-map method's, where a light runs it.
    pub distance_map: Option<DistanceMapTargets>,
    /// Every tile of the screen listed: the fixed blur runs over all of them.
    pub every_tile: Option<TileListTargets>,
    /// Compute clears of the textures above ([`ComputeTargets::clear`]).
    clears: TargetClears,
}

/// [`ComputeTargets`]' clears, one per cleared texture.
#[derive(Clone)]
struct TargetClears {
    visibility: OneClear,
    blurred: Option<OneClear>,
    distance: Option<OneClear>,
}

/// One texture's clear: a compute pass on a GPU, a render pass's clear on a CPU adapter (where a
/// render pass's clear is a memory fill and a compute pass runs a shader per texel: lavapipe's
/// frame took 4-7% longer with compute clears, an H100's screen-space passes 0.37 ms less on
/// teapot view 0; `PENUMBRA_CLEARS=compute` or `render` in the environment picks one whatever
/// the device, for tests).
#[derive(Clone)]
enum OneClear {
    Compute(StorageClear),
    RenderPass(wgpu::TextureView, wgpu::Color),
}

impl OneClear {
    /// Whether `device` clears with compute passes.
    fn compute(device: &wgpu::Device) -> bool {
        match std::env::var("PENUMBRA_CLEARS").as_deref() {
            Ok("compute") => true,
            Ok("render") => false,
            _ => device.adapter_info().device_type != wgpu::DeviceType::Cpu,
        }
    }

    fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        match self {
            OneClear::Compute(clear) => clear.encode(encoder),
            OneClear::RenderPass(view, value) => drop(crate::passes::begin_pass(
                encoder,
                "ComputeTargets::clear",
                &[crate::passes::cleared(view, *value)],
                None,
            )),
        }
    }
}

/// A texture of [`ComputeTargets`] that is cleared before the pass that fills it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Cleared {
    /// The visibility, to 1: a blur reads it beyond the tiles PCF wrote.
    Visibility,
    /// The blur's horizontal axis, to 1: its vertical axis reads beyond the tiles it wrote.
    Blurred,
    /// The distance map, to 0: no shadow outside the listed tiles.
    Distance,
}

/// The distance-map method's part of [`ComputeTargets`].
#[derive(Clone)]
pub(crate) struct DistanceMapTargets {
    /// R distance, G mask, B classification ([`DistanceMapCompute::FORMAT`]).
    pub distance: Target,
    /// The blur's deviations from the variable PCF.
    pub sigma: Target,
    /// The tile list the passes run over.
    pub tiles: TileListTargets,
}

/// Which parts of [`ComputeTargets`] the lights' chains use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct ComputeNeeds {
    pub blur: bool,
    pub distance_map: bool,
    pub every_tile: bool,
}

impl ComputeNeeds {
    /// What `chain` uses (nothing off the compute path).
    pub fn of(chain: &Chain) -> Self {
        if !chain.compute() {
            return Self::default();
        }
        Self {
            blur: chain.blur(),
            distance_map: chain.distance_map(),
            every_tile: chain.blur() && !chain.distance_map(),
        }
    }

    pub fn union(self, other: Self) -> Self {
        Self {
            blur: self.blur || other.blur,
            distance_map: self.distance_map || other.distance_map,
            every_tile: self.every_tile || other.every_tile,
        }
    }
}

impl ComputeTargets {
    /// For a screen of `size`, with the parts `needs` names.
    pub fn new(device: &wgpu::Device, size: (u32, u32), needs: ComputeNeeds) -> Self {
        let compute_clears = OneClear::compute(device);
        let target =
            |label, format| crate::passes::storage_target(device, label, size, format, !compute_clears);
        let visibility = target(
            "ComputeTargets::visibility",
            VariablePcfCompute::VISIBILITY_FORMAT,
        );
        let blurred = needs
            .blur
            .then(|| target("ComputeTargets::blurred", BlurCompute::FORMAT));
        let distance_map = needs.distance_map.then(|| DistanceMapTargets {
            distance: target("ComputeTargets::distance_map", DistanceMapCompute::FORMAT),
            sigma: target("ComputeTargets::sigma", VariablePcfCompute::SIGMA_FORMAT),
            tiles: TileListTargets::new(device, size),
        });
        let clear = |label, Target { texture, view }: &Target, value: wgpu::Color| {
            if compute_clears {
                let value = [value.r, value.g, value.b, value.a];
                OneClear::Compute(StorageClear::new(
                    device,
                    label,
                    (view, texture.format(), size),
                    value,
                ))
            } else {
                OneClear::RenderPass(view.clone(), value)
            }
        };
        let clears = TargetClears {
            visibility: clear(
                "ComputeTargets::clear_visibility",
                &visibility,
                wgpu::Color::WHITE,
            ),
            blurred: blurred
                .as_ref()
                .map(|b| clear("ComputeTargets::clear_blurred", b, wgpu::Color::WHITE)),
            distance: distance_map.as_ref().map(|d| {
                clear(
                    "ComputeTargets::clear_distance",
                    &d.distance,
                    wgpu::Color::TRANSPARENT,
                )
            }),
        };
        Self {
            visibility,
            blurred,
            distance_map,
            every_tile: needs
                .every_tile
                .then(|| TileListTargets::every_tile(device, size)),
            clears,
        }
    }

    /// Records the clear of `which` ([`OneClear`]: a compute pass on a GPU, where a render pass's
    /// clear of these storage textures costs more than the passes that fill them).
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder, which: Cleared) {
        let clear = match which {
            Cleared::Visibility => Some(&self.clears.visibility),
            Cleared::Blurred => self.clears.blurred.as_ref(),
            Cleared::Distance => self.clears.distance.as_ref(),
        };
        if let Some(clear) = clear {
            clear.encode(encoder);
        }
    }

    /// These are a screen of `size`'s, with exactly the parts `needs` names.
    pub fn fit(&self, size: (u32, u32), needs: ComputeNeeds) -> bool {
        let have = ComputeNeeds {
            blur: self.blurred.is_some(),
            distance_map: self.distance_map.is_some(),
            every_tile: self.every_tile.is_some(),
        };
        (self.visibility.texture.width(), self.visibility.texture.height()) == size && have == needs
    }

    pub fn allocated_bytes(&self) -> u64 {
        let bytes = |t: &Target| crate::gpu_helpers::texture_bytes(&t.texture);
        bytes(&self.visibility)
            + self.blurred.as_ref().map_or(0, bytes)
            + self.distance_map.as_ref().map_or(0, |d| {
                bytes(&d.distance) + bytes(&d.sigma) + d.tiles.allocated_bytes()
            })
            + self
                .every_tile
                .as_ref()
                .map_or(0, TileListTargets::allocated_bytes)
    }
}

/// A light's screen-space passes, one variant per [`Chain`] (one value per light, made when its
/// chain changes: their sizes differ, unboxed). Each chain owns every pass it runs, blur
/// included, except the distance-map method's blur as draws when lights are blurred in batches
/// ([`crate::PenumbraSettings::batch_lights`]): one blur pass then serves up to four lights,
/// and `Shadows` owns it.
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
        /// Its vertical draw writes the layer; none without a blur, or in a batch.
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

impl ScreenChain {
    /// The chain's stages, each once: what `allocated_bytes`, `resize` and `prepare` go over.
    fn stages(&self) -> Vec<&dyn ScreenStage> {
        match self {
            ScreenChain::MapOnly => vec![],
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                ..
            } => with_blur(vec![distance, pcf, resolve], blur.as_ref().map(|b| b as _)),
            ScreenChain::Ours {
                distance,
                pcf,
                blur,
                resolve,
            } => with_blur(vec![distance, pcf, resolve], blur.as_ref().map(|b| b as _)),
            ScreenChain::Traditional { pcf, blur, resolve } => {
                with_blur(vec![pcf, resolve], blur.as_ref().map(|b| b as _))
            }
            ScreenChain::TraditionalCompute {
                pcf, blur, resolve, ..
            } => with_blur(vec![pcf, resolve], blur.as_ref().map(|b| b as _)),
            ScreenChain::Pcss { pcss, resolve } => vec![pcss, resolve],
            ScreenChain::Hard { pcf, resolve } => vec![pcf, resolve],
        }
    }

    /// [`Self::stages`], to resize.
    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
        match self {
            ScreenChain::MapOnly => vec![],
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                ..
            } => with_blur(vec![distance, pcf, resolve], blur.as_mut().map(|b| b as _)),
            ScreenChain::Ours {
                distance,
                pcf,
                blur,
                resolve,
            } => with_blur(vec![distance, pcf, resolve], blur.as_mut().map(|b| b as _)),
            ScreenChain::Traditional { pcf, blur, resolve } => {
                with_blur(vec![pcf, resolve], blur.as_mut().map(|b| b as _))
            }
            ScreenChain::TraditionalCompute {
                pcf, blur, resolve, ..
            } => with_blur(vec![pcf, resolve], blur.as_mut().map(|b| b as _)),
            ScreenChain::Pcss { pcss, resolve } => vec![pcss, resolve],
            ScreenChain::Hard { pcf, resolve } => vec![pcf, resolve],
        }
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
                ),
                pcf: VariablePcfCompute::new(device, FRAME_SIZE, params.pcf_switches, kind),
                blur: blur.then(|| BlurCompute::new(device, FRAME_SIZE, params.blur_switches)),
                resolve: resolve(),
                targets: None,
            },
            Chain::Ours { blur, .. } => ScreenChain::Ours {
                distance: DistanceMapPass::new(device, FRAME_SIZE, params.distance_switches, kind),
                pcf: VariablePcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind),
                blur: (*blur && !params.batch_lights)
                    .then(|| BlurPass::new(device, FRAME_SIZE, params.blur_switches, 1)),
                resolve: resolve(),
            },
            Chain::Traditional { blur, compute: true } => ScreenChain::TraditionalCompute {
                pcf: PcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind, true),
                blur: blur.then(|| BlurCompute::new(device, FRAME_SIZE, params.blur_switches)),
                resolve: resolve(),
                targets: None,
            },
            Chain::Traditional { blur, .. } => ScreenChain::Traditional {
                pcf: PcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind, false),
                blur: blur.then(|| BlurPass::new(device, FRAME_SIZE, params.blur_switches, 1)),
                resolve: resolve(),
            },
            Chain::Pcss { compute } => ScreenChain::Pcss {
                pcss: PcssPass::new(device, FRAME_SIZE, kind, *compute),
                resolve: resolve(),
            },
            Chain::Hard { compute, .. } => ScreenChain::Hard {
                pcf: PcfPass::new(device, FRAME_SIZE, params.pcf_switches, kind, *compute),
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
                    && pcf.switches() == params.pcf_switches
                    && pcf.light_kind() == kind
                    && blur.is_some() == *wanted
                    && blur.as_ref().is_none_or(|b| b.switches() == params.blur_switches)
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
                    && blur.is_some() == (*wanted && !params.batch_lights)
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
            }
            (ScreenChain::Pcss { pcss, .. }, Chain::Pcss { compute }) => {
                pcss.light_kind() == kind && pcss.is_compute() == *compute
            }
            (ScreenChain::Hard { pcf, .. }, Chain::Hard { compute, .. }) => {
                pcf_fits(pcf) && pcf.is_compute() == *compute
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
        } = *inputs;
        let shadow_map = maps.shadow.view();
        match self {
            ScreenChain::MapOnly => {}
            ScreenChain::OursCompute {
                distance,
                pcf,
                blur,
                resolve,
                targets,
            } => {
                let (Some((fattened, exit)), Some(all)) = (&maps.fattened, compute) else {
                    return;
                };
                let Some(shared) = &all.distance_map else {
                    return;
                };
                *targets = Some(all.clone());
                let distance_map = &shared.distance.view;
                distance.bind(
                    device,
                    (distance_map, &shared.tiles),
                    frame,
                    (fattened.view(), fattened_size(fattened.texture())),
                    fattened.occluder_offset(),
                    exit.view(),
                    shadow_map,
                    depth,
                    mask,
                );
                let (visibility, sigma) = (&all.visibility.view, &shared.sigma.view);
                pcf.bind(
                    device,
                    (visibility, sigma),
                    frame,
                    depth,
                    distance_map,
                    shadow_map,
                );
                match blur {
                    Some(blur) => blur.bind(
                        device,
                        &all.blurred.as_ref().expect("made for a blurring chain").view,
                        frame,
                        (depth, mask),
                        (visibility, sigma, distance_map),
                        dummy,
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
                let Some((fattened, exit)) = &maps.fattened else {
                    return;
                };
                distance.bind(
                    device,
                    frame,
                    (fattened.view(), fattened_size(fattened.texture())),
                    fattened.occluder_offset(),
                    exit.view(),
                    shadow_map,
                    depth,
                    mask,
                );
                pcf.bind(device, frame, depth, distance.distance_map(), shadow_map);
                // A blur batched over lights is bound by `Shadows`.
                if let Some(blur) = blur {
                    let input = BlurInput {
                        visibility: pcf.visibility(),
                        distance_map: distance.distance_map(),
                        blur_sigma: pcf.blur_sigma(),
                    };
                    blur.bind(device, frame, (depth, mask), &[input], dummy);
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
                pcf.bind(device, frame, depth, shadow_map, None);
                let Some(mut visibility) = pcf.visibility() else {
                    return;
                };
                if let Some(blur) = blur {
                    let input = BlurInput {
                        visibility,
                        distance_map: dummy,
                        blur_sigma: dummy,
                    };
                    blur.bind(device, frame, (depth, mask), &[input], dummy);
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
                pcf.bind(device, frame, depth, shadow_map, Some(&all.visibility));
                let visibility = &all.visibility.view;
                match (blur, &all.blurred) {
                    (Some(blur), Some(blurred)) => blur.bind(
                        device,
                        &blurred.view,
                        frame,
                        (depth, mask),
                        (visibility, dummy, dummy),
                        dummy,
                    ),
                    _ => resolve.bind(device, frame, depth, dummy, visibility, mask),
                }
            }
            ScreenChain::Pcss { pcss, resolve } => {
                let shared = compute.map(|c| &c.visibility);
                pcss.bind(device, frame, depth, shadow_map, shared);
                if let Some(visibility) = pcss.visibility() {
                    resolve.bind(device, frame, depth, dummy, visibility, mask);
                }
            }
            ScreenChain::Hard { pcf, resolve } => {
                let shared = compute.map(|c| &c.visibility);
                pcf.bind(device, frame, depth, shadow_map, shared);
                if let Some(visibility) = pcf.visibility() {
                    resolve.bind(device, frame, depth, dummy, visibility, mask);
                }
            }
        }
    }

    /// Records `chain`'s passes in order into the light's `layer` (`maps_drawn`: the light's
    /// maps were drawn this frame), calling `mark(encoder, pass)` after each. `packed`: the
    /// light is blurred in a batch, whose packed visibility its PCF also writes (`.1`: it comes
    /// first and clears it); its batch's blur runs after every light's chain.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        chain: &Chain,
        maps_drawn: bool,
        layer: &wgpu::TextureView,
        packed: Option<(&PackedVisibility, bool)>,
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
                run(encoder, mark, "distance map", &|e| {
                    targets.clear(e, Cleared::Distance);
                    distance.encode(e, maps_drawn)
                });
                // The tiles turned away from the light get 0 from each pass, without taps.
                let away = distance.away().filter(|_| distance.switches().facing_away);
                run(encoder, mark, "pcf", &|e| {
                    targets.clear(e, Cleared::Visibility);
                    pcf.encode(e, listed, away)
                });
                match blur {
                    Some(blur) => run(encoder, mark, "blur", &|e| {
                        targets.clear(e, Cleared::Blurred);
                        blur.encode(e, listed, away, layer)
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
                match packed {
                    Some((packed, first)) => run(encoder, mark, "pcf", &|e| {
                        pcf.encode_packed(e, classification, packed, first)
                    }),
                    None => run(encoder, mark, "pcf", &|e| pcf.encode(e, classification)),
                }
                // Batched, the blur runs after every light's chain (`Shadows`).
                if let Some(blur) = blur {
                    run(encoder, mark, "blur", &|e| {
                        blur.encode(e, Some(classification), &[layer])
                    });
                }
                if chain.resolve() {
                    run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
                }
            }
            ScreenChain::Traditional { pcf, blur, resolve } => {
                run(encoder, mark, "pcf", &|e| pcf.encode(e));
                if let Some(blur) = blur {
                    run(encoder, mark, "blur", &|e| blur.encode(e, None, &[layer]));
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
                        blur.encode(e, listed, None, layer)
                    }),
                    _ => run(encoder, mark, "resolve", &|e| resolve.encode(e, layer)),
                }
            }
            ScreenChain::Pcss { pcss, resolve } => {
                run(encoder, mark, "pcss", &|e| pcss.encode(e));
                run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
            }
            ScreenChain::Hard { pcf, resolve } => {
                run(encoder, mark, "pcf", &|e| pcf.encode(e));
                run(encoder, mark, "resolve", &|e| resolve.encode(e, layer));
            }
        }
    }

    /// The distance-map method's distance map and PCF (which its batched blur reads).
    pub fn distance_map(&self) -> Option<(&DistanceMapPass, &VariablePcfPass)> {
        match self {
            ScreenChain::Ours { distance, pcf, .. } => Some((distance, pcf)),
            _ => None,
        }
    }

    /// The penumbra widths the compute path's PCF counts ([`crate::map_resolution`]).
    pub(crate) fn width_probe_mut(&mut self) -> Option<&mut crate::map_resolution::WidthProbe> {
        match self {
            ScreenChain::OursCompute { pcf, .. } => Some(pcf.probe_mut()),
            _ => None,
        }
    }

    pub fn variable_pcf_mut(&mut self) -> Option<&mut VariablePcfPass> {
        match self {
            ScreenChain::Ours { pcf, .. } => Some(pcf),
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

/// A fattened map's width and height in texels.
fn fattened_size(texture: &wgpu::Texture) -> (u32, u32) {
    (texture.width(), texture.height())
}
