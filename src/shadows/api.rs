//! [`Shadows`]: every light's state on an engine's depth, each frame planned
//! ([`Shadows::prepare`]) and recorded ([`Shadows::encode`]).

use crate::casters::Casters;
pub use crate::chain::Chain;
use crate::device::DeviceLoss;
use crate::error::{PenumbraError, Result};
use crate::frame::{FrameSlots, PassParams};
use crate::gpu_helpers::screen_target;
use crate::gpu_helpers::{Target, scoped, texture_bytes};
use crate::light_maps::FarPlaneFill;
use crate::light_maps::{LightMaps, MapPools, Moved};
use crate::lights::Light;
use crate::pipeline_cache::{CachedDevice, PipelineCache};
use crate::screen::{ComputeNeeds, ComputeTargets, DistanceMaps, LightGroup, ScreenChain};
use crate::settings::{ShadowMethod, ShadowSettings};
use crate::timing::PassStage;

use super::inputs::{
    Inputs, ViewInputs, check_depth, check_mask, check_target, layer_views, visibility_array,
};
use super::light_state::LightState;
use super::plan::{FramePlan, plan_light};
use super::report::{LightId, LightReport, LightTexture};

/// How many times a sun's fatten distance over the whole scene may exceed the one over the
/// window its view needs before the window's is taken: a scene far wider or deeper than the
/// view (a huge ground) takes the window's; one that fits its view keeps the scene's.
pub(super) const SCENE_FATTEN_RATIO: f32 = 8.0;

/// Soft shadows for several lights on an engine's depth buffer. See the module docs and the
/// `docs/embedding.md` page.
///
/// Lights are added, changed and removed at any time; each keeps its layer of
/// [`Shadows::visibility`] until it is removed, and a removed light's layer is given to the
/// next light added:
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use penumbra::{Light, PointLight, Shadows, ShadowSettings, SpotLight};
/// let gpu = penumbra::HeadlessGpu::new()?;
/// let mut shadows = Shadows::new(&gpu.device, ShadowSettings::default())?;
/// let lamp = Light::Point(PointLight {
///     position: glam::Vec3::new(0.0, 2.0, 0.0),
///     radius: 0.05,
///     color: glam::Vec3::ONE,
///     intensity: 100.0,
///     range: None,
/// });
/// let first = shadows.add_light(&gpu.device, lamp)?;
/// let second = shadows.add_light(&gpu.device, lamp)?;
/// assert_eq!((first.layer(), second.layer()), (0, 1));
/// // A spot now, where the second point light was.
/// shadows.set_light(second, Light::Spot(SpotLight {
///     position: glam::Vec3::new(2.0, 3.0, 0.0),
///     direction: glam::Vec3::new(-0.5, -1.0, 0.0),
///     cone_angle_deg: 40.0,
///     radius: 0.1,
///     color: glam::Vec3::ONE,
///     intensity: 200.0,
///     range: None,
/// }))?;
/// shadows.remove_light(first)?;
/// assert_eq!(shadows.light_ids(), vec![second]);
/// // Every frame: shadows.render(&device, &queue, &mut encoder, &casters, &view_inputs)?
/// # Ok(()) }
/// ```
pub struct Shadows {
    settings: ShadowSettings,
    lights: Vec<Option<LightState>>,
    size: (u32, u32),
    inputs: Option<Inputs>,
    /// R16F, one layer per light slot.
    visibility: Option<(wgpu::Texture, wgpu::TextureView, Vec<wgpu::TextureView>)>,
    /// The engine's texture the visibility is written into ([`Shadows::set_visibility_target`]).
    target: Option<wgpu::Texture>,
    /// Counts the visibility textures made or taken ([`Shadows::visibility_generation`]).
    generation: u64,
    /// The device is a software rasterizer (for [`crate::TileClassification::Auto`]).
    software: bool,
    /// The device runs compute passes ([`crate::PenumbraSettings::fragment_passes`]).
    compute: bool,
    /// The device's fragment shaders write storage buffers: the shadow map's pass can keep the
    /// exit map ([`crate::ExecutionSettings::exit_map_draw`]).
    fragment_storage: bool,
    /// The device can write the visibility's half floats from a compute pass, so the compute
    /// passes that finish a light write its layer themselves ([`stores_half_floats`]), where
    /// [`crate::ExecutionSettings::compute_layer_writes`] is on.
    layer_storage: bool,
    /// The device can also write two half floats a texel (RG16F) from a compute pass, so the
    /// compute path's intermediates are stored in half floats ([`stores_half_float_pairs`]),
    /// where [`crate::ExecutionSettings::half_intermediates`] is on.
    intermediate_storage: bool,
    /// The compute path's intermediates, shared by the lights.
    compute_targets: Option<ComputeTargets>,
    /// The light whose chain runs last, so that its intermediates stay readable
    /// ([`Shadows::inspect`]).
    inspected: Option<LightId>,
    /// 1x1 stand-ins for inputs a chain does not have.
    dummy: Target,
    /// Whose casters the pipelines were made for.
    casters_id: Option<u64>,
    /// False: only the light-space maps are rendered (the convenience renderer's forward
    /// and reference paths).
    screen_space: bool,
    prepared: bool,
    /// Reports the device's loss ([`Shadows::watch_device_loss`]).
    loss: Option<DeviceLoss>,
    /// Sets the lights' 16-bit atlases to the far plane by a copy ([`FarPlaneFill`]).
    far_plane: Option<FarPlaneFill>,
    /// The arrays the lights' maps are layers of.
    map_pools: MapPools,
    /// Every light's frame uniform, a slot a light (the light's slot in `lights`): one buffer,
    /// which a pass over several lights can bind whole.
    frames: FrameSlots,
    /// The groups of lights whose screen-space passes run as one
    /// ([`crate::ExecutionSettings::light_groups`]).
    groups: Vec<LightGroup>,
    /// The pipelines the lights' passes share ([`crate::pipeline_cache`]).
    pipelines: std::sync::Arc<PipelineCache>,
}

