//! One light's plan for a frame ([`plan_light`]): its chain, its maps' resolution, its fit to
//! what it sees, its spreads, its frame uniform and whether its maps must be drawn again.
//! [`super::Shadows::prepare`] runs it for each light after the frame-wide checks.

use super::api::{SCENE_FATTEN_RATIO, pass_params};
use super::light_state::{LightState, Planned, ShadowKey, narrowest_texels, redrawn_tiles, sees, spreads};
use super::report::LightId;
use crate::bounds::Aabb;
use crate::casters::Casters;
use crate::chain::Chain;
use crate::frame::{DerivedSpreads, FrameInputs, FrameUniform, PassParams, derive_spreads};
use crate::light_maps::{LightMaps, MapPools, MapUpload, Moved};
use crate::light_space::{FitInputs, LightView};
use crate::lights::Light;
use crate::settings::{CascadeSettings, LightFit, ShadowMapSettings, ShadowSettings};
use crate::view::CameraMatrices;

/// What every light's plan shares in a frame: the device, the view, the settings and the
/// casters' extent.
pub(super) struct FramePlan<'a> {
    pub device: &'a crate::pipeline_cache::CachedDevice<'a>,
    pub queue: &'a wgpu::Queue,
    pub casters: &'a Casters,
    pub camera: &'a CameraMatrices,
    pub settings: &'a ShadowSettings,
    /// The engine's depth buffer's size.
    pub size: (u32, u32),
    /// The depth buffer's size changed this frame.
    pub resized: bool,
    /// Every light's passes must be bound again (new inputs or a new visibility array).
    pub rebind_all: bool,
    /// The compute passes write the lights' layers themselves.
    pub layer_writes: bool,
    /// The compute path's intermediates are stored in half floats.
    pub half_intermediates: bool,
    /// The lights' maps share arrays, which the compute passes bind whole
    /// ([`MapPools::shares`]).
    pub map_arrays: bool,
    /// The device is a software rasterizer (its adapter a CPU).
    pub software: bool,
    /// The device runs compute passes.
    pub compute: bool,
    /// The shadow map's pass keeps the exit map (the device and the settings allow it).
    pub exit_in_shadow_pass: bool,
    /// The fattened map is derived from the shadow map (the device runs compute passes and
    /// [`crate::Fattening::derived`] says so for the casters).
    pub derived_fattening: bool,
    /// False: only the light-space maps ([`super::Shadows::set_maps_only`]).
    pub screen_space: bool,
    /// The engine gave a receiver mask.
    pub has_mask: bool,
    pub shadow_bounds: Aabb,
    pub caster_bounds: Aabb,
    pub parts: Vec<Aabb>,
    pub caster_parts: Vec<Aabb>,
}

/// What a light sees of the scene: everything for a sun, what lies in its reach for a spot or
/// point light.
struct Seen<'a> {
    shadow_bounds: Aabb,
    caster_bounds: Aabb,
    parts: &'a [Aabb],
    caster_parts: &'a [Aabb],
}

