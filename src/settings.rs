//! Public shadow settings: plain structs with defaults, units and ranges.

use crate::error::{PenumbraError, Result};

/// How shadows are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ShadowMethod {
    /// The distance-map method: a fattened shadow map bounds where penumbrae can fall, a
    /// screen-space distance map stores each pixel's distance to its occluder, PCF taps spread
    /// and a separable Gaussian blur widens with that distance, so shadows are sharp at contact
    /// and soft far away (the 2008 distance-map soft-shadow paper; a close relative is Gumbau,
    /// Chover and Sbert, "Screen Space Soft Shadows", GPU Pro, 2010).
    #[default]
    Ours,
    /// [`ShadowMethod::Ours`] without PCF: one hard tap per pixel, the penumbra comes from the
    /// distance-driven blur alone.
    OursFast,
    /// The paper's baseline: fixed-spacing PCF followed by a fixed separable Gaussian blur in
    /// screen space; every edge gets the same softness.
    Traditional,
    /// Percentage-closer soft shadows (Fernando, "Percentage-Closer Soft Shadows", NVIDIA,
    /// 2005): a blocker search estimates the occluder depth, then PCF over a disk whose size
    /// follows the light's size.
    Pcss,
    /// One depth comparison per pixel, nearest texel: hard, aliased edges.
    Hard,
    /// The hardware's bilinear 2x2 percentage-closer filter (one comparison sample with
    /// linear filtering; Reeves, Salesin and Cook, "Rendering antialiased shadows with depth
    /// maps", SIGGRAPH 1987): edges one shadow-map texel wide.
    Hardware2x2,
    /// The ground truth: the average of N hard shadows from N points stratified over the light
    /// ([`ReferenceSettings::samples`]). Not real time: render it with
    /// [`crate::Renderer::render_reference`].
    Reference,
}

impl ShadowMethod {
    /// Every method, in the order tools list them.
    pub const ALL: [ShadowMethod; 7] = [
        ShadowMethod::Ours,
        ShadowMethod::OursFast,
        ShadowMethod::Traditional,
        ShadowMethod::Pcss,
        ShadowMethod::Hard,
        ShadowMethod::Hardware2x2,
        ShadowMethod::Reference,
    ];

    /// The real-time methods: all but the reference, which [`ShadowMethod::ALL`] lists last.
    pub const REAL_TIME: [ShadowMethod; 6] = {
        assert!(matches!(Self::ALL[6], ShadowMethod::Reference));
        let mut methods = [ShadowMethod::Ours; 6];
        let mut i = 0;
        while i < methods.len() {
            methods[i] = Self::ALL[i];
            i += 1;
        }
        methods
    };

    /// The name used on command lines (`ours`, `ours-fast`, `traditional`, `pcss`, `hard`, `hw2x2`).
    pub fn name(self) -> &'static str {
        match self {
            ShadowMethod::Ours => "ours",
            ShadowMethod::OursFast => "ours-fast",
            ShadowMethod::Traditional => "traditional",
            ShadowMethod::Pcss => "pcss",
            ShadowMethod::Hard => "hard",
            ShadowMethod::Hardware2x2 => "hw2x2",
            ShadowMethod::Reference => "reference",
        }
    }

    /// Parses a command-line name; the error lists the valid ones.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| {
            let names: Vec<_> = Self::ALL.iter().map(|m| m.name()).collect();
            PenumbraError::setting(
                "method",
                format!("unknown method `{name}`; choose one of {}", names.join(", ")),
            )
        })
    }

    /// True for the methods that compute a screen-space visibility texture and composite it.
    pub fn is_screen_space(self) -> bool {
        !matches!(self, ShadowMethod::Hard | ShadowMethod::Hardware2x2)
    }

    /// True for the distance-map methods (fattened map, distance map, distance-driven passes).
    pub fn uses_distance_map(self) -> bool {
        matches!(self, ShadowMethod::Ours | ShadowMethod::OursFast)
    }
}

/// Quality presets: more taps cost more time and give smoother penumbrae.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Quality {
    /// A 1024-texel shadow map, 3x3 PCF, 7 blur taps, 8 PCSS blocker and PCF samples, 64
    /// reference samples.
    Low,
    /// The defaults: a 2048-texel shadow map, 3x3 PCF, 11 blur taps, 16 PCSS samples, 256
    /// reference samples.
    #[default]
    Medium,
    /// A 2048-texel shadow map, 4x4 PCF, 15 blur taps, 24 PCSS samples, 512 reference samples.
    High,
    /// A 4096-texel shadow map, 5x5 PCF, 21 blur taps, 32 PCSS samples, 1024 reference samples.
    Ultra,
}

impl Quality {
    /// Every preset, from cheapest to most expensive.
    pub const ALL: [Quality; 4] = [Quality::Low, Quality::Medium, Quality::High, Quality::Ultra];

    /// The name used on command lines and in files: `low`, `medium`, `high` or `ultra`.
    pub fn name(self) -> &'static str {
        match self {
            Quality::Low => "low",
            Quality::Medium => "medium",
            Quality::High => "high",
            Quality::Ultra => "ultra",
        }
    }

    /// Parses a name given by [`Quality::name`]; any other name is a
    /// [`PenumbraError::InvalidSetting`] for `quality` that lists the valid ones.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL.into_iter().find(|q| q.name() == name).ok_or_else(|| {
            PenumbraError::setting(
                "quality",
                format!("unknown preset `{name}`; choose one of low, medium, high, ultra"),
            )
        })
    }
}

/// How the distance-map method's spreads are chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum SpreadMode {
    /// Derived from the light's size (directional: angular diameter; spot: radius), the shadow
    /// map's texel size and the camera's projection, so the penumbra width matches
    /// `2 d tan(theta / 2)` (directional) or `2 R d / D` (spot) at every pixel.
    Physical,
    /// Set by hand, as in the paper.
    Manual {
        /// How far casters are pushed out along their smoothed normals for the fattened map,
        /// world units, >= 0.
        fatten_distance: f32,
        /// PCF tap spacing gained per world unit of receiver-to-occluder distance, in
        /// shadow-map texels, >= 0.
        pcf_spread: f32,
        /// Blur step gained per world unit of receiver-to-occluder distance, in pixels, >= 0.
        blur_spread: f32,
    },
}

/// PCF kernel: N x N taps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PcfKernel {
    /// 3 x 3 = 9 taps (the default).
    #[default]
    Pcf3x3,
    /// 4 x 4 = 16 taps.
    Pcf4x4,
    /// 5 x 5 = 25 taps.
    Pcf5x5,
}

