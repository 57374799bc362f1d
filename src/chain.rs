//! Each method's chain of passes, written once: [`Chain`] names what a light's frame runs, the
//! crate-internal [`LightMaps`] hold the maps it draws from the light, and
//! `crate::screen::ScreenChain` its screen-space stages.

use crate::casters::Casters;
use crate::frame::{FrameUniform, has_no_size};
use crate::light_space::LightView;
use crate::passes::{ExitMapPass, FarPlaneFill, FattenedShadowMapPass, ShadowMapPass};
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
        /// shadow can reach (the blur's vertical axis writes the light's layer where the device
        /// stores half floats; elsewhere a draw of those tiles copies its result there);
        /// otherwise as draws ([`crate::PenumbraSettings::fragment_passes`]).
        compute: bool,
    },
    /// The baseline ([`ShadowMethod::Traditional`]): fixed-spacing PCF, a fixed Gaussian
    /// blur (`blur`: it has more than one tap), a resolve.
    Traditional {
        /// The blur has more than one tap.
        blur: bool,
        /// PCF and both axes of the blur are compute passes over the screen, the vertical axis
        /// writing the light's layer where the device stores half floats, else a draw copying
        /// the result there (else draws).
        compute: bool,
    },
    /// [`ShadowMethod::Pcss`]: PCSS, a resolve.
    Pcss {
        /// PCSS is a compute pass over the screen (else a draw).
        compute: bool,
        /// A draw writes the light's layer: false where the compute pass writes it itself (the
        /// device stores half floats, [`crate::Shadows`] decides).
        resolve: bool,
    },
    /// Screen-space hard shadows ([`ShadowMethod::Hard`], [`ShadowMethod::Hardware2x2`], and a
    /// method that needs a light size under a light without one): one PCF tap (a bilinear
    /// 2 x 2 comparison), a resolve.
    Hard {
        /// The method drawn.
        method: ShadowMethod,
        /// The tap is a compute pass over the screen (else a draw).
        compute: bool,
        /// A draw writes the light's layer: false where the compute pass writes it itself.
        resolve: bool,
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
                    resolve: true,
                }
            }
            method @ (ShadowMethod::Ours | ShadowMethod::OursFast) => Chain::Ours {
                method,
                blur: settings.penumbra.blur_taps > 1,
                // PCF at half resolution is draws only.
                compute: compute && !settings.penumbra.reduced_resolution,
            },
            ShadowMethod::Traditional => Chain::Traditional {
                blur: settings.traditional.blur_taps > 1,
                compute,
            },
            ShadowMethod::Pcss => Chain::Pcss {
                compute,
                resolve: true,
            },
            method @ (ShadowMethod::Hard | ShadowMethod::Hardware2x2) => Chain::Hard {
                method,
                compute,
                resolve: true,
            },
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
            Chain::Pcss { .. } => Chain::Pcss {
                compute: false,
                resolve: true,
            },
            Chain::Hard { method, .. } => Chain::Hard {
                method,
                compute: false,
                resolve: true,
            },
            other => other,
        }
    }

    /// The chain where the compute passes write the light's layer themselves (`on`: the device
    /// stores half floats and the layer allows it): PCSS's and the hard shadows' compute pass
    /// then leave no resolve to draw.
    pub(crate) fn writing_layers(self, on: bool) -> Self {
        match self {
            Chain::Pcss { compute, .. } => Chain::Pcss {
                compute,
                resolve: !(compute && on),
            },
            Chain::Hard { method, compute, .. } => Chain::Hard {
                method,
                compute,
                resolve: !(compute && on),
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
                | Chain::Pcss { compute: true, .. }
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

    /// A resolve pass writes the light's layer (otherwise the blur's vertical axis does, or
    /// PCSS's or the hard shadows' compute pass).
    pub fn resolve(&self) -> bool {
        match self {
            Chain::Ours { blur, .. } => !blur,
            Chain::Traditional { blur, compute } => !(*blur && *compute),
            Chain::Pcss { resolve, .. } | Chain::Hard { resolve, .. } => *resolve,
            Chain::MapOnly { .. } => false,
        }
    }

    /// How many maps are drawn from the light when they are redrawn.
    pub fn light_maps(&self) -> u32 {
        if self.fattened_map() { 3 } else { 1 }
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
        self.shadow.atlas.allocated_bytes()
            + self.fattened.as_ref().map_or(0, |(fattened, exit)| {
                fattened.allocated_bytes() + exit.atlas.allocated_bytes()
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
                if (m.shadow.atlas.grid, m.shadow.atlas.tile) != (grid, tile) {
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
        self.shadow.atlas.redraw_only(tiles);
        if let Some((fattened, exit)) = &mut self.fattened {
            fattened.prepare(device, queue, casters, light_view, fatten_distance, layers);
            fattened.atlas.redraw_only(tiles);
            exit.prepare(device, queue, casters, light_view, layers);
            exit.atlas.redraw_only(tiles);
        }
    }

    /// Bytes a [`FarPlaneFill`] needs to fill the largest of these maps.
    pub fn fill_bytes(&self) -> u64 {
        let support = self.fattened.as_ref().map_or(0, |(fattened, exit)| {
            fattened.atlas.fill_bytes().max(exit.atlas.fill_bytes())
        });
        self.shadow.atlas.fill_bytes().max(support)
    }

    /// Draws the maps, calling `mark(encoder, pass)` after each; `fill` sets a whole atlas to
    /// the far plane where it can.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
        fill: Option<&FarPlaneFill>,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    ) {
        run(encoder, mark, "shadow map", |e| {
            self.shadow.encode(e, casters, fill)
        });
        if let Some((fattened, exit)) = &self.fattened {
            run(encoder, mark, "fattened shadow map", |e| {
                fattened.encode(e, casters, fill)
            });
            run(encoder, mark, "exit map", |e| exit.encode(e, casters, fill));
        }
    }
}

/// Records one pass in a debug group of its name, then `mark`s it.
pub(crate) fn run(
    encoder: &mut wgpu::CommandEncoder,
    mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    name: &'static str,
    pass: impl FnOnce(&mut wgpu::CommandEncoder),
) {
    encoder.push_debug_group(name);
    pass(encoder);
    encoder.pop_debug_group();
    mark(encoder, name);
}