/// Plans the light in `slot` for the frame: sets `state.planned` and `state.report`, uploads
/// its frame uniform and prepares the maps' draws it needs (its maps layers of `pools`'
/// arrays).
pub(super) fn plan_light(frame: &FramePlan, slot: usize, state: &mut LightState, pools: &mut MapPools) {
    let (chain, effective, params) = chain_of(frame, &state.light);
    // The maps' resolution: the configured one, or a coarser one the light's
    // penumbrae allow (`MapResolution::FromPenumbra`).
    let level = state.wanted_level(frame.settings, &chain);
    if level != state.map_level {
        // Windows snapped to the old texel grid are not kept.
        state.drawn_with = None;
        state.map_level = level;
    }
    if let Some((_, taken)) = &mut state.widths {
        *taken = true;
    }
    let sm = ShadowMapSettings {
        resolution: frame.settings.shadow_map.resolution >> state.map_level,
        ..frame.settings.shadow_map
    };
    let effective = ShadowSettings {
        shadow_map: sm,
        ..effective
    };
    if state.allocate_screen(frame.device, &chain, &params, frame.size, frame.resized) || frame.rebind_all {
        state.bound = None;
    }
    let light = state.light;
    // Fit once to find the depth range (and so the widest penumbra), then fit the sides
    // to the casters widened by that penumbra.
    let loose = LightView::fit(&light, &frame.shadow_bounds);
    // A spot's or point light's maps depend only on what lies in its reach (within its
    // size of its frustum): a caster moving elsewhere changes neither its fit nor its
    // penumbra widths. A sun sees the whole scene.
    let own;
    let everything = Seen {
        shadow_bounds: frame.shadow_bounds,
        caster_bounds: frame.caster_bounds,
        parts: &frame.parts,
        caster_parts: &frame.caster_parts,
    };
    let seen = match light {
        Light::Directional(_) => everything,
        _ => {
            let radius = light.enclosing_radius();
            own = frame.casters.seen_by(|b| sees(&loose, b, radius));
            if own.all.is_empty() {
                everything
            } else {
                Seen {
                    shadow_bounds: own.all,
                    caster_bounds: own.casters,
                    parts: &own.parts,
                    caster_parts: &own.caster_parts,
                }
            }
        }
    };
    // Fitted again to what it sees, so that nothing outside changes it.
    let loose = match light {
        Light::Directional(_) => loose,
        _ => LightView::fit(&light, &seen.shadow_bounds),
    };
    let map_scale = (1u32 << state.map_level) as f32;
    let (light_view, spreads) = fit_light(
        frame,
        state,
        (&light, &chain),
        (&effective, &sm),
        &seen,
        &loose,
        map_scale,
    );
    // The maps hold the tiles the fit uses (a sun's cascades in use).
    if LightMaps::allocate(
        &mut state.maps,
        (frame.device, pools),
        frame.casters,
        &sm,
        &light_view,
        &chain,
    ) {
        state.key = None;
        state.bound = None;
    }
    // An array made again for another light's maps: these maps copied into it (bound again),
    // or lost (drawn again whole).
    match state.maps.as_mut().map_or(Moved::No, |m| m.refresh(pools)) {
        Moved::No => {}
        Moved::Copied => state.bound = None,
        Moved::Lost => {
            state.key = None;
            state.bound = None;
        }
    }
    // Where the shadow map's pass could not keep the exit map after all (tiles under 128
    // texels, a buffer past the device's storage bindings), the exit map has its own pass: the
    // report counts it.
    let kept = state.maps.as_ref().is_some_and(|m| m.shadow.keeps_exit());
    let chain = chain.exit_in_shadow_pass_where(chain.exit_in_shadow_pass() && kept);
    upload_frame(
        frame,
        state,
        (&light, &light_view, &effective),
        spreads,
        seen.caster_bounds.radius(),
        chain.distance_map(),
        map_scale,
    );
    let key = ShadowKey {
        casters: frame.casters.id(),
        light,
        light_view: light_view.map_matrices(),
        shadow_map: sm,
        fatten_distance: chain.fattened_map().then_some(spreads.fatten_distance),
        layers: state.layers,
    };
    let margin = spreads.fatten_distance * 2.0;
    let tiles = redrawn_tiles(
        state,
        &key,
        &light_view,
        frame.camera,
        frame.casters,
        !seen.caster_bounds.is_empty(),
        margin,
    );
    let render_maps = tiles != 0;
    if render_maps && let Some(maps) = &mut state.maps {
        let upload = MapUpload {
            device: frame.device,
            queue: frame.queue,
            casters: frame.casters,
            light: &light_view,
            layers: state.layers,
        };
        maps.prepare(&upload, &spreads, tiles);
    }
    state.screen.prepare(frame.queue, &params);
    let probe = reset_probe(frame, state, &chain, light_view.tile);
    let planned = Planned {
        chain,
        key,
        render_maps,
        tiles,
        spreads,
        light_view,
        probe,
        unheld_caster: light_view.unheld_caster(frame.camera, seen.caster_parts),
    };
    state.report = Some(planned.report(LightId(slot as u32), state.widths.map(|(w, _)| w)));
    state.planned = Some(planned);
}

/// The chain `light` runs this frame (on this device, with the renderer's choices), the
/// settings it is drawn with and its passes' parameters.
fn chain_of(frame: &FramePlan, light: &Light) -> (Chain, ShadowSettings, PassParams) {
    let mut chain = Chain::new(frame.settings, light)
        .writing_layers(frame.layer_writes)
        .pcf_writing_layer(
            frame.layer_writes && frame.half_intermediates && !frame.settings.execution.raw_visibility,
        )
        .exit_in_shadow_pass_where(frame.exit_in_shadow_pass)
        .fattening_derived_where(frame.derived_fattening);
    if !frame.compute {
        chain = chain.without_compute();
    }
    if !frame.screen_space {
        // Only the light-space map: the renderer shades in its forward pass.
        chain = chain.map_only();
    }
    let effective = ShadowSettings {
        method: chain.method(),
        ..*frame.settings
    };
    let mut params = PassParams {
        layer_writes: frame.layer_writes,
        half_intermediates: frame.half_intermediates,
        map_arrays: frame.map_arrays,
        ..pass_params(&effective, frame.software)
    };
    // Which fattened map and whether an exit map: as the chain draws them.
    params.distance_switches.exit_map = chain.exit_map();
    params.distance_switches.dilated_map = chain.fattened_map() && !chain.draws_fattened_map();
    (chain, effective, params)
}

