//! Each method's chain of passes, written once: [`Chain`] names what a light's frame runs, the
//! crate-internal [`LightMaps`] hold the maps it draws from the light, and
//! `crate::screen::ScreenChain` its screen-space stages.

use crate::frame::{FrameUniform, has_no_size};
use crate::lights::Light;
use crate::settings::{ShadowMethod, ShadowSettings};

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
        /// The fattened map is derived from the shadow map in compute
        /// ([`crate::Fattening::Dilation`], the compute path only); otherwise the casters are
        /// drawn again, pushed out.
        dilated: bool,
        /// The exit map is drawn ([`crate::PenumbraSettings::exit_map`]).
        exit_map: bool,
        /// The shadow map's pass keeps the exit map (fragment atomics beside its depth test),
        /// which then has no pass of its own ([`crate::ExecutionSettings::exit_map_draw`],
        /// where the device's fragment shaders write storage and the shadow map culls no face).
        exit_in_shadow_pass: bool,
        /// The variable PCF writes the light's layer, which the blur reads back (the compute
        /// path with a blur, where the compute passes write the layer in half floats, and
        /// [`crate::ExecutionSettings::raw_visibility`] is off): no visibility texture of its
        /// own.
        pcf_in_layer: bool,
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
            method @ (ShadowMethod::Ours | ShadowMethod::OursFast) => {
                // PCF at half resolution is draws only.
                let compute = compute && !settings.penumbra.reduced_resolution;
                Chain::Ours {
                    method,
                    blur: settings.penumbra.blur_taps > 1,
                    compute,
                    // `Fattening::Auto` by the casters: `fattening_derived_where` when they are known.
                    dilated: compute && settings.penumbra.fattening == crate::Fattening::Dilation,
                    exit_map: settings.penumbra.exit_map,
                    exit_in_shadow_pass: false,
                    pcf_in_layer: false,
                }
            }
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
            Chain::Ours {
                method,
                blur,
                exit_map,
                ..
            } => Chain::Ours {
                method,
                blur,
                compute: false,
                // The dilation is a compute pass: the casters are drawn pushed out instead.
                dilated: false,
                exit_map,
                // So is the resolve of the exit map the shadow map's pass keeps.
                exit_in_shadow_pass: false,
                pcf_in_layer: false,
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

    /// The chain where `on` (the compute passes write the layer in half floats and
    /// [`crate::ExecutionSettings::raw_visibility`] is off): the distance-map method's variable
    /// PCF then writes the light's layer, which its blur reads back.
    pub(crate) fn pcf_writing_layer(mut self, on: bool) -> Self {
        if let Chain::Ours {
            blur,
            compute,
            pcf_in_layer,
            ..
        } = &mut self
        {
            *pcf_in_layer = on && *compute && *blur;
        }
        self
    }

    /// The chain with its fattened map derived from the shadow map where `on` (what
    /// [`crate::Fattening::derived`] says for the casters) and it runs compute passes.
    pub(crate) fn fattening_derived_where(mut self, on: bool) -> Self {
        if let Chain::Ours { compute, dilated, .. } = &mut self {
            *dilated = on && *compute;
        }
        self
    }

    /// The chain where `on` (the device's fragment shaders write storage, it runs compute
    /// passes, the shadow map culls no face and
    /// [`crate::ExecutionSettings::exit_map_draw`] is on): the distance-map method's
    /// exit map is then kept by the shadow map's pass.
    pub(crate) fn exit_in_shadow_pass_where(mut self, on: bool) -> Self {
        if let Chain::Ours {
            exit_map,
            exit_in_shadow_pass,
            ..
        } = &mut self
        {
            *exit_in_shadow_pass = on && *exit_map;
        }
        self
    }

    /// The shadow map's pass keeps the exit map: it has no pass of its own
    /// ([`Chain::Ours`]'s `exit_in_shadow_pass`).
    pub fn exit_in_shadow_pass(&self) -> bool {
        matches!(
            self,
            Chain::Ours {
                exit_in_shadow_pass: true,
                ..
            }
        )
    }

    /// The distance-map method's variable PCF writes the light's layer, which its blur reads
    /// back: there is no visibility texture of its own ([`Chain::Ours`]'s `pcf_in_layer`).
    pub fn pcf_in_layer(&self) -> bool {
        matches!(
            self,
            Chain::Ours {
                pcf_in_layer: true,
                ..
            }
        )
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

    /// The light has a fattened map (the distance-map method), drawn or derived.
    pub fn fattened_map(&self) -> bool {
        matches!(self, Chain::Ours { .. })
    }

    /// The fattened map is drawn: the casters again, pushed out (not derived from the shadow
    /// map, [`crate::Fattening::Dilation`]).
    pub fn draws_fattened_map(&self) -> bool {
        matches!(self, Chain::Ours { dilated: false, .. })
    }

    /// The casters' back faces from the light: how near the receiver an occluder ends, for
    /// the distance inside thick occluders' shadows (the distance-map method, unless
    /// [`crate::PenumbraSettings::exit_map`] is off).
    pub fn exit_map(&self) -> bool {
        matches!(self, Chain::Ours { exit_map: true, .. })
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

    /// How many passes draw the casters from the light (geometry passes) when the maps are
    /// redrawn: the shadow map's, and the fattened map's and the exit map's where each is drawn
    /// by a pass of its own.
    pub fn light_maps(&self) -> u32 {
        1 + self.draws_fattened_map() as u32 + (self.exit_map() && !self.exit_in_shadow_pass()) as u32
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