impl PcfKernel {
    /// Taps per side.
    pub fn side(self) -> u32 {
        match self {
            PcfKernel::Pcf3x3 => 3,
            PcfKernel::Pcf4x4 => 4,
            PcfKernel::Pcf5x5 => 5,
        }
    }
}

/// The tile classification of [`PenumbraSettings::tiles`]: a pass bounds each 16 x 16 pixel
/// screen tile's pixels by its depth range and tests them against the fattened map reduced
/// 8 x 8 to its least depth, and the distance map draws only the tiles where a pixel can lie
/// inside the fattened shadow (conservative: the visibility is the same as without it).
///
/// Measured on the teapot at 1280x1024: on Mesa's software rasterizer, where a full-screen pass
/// costs about the same whatever its shader does, the distance map went from 48 to 36 ms; on an
/// NVIDIA H200, whose depth test already skips the pixels cheaply, it went from 0.60 to 0.69 ms
/// (the classification's own cost), at every camera distance (`docs/bench/archive/report-full-h200.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TileClassification {
    /// The compute path (the default, [`PenumbraSettings::fragment_passes`] off): on, its
    /// passes run over the list of kept tiles. The draws: on where the device is a software
    /// rasterizer (its adapter a CPU), off on GPUs.
    #[default]
    Auto,
    /// Always classify the tiles (on a GPU too), as long as
    /// [`PenumbraSettings::mask_early_out`] is on.
    On,
    /// Never classify: the distance map runs over the whole screen (the compute path lists
    /// every tile).
    Off,
}

/// How the distance-map method makes its fattened map ([`PenumbraSettings::fattening`]): the
/// map of where a penumbra can fall beside a caster, which the tile classification and the
/// distance map test each pixel against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Fattening {
    /// [`Fattening::Dilation`] where the casters have at least [`Fattening::AUTO_TRIANGLES`]
    /// triangles, [`Fattening::Geometry`] below: the drawn map costs by the vertex, the derived
    /// one by the texel whatever the casters. With the exit map kept by the shadow map's pass
    /// ([`crate::ExitMapDraw::Auto`], from the same count) a light then draws its casters once.
    /// On lavapipe (the bench's caster sweep, `docs/bench/quick-lavapipe.md`, "Growth", the run
    /// at f5a481c) `ours`' own cost with the derived map was 1.50x / 1.11x / 0.82x that with the
    /// drawn one (both with the exit map kept) at 9,216 / 147,456 / 2,359,296 triangles (1.69x /
    /// 1.14x / 0.65x in the run before, at 28fe8e5: three frames a figure); not measured on a
    /// GPU.
    #[default]
    Auto,
    /// The method's own: the casters drawn again from the light, each vertex pushed out along
    /// its smoothed normal by the fatten distance (a second geometry pass per light). What the
    /// draws use (a device without compute shaders, or [`PenumbraSettings::fragment_passes`]).
    Geometry,
    /// Derived from the shadow map in compute, with no second geometry pass
    /// (`light_maps::dilated_map`), at a quarter of the shadow map's resolution. Each texel
    /// holds the least depth of the shadow map's silhouettes (its steps of more than four
    /// texels along the light) within the fatten distance of it across the light (for a spot or
    /// point light, at each silhouette's own distance from it) and of the caster under it:
    /// where a shadow can fall. Beside a shadow the distance is taken to the silhouette nearest
    /// the texel, found by a jump flood. Measured against the reference
    /// (`docs/bench/fattening-lavapipe.md`). The draws fall back to [`Fattening::Geometry`].
    Dilation,
}

impl Fattening {
    /// Casters' triangles from which [`Fattening::Auto`] derives the fattened map: the
    /// exit map's ([`crate::ExitMapDraw::AUTO_TRIANGLES`]), so that both leave the casters'
    /// second and third drawing together.
    pub const AUTO_TRIANGLES: usize = crate::ExitMapDraw::AUTO_TRIANGLES;

    /// Whether the fattened map is derived for casters of `triangles` triangles (where the
    /// device runs compute passes).
    pub fn derived(self, triangles: usize) -> bool {
        match self {
            Fattening::Auto => triangles >= Self::AUTO_TRIANGLES,
            Fattening::Geometry => false,
            Fattening::Dilation => true,
        }
    }
}

