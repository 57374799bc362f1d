//! One light inside [`Shadows`](super::Shadows): its maps, its chain's screen-space passes and
//! what decides when they are redrawn (its key, the tiles of its maps a frame redraws), and
//! the spreads and map resolution a frame derives for it.

use crate::bounds::Aabb;
use crate::casters::Casters;
use crate::chain::Chain;
use crate::frame::{DerivedSpreads, FrameSlot, PassParams, light_kind};
use crate::light_maps::LightMaps;
use crate::light_space::tile_resolution;
use crate::light_space::{LightView, MAX_TILES};
use crate::lights::Light;
use crate::map_resolution::PenumbraWidths;
use crate::screen::{ComputeTargets, ScreenChain, ScreenInputs};
use crate::settings::{MapResolution, ShadowMapSettings, ShadowSettings, SpreadMode};
use crate::view::CameraMatrices;

use super::report::{LightId, LightReport};

/// What decides whether a light's shadow maps can be reused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct ShadowKey {
    pub(super) casters: u64,
    pub(super) light: Light,
    /// The whole window's and each cascade's matrices.
    pub(super) light_view: [glam::Mat4; MAX_TILES + 1],
    pub(super) shadow_map: ShadowMapSettings,
    pub(super) fatten_distance: Option<f32>,
    /// The casters' layers it draws ([`Shadows::set_light_layers`]).
    pub(super) layers: u32,
}

/// What [`Shadows::prepare`] decided for one light, for [`Shadows::encode`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Planned {
    pub(super) chain: Chain,
    pub(super) key: ShadowKey,
    pub(super) render_maps: bool,
    /// The map tiles (cascades, cube faces) redrawn, one bit each.
    pub(super) tiles: u32,
    pub(super) spreads: DerivedSpreads,
    pub(super) light_view: LightView,
    /// The limits the PCF pass counts penumbra widths below, and the tile resolution drawn
    /// ([`crate::MapResolution::FromPenumbra`]).
    pub(super) probe: Option<([f32; 3], u32)>,
    /// A sun's smallest caster in view that its map cannot hold.
    pub(super) unheld_caster: Option<crate::light_space::UnheldCaster>,
}

impl Planned {
    /// The report of light `light`'s frame as planned, with the penumbra widths last measured.
    pub(super) fn report(&self, light: LightId, penumbra_widths: Option<PenumbraWidths>) -> LightReport {
        LightReport {
            light,
            chain: self.chain,
            shadow_maps_rendered: self.render_maps,
            tiles_rendered: self.tiles,
            spreads: self.spreads,
            light_view: self.light_view,
            map_resolution: self.light_view.tile,
            penumbra_widths,
            unheld_caster: self.unheld_caster,
        }
    }
}

/// One light: its maps, its screen-space passes and its cache.
pub(super) struct LightState {
    pub(super) light: Light,
    pub(super) frame: FrameSlot,
    /// The maps drawn from the light, made in [`Shadows::prepare`] with the casters' layouts.
    pub(super) maps: Option<LightMaps>,
    /// The chain's screen-space passes.
    pub(super) screen: ScreenChain,
    /// The chain the passes are bound for (rebinding when it changes).
    pub(super) bound: Option<Chain>,
    pub(super) key: Option<ShadowKey>,
    /// The fit the maps were last drawn with (its cascades' windows are kept while they do).
    pub(super) drawn_with: Option<LightView>,
    pub(super) seen_revision: u64,
    pub(super) planned: Option<Planned>,
    pub(super) report: Option<LightReport>,
    /// The light's maps are drawn at the configured resolution divided by `2^map_level`
    /// ([`crate::MapResolution::FromPenumbra`]).
    pub(super) map_level: u32,
    /// The penumbra widths last measured, and whether the level has taken them yet.
    pub(super) widths: Option<(PenumbraWidths, bool)>,
    /// The layers whose casters it draws ([`Shadows::set_light_layers`]).
    pub(super) layers: u32,
}

impl LightState {
    /// GPU memory this light's maps and passes take, in bytes (its frame uniform is a slot of
    /// the frame uniforms every light shares, counted by `Shadows`).
    pub(super) fn allocated_bytes(&self) -> u64 {
        self.maps.as_ref().map_or(0, LightMaps::allocated_bytes) + self.screen.allocated_bytes()
    }

    /// A light whose frame uniform is `frame` (its slot's).
    pub(super) fn new(frame: FrameSlot, light: Light) -> Self {
        Self {
            light,
            frame,
            maps: None,
            screen: ScreenChain::map_only(),
            bound: None,
            key: None,
            drawn_with: None,
            layers: crate::casters::ALL_LAYERS,
            seen_revision: 0,
            planned: None,
            report: None,
            map_level: 0,
            widths: None,
        }
    }

    /// Takes the penumbra widths a read-back returned, if one has, and starts the next
    /// ([`crate::map_resolution::WidthProbe::collect`]).
    pub(super) fn collect_widths(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        if let Some(probe) = self.screen.width_probe_mut()
            && let Some(widths) = probe.collect(device, queue)
        {
            self.widths = Some((widths, false));
            if let Some(report) = &mut self.report {
                report.penumbra_widths = Some(widths);
            }
        }
    }