impl Shadows {
    /// Soft shadows with `settings` (validated; [`ShadowMethod::Reference`] is refused: it
    /// is an offline renderer, see [`crate::Renderer`]).
    pub fn new(device: &wgpu::Device, settings: ShadowSettings) -> Result<Self> {
        Self::check_settings(device, &settings)?;
        let pipelines = std::sync::Arc::new(PipelineCache::new(device));
        let cached = &CachedDevice::new(device, &pipelines);
        let (shadows, error) = scoped(device, || Self {
            settings,
            lights: Vec::new(),
            size: (0, 0),
            inputs: None,
            visibility: None,
            target: None,
            generation: 0,
            dummy: screen_target(device, "Shadows::dummy", 1, 1, wgpu::TextureFormat::R16Float),
            casters_id: None,
            screen_space: true,
            prepared: false,
            software: device.adapter_info().device_type == wgpu::DeviceType::Cpu,
            compute: crate::screen::has_compute(device),
            fragment_storage: crate::light_maps::exit_in_shadow_pass_supported(device),
            layer_storage: stores_half_floats(device),
            intermediate_storage: stores_half_floats(device) && stores_half_float_pairs(device),
            compute_targets: None,
            inspected: None,
            loss: None,
            far_plane: FarPlaneFill::new(cached, &settings.shadow_map),
            map_pools: MapPools::new(cached, crate::screen::has_compute(device)),
            frames: FrameSlots::new(device),
            groups: Vec::new(),
            pipelines: pipelines.clone(),
        });
        match error {
            Some(error) => Err(PenumbraError::gpu("creating the shadows", error)),
            None => Ok(shadows),
        }
    }

    /// Makes this `Shadows` take its passes' pipelines, shader modules and bind group layouts
    /// from where `other` takes its own: from then on the two compile each pass once between
    /// them, as the lights of one `Shadows` do, for several views of one scene (an engine's
    /// cameras, a split screen). Both must have been made on the same device; otherwise the
    /// error names `other`. The passes this one made before keep what they hold.
    pub fn share_pipelines_with(&mut self, other: &Shadows) -> Result<()> {
        if !other.pipelines.is_for(self.pipelines.device_handle()) {
            return Err(PenumbraError::input(
                "share_pipelines_with: other",
                "that Shadows was made on another device: pipelines serve the device they were made on",
            ));
        }
        self.pipelines = other.pipelines.clone();
        Ok(())
    }

    /// Has every later call report [`PenumbraError::DeviceLost`] once `loss` has seen the
    /// device lost, instead of drawing nothing without a word (a lost device takes commands
    /// and does nothing). See [`DeviceLoss`] for how it learns of the loss.
    pub fn watch_device_loss(&mut self, loss: DeviceLoss) {
        self.loss = Some(loss);
    }

    /// [`PenumbraError::DeviceLost`] where the watched device is lost.
    fn check_device(&self) -> Result<()> {
        self.loss.as_ref().map_or(Ok(()), DeviceLoss::check)
    }

    /// An error naming `device` where it is not the one this `Shadows` was made on (its passes
    /// and their pipelines serve that one).
    fn check_same_device(&self, device: &wgpu::Device, during: &str) -> Result<()> {
        if self.pipelines.is_for(device) {
            return Ok(());
        }
        Err(PenumbraError::input(
            "device",
            format!("{during}: not the device this Shadows was made on"),
        ))
    }

    /// Runs `f` after checking the device, inside wgpu error scopes: a wgpu error it raises is
    /// returned as [`PenumbraError::Gpu`] naming `during`.
    fn guarded<T>(
        &mut self,
        device: &wgpu::Device,
        during: &str,
        f: impl FnOnce(&mut Self) -> Result<T>,
    ) -> Result<T> {
        self.check_device()?;
        self.check_same_device(device, during)?;
        PenumbraError::scoped(device, || during.into(), || f(self))
    }