/// Settings of the distance-map method ([`ShadowMethod::Ours`] and [`ShadowMethod::OursFast`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PenumbraSettings {
    /// Default [`SpreadMode::Physical`].
    pub spreads: SpreadMode,
    /// PCF taps (the fast mode uses one hard tap whatever this says). Default 3x3.
    pub pcf_kernel: PcfKernel,
    /// Tap spacing at zero distance, shadow-map texels, in [0, 16]: in physical mode the least
    /// spacing, which smooths the map's texels at contact. Default 0.5.
    pub pcf_base_spacing: f32,
    /// In physical mode, the share of the penumbra's variance made by PCF (the rest by the
    /// blur), in [0, 1]. Default 0.75: PCF filters the shadow map across the light, where a
    /// caster's shape and a receiver's slant are what they are, and the screen-space blur only
    /// smooths its taps. With 0.5, penumbrae on walls the light grazes were 0.83-0.87x as wide
    /// as the reference's (tests/accuracy/near_blocker.rs), and the bench scenes' penumbra error was
    /// higher (docs/benchmark.md). The fast mode uses 0.
    pub pcf_variance_share: f32,
    /// Rotate the PCF taps per pixel by a noise angle to break up banding. Default true.
    pub rotate_taps: bool,
    /// Take no shadow-map taps where the mask says no shadow can fall. Default true.
    pub mask_early_out: bool,
    /// Beside a shadow (inside the fattened shadow, the light's centre in sight), take the
    /// distance to the caster the receiver sees nearest the light's centre: a search of 16 taps
    /// of the real shadow map, only at those pixels. Without it the distance there is the
    /// fattened surface's, which beside a thick caster's foot is too far: without the search
    /// the penumbra there is more than 1.3x the reference's width, with it within 15%
    /// (`tests/accuracy/truth.rs`). Inside a shadow (the light's centre hidden) it takes the distance to
    /// the silhouette the receiver sees nearest the light's centre: 8 rays of up to 4 taps of the
    /// real shadow map, 2 more to bisect the nearest crossing and 2 of the exit map. Without it
    /// the distance there is to the back face under the receiver, which beside a rounded body
    /// is too near. Default true.
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub nearest_caster: bool,
    /// Whether the distance map (and so PCF and the blur) runs only on the 16 x 16 pixel screen
    /// tiles where the light's fattened shadow can fall. Needs `mask_early_out`. Default
    /// [`TileClassification::Auto`].
    #[cfg_attr(feature = "serde", serde(default))]
    pub tiles: TileClassification,
    /// On the compute path, list apart the screen tiles whose every pixel lies on a surface
    /// turned away from the light (by more than the light's angular radius there, plus a
    /// margin): the light reaches none of it, so the distance map, PCF and the blur skip those
    /// tiles and their visibility is 0 (the lit passes' cosine is 0 there too). Pixels the
    /// receiver mask leaves out keep a tile listed as before. Off: those tiles get PCF's and the
    /// blur's values, near 0 on a closed caster's far side; an engine that lights the back of
    /// thin surfaces through the visibility (foliage translucency) may want that. Default true
    /// (docs/cost.md, "Tiles facing away from the light").
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub skip_tiles_facing_away: bool,
    /// On the compute path, list apart the screen tiles that lie deep inside a shadow: every
    /// pixel on one plane, one map tile (cascade, cube face) serving them, and every shadow-map
    /// texel that the PCF's taps or the blur's pixels around them can read, at the widest
    /// penumbra the casters nearby allow, in front of the receiver plane by two texels. The
    /// distance map, PCF and the blur skip those tiles and write their visibility 0, which is
    /// what the taps would find there; the work then follows the penumbrae, not the shadows'
    /// area. Only in physical mode with the nearest-caster search, without the indirect term and
    /// for lights other than rectangles and disks (elsewhere the test is not made). The frame is
    /// the same to the bit where the blur reads no other surface (the floor under the teapot);
    /// across a depth edge the blur's little light there is dropped (0.007 under the room's desk).
    /// Default false: it costs a reduction of the shadow map when the maps are drawn and a test of
    /// each kept tile, and on Mesa's software rasterizer that took about what it saved (0.94x to
    /// 1.11x the screen-space passes' time, docs/cost.md, "Tiles deep in the umbra"); it has not
    /// been measured on a GPU yet.
    #[cfg_attr(feature = "serde", serde(default))]
    pub skip_umbra_tiles: bool,
    /// In physical mode, PCF at half resolution where the penumbra is wide (its standard
    /// deviation at least 2 pixels along both screen axes): one pixel of each 2 x 2 block takes
    /// the taps in a draw of its own and the others interpolate, except near contact and at
    /// depth edges, which keep full resolution. Default false: on Mesa's software rasterizer,
    /// where a pass costs what its pixels do whatever its shader does, it makes PCF slower
    /// (docs/cost.md), and it has not been measured on a GPU yet.
    #[cfg_attr(feature = "serde", serde(default))]
    pub reduced_resolution: bool,
    /// Taps of each blur direction, odd, in [1, 31]. Default 11.
    pub blur_taps: u32,
    /// Weight blur taps by how near they lie to the blurred pixel's plane (its depth and, where
    /// the receiver is flat, the depth's slope along the blur's axis), so the blur does not
    /// bleed across depth discontinuities but runs its whole length along a receiver seen at a
    /// grazing angle (weighting by the pixel's own depth cut it short there: a wall's or a
    /// floor's penumbra came out too narrow). Default true.
    pub depth_aware_blur: bool,
    /// Run the screen-space passes as draws, as before the compute path. Default false: where
    /// the device has compute shaders they are compute passes, the distance-map method's over a
    /// list of the 16 x 16 pixel screen tiles a shadow can reach (it then costs what those
    /// tiles do; on a GPU, fragment work costs many times the same work in compute), the
    /// baselines' over the screen; the writes into the light's layer (the resolve, the copy of
    /// the blur's result over the listed tiles) stay draws. [`Self::reduced_resolution`] is
    /// draws only: it turns the draws on for the distance-map method, as does a device without
    /// compute shaders (WebGL 2, wgpu's GL backend).
    #[cfg_attr(feature = "serde", serde(default))]
    pub fragment_passes: bool,
    /// How much shadows far from their occluder are lightened by bounced light, in [0, 1];
    /// 0 turns it off. Default 0.
    pub indirect_weight: f32,
    /// The resolution of the light's maps. Default [`MapResolution::Configured`]: coarser maps
    /// cost accuracy where measured (see [`MapResolution::FromPenumbra`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub map_resolution: MapResolution,
    /// How the fattened map is made: the casters drawn again, pushed out, or derived from the
    /// shadow map in compute ([`Fattening`]). Default [`Fattening::Auto`]: derived from
    /// [`Fattening::AUTO_TRIANGLES`] caster triangles.
    #[cfg_attr(feature = "serde", serde(default))]
    pub fattening: Fattening,
    /// Draw the exit map: the casters' back faces from the light, a geometry pass of its own.
    /// Inside a shadow, the distance map extrapolates where the rays leave the occluder to the
    /// silhouette nearest the light's centre, and takes the distance to the back face under
    /// the receiver when that is nearer than the front's. Off: the distance there is to the
    /// silhouette's caster as the shadow map holds it (its front): beside a pillar's foot under
    /// a sun the penumbra was then 1.49x the reference's width (with the derived fattened map,
    /// `docs/bench/fattening-lavapipe.md`).
    /// Default true.
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub exit_map: bool,
}

/// The resolution the distance-map method draws a light's maps at
/// ([`PenumbraSettings::map_resolution`]; the other methods draw at
/// [`ShadowMapSettings::resolution`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapResolution {
    /// [`ShadowMapSettings::resolution`], always (the default).
    #[default]
    Configured,
    /// [`ShadowMapSettings::resolution`], or half of it (never under 256 texels) while the
    /// light's penumbrae are wide enough: a wide penumbra hides a coarse map, and the
    /// light-space passes cost what their texels do. Where a penumbra is narrower than a
    /// screen pixel, the pixel's width counts instead: a map texel finer than the pixel does
    /// not show. The compute path's PCF pass counts the pixels in a penumbra and those whose
    /// penumbra is narrower than `narrowest_texels` texels of the map at half the resolution;
    /// half is taken while at most 5% are (`crate::map_resolution::NARROW_SHARE`), the
    /// configured resolution again once more than 10% are at the resolution drawn. Penumbrae
    /// narrow to nothing where a caster touches its receiver, so a contact seen close keeps
    /// the configured resolution (the benchmark's teapot and character do at 1280x1024).
    ///
    /// What half the resolution costs, where it was taken (`tests/lights/map_resolution.rs`,
    /// `tests/accuracy/truth.rs`, `tests/accuracy/near_blocker.rs`): a floating box's penumbra keeps its width;
    /// under the truth scene's sphere light the mean signed error in the penumbrae's inner
    /// halves went from +0.017 to +0.032 and one width from 1.07x to 1.11x the reference's;
    /// the room's lamp kept its wall widths within 0.93x of the reference's and its penumbra
    /// RMSE went from 0.053 to 0.057. At a quarter, the lamp shade's rim was found less
    /// precisely and a width fell to 0.89x: a quarter is not offered.
    ///
    /// The counts come back a frame or two later without a wait, so a light starts at the
    /// configured resolution and moves in a few frames; [`crate::LightReport`] says what each
    /// light drew at and what it measured ([`crate::Shadows::settle`] waits for them). The
    /// draws ([`PenumbraSettings::fragment_passes`], or a device without compute shaders) and
    /// the manual spreads measure nothing and keep the configured resolution.
    FromPenumbra {
        /// The narrowest penumbra (or pixel), in texels of the coarser map, that may be drawn
        /// with it, in [1, 64]. 4 is [`MapResolution::from_penumbra`]'s: at 2 the benchmark's
        /// character went to half the resolution at 400x320 and its penumbra RMSE from 0.066
        /// to 0.078.
        narrowest_texels: f32,
    },
}