    /// The level the light's maps should be drawn at for `chain` under `settings`: 0 unless
    /// the chain measures its penumbrae, else what the last widths measured ask for.
    pub(super) fn wanted_level(&self, settings: &ShadowSettings, chain: &Chain) -> u32 {
        if narrowest_texels(settings, chain).is_none() {
            return 0;
        }
        let configured = tile_resolution(&self.light, settings.shadow_map.resolution);
        match self.widths {
            Some((widths, false)) => {
                match (0..=crate::map_resolution::MAX_LEVEL).find(|&l| configured >> l == widths.resolution) {
                    Some(measured_at) => crate::map_resolution::next_level(measured_at, &widths, configured),
                    None => self.map_level,
                }
            }
            _ => self.map_level,
        }
    }

    /// Makes the screen-space passes `chain` needs, or keeps those that serve it, and sizes
    /// their targets; returns true when anything was made or resized (the bind groups must
    /// then be rebuilt). The light-space maps are made after the fit
    /// ([`LightMaps::allocate`]).
    pub(super) fn allocate_screen(
        &mut self,
        device: &crate::pipeline_cache::CachedDevice<'_>,
        chain: &Chain,
        params: &PassParams,
        size: (u32, u32),
        resized: bool,
    ) -> bool {
        let mut changed = false;
        let kind = light_kind(&self.light);
        if !self.screen.fits(chain, params, kind) {
            self.screen = ScreenChain::new(device, chain, params, kind, size);
            changed = true;
        } else if resized {
            self.screen.resize(device, size.0, size.1);
            changed = true;
        }
        changed
    }

    /// Points every pass of the chain at its inputs: the engine's depth and receiver mask, a
    /// stand-in, the compute path's intermediates, the light's layer where the compute
    /// passes write it themselves, and whether it runs in a group.
    pub(super) fn bind(
        &mut self,
        device: &crate::pipeline_cache::CachedDevice<'_>,
        (depth, mask): (&wgpu::TextureView, &wgpu::TextureView),
        dummy: &wgpu::TextureView,
        (compute, layer, grouped): (Option<&ComputeTargets>, Option<&wgpu::TextureView>, bool),
    ) {
        let Some(maps) = &self.maps else { return };
        let views = maps.screen_views(self.screen.map_arrays());
        let inputs = ScreenInputs {
            frame: &self.frame,
            depth,
            mask,
            maps,
            views: &views,
            dummy,
            compute,
            layer,
            grouped,
        };
        self.screen.bind(device, &inputs);
    }
}

/// The fatten distance and penumbra scale for a frame: those `derived` from the light in
/// physical mode, with the user's fatten distance in manual mode.
pub(crate) fn spreads(settings: &ShadowSettings, derived: DerivedSpreads) -> DerivedSpreads {
    match settings.penumbra.spreads {
        SpreadMode::Physical => derived,
        SpreadMode::Manual { fatten_distance, .. } => DerivedSpreads {
            fatten_distance,
            ..derived
        },
    }
}

/// The narrowest penumbra, in texels, `chain` lets its maps be coarsened to under `settings`
/// ([`crate::MapResolution::FromPenumbra`]), or `None` where it measures nothing: the draws,
/// the manual spreads, the other methods.
pub(super) fn narrowest_texels(settings: &ShadowSettings, chain: &Chain) -> Option<f32> {
    match (settings.penumbra.map_resolution, settings.penumbra.spreads) {
        (MapResolution::FromPenumbra { narrowest_texels }, SpreadMode::Physical)
            if chain.distance_map() && chain.compute() =>
        {
            Some(narrowest_texels)
        }
        _ => None,
    }
}

/// The tiles of a light's maps (cascades, cube faces) to redraw this frame, one bit each: all
/// of them when the maps were never drawn or anything but the cascades' windows changed (the
/// casters' set, the light, the settings, the fatten distance); otherwise each tile whose window
/// moved, and each tile a changed caster's box reaches where its shadow can fall on the pixels
/// the tile serves (`any_caster`: the light sees a caster; one that sees none has empty maps,
/// and only a caster coming into its reach, which changes its key, redraws them).
pub(super) fn redrawn_tiles(
    state: &LightState,
    key: &ShadowKey,
    light_view: &LightView,
    camera: &CameraMatrices,
    casters: &Casters,
    any_caster: bool,
    margin: f32,
) -> u32 {
    let cascades = light_view.cascades();
    let all = (1u32 << cascades.len()) - 1;
    let Some(old) = &state.key else { return all };
    let same_but_windows = old.casters == key.casters
        && old.light == key.light
        && old.shadow_map == key.shadow_map
        && old.fatten_distance == key.fatten_distance
        && old.layers == key.layers;
    if !same_but_windows {
        return all;
    }
    let mut tiles = 0;
    for (i, cascade) in cascades.iter().enumerate() {
        let moved = old.light_view[i + 1] != key.light_view[i + 1];
        let touched = any_caster
            && casters.changed_inside(state.seen_revision, |b| {
                crate::light_space::box_reaches_clip(&cascade.view_projection, b, margin)
                    && light_view.cascade_may_see_shadow_of(i, camera, b, margin)
            });
        if moved || touched {
            tiles |= 1 << i;
        }
    }
    tiles
}

/// True unless `b` (grown by `margin`) lies wholly outside one side of the light's frustum
/// (a point light's cube: farther from the light than its far plane).
pub(super) fn sees(light_view: &LightView, b: &Aabb, margin: f32) -> bool {
    if b.is_empty() {
        return false;
    }
    if light_view.cascades().len() == 6 {
        // A point light's cube sees every way, as far as its far plane.
        let position = light_view.source().truncate();
        return position.clamp(b.min, b.max).distance(position) <= light_view.far + margin;
    }
    crate::light_space::box_reaches_clip(&light_view.view_projection, b, margin)
}