    fn check_settings(device: &wgpu::Device, settings: &ShadowSettings) -> Result<()> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        if settings.method == ShadowMethod::Reference {
            return Err(PenumbraError::setting(
                "method",
                "`reference` is an offline renderer; Shadows runs the real-time methods (use Renderer::render_reference)",
            ));
        }
        Ok(())
    }

    /// The settings every light runs with ([`Shadows::set_settings`] changes them).
    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    /// Applies new settings to every light. Maps are recreated when their resolution, format,
    /// bias or culling change; passes a method no longer uses are dropped.
    pub fn set_settings(&mut self, device: &wgpu::Device, settings: ShadowSettings) -> Result<()> {
        self.guarded(device, "applying new settings", |this| {
            this.set_settings_now(device, settings)
        })
    }

    fn set_settings_now(&mut self, device: &wgpu::Device, settings: ShadowSettings) -> Result<()> {
        Self::check_settings(device, &settings)?;
        let maps_changed = settings.shadow_map != self.settings.shadow_map;
        self.settings = settings;
        if maps_changed {
            let pipelines = self.pipelines.clone();
            self.far_plane =
                FarPlaneFill::new(&CachedDevice::new(device, &pipelines), &self.settings.shadow_map);
        }
        for state in self.lights.iter_mut().flatten() {
            if maps_changed {
                *state = LightState::new(state.frame.clone(), state.light);
            } else {
                state.bound = None;
            }
        }
        Ok(())
    }

    /// Draws only the lights' shadow maps, no screen-space pass, for an engine that shades with
    /// the maps itself (read them with [`Shadows::light_texture`] and
    /// [`LightTexture::ShadowMap`]; each light's view and cascades are in its [`LightReport`]).
    /// Turning it on frees the screen-space passes and the distance-map method's fattened and
    /// exit maps at once; [`Shadows::visibility`] is not written while it is on. Off by
    /// default. The convenience renderer's hard shadows use it (its forward pass), and its
    /// reference, which draws its own maps.
    pub fn set_maps_only(&mut self, maps_only: bool) {
        if maps_only && self.screen_space {
            for state in self.lights.iter_mut().flatten() {
                state.screen = ScreenChain::map_only();
                if let Some(maps) = &mut state.maps {
                    maps.fattened = None;
                    maps.exit = None;
                    maps.shadow.exit = None;
                }
                state.bound = None;
            }
        }
        self.screen_space = !maps_only;
    }

    /// Adds a shadowed light (validated). As many as the device's texture arrays hold
    /// ([`Shadows::max_lights`]: the visibility holds a layer a light, and so do the arrays of
    /// the lights' maps); each light adds its maps, its layer and a 1,280-byte frame uniform
    /// (`docs/lights.md`, "How many lights").
    ///
    /// What each field of the [`Light`] means here, where penumbra computes visibility only:
    /// - the position, direction and size (angular diameter, radius) set where the shadows
    ///   fall and how soft they are;
    /// - a spot's `cone_angle_deg` bounds its shadow map; its layer does *not* include the
    ///   cone's falloff (the engine applies its own), and outside the cone it holds no
    ///   shadow worth reading;
    /// - `color` and `intensity` are not used: the visibility is unitless (1 lit, 0 in the
    ///   umbra), and the engine multiplies it into its own light's direct term.
    pub fn add_light(&mut self, device: &wgpu::Device, light: Light) -> Result<LightId> {
        self.guarded(device, "adding a light", |this| this.add_light_now(device, light))
    }

    /// The most lights a `Shadows` holds on `device`: its `max_texture_array_layers` (256 with the
    /// limits [`crate::device_descriptor`] asks for, wgpu's downlevel defaults; more where the
    /// device was made with more). Each light's visibility is a layer of one array, and lights
    /// whose maps have one size share an array of them.
    /// (The convenience renderer and the Bevy plugin shade at most [`crate::MAX_LIGHTS`].)
    pub fn max_lights(device: &wgpu::Device) -> usize {
        device.limits().max_texture_array_layers as usize
    }

    fn add_light_now(&mut self, device: &wgpu::Device, light: Light) -> Result<LightId> {
        light.validate()?;
        let slot = match self.lights.iter().position(Option::is_none) {
            Some(slot) => slot,
            None if self.lights.len() < Self::max_lights(device) => {
                self.lights.push(None);
                self.lights.len() - 1
            }
            None => {
                return Err(PenumbraError::input(
                    "light",
                    format!(
                        "a Shadows holds at most {} lights on this device (its max_texture_array_layers: \
                         each light's visibility is a layer of one texture array)",
                        Self::max_lights(device)
                    ),
                ));
            }
        };
        if self.frames.reserve(device, slot + 1) {
            // The frame uniforms moved to a larger buffer: every light takes its slot of it
            // again, and its passes and its group's are bound again.
            for (other, state) in self.lights.iter_mut().enumerate() {
                if let Some(state) = state {
                    state.frame = self.frames.slot(other);
                    state.bound = None;
                }
            }
            for group in &mut self.groups {
                group.bound = false;
            }
        }
        self.lights[slot] = Some(LightState::new(self.frames.slot(slot), light));
        if self.target.is_none()
            && self
                .visibility
                .as_ref()
                .is_some_and(|v| v.2.len() < self.lights.len())
        {
            self.visibility = None;
        }
        Ok(LightId(slot as u32))
    }

    /// Changes a light (validated). Its maps are re-rendered next frame.
    pub fn set_light(&mut self, id: LightId, light: Light) -> Result<()> {
        light.validate()?;
        self.state_mut(id)?.light = light;
        Ok(())
    }

    /// Keeps light `id`'s shadows to the casters on `layers` (a bit mask: those with a layer in
    /// common, [`crate::Casters::set_layers`]); [`crate::ALL_LAYERS`] when added. As with render
    /// layers (Bevy's `RenderLayers`), the other casters cast no shadow from it. Its maps are
    /// re-rendered next frame.
    pub fn set_light_layers(&mut self, id: LightId, layers: u32) -> Result<()> {
        self.state_mut(id)?.layers = layers;
        Ok(())
    }

    /// The layers whose casters light `id` shadows ([`Shadows::set_light_layers`]).
    pub fn light_layers(&self, id: LightId) -> Result<u32> {
        self.state(id).map(|s| s.layers)
    }

    /// Removes a light; its layer keeps its last content until the slot is reused. The slots
    /// past the highest one still in use are given up, so an engine's visibility target
    /// ([`Shadows::set_visibility_target`]) needs layers only up to that one.
    pub fn remove_light(&mut self, id: LightId) -> Result<()> {
        self.state_mut(id)?;
        self.lights[id.0 as usize] = None;
        while self.lights.last().is_some_and(Option::is_none) {
            self.lights.pop();
        }
        Ok(())
    }

    /// Light `id` as last set; an error for an id that was removed or never added.
    pub fn light(&self, id: LightId) -> Result<Light> {
        self.state(id).map(|s| s.light)
    }

    /// The GPU memory these shadows allocated, in bytes: every light's maps, screen-space
    /// passes and uniforms and the visibility array (not a target given to
    /// [`Shadows::set_visibility_target`], nor anything of the engine's). Texels are counted at
    /// their format's size; what a driver adds for alignment is not, nor the part of its memory
    /// blocks no resource holds. It follows the lights, the methods and the view's size, and
    /// comes back to the same value when they do, but for the spare layers a map array keeps
    /// where it grew (at most 8 maps of each kind; a removed light's layer takes them with it).
    pub fn allocated_bytes(&self) -> u64 {
        let own_visibility = match (&self.target, &self.visibility) {
            (None, Some((texture, ..))) => texture_bytes(texture),
            _ => 0,
        };
        own_visibility
            + texture_bytes(&self.dummy.texture)
            + self.frames.allocated_bytes()
            + self.map_pools.unused_bytes()
            + self.far_plane.as_ref().map_or(0, FarPlaneFill::allocated_bytes)
            + self
                .compute_targets
                .as_ref()
                .map_or(0, ComputeTargets::allocated_bytes)
            + self
                .lights
                .iter()
                .flatten()
                .map(LightState::allocated_bytes)
                .sum::<u64>()
            + self.groups.iter().map(LightGroup::allocated_bytes).sum::<u64>()
    }

    /// The lights, in layer order.
    pub fn light_ids(&self) -> Vec<LightId> {
        (0..self.lights.len())
            .filter(|&i| self.lights[i].is_some())
            .map(|i| LightId(i as u32))
            .collect()
    }

    /// Decides this frame's work (CPU only, plus uniform uploads): validates the engine's
    /// inputs, fits each light's map to the casters and the camera, derives the spreads, and
    /// decides which lights' maps must be re-rendered. Call [`Shadows::encode`] next, with the
    /// same casters.
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        casters: &Casters,
        view: &ViewInputs,
    ) -> Result<()> {
        self.prepared = false;
        self.guarded(device, "preparing the shadows", |this| {
            let pipelines = this.pipelines.clone();
            let device = &CachedDevice::new(device, &pipelines);
            let taken = this.take_view(device, view)?;
            let (width, height) = this.size;
            // The compute passes write the layers themselves where the device and the texture
            // (an engine's may lack the usage) allow it.
            let layer_writes = this.layer_storage
                && this.settings.execution.compute_layer_writes
                && this
                    .visibility
                    .as_ref()
                    .is_some_and(|v| v.0.usage().contains(wgpu::TextureUsages::STORAGE_BINDING));
            // The passes that write the layers hold them.
            let rebind_all = taken.resized || taken.inputs_changed || (taken.replaced && layer_writes);
            this.casters_id = Some(casters.id());

            // The penumbra widths earlier frames measured, before anything is written for this
            // one (their read-back submits a copy of its own).
            if this
                .lights
                .iter_mut()
                .flatten()
                .any(|s| s.screen.width_probe_mut().is_some_and(|p| p.pending()))
            {
                let _ = device.poll(wgpu::PollType::Poll);
            }
            for state in this.lights.iter_mut().flatten() {
                state.collect_widths(device, queue);
            }
            let frame = FramePlan {
                device,
                queue,
                casters,
                camera: &view.camera,
                settings: &this.settings,
                size: (width, height),
                resized: taken.resized,
                rebind_all,
                layer_writes,
                half_intermediates: this.half_intermediates(),
                map_arrays: this.map_pools.shares(),
                software: this.software,
                compute: this.compute,
                exit_in_shadow_pass: this.fragment_storage
                    && this.compute
                    && this
                        .settings
                        .execution
                        .exit_map_draw
                        .in_shadow_pass(casters.caster_triangle_count())
                    && this.settings.shadow_map.cull_mode == crate::CullMode::None,
                derived_fattening: this.compute
                    && this
                        .settings
                        .penumbra
                        .fattening
                        .derived(casters.caster_triangle_count()),
                screen_space: this.screen_space,
                has_mask: view.receiver_mask.is_some(),
                shadow_bounds: casters.shadow_bounds(),
                caster_bounds: casters.caster_bounds(),
                parts: casters.shadow_parts(),
                caster_parts: casters.caster_parts(),
            };
            // The layers of lights removed or resized since the last frame given back first.
            this.map_pools.trim(device);
            let generation = this.map_pools.generation();
            for (slot, state) in this
                .lights
                .iter_mut()
                .enumerate()
                .filter_map(|(slot, s)| Some((slot, s.as_mut()?)))
            {
                plan_light(&frame, slot, state, &mut this.map_pools);
            }
            // An array made again while the lights were planned (a light needed one more
            // layer): the lights planned before hold views of the old one. They are planned
            // again onto the new one, where their maps were copied (bound again, and a derived
            // map's pass made for the new view) or could not be (drawn again whole).
            if this.map_pools.generation() != generation {
                for (slot, state) in this
                    .lights
                    .iter_mut()
                    .enumerate()
                    .filter_map(|(slot, s)| Some((slot, s.as_mut()?)))
                {
                    let Some(maps) = &mut state.maps else {
                        continue;
                    };
                    let moved = maps.refresh(&this.map_pools);
                    if moved == Moved::No {
                        continue;
                    }
                    state.bound = None;
                    if moved == Moved::Lost {
                        state.key = None;
                    }
                    plan_light(&frame, slot, state, &mut this.map_pools);
                }
            }
            this.map_pools.flush(device, queue);
            this.fit_groups(device, layer_writes);
            this.fit_compute_targets(device);
            let rebound = this.bind_lights(device, layer_writes);
            this.bind_groups(device, &rebound);
            let inspected = this.inspected.map(|id| id.0 as usize);
            for group in &mut this.groups {
                group.inspect(device, queue, inspected);
            }
            for group in &this.groups {
                // The parameters of the members' method (one chain key: one method).
                let first = this.lights.get(group.slots()[0]).and_then(Option::as_ref);
                let Some(planned) = first.and_then(|s| s.planned) else {
                    continue;
                };
                let settings = ShadowSettings {
                    method: planned.chain.method(),
                    ..this.settings
                };
                group.prepare(queue, &pass_params(&settings, this.software));
            }
            // The far-plane buffer as large as the largest 16-bit map the lights hold now.
            if let Some(fill) = &mut this.far_plane {
                let needed = this
                    .lights
                    .iter()
                    .flatten()
                    .filter_map(|s| s.maps.as_ref())
                    .map(LightMaps::fill_bytes)
                    .max()
                    .unwrap_or(0);
                fill.fit(device, needed);
            }
            Ok(())
        })?;
        self.prepared = true;
        Ok(())
    }

    /// Takes the engine's view for this frame: checks its depth and mask, keeps views of them
    /// when they changed, and makes the visibility layers again when the size changed.
    fn take_view(&mut self, device: &wgpu::Device, view: &ViewInputs) -> Result<ViewTaken> {
        view.camera.validate()?;
        let (width, height) = check_depth(view.depth)?;
        if let Some(mask) = view.receiver_mask {
            check_mask(mask, (width, height))?;
        }
        let resized = self.size != (width, height);
        self.size = (width, height);
        let inputs_changed = match &self.inputs {
            Some(inputs) => {
                inputs.depth != *view.depth || inputs.mask.as_ref().map(|m| &m.texture) != view.receiver_mask
            }
            None => true,
        };
        if inputs_changed {
            self.inputs = Some(Inputs {
                depth: view.depth.clone(),
                depth_view: view.depth.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("Shadows::depth"),
                    aspect: wgpu::TextureAspect::DepthOnly,
                    ..Default::default()
                }),
                mask: view.receiver_mask.map(|m| Target {
                    texture: m.clone(),
                    view: m.create_view(&Default::default()),
                }),
            });
        }
        if let Some(target) = &self.target {
            check_target(target, Some(((width, height), self.lights.len())))?;
        }
        let replaced = resized || self.visibility.is_none();
        if replaced {
            self.visibility = Some(match &self.target {
                Some(target) => layer_views(target.clone()),
                None => layer_views(visibility_array(
                    device,
                    width,
                    height,
                    self.lights.len().max(1) as u32,
                    self.layer_storage,
                )),
            });
            self.generation += 1;
        }
        Ok(ViewTaken {
            resized,
            inputs_changed,
            replaced,
        })
    }

    /// Makes or keeps the compute path's intermediates, one set for every light that runs it
    /// (none when no light does) and what the lights outside a group need of it (a group keeps
    /// its members' own, [`Shadows::fit_groups`] first); the lights are bound again when they
    /// are made.
    fn fit_compute_targets(&mut self, device: &CachedDevice<'_>) {
        let planned = || self.lights.iter().flatten().filter_map(|s| s.planned);
        let grouped = |slot: usize| self.groups.iter().any(|g| g.slots().contains(&slot));
        let needs = self
            .lights
            .iter()
            .enumerate()
            .filter(|(slot, _)| !grouped(*slot))
            .filter_map(|(_, s)| s.as_ref()?.planned)
            .map(|p| ComputeNeeds::of(&p.chain))
            .fold(ComputeNeeds::default(), ComputeNeeds::union);
        let clears = (self.settings.execution.clears, self.half_intermediates());
        if !planned().any(|p| p.chain.compute()) {
            self.compute_targets = None;
        } else if self
            .compute_targets
            .as_ref()
            .is_none_or(|t| !t.fit(device, self.size, needs, clears))
        {
            self.compute_targets = Some(ComputeTargets::new(device, self.size, needs, clears));
            for state in self.lights.iter_mut().flatten() {
                state.bound = None;
            }
        }
    }

    /// The compute path's intermediates are stored in half floats: the device stores them and
    /// the settings ask for it.
    fn half_intermediates(&self) -> bool {
        self.intermediate_storage && self.settings.execution.half_intermediates
    }

    /// Points each light's passes whose chain changed at their inputs (the compute passes at
    /// the light's layer where they write it, `layer_writes`; a group's member at its part of
    /// the group); returns the slots of the lights bound.
    fn bind_lights(&mut self, device: &CachedDevice<'_>, layer_writes: bool) -> Vec<usize> {
        let inputs = self.inputs.as_ref().expect("taken before");
        let mask_view = inputs.mask.as_ref().map_or(&self.dummy.view, |m| &m.view);
        let layers = &self.visibility.as_ref().expect("taken before").2;
        let mut rebound = Vec::new();
        for (slot, state) in self
            .lights
            .iter_mut()
            .enumerate()
            .filter_map(|(slot, s)| Some((slot, s.as_mut()?)))
        {
            let chain = state.planned.expect("planned before").chain;
            if state.bound != Some(chain) {
                let compute = self.compute_targets.as_ref().filter(|_| chain.compute());
                let layer = layers.get(slot).filter(|_| layer_writes);
                let grouped = self.groups.iter().any(|g| g.slots().contains(&slot));
                let depth = (&inputs.depth_view, mask_view);
                state.bind(device, depth, &self.dummy.view, (compute, layer, grouped));
                state.bound = Some(chain);
                rebound.push(slot);
            }
        }
        rebound
    }

    /// Forms the groups of lights whose screen-space passes run as one, where the settings ask
    /// for it ([`crate::ExecutionSettings::light_groups`]): the lights planned for chains of
    /// one key that [`LightGroup::groups`], whose maps are layers of the same arrays, and whose
    /// penumbrae are not measured ([`crate::MapResolution::FromPenumbra`]), two or more. A
    /// member's intermediates are its own (layers of the group's), so an inspected light
    /// ([`Shadows::inspect`]) groups too. A group that stays as it was is kept;
    /// the lights that join or leave a group are bound again.
    fn fit_groups(&mut self, device: &CachedDevice<'_>, layer_writes: bool) {
        let mut wanted: Vec<(crate::screen::ChainKey, [Option<wgpu::Texture>; 4], Vec<usize>)> = Vec::new();
        let on = self.settings.execution.light_groups && layer_writes && self.screen_space;
        for (slot, state) in self
            .lights
            .iter()
            .enumerate()
            .filter_map(|(slot, s)| Some((slot, s.as_ref()?)))
            .filter(|_| on)
        {
            let key = *state.screen.key();
            let (Some(plan), Some(maps)) = (&state.planned, &state.maps) else {
                continue;
            };
            if plan.probe.is_some() || !LightGroup::groups(&key, device) {
                continue;
            }
            let arrays = maps.array_textures();
            let joins = wanted.iter_mut().find(|(k, a, slots)| {
                *k == key && *a == arrays && slots.len() < crate::screen::MAX_GROUP_MEMBERS
            });
            match joins {
                Some((_, _, slots)) => slots.push(slot),
                None => wanted.push((key, arrays, vec![slot])),
            }
        }
        wanted.retain(|(_, _, slots)| slots.len() > 1);
        let mut old: Vec<Option<LightGroup>> =
            std::mem::take(&mut self.groups).into_iter().map(Some).collect();
        let mut moved = Vec::new();
        let pool = self.settings.execution.light_group_pool;
        for (key, _, slots) in wanted {
            let kept = old
                .iter_mut()
                .find(|g| g.as_ref().is_some_and(|g| g.fits(&key, &slots, self.size, pool)))
                .and_then(Option::take);
            let group = kept.unwrap_or_else(|| {
                moved.extend(&slots);
                LightGroup::new(device, key, slots, self.size, pool)
            });
            self.groups.push(group);
        }
        moved.extend(old.iter().flatten().flat_map(|g| g.slots().to_vec()));
        for slot in moved {
            if let Some(Some(state)) = self.lights.get_mut(slot) {
                state.bound = None;
            }
        }
    }

    /// Points each group's passes at their inputs where one of its lights was bound again
    /// (`rebound`) or it is new, and uploads their parameters.
    fn bind_groups(&mut self, device: &CachedDevice<'_>, rebound: &[usize]) {
        if self.groups.is_empty() {
            return;
        }
        let inputs = self.inputs.as_ref().expect("taken before");
        let mask_view = inputs.mask.as_ref().map_or(&self.dummy.view, |m| &m.view);
        let visibility = &self.visibility.as_ref().expect("taken before").1;
        for group in &mut self.groups {
            if group.bound && !group.slots().iter().any(|s| rebound.contains(s)) {
                continue;
            }
            // Every member's maps are layers of the first one's arrays.
            let first = group.slots()[0];
            let Some(Some(maps)) = self
                .lights
                .get(first)
                .map(|s| s.as_ref().and_then(|s| s.maps.as_ref()))
            else {
                continue;
            };
            let views = maps.screen_views(true);
            let Some(distance_maps) = DistanceMaps::of(maps, &views) else {
                continue;
            };
            let screen = (&inputs.depth_view, mask_view, &self.dummy.view);
            group.bind(device, &self.frames, screen, &distance_maps, visibility);
        }
    }

    /// Records the frame [`Shadows::prepare`] planned: per light, the maps when they must be
    /// re-rendered, then the screen-space chain into the light's layer of
    /// [`Shadows::visibility`].
    pub fn encode(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
    ) -> Result<Vec<LightReport>> {
        self.encode_with_marks(encoder, casters, &mut |_, _, _| {})
    }

    /// [`Shadows::encode`], calling `mark(encoder, pass, stage)` after each pass it records,
    /// `pass` its name ("shadow map", "distance map", "pcf", "blur", ...) and `stage` whether
    /// it draws from the light or runs over the screen: where an engine writes its own GPU
    /// timestamps, to time penumbra pass by pass.
    pub fn encode_with_marks(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str, PassStage),
    ) -> Result<Vec<LightReport>> {
        self.check_device()?;
        if !self.prepared || self.casters_id != Some(casters.id()) {
            return Err(PenumbraError::input(
                "Shadows::encode",
                "call prepare with the same casters first",
            ));
        }
        self.prepared = false;
        let layers = &self.visibility.as_ref().expect("prepared").2;
        let mut reports = Vec::new();
        // Slot order, the inspected light last where its chain shares the compute path's
        // intermediates.
        let mut order: Vec<usize> = (0..self.lights.len()).collect();
        if let Some(id) = self.inspected
            && let Some(Some(state)) = self.lights.get(id.0 as usize)
            && state.planned.is_some_and(|p| p.chain.compute())
        {
            order.retain(|&slot| slot != id.0 as usize);
            order.push(id.0 as usize);
        }
        // The lights whose maps are drawn this frame: a group reduces its fattened maps again.
        let mut drawn = Vec::new();
        for slot in order {
            let Some(state) = &mut self.lights[slot] else {
                continue;
            };
            let Some(plan) = state.planned.take() else {
                continue;
            };
            if plan.render_maps {
                drawn.push(slot);
                if let Some(maps) = &state.maps {
                    let light_space =
                        &mut |e: &mut wgpu::CommandEncoder, pass| mark(e, pass, PassStage::LightSpace);
                    maps.encode(encoder, casters, self.far_plane.as_ref(), light_space);
                }
                state.key = Some(plan.key);
                state.drawn_with = Some(plan.light_view);
                state.seen_revision = casters.revision();
            }
            if self.screen_space {
                let screen_space =
                    &mut |e: &mut wgpu::CommandEncoder, pass| mark(e, pass, PassStage::ScreenSpace);
                state
                    .screen
                    .encode(encoder, plan.render_maps, &layers[slot], screen_space);
            }
            if let (Some((limits, resolution)), Some(probe)) = (plan.probe, state.screen.width_probe_mut()) {
                probe.recorded(limits, resolution);
            }
            let report = plan.report(LightId(slot as u32), state.widths.map(|(w, _)| w));
            state.report = Some(report);
            reports.push(report);
        }
        // Each group's passes, after its lights' classifications.
        if self.screen_space {
            let visibility = &self.visibility.as_ref().expect("prepared").1;
            for group in &self.groups {
                let screen_space =
                    &mut |e: &mut wgpu::CommandEncoder, pass| mark(e, pass, PassStage::ScreenSpace);
                let maps_drawn = group.slots().iter().any(|s| drawn.contains(s));
                group.encode(encoder, visibility, maps_drawn, screen_space);
            }
        }
        reports.sort_by_key(|r| r.light.layer());
        Ok(reports)
    }

    /// Keeps `light`'s intermediate textures readable after each frame
    /// ([`Shadows::light_texture`]): the compute path's screen-space intermediates are shared
    /// by the lights (each light's chain runs whole before the next one's), so after a frame
    /// they hold the last light's, and this light's chain runs last. `None`: slot order. A
    /// light in a group ([`crate::ExecutionSettings::light_groups`]) stays there: its tile
    /// classes are its layer of the group's ([`Shadows::light_texture_layer`] says which), and
    /// while it is inspected its distance map is copied out of the group's pool (2 bytes a
    /// pixel more, in half floats), the only way to read it.
    pub fn inspect(&mut self, light: Option<LightId>) {
        self.inspected = light;
    }

    /// Waits for the penumbra widths the last encoded frame measured
    /// ([`crate::MapResolution::FromPenumbra`]; its commands must have been submitted) and
    /// returns whether a light's maps will be drawn at another resolution from the next frame:
    /// a tool that renders one frame and reads it back renders again while this says so, to
    /// show what a running application settles to. Without it the widths come back a frame or
    /// two later, without a wait.
    pub fn settle(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<bool> {
        self.check_device()?;
        self.check_same_device(device, "waiting for the penumbra widths")?;
        for state in self.lights.iter_mut().flatten() {
            state.collect_widths(device, queue);
        }
        if self
            .lights
            .iter_mut()
            .flatten()
            .any(|s| s.screen.width_probe_mut().is_some_and(|p| p.pending()))
        {
            crate::error::wait_for_gpu(device, "waiting for the penumbra widths")?;
        }
        let mut changes = false;
        for state in self.lights.iter_mut().flatten() {
            state.collect_widths(device, queue);
            if let Some(report) = &state.report {
                changes |= state.wanted_level(&self.settings, &report.chain) != state.map_level;
            }
        }
        Ok(changes)
    }

    /// [`Shadows::prepare`] then [`Shadows::encode`].
    pub fn render(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
        view: &ViewInputs,
    ) -> Result<Vec<LightReport>> {
        self.prepare(device, queue, casters, view)?;
        self.encode(encoder, casters)
    }

    /// The visibility of every light: an `R16Float` 2D array texture of the depth's size, one
    /// layer per light ([`LightId::layer`]), 1 lit and 0 shadowed, indirect attenuation
    /// applied. Sample it with `textureLoad(visibility, pixel, layer, 0)` (bound as
    /// `texture_2d_array<f32>`, filterable). `None` before the first frame.
    ///
    /// The texture is replaced (and an engine's bind group that holds it must be rebuilt) on
    /// the first frame, when the depth's size changes and when a light is added beyond the
    /// layers it has: [`Shadows::visibility_generation`] changes exactly then. An engine that
    /// would rather own the texture gives it with [`Shadows::set_visibility_target`].
    pub fn visibility(&self) -> Option<&wgpu::TextureView> {
        self.visibility.as_ref().map(|v| &v.1)
    }

    /// A number that changes whenever [`Shadows::visibility`] starts returning another
    /// texture (0 before the first frame): rebuild the bind groups that hold it when it does.
    pub fn visibility_generation(&self) -> u64 {
        self.generation
    }

    /// Writes the visibility into the engine's own texture from the next frame on (`None`:
    /// into one of penumbra's). It must be an `R16Float` 2D texture with `RENDER_ATTACHMENT`
    /// usage; each frame, its size must be the depth's and it needs a layer for every light
    /// slot up to the highest in use ([`LightId::layer`]). Layers of slots with no light are
    /// left as they are. With
    /// `STORAGE_BINDING` too, where the device allows it ([`Shadows::visibility_usages`]),
    /// the compute passes write its layers themselves, saving a draw per light.
    pub fn set_visibility_target(&mut self, target: Option<wgpu::Texture>) -> Result<()> {
        if let Some(t) = &target {
            check_target(t, None)?;
        }
        if self.target != target {
            self.target = target;
            self.visibility = None;
        }
        Ok(())
    }

    /// The usages an engine's visibility target ([`Shadows::set_visibility_target`]) should
    /// have on `device`: `RENDER_ATTACHMENT` and `TEXTURE_BINDING`, and `STORAGE_BINDING`
    /// where a compute pass can write its half floats (the device has
    /// `TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES` and the adapter allows it): the compute
    /// passes that finish a light then write its layer themselves instead of a draw copying
    /// their result there.
    pub fn visibility_usages(device: &wgpu::Device) -> wgpu::TextureUsages {
        let usages = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        if stores_half_floats(device) {
            usages | wgpu::TextureUsages::STORAGE_BINDING
        } else {
            usages
        }
    }

    /// The bind group layout entry an engine's lit shader declares for [`Shadows::visibility`]:
    /// a filterable float 2D array texture read in the fragment stage.
    pub fn visibility_layout_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
        crate::gpu_helpers::entry::texture(
            binding,
            wgpu::TextureSampleType::Float { filterable: true },
            wgpu::TextureViewDimension::D2Array,
        )
    }

    /// The texture behind [`Shadows::visibility`] (R16F, one layer per light, the view's
    /// size), once a frame has been encoded.
    pub fn visibility_texture(&self) -> Option<&wgpu::Texture> {
        self.visibility.as_ref().map(|v| &v.0)
    }

    /// One light's layer as a 2D view.
    pub fn visibility_layer(&self, id: LightId) -> Option<&wgpu::TextureView> {
        self.visibility.as_ref().and_then(|v| v.2.get(id.0 as usize))
    }

    /// What a light's frame does: written by [`Shadows::prepare`] (its fit, spreads and chain
    /// are known before anything is encoded), kept after [`Shadows::encode`] until the next
    /// prepare.
    pub fn report(&self, id: LightId) -> Option<&LightReport> {
        self.state(id).ok().and_then(|s| s.report.as_ref())
    }

    /// An intermediate texture of a light's last frame, if its chain has it, which may hold
    /// other lights' too: the light's is its layer [`Shadows::light_texture_layer`]. The
    /// lights' maps ([`LightTexture::ShadowMap`], a drawn [`LightTexture::FattenedMap`] and
    /// [`LightTexture::ExitMap`]) are layers of arrays that the lights whose maps have the same
    /// size share, where the device runs compute passes. The compute path's screen-space
    /// intermediates ([`LightTexture::DistanceMap`], [`LightTexture::Visibility`]) are shared by
    /// the lights: they hold the light whose chain ran last, which [`Shadows::inspect`] chooses
    /// (by default the last light in slot order).
    pub fn light_texture(&self, id: LightId, which: LightTexture) -> Option<&wgpu::Texture> {
        let s = self.state(id).ok()?;
        if let Some((texture, _)) = self.group_texture(id, which) {
            return Some(texture);
        }
        let maps = s.maps.as_ref();
        match which {
            LightTexture::ShadowMap => maps.map(|m| m.shadow.atlas.texture()),
            LightTexture::FattenedMap => maps.and_then(|m| m.fattened.as_ref()).map(|f| f.texture()),
            LightTexture::ExitMap => maps.and_then(|m| m.exit_texture()),
            LightTexture::DistanceMap => s.screen.distance_texture(),
            LightTexture::TileClasses => s.screen.tile_classes_texture(),
            LightTexture::Visibility => s.screen.raw_visibility(),
            LightTexture::BlurredVisibility => match s.report.map(|r| r.chain) {
                // The blur writes the layer: after the distance map, and on the compute path.
                Some(chain) if chain.blur() && (chain.distance_map() || chain.compute()) => {
                    self.visibility.as_ref().map(|v| &v.0)
                }
                _ => s.screen.blurred_visibility(),
            },
        }
    }

    /// The layer of [`Shadows::light_texture`]'s texture that holds light `id`'s (0 for a
    /// texture of one layer), if it has that texture.
    pub fn light_texture_layer(&self, id: LightId, which: LightTexture) -> Option<u32> {
        if let Some((_, layer)) = self.group_texture(id, which) {
            return Some(layer);
        }
        let texture = self.light_texture(id, which)?;
        let s = self.state(id).ok()?;
        let maps = s.maps.as_ref();
        let layer = match which {
            LightTexture::ShadowMap => maps.map(|m| m.shadow.atlas.layer()),
            LightTexture::FattenedMap => maps.and_then(|m| m.fattened.as_ref()).map(|f| f.layer()),
            LightTexture::ExitMap => maps.and_then(|m| m.exit_layer()),
            LightTexture::BlurredVisibility if self.visibility.as_ref().is_some_and(|v| &v.0 == texture) => {
                Some(id.0)
            }
            _ => Some(0),
        };
        layer.filter(|&l| l < texture.depth_or_array_layers())
    }

    /// Light `id`'s intermediate `which` and its layer where a group of lights holds it: its
    /// distance map and tile classes ([`LightGroup::member_intermediates`]).
    fn group_texture(&self, id: LightId, which: LightTexture) -> Option<(&wgpu::Texture, u32)> {
        let (distance, classes, layer) = self
            .groups
            .iter()
            .find_map(|g| g.member_intermediates(id.0 as usize))?;
        match which {
            // Copied out of the group's pool while the light is inspected.
            LightTexture::DistanceMap => distance.map(|d| (d, 0)),
            LightTexture::TileClasses => Some((classes, layer)),
            _ => None,
        }
    }

    fn state(&self, id: LightId) -> Result<&LightState> {
        crate::error::slot(&self.lights, "light", id.0)
    }

    fn state_mut(&mut self, id: LightId) -> Result<&mut LightState> {
        crate::error::slot_mut(&mut self.lights, "light", id.0)
    }
}