impl MapResolution {
    /// [`MapResolution::FromPenumbra`] with 4 texels.
    pub fn from_penumbra() -> Self {
        MapResolution::FromPenumbra {
            narrowest_texels: 4.0,
        }
    }
}

impl Default for PenumbraSettings {
    fn default() -> Self {
        Self {
            spreads: SpreadMode::Physical,
            pcf_kernel: PcfKernel::Pcf3x3,
            pcf_base_spacing: 0.5,
            pcf_variance_share: 0.75,
            rotate_taps: true,
            mask_early_out: true,
            nearest_caster: true,
            tiles: TileClassification::Auto,
            skip_tiles_facing_away: true,
            skip_umbra_tiles: false,
            reduced_resolution: false,
            blur_taps: 11,
            depth_aware_blur: true,
            fragment_passes: false,
            indirect_weight: 0.0,
            map_resolution: MapResolution::default(),
            fattening: Fattening::Auto,
            exit_map: true,
        }
    }
}

/// Settings of the baseline: fixed PCF + fixed Gaussian blur.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TraditionalSettings {
    /// Default 3x3.
    pub pcf_kernel: PcfKernel,
    /// Spacing between PCF taps, shadow-map texels, in [0, 16]. Default 1.5.
    pub pcf_spacing: f32,
    /// Taps of each blur direction, odd, in [1, 31]. Default 11.
    pub blur_taps: u32,
    /// Step between blur taps, pixels, in [0, 16]. Default 1.
    pub blur_step: f32,
}

impl Default for TraditionalSettings {
    fn default() -> Self {
        Self {
            pcf_kernel: PcfKernel::Pcf3x3,
            pcf_spacing: 1.5,
            blur_taps: 11,
            blur_step: 1.0,
        }
    }
}

/// Settings of the ground-truth reference.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ReferenceSettings {
    /// Points sampled on the light, each one hard shadow map, in [1, 4096]. Default 256.
    pub samples: u32,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        Self { samples: 256 }
    }
}

/// Settings of PCSS.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PcssSettings {
    /// Blocker-search taps, in [1, 64]. Default 16.
    pub blocker_samples: u32,
    /// PCF taps, in [1, 64]. Default 16.
    pub pcf_samples: u32,
}

impl Default for PcssSettings {
    fn default() -> Self {
        Self {
            blocker_samples: 16,
            pcf_samples: 16,
        }
    }
}

/// Depth format of the light's maps (the shadow map, and the distance-map method's fattened
/// and exit maps).
///
/// The default is 16 bits: half the bytes, and a GPU clears and writes a map in proportion to
/// its texels (on an NVIDIA H100 the shadow-map pass took 0.12 / 0.42 / 1.55 ms at 1024 /
/// 2048 / 4096 texels a cascade, `docs/bench/archive/report-full-h100.md`); what 16 bits save there
/// has not been timed yet.
/// Its precision holds where measured on the software adapter: the room's lamp and monitor
/// (a point and a spot light, `tests/accuracy/near_blocker.rs`) gave penumbra RMSE 0.0530 against
/// 0.0543 in 32 bits and wall widths within 0.002 of them; the truth scene's widths under a
/// spot, a sphere and a sun light (`tests/accuracy/truth.rs`) moved by at most 0.002 of the ratio; and
/// no acne nor detached shadow at a grazing sun in 16 bits (`tests/robustness/grazing.rs`). The
/// reference renders its samples in 32 bits whatever this says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DepthFormat {
    /// 16-bit normalized: half the memory, needs a tight near/far fit.
    #[default]
    Depth16,
    /// At least 24 bits (the device picks 24-bit unorm or 32-bit float).
    Depth24,
    /// 32-bit float.
    Depth32,
}

impl DepthFormat {
    /// The wgpu format the light's depth maps are created with: `Depth16Unorm`,
    /// `Depth24Plus` or `Depth32Float`.
    pub fn texture_format(self) -> wgpu::TextureFormat {
        match self {
            DepthFormat::Depth16 => wgpu::TextureFormat::Depth16Unorm,
            DepthFormat::Depth24 => wgpu::TextureFormat::Depth24Plus,
            DepthFormat::Depth32 => wgpu::TextureFormat::Depth32Float,
        }
    }
}

/// Which triangles the shadow pass skips.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CullMode {
    /// Draw both sides: works for open meshes and single-sided planes (the default).
    #[default]
    None,
    /// Skip triangles facing away from the light: the usual choice for a camera.
    Back,
    /// Skip triangles facing the light, so depth comes from the back sides of closed meshes:
    /// less acne on lit surfaces, but open meshes and planes cast no shadow.
    Front,
}

impl CullMode {
    /// The face the shadow-map pipelines cull, as wgpu's primitive state takes it (`None`:
    /// no culling).
    pub fn face(self) -> Option<wgpu::Face> {
        match self {
            CullMode::None => None,
            CullMode::Back => Some(wgpu::Face::Back),
            CullMode::Front => Some(wgpu::Face::Front),
        }
    }
}

fn default_normal_offset() -> f32 {
    1.5
}

fn default_true() -> bool {
    true
}

/// Where a light's shadow map is placed: a directional light's orthographic window, a spot
/// light's window inside its cone (an off-centre perspective projection).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LightFit {
    /// Around every caster's shadow in the scene (a spot light: its whole cone), wherever the
    /// camera looks. The map does not move with the camera, so its texels are wasted on what
    /// the camera does not see.
    Scene,
    /// Around what the camera sees: the light-space bounds of the camera frustum up to
    /// `max_distance` world units from the eye (0: up to the camera's far plane), clipped to
    /// where casters can throw shadows (a spot light: the part of its cone in which the
    /// camera sees the scene's bounds). Sharper than [`LightFit::Scene`] when the camera is
    /// close to a large scene or sees a small part of a wide cone; the map follows the camera
    /// (see [`ShadowMapSettings::snap_to_texels`]).
    CameraFrustum {
        /// World units, >= 0 and finite; 0 means the camera's far plane.
        max_distance: f32,
    },
}