/// Resets the PCF pass's count of the penumbra widths below its limits (in texels of the map
/// as drawn, `tile` a side), where the chain counts them; the limits and the map's size.
fn reset_probe(
    frame: &FramePlan,
    state: &mut LightState,
    chain: &Chain,
    tile: u32,
) -> Option<([f32; 3], u32)> {
    let texels = narrowest_texels(frame.settings, chain)?;
    let probe = state.screen.width_probe_mut()?;
    let limits = [texels, 2.0 * texels, 4.0 * texels];
    probe.reset(frame.queue, limits);
    Some((limits, tile))
}

/// The light's view for this frame (fitted to what it sees, widened by its fatten distance,
/// keeping the cascades whose maps still hold what they must) and its spreads.
fn fit_light(
    frame: &FramePlan,
    state: &LightState,
    (light, chain): (&Light, &Chain),
    (effective, sm): (&ShadowSettings, &ShadowMapSettings),
    seen: &Seen,
    loose: &LightView,
    map_scale: f32,
) -> (LightView, DerivedSpreads) {
    let spreads_of = |view: &LightView| {
        let derived = derive_spreads(light, view, &seen.shadow_bounds, seen.caster_parts, map_scale);
        spreads(effective, derived)
    };
    let mut spreads = spreads_of(loose);
    // A sun fitted to the view over a scene far wider or deeper than the view needs
    // (a ground hundreds of thousands of units wide): its penumbrae and texels are
    // those of the window the view needs. The whole scene's made the fatten
    // distance, and with it every cascade's margin, as wide as the ground. Where
    // the scene's fatten distance is within `SCENE_FATTEN_RATIO` of the window's it
    // is kept (the scenes that fit their view, as before).
    if let (Light::Directional(_), LightFit::CameraFrustum { .. }) = (*light, sm.fit) {
        let window = LightView::fit_with(&FitInputs {
            light,
            casters: seen.caster_bounds,
            casters_and_receivers: seen.shadow_bounds,
            parts: seen.parts,
            margin: 0.0,
            fit: sm.fit,
            camera: Some(*frame.camera),
            resolution: sm.resolution,
            snap_to_texels: false,
            cascades: CascadeSettings {
                count: 1,
                ..sm.cascades
            },
        });
        let fitted = spreads_of(&window);
        if spreads.fatten_distance > SCENE_FATTEN_RATIO * fitted.fatten_distance {
            spreads = fitted;
        }
    }
    // The margin keeps the fattened casters, pushed toward a spot or point light, in
    // front of its near plane; a chain that draws no fattened map keeps the tightest
    // near plane (PCSS searches for blockers from it). A sun's cascades are widened
    // by it for every method: penumbrae reach in from casters beside them.
    let margin = match *light {
        Light::Directional(_) => spreads.fatten_distance * 2.0,
        _ if chain.fattened_map() => spreads.fatten_distance * 2.0,
        _ => 0.0,
    };
    let light_view = LightView::fit_with(&FitInputs {
        light,
        casters: seen.caster_bounds,
        casters_and_receivers: seen.shadow_bounds,
        parts: seen.parts,
        margin,
        fit: sm.fit,
        camera: Some(*frame.camera),
        resolution: sm.resolution,
        snap_to_texels: sm.snap_to_texels,
        cascades: sm.cascades,
    });
    // Cascades whose maps still hold what they must stay as drawn.
    let light_view = match &state.drawn_with {
        Some(previous) => light_view.keeping_windows_of(previous, sm.resolution),
        None => light_view,
    };
    (light_view, spreads)
}

/// Uploads the light's frame uniform.
fn upload_frame(
    frame: &FramePlan,
    state: &LightState,
    (light, light_view, effective): (&Light, &LightView, &ShadowSettings),
    spreads: DerivedSpreads,
    caster_radius: f32,
    distance_map: bool,
    map_scale: f32,
) {
    state.frame.write(
        frame.queue,
        &FrameUniform::new(&FrameInputs {
            camera: frame.camera,
            width: frame.size.0,
            height: frame.size.1,
            light,
            ambient: glam::Vec3::ZERO,
            light_view,
            settings: effective,
            spreads,
            caster_radius,
            receiver_mask: frame.has_mask,
            distance_map,
            map_scale,
            map_layers: state.maps.as_ref().map(LightMaps::layers).unwrap_or_default(),
        }),
    );
}