// An engine keeps `Shadows` and `Casters` in state shared between threads (Bevy's render world
// asks `Send + Sync` of a resource): checked when the crate builds. Not on the web, where wgpu's
// objects are neither (one thread; wgpu's `fragile-send-sync-non-atomic-wasm` would make them
// so).
#[cfg(not(target_arch = "wasm32"))]
const _: () = {
    const fn shared<T: Send + Sync>() {}
    shared::<Shadows>();
    shared::<Casters>();
};

/// Whether a compute pass on `device` can write the texture `probe` makes (a 1 x 1 storage
/// texture of the format tried): the device has the adapter's own format features and they
/// include that format's storage (desktop Vulkan and Metal do for half floats, lavapipe too; the
/// web and wgpu's GL backend do not). Tried, since the format's features are the adapter's,
/// which a `Shadows` does not see.
fn stores<T>(device: &wgpu::Device, probe: impl FnOnce() -> T) -> bool {
    if !device
        .features()
        .contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
        || !crate::screen::has_compute(device)
    {
        return false;
    }
    let (_, error) = scoped(device, probe);
    error.is_none()
}

/// Whether a compute pass on `device` can write the visibility's half floats (R16F).
fn stores_half_floats(device: &wgpu::Device) -> bool {
    stores(device, || visibility_array(device, 1, 1, 1, true))
}

/// Whether a compute pass on `device` can write two half floats a texel (RG16F, the blur's
/// deviations).
fn stores_half_float_pairs(device: &wgpu::Device) -> bool {
    stores(device, || {
        crate::gpu_helpers::texture_2d(
            device,
            "Shadows::half_float_pairs",
            (1, 1),
            crate::screen::sigma_storage(true),
            wgpu::TextureUsages::STORAGE_BINDING,
        )
    })
}

/// The passes' parameters for `settings`, the tile classification's `Auto` decided for the
/// device (`software`: a CPU rasterizer).
pub(super) fn pass_params(settings: &ShadowSettings, software: bool) -> PassParams {
    let mut params = PassParams::new(settings);
    if settings.penumbra.tiles == crate::settings::TileClassification::Auto && !software {
        params.distance_switches.tiles = false;
        params.pcf_switches.tiles = false;
        params.blur_switches.tiles = false;
    }
    params
}
/// What [`Shadows::prepare`] found of the engine's view.
struct ViewTaken {
    /// The depth's size changed.
    resized: bool,
    /// Another depth or mask texture.
    inputs_changed: bool,
    /// The visibility layers were made again.
    replaced: bool,
}