impl Default for LightFit {
    fn default() -> Self {
        LightFit::CameraFrustum { max_distance: 0.0 }
    }
}

/// The shadow map: its size, format, bias and culling.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShadowMapSettings {
    /// Width and height in texels, a power of two in [64, 8192] and within the device's limit;
    /// with cascades, each cascade's, at most [`MAX_CASCADE_RESOLUTION`]. Default 2048.
    pub resolution: u32,
    /// Default [`DepthFormat::Depth16`].
    pub depth_format: DepthFormat,
    /// Constant depth bias, in units of the depth format's smallest resolvable difference
    /// (for 32-bit float, about 2^-23 times the largest depth in the triangle). Default 4.
    pub constant_bias: i32,
    /// Slope-scaled depth bias: times the triangle's largest depth slope in light space.
    /// In [0, 16]. Default 2.0.
    pub slope_bias: f32,
    /// Normal-offset bias: receivers are moved this many shadow-map texels along their surface
    /// normal before the shadow-map lookup, in [0, 8]. It removes acne on surfaces nearly
    /// parallel to the light, where depth biases would have to be large; too much detaches
    /// thin contact shadows. Default 1.5. (The reference takes no offset.)
    #[cfg_attr(feature = "serde", serde(default = "default_normal_offset"))]
    pub normal_offset: f32,
    /// Which faces the shadow pass culls. Default [`CullMode::None`].
    pub cull_mode: CullMode,
    /// Where the shadow map is placed. Default: fitted to the camera frustum
    /// ([`LightFit::CameraFrustum`] up to the far plane). Either fit computes the near and far
    /// planes by clipping the scene's bounds against the four sides of the light's frustum, so
    /// no depth precision is spent outside them.
    #[cfg_attr(feature = "serde", serde(default))]
    pub fit: LightFit,
    /// Keep the light's texel size fixed while the camera moves (it changes in steps of
    /// 2^(1/8) when the camera's view grows or shrinks) and move its map in whole texels, so
    /// shadow edges do not shimmer. Costs up to a few percent of the resolution. Default true.
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub snap_to_texels: bool,
    /// Cascades of a directional light's map fitted to the camera
    /// ([`LightFit::CameraFrustum`], perspective camera). Default: 4.
    #[cfg_attr(feature = "serde", serde(default))]
    pub cascades: CascadeSettings,
    /// Set a 16-bit light map to the far plane, before its casters are drawn, with a copy from
    /// a buffer of 0xffff instead of the depth pass's clear: the same depths, for less time on
    /// the devices measured (an NVIDIA H200: the teapot's shadow-map pass 0.52 -> 0.40 ms;
    /// lavapipe: 12.4 -> 9.0 ms; docs/cost.md, "The light maps' clears"). The buffer is as
    /// large as the largest atlas, and every light shares it: 8 MiB beside a spot light's
    /// 2048^2 map, 16 MiB beside a sun's two cascades ([`crate::Shadows::allocated_bytes`]
    /// counts it). No effect on 24- and 32-bit maps, on wgpu's GL backend, or on an atlas that
    /// keeps some of its tiles this frame (it clears the others as before). Default true.
    #[cfg_attr(feature = "serde", serde(default = "default_true"))]
    pub clear_by_copy: bool,
    /// How the distance-map method's exit map finds the faces turned away from the light (the
    /// same map either way). Default [`ExitFaces::Winding`].
    #[cfg_attr(feature = "serde", serde(default))]
    pub exit_faces: ExitFaces,
}

/// How the exit map ([`ShadowMapSettings::exit_faces`]) finds the faces turned away from the
/// light. Both give the same map (`tests/execution.rs` compares them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ExitFaces {
    /// Draws of meshes whose triangles all turn one way cull the faces toward the light; the
    /// others test each fragment's side. On an NVIDIA H200 the teapot's exit map took 0.11 ms
    /// against 0.16 with [`ExitFaces::Fragment`] (`docs/cost.md`); on lavapipe 2.7 ms against
    /// 6.3: with no fragment stage the rasterizer tests depth before shading.
    #[default]
    Winding,
    /// Every draw tests each fragment's side.
    Fragment,
}

/// The largest [`ShadowMapSettings::resolution`] with two or more cascades: an atlas of 2 x 2
/// is then 8192 texels a side.
pub const MAX_CASCADE_RESOLUTION: u32 = 4096;

/// Cascaded shadow maps: a directional light's map split along the camera's view distance
/// into windows of the same resolution, the nearest smallest, so texels near the camera are
/// small and far ones large. The cascades lie side by side in one atlas of tiles of
/// [`ShadowMapSettings::resolution`] texels, as many as the view uses: one tile, 2 x 1 for two
/// cascades, 2 x 2 for three or four ([`crate::light_space::AtlasGrid`]); every pixel reads the
/// cascade its view distance falls in. Spot lights and orthographic cameras use one map.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CascadeSettings {
    /// Number of cascades, 1 to 4. Default 4. One is the single map of earlier versions.
    pub count: u32,
    /// The split scheme, in [0, 1]: cascade `i` of `N` ends at view distance
    /// `split x n (f / n)^(i/N) + (1 - split) x (n + (f - n) i / N)`, where `n` and `f` are
    /// the nearest and farthest view distances of the scene inside the camera's frustum.
    /// 0 splits uniformly (equal depth ranges), 1 logarithmically (equal ratios: the texel
    /// size grows in step with the distance). Default 0.8.
    pub split: f32,
    /// The blend band between cascades, as a fraction of a cascade's depth range, in [0, 0.5].
    /// Inside it pixels pick the next cascade with a probability rising from 0 to 1 across the
    /// band (an ordered dither the blur smooths over), so the boundary does not show as a
    /// line. Default 0.1.
    pub blend: f32,
    /// The view distance where the first cascade ends, in world units (0, the default: where
    /// `split` puts it). The others then split the rest of the range by `split`. An engine's
    /// own cascade setting carries over this way (Bevy's `first_cascade_far_bound`); a value
    /// outside the range the scene takes in the view is not used.
    #[cfg_attr(feature = "serde", serde(default))]
    pub first_end: f32,
}

