//! The compute path's screen-sized intermediates, which every light's chain shares
//! ([`ComputeTargets`]), and their clears.

use super::{DistanceMapCompute, StorageClear, TileListTargets, sigma_storage, visibility_storage};
use crate::chain::Chain;
use crate::gpu_helpers::Target;
use crate::pipeline_cache::CachedDevice;
use crate::settings::DevicePath;

/// The compute path's screen-sized intermediates. Each light's chain runs whole, blur
/// included, before the next light's starts, so one set serves every light: a light adds only
/// its layer of the visibility array to the screen-space memory. After a frame they hold the
/// last light's values (see `Shadows::inspect`).
#[derive(Clone)]
pub(crate) struct ComputeTargets {
    /// The visibility before any blur (PCF, PCSS); none where only the distance-map method's
    /// chains run, each writing its PCF into its light's layer ([`crate::Chain::pcf_in_layer`]).
    pub visibility: Option<Target>,
    /// The screen's size.
    size: (u32, u32),
    /// The blur's horizontal axis, where a chain blurs.
    pub blurred: Option<Target>,
    /// The distance-map method's, where a light runs it.
    pub distance_map: Option<DistanceMapTargets>,
    /// Every tile of the screen listed: the fixed blur runs over all of them.
    pub every_tile: Option<TileListTargets>,
    /// Compute clears of the textures above ([`ComputeTargets::clear`]).
    clears: TargetClears,
    /// Whether they clear by compute passes.
    compute_clears: bool,
    /// Whether the visibility, the blur's axis and the deviations are half floats
    /// ([`visibility_storage`], [`sigma_storage`]).
    half: bool,
}

/// [`ComputeTargets`]' clears, one per cleared texture.
#[derive(Clone)]
struct TargetClears {
    visibility: Option<OneClear>,
    blurred: Option<OneClear>,
    distance: Option<OneClear>,
}

/// One texture's clear: a compute pass on a GPU, a render pass's clear on a CPU adapter (where a
/// render pass's clear is a memory fill and a compute pass runs a shader per texel: lavapipe's
/// frame took 4-7% longer with compute clears, an H100's screen-space passes 0.37 ms less on
/// teapot view 0; [`crate::ExecutionSettings::clears`] picks one whatever the device).
#[derive(Clone)]
enum OneClear {
    Compute(StorageClear),
    RenderPass(wgpu::TextureView, wgpu::Color),
}

impl OneClear {
    fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        match self {
            OneClear::Compute(clear) => clear.encode(encoder),
            OneClear::RenderPass(view, value) => drop(crate::gpu_helpers::begin_pass(
                encoder,
                "ComputeTargets::clear",
                &[crate::gpu_helpers::cleared(view, *value)],
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
    /// The distance map, to [`DistanceMapCompute::CLEARED`]: no shadow outside the listed tiles.
    Distance,
}

/// The distance-map method's part of [`ComputeTargets`].
#[derive(Clone)]
pub(crate) struct DistanceMapTargets {
    /// One value a pixel: the distance, or where none is a negative code
    /// ([`DistanceMapCompute::format`]).
    pub distance: Target,
    /// The blur's deviations from the variable PCF.
    pub sigma: Target,
    /// The tile list the passes run over.
    pub tiles: TileListTargets,
}

/// Which parts of [`ComputeTargets`] the lights' chains use.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct ComputeNeeds {
    pub visibility: bool,
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
            visibility: !chain.pcf_in_layer(),
            blur: chain.blur(),
            distance_map: chain.distance_map(),
            every_tile: chain.blur() && !chain.distance_map(),
        }
    }

    pub fn union(self, other: Self) -> Self {
        Self {
            visibility: self.visibility || other.visibility,
            blur: self.blur || other.blur,
            distance_map: self.distance_map || other.distance_map,
            every_tile: self.every_tile || other.every_tile,
        }
    }
}

impl ComputeTargets {
    /// For a screen of `size`, with the parts `needs` names, cleared as `clears` says, in half
    /// floats with `half` (the device stores them and the lights' chains were made so).
    pub fn new(
        device: &CachedDevice<'_>,
        size: (u32, u32),
        needs: ComputeNeeds,
        (clears, half): (DevicePath, bool),
    ) -> Self {
        let compute_clears = clears.compute(device);
        let target = |label, format| super::storage_target(device, label, size, format, !compute_clears);
        let visibility = needs
            .visibility
            .then(|| target("ComputeTargets::visibility", visibility_storage(half)));
        let blurred = needs
            .blur
            .then(|| target("ComputeTargets::blurred", visibility_storage(half)));
        let distance_map = needs.distance_map.then(|| DistanceMapTargets {
            distance: target("ComputeTargets::distance_map", DistanceMapCompute::format(half)),
            sigma: target("ComputeTargets::sigma", sigma_storage(half)),
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
            visibility: visibility
                .as_ref()
                .map(|v| clear("ComputeTargets::clear_visibility", v, wgpu::Color::WHITE)),
            blurred: blurred
                .as_ref()
                .map(|b| clear("ComputeTargets::clear_blurred", b, wgpu::Color::WHITE)),
            distance: distance_map.as_ref().map(|d| {
                clear(
                    "ComputeTargets::clear_distance",
                    &d.distance,
                    wgpu::Color {
                        r: DistanceMapCompute::CLEARED,
                        ..wgpu::Color::TRANSPARENT
                    },
                )
            }),
        };
        Self {
            visibility,
            size,
            blurred,
            distance_map,
            every_tile: needs
                .every_tile
                .then(|| TileListTargets::every_tile(device, size)),
            clears,
            compute_clears,
            half,
        }
    }

    /// Records the clear of `which` ([`OneClear`]: a compute pass on a GPU, where a render pass's
    /// clear of these storage textures costs more than the passes that fill them).
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder, which: Cleared) {
        let clear = match which {
            Cleared::Visibility => self.clears.visibility.as_ref(),
            Cleared::Blurred => self.clears.blurred.as_ref(),
            Cleared::Distance => self.clears.distance.as_ref(),
        };
        if let Some(clear) = clear {
            clear.encode(encoder);
        }
    }

    /// These are a screen of `size`'s, with exactly the parts `needs` names, cleared as
    /// `clears` says on `device`, in half floats exactly with `half`.
    pub fn fit(
        &self,
        device: &CachedDevice<'_>,
        size: (u32, u32),
        needs: ComputeNeeds,
        (clears, half): (DevicePath, bool),
    ) -> bool {
        let have = ComputeNeeds {
            visibility: self.visibility.is_some(),
            blur: self.blurred.is_some(),
            distance_map: self.distance_map.is_some(),
            every_tile: self.every_tile.is_some(),
        };
        self.size == size
            && have == needs
            && self.compute_clears == clears.compute(device)
            && self.half == half
    }

    pub fn allocated_bytes(&self) -> u64 {
        let bytes = |t: &Target| crate::gpu_helpers::texture_bytes(&t.texture);
        self.visibility.as_ref().map_or(0, bytes)
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