impl Default for CascadeSettings {
    fn default() -> Self {
        Self {
            count: 4,
            split: 0.8,
            blend: 0.1,
            first_end: 0.0,
        }
    }
}

impl Default for ShadowMapSettings {
    fn default() -> Self {
        Self {
            resolution: 2048,
            depth_format: DepthFormat::default(),
            constant_bias: 4,
            slope_bias: 2.0,
            normal_offset: default_normal_offset(),
            cull_mode: CullMode::default(),
            fit: LightFit::default(),
            snap_to_texels: true,
            cascades: CascadeSettings::default(),
            clear_by_copy: true,
            exit_faces: ExitFaces::default(),
        }
    }
}

/// All shadow settings. `Default` is the distance-map method in physical mode on a 2048^2
/// 32-bit shadow map.
///
/// Start from [`ShadowSettings::default`] or a [`ShadowSettings::preset`], change fields, and
/// check them with [`ShadowSettings::validate`] ([`crate::Shadows`] checks them too):
///
/// ```
/// # fn main() -> penumbra::Result<()> {
/// use penumbra::{PenumbraError, Quality, ShadowMethod, ShadowSettings};
///
/// // The PCF + Gaussian baseline at high quality: 4x4 PCF on a 2048-texel map.
/// let mut settings = ShadowSettings::preset(ShadowMethod::Traditional, Quality::High);
/// assert_eq!(settings.traditional.pcf_kernel.side(), 4);
/// assert_eq!(settings.shadow_map.resolution, 2048);
/// // Checked against a device's largest texture side (its `max_texture_dimension_2d`).
/// settings.validate(Some(8192))?;
///
/// // An even blur tap count is refused, and the error names the field.
/// settings.traditional.blur_taps = 12;
/// match settings.validate(None) {
///     Err(PenumbraError::InvalidSetting { name, .. }) => assert_eq!(name, "traditional.blur_taps"),
///     other => panic!("expected an invalid setting, got {other:?}"),
/// }
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ShadowSettings {
    /// Which method filters the shadows. Default [`ShadowMethod::Ours`].
    pub method: ShadowMethod,
    /// The lights' shadow maps (size, format, biases, fit, cascades): used by every method.
    pub shadow_map: ShadowMapSettings,
    /// Read by the distance-map methods ([`ShadowMethod::Ours`], [`ShadowMethod::OursFast`]).
    pub penumbra: PenumbraSettings,
    /// Read by the PCF + Gaussian baseline ([`ShadowMethod::Traditional`]).
    pub traditional: TraditionalSettings,
    /// Read by [`ShadowMethod::Pcss`].
    pub pcss: PcssSettings,
    /// Read by the ground truth ([`ShadowMethod::Reference`]).
    pub reference: ReferenceSettings,
    /// How some passes do their work on the device: each choice gives the same shadows (but
    /// for a half float's rounding). The defaults choose by device; the benchmark and the
    /// tests set them to compare.
    #[cfg_attr(feature = "serde", serde(default))]
    pub execution: ExecutionSettings,
}

/// How some screen-space passes do their work ([`ShadowSettings::execution`]). Every choice
/// gives the same shadows (`tests/execution.rs` renders each way and compares), but for
/// [`ExecutionSettings::half_intermediates`]' rounding and the few exit-map texels
/// [`ExecutionSettings::exit_map_draw`] sees otherwise; they differ in cost and memory, which
/// depend on the device. The defaults are what measured cheaper on each kind of
/// device.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(default))]
pub struct ExecutionSettings {
    /// How the compute path clears its screen-space intermediates. Default
    /// [`DevicePath::Auto`]: compute passes on a GPU (an H100's screen-space passes 0.37 ms less
    /// on the teapot's first view), render passes' clears on a CPU adapter (a memory fill
    /// there; lavapipe's frame took 4-7% longer with compute clears).
    pub clears: DevicePath,
    /// How the tile classification tests the kept tiles' pixels: a workgroup per tile, one
    /// pixel an invocation, or one invocation per tile looping over its pixels. Default
    /// [`TilePixels::Auto`].
    pub tile_pixels: TilePixels,
    /// The compute path's variable PCF reads the distance to the occluder itself, in the same
    /// pass (true), or reads what a distance-map pass of its own wrote (false). Default true.
    pub distance_in_pcf: bool,
    /// The compute passes that finish a light's visibility write its layer themselves where
    /// the device can store half floats and the layer allows it (true), or a draw writes it
    /// (false). Default true.
    pub compute_layer_writes: bool,
    /// The compute path keeps its screen-space intermediates (the visibility before the blur
    /// and between its axes, the blur's deviations along x and y, the distance map) in single
    /// or paired half floats where the device can store them (true: for `ours` 10 bytes a
    /// pixel where 32-bit floats take 20), or in 32-bit floats (false). Unlike the other choices here, the two differ by a half
    /// float's rounding: the layers within 2e-3 but at about one texel in 10,000, the frames
    /// within 2 of 255 (`tests/execution.rs`). The draws keep half floats either way. Default
    /// true.
    pub half_intermediates: bool,
    /// Keep `ours`' visibility before the blur in a texture of its own, which
    /// [`crate::LightTexture::Visibility`] (the `pcf` debug view) reads (true). Off (the
    /// default), where the compute passes write the light's layer and keep half floats
    /// ([`Self::compute_layer_writes`], [`Self::half_intermediates`]), the variable PCF writes
    /// straight into the light's layer, which the blur's horizontal axis reads and its vertical
    /// axis then overwrites: the same shadows in 2 bytes a pixel less, with no raw visibility
    /// left to read.
    pub raw_visibility: bool,
    /// Which pass makes the distance-map method's exit map (the casters' faces turned away
    /// from the light). Default [`ExitMapDraw::Auto`].
    pub exit_map_draw: ExitMapDraw,
    /// Run the screen-space passes of lights alike as one (true): the tile classification (with
    /// the reduction of the fattened maps before it), the variable PCF and each blur axis are
    /// each one dispatch over every light of the group (each light's tiles listed apart in it),
    /// where each light would run its own. A group is the lights of `ours` of one kind whose
    /// maps share arrays and whose chains are alike, where the compute passes write the
    /// lights' layers, keep half floats and test the tiles' pixels by workgroups (a GPU;
    /// [`TilePixels::Workgroup`] elsewhere), the umbra's tiles are not listed apart
    /// ([`PenumbraSettings::skip_umbra_tiles`]) and the light's maps are not sized from the
    /// penumbra ([`MapResolution::FromPenumbra`]). Fewer dispatches a light (what a GPU pays per
    /// dispatch, not per pixel). A group keeps its lights' intermediates (the distance map, the
    /// deviations, the blur's horizontal result: 8 bytes a pixel in half floats) per listed
    /// tile, in a pool of [`Self::light_group_pool`] screens' worth of tiles. Not measured on a
    /// GPU yet. Default false.
    pub light_groups: bool,
    /// How many screens' worth of listed tiles a group of lights' pool of intermediates holds
    /// ([`Self::light_groups`]; 8 bytes a pixel each in half floats, at most the group's lights;
    /// 0: as many as the group has lights). Where the group's lights list more tiles than that
    /// in a frame, whole lights wait for a later round of the PCF and the blur; the passes
    /// record enough rounds for any lists (the lights over this, rounded up: each round holds at
    /// least this many lights), each a dispatch of each pass, with no workgroups where every
    /// light's tiles fit. Default 2: a group of two lights or more holds 16 bytes a pixel of
    /// intermediates, each of its lights adds its 2-byte layer of the visibility, and sixteen
    /// lights record eight rounds.
    pub light_group_pool: u32,
}

/// A choice of [`ExecutionSettings::exit_map_draw`]: the exit map kept by the shadow map's pass,
/// which takes each fragment of a face turned away from the light into a buffer with an atomic
/// minimum beside its depth test (one geometry pass a light fewer, a fragment stage on every
/// fragment of the shadow map), or drawn by a pass of its own (the casters drawn again, at half
/// the side, with no fragment stage where a mesh's winding is known). The two maps differ only
/// where a texel's four shadow-map texels see different back faces and by the depth bias
/// (`tests/execution.rs`). Where the device's fragment shaders cannot write storage (wgpu's GL
/// backend), it has no compute passes, the shadow map culls faces
/// ([`ShadowMapSettings::cull_mode`] other than `None`), its tiles are under 128 texels or the
/// buffer would pass the device's largest storage binding, the exit map has its own pass
/// whatever the choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ExitMapDraw {
    /// The shadow map's pass where the casters have at least
    /// [`ExitMapDraw::AUTO_TRIANGLES`] triangles, its own pass below: the fragment stage costs
    /// by the fragment and by the triangle, the second drawing by the vertex. On lavapipe
    /// (the bench's caster sweep, teapot split, 1280x1024) `ours`' own cost with the exit map
    /// kept against drawn apart was 1.11x at 9,216 triangles, 1.31x at 147,456 and 0.81x at
    /// 2,359,296 (the first of the two runs in `docs/cost.md`'s table; lavapipe's timings are
    /// noisy, the quick runs since read 1.08x / 1.02x / 0.88x and 1.60x / 0.93x / 0.95x); not
    /// measured on a GPU.
    #[default]
    Auto,
    /// The shadow map's pass, whatever the casters.
    ShadowMapPass,
    /// A pass of its own, whatever the casters.
    OwnPass,
}

impl ExitMapDraw {
    /// Casters' triangles from which [`ExitMapDraw::Auto`] keeps the exit map in the shadow map's
    /// pass: about where the two crossed on lavapipe (between 147,456 and 2,359,296 triangles,
    /// about 560,000 taken as linear between them).
    pub const AUTO_TRIANGLES: usize = 500_000;

    /// Whether the shadow map's pass keeps the exit map for casters of `triangles` triangles
    /// (where the device allows it).
    pub fn in_shadow_pass(self, triangles: usize) -> bool {
        match self {
            ExitMapDraw::Auto => triangles >= Self::AUTO_TRIANGLES,
            ExitMapDraw::ShadowMapPass => true,
            ExitMapDraw::OwnPass => false,
        }
    }
}

impl Default for ExecutionSettings {
    fn default() -> Self {
        Self {
            clears: DevicePath::Auto,
            tile_pixels: TilePixels::Auto,
            distance_in_pcf: true,
            compute_layer_writes: true,
            half_intermediates: true,
            raw_visibility: false,
            exit_map_draw: ExitMapDraw::Auto,
            light_groups: false,
            light_group_pool: 2,
        }
    }
}

/// A choice of [`ExecutionSettings::clears`]: by device, or one whatever the device.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DevicePath {
    /// Compute on a GPU, render passes on a CPU adapter.
    #[default]
    Auto,
    /// Compute passes.
    Compute,
    /// Render passes.
    RenderPass,
}

impl DevicePath {
    /// Whether compute is used on `device`.
    pub(crate) fn compute(self, device: &wgpu::Device) -> bool {
        match self {
            DevicePath::Auto => device.adapter_info().device_type != wgpu::DeviceType::Cpu,
            DevicePath::Compute => true,
            DevicePath::RenderPass => false,
        }
    }
}

/// A choice of [`ExecutionSettings::tile_pixels`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TilePixels {
    /// A workgroup per tile on a GPU; a loop on a CPU adapter, where the loop mostly stops at
    /// the first pixel and a workgroup costs every pixel.
    #[default]
    Auto,
    /// A workgroup per tile, one pixel an invocation.
    Workgroup,
    /// One invocation per tile, looping over its pixels.
    Loop,
}

impl TilePixels {
    /// Whether `device` tests the pixels with a workgroup per tile.
    pub(crate) fn by_workgroup(self, device: &wgpu::Device) -> bool {
        match self {
            TilePixels::Auto => device.adapter_info().device_type != wgpu::DeviceType::Cpu,
            TilePixels::Workgroup => true,
            TilePixels::Loop => false,
        }
    }
}

impl ShadowSettings {
    /// Checks every field against its documented range (and the device's texture limit when
    /// `max_texture_side` is given); the error names the field.
    pub fn validate(&self, max_texture_side: Option<u32>) -> Result<()> {
        let sm = &self.shadow_map;
        if !(64..=8192).contains(&sm.resolution) || !sm.resolution.is_power_of_two() {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!("{} is not a power of two in [64, 8192]", sm.resolution),
            ));
        }
        if let Some(limit) = max_texture_side
            && sm.resolution > limit
        {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!("{} exceeds this device's limit of {limit}", sm.resolution),
            ));
        }
        if let LightFit::CameraFrustum { max_distance } = sm.fit
            && !(max_distance >= 0.0 && max_distance.is_finite())
        {
            return Err(PenumbraError::setting(
                "shadow_map.fit.max_distance",
                format!("{max_distance} must be finite and >= 0"),
            ));
        }
        if !(1..=4).contains(&sm.cascades.count) {
            return Err(PenumbraError::setting(
                "shadow_map.cascades.count",
                format!("{} is outside [1, 4]", sm.cascades.count),
            ));
        }
        if sm.cascades.count > 1 && sm.resolution > MAX_CASCADE_RESOLUTION {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!(
                    "{} texels a cascade makes a {}-texel atlas of {} cascades; at most {MAX_CASCADE_RESOLUTION} with cascades (or set shadow_map.cascades.count to 1)",
                    sm.resolution,
                    2 * sm.resolution,
                    sm.cascades.count
                ),
            ));
        }
        if let Some(limit) = max_texture_side
            && sm.cascades.count > 1
            && 2 * sm.resolution > limit
        {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!(
                    "the cascades' atlas of {} texels exceeds this device's limit of {limit}",
                    2 * sm.resolution
                ),
            ));
        }
        check_range("shadow_map.cascades.split", sm.cascades.split, 0.0, 1.0)?;
        check_range("shadow_map.cascades.blend", sm.cascades.blend, 0.0, 0.5)?;
        if !(sm.cascades.first_end >= 0.0 && sm.cascades.first_end.is_finite()) {
            return Err(PenumbraError::setting(
                "shadow_map.cascades.first_end",
                format!("{} must be finite and >= 0", sm.cascades.first_end),
            ));
        }
        if !(0.0..=8.0).contains(&sm.normal_offset) {
            return Err(PenumbraError::setting(
                "shadow_map.normal_offset",
                format!("{} is outside [0, 8]", sm.normal_offset),
            ));
        }
        if !(0.0..=16.0).contains(&sm.slope_bias) {
            return Err(PenumbraError::setting(
                "shadow_map.slope_bias",
                format!("{} is outside [0, 16]", sm.slope_bias),
            ));
        }
        if !(0..=1 << 20).contains(&sm.constant_bias) {
            return Err(PenumbraError::setting(
                "shadow_map.constant_bias",
                format!("{} is outside [0, 1048576]", sm.constant_bias),
            ));
        }
        let p = &self.penumbra;
        if let SpreadMode::Manual {
            fatten_distance,
            pcf_spread,
            blur_spread,
        } = p.spreads
        {
            for (name, v) in [
                ("penumbra.fatten_distance", fatten_distance),
                ("penumbra.pcf_spread", pcf_spread),
                ("penumbra.blur_spread", blur_spread),
            ] {
                if !(v >= 0.0 && v.is_finite()) {
                    return Err(PenumbraError::setting(
                        name,
                        format!("{v} must be finite and >= 0"),
                    ));
                }
            }
        }
        check_range("penumbra.pcf_base_spacing", p.pcf_base_spacing, 0.0, 16.0)?;
        check_range("penumbra.pcf_variance_share", p.pcf_variance_share, 0.0, 1.0)?;
        check_range("penumbra.indirect_weight", p.indirect_weight, 0.0, 1.0)?;
        if let MapResolution::FromPenumbra { narrowest_texels } = p.map_resolution {
            check_range(
                "penumbra.map_resolution.narrowest_texels",
                narrowest_texels,
                1.0,
                64.0,
            )?;
        }
        check_taps("penumbra.blur_taps", p.blur_taps)?;
        let t = &self.traditional;
        check_range("traditional.pcf_spacing", t.pcf_spacing, 0.0, 16.0)?;
        check_range("traditional.blur_step", t.blur_step, 0.0, 16.0)?;
        check_taps("traditional.blur_taps", t.blur_taps)?;
        if !(1..=4096).contains(&self.reference.samples) {
            return Err(PenumbraError::setting(
                "reference.samples",
                format!("{} is outside [1, 4096]", self.reference.samples),
            ));
        }
        for (name, n) in [
            ("pcss.blocker_samples", self.pcss.blocker_samples),
            ("pcss.pcf_samples", self.pcss.pcf_samples),
        ] {
            if !(1..=64).contains(&n) {
                return Err(PenumbraError::setting(name, format!("{n} is outside [1, 64]")));
            }
        }
        Ok(())
    }

    /// The settings of `quality` for `method`: kernel sizes, tap counts and shadow-map size.
    pub fn preset(method: ShadowMethod, quality: Quality) -> Self {
        let mut s = ShadowSettings {
            method,
            ..Default::default()
        };
        let (resolution, kernel, taps, pcss) = match quality {
            Quality::Low => (1024, PcfKernel::Pcf3x3, 7, 8),
            Quality::Medium => (2048, PcfKernel::Pcf3x3, 11, 16),
            Quality::High => (2048, PcfKernel::Pcf4x4, 15, 24),
            Quality::Ultra => (4096, PcfKernel::Pcf5x5, 21, 32),
        };
        s.shadow_map.resolution = resolution;
        s.penumbra.pcf_kernel = kernel;
        s.penumbra.blur_taps = taps;
        s.traditional.pcf_kernel = kernel;
        s.traditional.blur_taps = taps;
        s.pcss.blocker_samples = pcss;
        s.pcss.pcf_samples = pcss;
        s.reference.samples = match quality {
            Quality::Low => 64,
            Quality::Medium => 256,
            Quality::High => 512,
            Quality::Ultra => 1024,
        };
        s
    }
}

fn check_range(name: &'static str, v: f32, lo: f32, hi: f32) -> Result<()> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(PenumbraError::setting(
            name,
            format!("{v} is outside [{lo}, {hi}]"),
        ))
    }
}

fn check_taps(name: &'static str, n: u32) -> Result<()> {
    if (1..=31).contains(&n) && n % 2 == 1 {
        Ok(())
    } else {
        Err(PenumbraError::setting(
            name,
            format!("{n} must be odd and in [1, 31]"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        ShadowSettings::default().validate(Some(8192)).unwrap();
        let mut s = ShadowSettings::default();
        s.shadow_map.resolution = 1000;
        assert!(
            s.validate(None)
                .unwrap_err()
                .to_string()
                .contains("shadow_map.resolution")
        );
        s.shadow_map.resolution = 4096;
        assert!(s.validate(Some(2048)).unwrap_err().to_string().contains("limit"));
        s.shadow_map.resolution = 1024;
        s.shadow_map.slope_bias = f32::NAN;
        assert!(s.validate(None).unwrap_err().to_string().contains("slope_bias"));
        let mut s = ShadowSettings::default();
        s.shadow_map.normal_offset = -1.0;
        assert!(
            s.validate(None)
                .unwrap_err()
                .to_string()
                .contains("normal_offset")
        );
    }

    #[test]
    fn method_names_round_trip() {
        for m in ShadowMethod::ALL {
            assert_eq!(ShadowMethod::from_name(m.name()).unwrap(), m);
        }
        let err = ShadowMethod::from_name("vsm").unwrap_err().to_string();
        assert!(err.contains("vsm") && err.contains("hw2x2"), "{err}");
    }
}
