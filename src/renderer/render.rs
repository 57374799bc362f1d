//! The convenience renderer: a whole lit frame of a [`GpuScene`], built on the embedding API.
//!
//! It does what an engine would: a depth prepass of its own (with a receiver mask), then
//! [`Shadows`] for the scene's lights on that depth (the key light and
//! [`crate::Scene::more_lights`], up to [`crate::MAX_LIGHTS`]), then a lit composite that adds
//! each light times its resolved visibility. With one light, hard shadows and hardware 2x2 PCF
//! shade in one forward pass with the light's shadow map instead, and the ground truth
//! accumulates one hard shadow map per light sample and light ([`Renderer::render_reference`]).

use super::composite::CompositePass;
use super::depth_prepass::DepthPrepass;
use super::forward::ForwardPass;
use super::gpu_scene::GpuScene;
use super::ground_truth::{GroundTruth, ReferenceProgress, SampleInputs};
use crate::camera::Camera;
use crate::error::{PenumbraError, Result};
use crate::frame::{DerivedSpreads, FrameInputs, FrameUniform, derive_spreads};
use crate::layouts::SceneLayouts;
use crate::light_space::LightView;
use crate::lights::Light;
use crate::settings::{ShadowMethod, ShadowSettings};
use crate::shadows::{Chain, LightId, LightReport, LightTexture, Shadows, ViewInputs};
use crate::timing::PassStage;
use crate::view::CameraMatrices;

/// Which passes a frame of the [`Renderer`] runs: the key light's [`Chain`] (each further
/// light runs the same chain) and the renderer's own passes around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PassPlan {
    /// What each light runs. [`Chain::MapOnly`] where the forward pass shades with the shadow
    /// map (hard shadows with one light) or the reference accumulates its own maps.
    pub chain: Chain,
    /// The camera depth prepass (every method but the forward pass's).
    pub depth_prepass: bool,
    /// The reference's accumulated visibility is composited (accumulated by
    /// [`Renderer::render_reference`]); no light runs a chain.
    pub reference: bool,
    /// The lit pass over the prepass depth that reads every light's visibility layer.
    pub composite: bool,
    /// The one-pass lit forward pass (hard and hw2x2 with one light).
    pub forward: bool,
}

impl PassPlan {
    /// The passes of a frame with `count` lights, `light` the key light: as [`PassPlan::new`],
    /// except that several lights are never shaded in the one-light forward pass: hard shadows
    /// then run each light's screen-space chain (one PCF tap) and the composite shades them all.
    pub fn for_lights(settings: &ShadowSettings, light: &Light, count: usize) -> Self {
        let plan = Self::new(settings, light);
        if count <= 1 || !plan.forward {
            return plan;
        }
        PassPlan {
            chain: Chain::new(settings, light),
            depth_prepass: true,
            reference: false,
            composite: true,
            forward: false,
        }
    }

    /// The passes `settings.method` needs under `light` with one light: the method's
    /// [`Chain`] plus the renderer's own prepass and composite, or the forward pass.
    pub fn new(settings: &ShadowSettings, light: &Light) -> Self {
        let chain = Chain::new(settings, light);
        match chain.method() {
            ShadowMethod::Hard | ShadowMethod::Hardware2x2 => PassPlan {
                chain: chain.map_only(),
                depth_prepass: false,
                reference: false,
                composite: false,
                forward: true,
            },
            ShadowMethod::Reference => PassPlan {
                chain,
                depth_prepass: true,
                reference: true,
                composite: true,
                forward: false,
            },
            _ => PassPlan {
                chain,
                depth_prepass: true,
                reference: false,
                composite: true,
                forward: false,
            },
        }
    }

    /// The method actually drawn: a method that needs a light size falls back to
    /// [`ShadowMethod::Hard`] when the light has none.
    pub fn method(&self) -> ShadowMethod {
        self.chain.method()
    }

    /// The lights' chains run (every frame but the reference's).
    pub fn shadow_map(&self) -> bool {
        !self.reference
    }

    /// How many times the frame draws the scene's geometry: the light-space maps (when they
    /// are re-rendered), the prepass, the composite or the forward pass.
    pub fn geometry_passes(&self, shadow_maps_rendered: bool) -> u32 {
        let maps = if shadow_maps_rendered && self.shadow_map() {
            self.chain.light_maps()
        } else {
            0
        };
        maps + self.depth_prepass as u32 + self.composite as u32 + self.forward as u32
    }
}

/// What a frame of the [`Renderer`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameReport {
    /// The passes it planned.
    pub plan: PassPlan,
    /// The names of the passes it recorded, in order (a light's passes once per light).
    pub passes: Vec<&'static str>,
    /// What the key light did. For the reference, which draws its own maps, its chain is
    /// [`Chain::MapOnly`], nothing is reported rendered, and the light's view and spreads are
    /// those of a fit to the scene's bounds.
    pub light: LightReport,
}

/// Owns a [`Shadows`] for the scene's lights and the passes around it. Made once per output
/// format; [`Renderer::resize`] when the output size changes, [`Renderer::set_settings`] when
/// settings change. Passes are allocated on the first frame that needs them and dropped when
/// the method no longer does.
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use penumbra::{GpuScene, Renderer, ShadowMethod, ShadowSettings};
/// let gpu = penumbra::HeadlessGpu::new()?;
/// let scene = penumbra::load_scene(std::path::Path::new("assets/scenes/teapot.ron"))?;
/// let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, ShadowSettings::default())?;
/// renderer.watch_device_loss(gpu.device_loss.clone());
/// let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
/// let camera = scene.view(0)?;
/// // The distance-map method, then PCSS for comparison, on the same scene.
/// let ours = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 640, 480)?;
/// let plan = renderer.last_report().expect("a frame").plan;
/// assert!(plan.chain.distance_map());
/// renderer.set_settings(&gpu.device, ShadowSettings { method: ShadowMethod::Pcss, ..ShadowSettings::default() })?;
/// let pcss = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 640, 480)?;
/// // Every intermediate texture of the last frame, for inspection:
/// let raw = renderer.debug_texture(penumbra::LightTexture::Visibility);
/// # let _ = (ours, pcss, raw); Ok(()) }
/// ```
pub struct Renderer {
    device: wgpu::Device,
    settings: ShadowSettings,
    color_format: wgpu::TextureFormat,
    layouts: SceneLayouts,
    /// The camera's frame uniform (prepass, composite, reference).
    frame_buffer: wgpu::Buffer,
    shadows: Shadows,
    /// The key light's id in `shadows`.
    light: LightId,
    /// The ids of the scene's further lights, in the scene's order.
    more: Vec<LightId>,
    /// Whose maps [`Renderer::debug_texture`] gives: 0 the key light, k further light k - 1.
    debug_light: usize,
    prepass: Option<DepthPrepass>,
    composite: Option<CompositePass>,
    /// The visibility texture the composite is bound to.
    composite_source: Option<wgpu::TextureView>,
    forward: Option<ForwardPass>,
    /// The shadow map the forward pass is bound to.
    forward_source: Option<wgpu::Texture>,
    /// The ground truth's running mean (method `reference` only).
    reference: Option<GroundTruth>,
    /// A 1x1 depth standing in for the prepass where the forward pass runs alone: the light's
    /// map needs only the camera's matrices.
    no_depth: wgpu::Texture,
    size: (u32, u32),
    last_report: Option<FrameReport>,
    /// Reports the device's loss ([`Renderer::watch_device_loss`]).
    loss: Option<crate::device::DeviceLoss>,
    timer: Option<crate::timing::Timer>,
}

const FRAME_SIZE: usize = size_of::<FrameUniform>();

/// The least time [`Renderer::time_frames`] spends on its warm-up frames, in milliseconds: a
/// GPU that idles between configurations runs its first frames at a low clock (an H100 read
/// 345 MHz idle against 1980 at most, and a frame's passes took twice their time).
pub const WARMUP_MIN_MS: f64 = 150.0;

impl Renderer {
    /// Creates a renderer drawing into targets of `color_format` with `settings`.
    pub fn new(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        settings: ShadowSettings,
    ) -> Result<Self> {
        Self::with_layouts(device, color_format, settings, SceneLayouts::new(device))
    }

    /// As [`Renderer::new`], drawing scenes made with `layouts` (shared with other renderers,
    /// so that one [`GpuScene`] serves them all, as in a side-by-side comparison).
    pub fn with_layouts(
        device: &wgpu::Device,
        color_format: wgpu::TextureFormat,
        settings: ShadowSettings,
        layouts: SceneLayouts,
    ) -> Result<Self> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        let mut shadows = Shadows::new(device, shadows_settings(&settings))?;
        let light = shadows.add_light(device, Light::default())?;
        let frame_buffer = crate::gpu_helpers::uniform_buffer(device, "Renderer::frame", FRAME_SIZE as u64);
        let mut renderer = Self {
            device: device.clone(),
            settings,
            color_format,
            layouts,
            frame_buffer,
            shadows,
            light,
            more: Vec::new(),
            debug_light: 0,
            prepass: None,
            composite: None,
            composite_source: None,
            forward: None,
            forward_source: None,
            reference: None,
            no_depth: device.create_texture(&wgpu::TextureDescriptor {
                label: Some("Renderer::no_depth"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DepthPrepass::DEPTH_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            }),
            size: (0, 0),
            last_report: None,
            loss: None,
            timer: None,
        };
        renderer.allocate_checked()?;
        Ok(renderer)
    }

    /// The layouts a [`GpuScene`] must be made with to be drawn by this renderer.
    pub fn layouts(&self) -> &SceneLayouts {
        &self.layouts
    }

    /// The settings the renderer draws with ([`Renderer::set_settings`] changes them).
    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    /// The format of the targets [`Renderer::render`] draws into.
    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.color_format
    }

    /// Applies new settings: the light's maps are recreated when their resolution, format,
    /// bias or culling change; a new method's passes are allocated on its first frame and the
    /// old method's dropped.
    pub fn set_settings(&mut self, device: &wgpu::Device, settings: ShadowSettings) -> Result<()> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        self.shadows.set_settings(device, shadows_settings(&settings))?;
        if settings.shadow_map != self.settings.shadow_map {
            self.forward = None;
            self.forward_source = None;
        }
        self.settings = settings;
        self.allocate_checked()
    }

    /// Sets the output size. A zero width or height (a minimized window) is accepted: frames
    /// are then skipped until a non-zero size is set again.
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        if self.size == (width, height) {
            return;
        }
        self.size = (width, height);
        if width > 0 && height > 0 {
            if let Some(p) = &mut self.prepass {
                p.resize(device, width, height);
            }
            if let Some(p) = &mut self.reference {
                p.resize(device, width, height);
            }
            if let Some(p) = &mut self.forward {
                p.resize(device, width, height);
            }
            self.composite_source = None;
        }
    }

    /// The output size in pixels, as last given to [`Renderer::resize`].
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Times every pass from now on: with GPU timestamps where the device has them (returns
    /// true), otherwise by submitting and waiting after every pass (returns false; slower, for
    /// measuring only).
    pub fn enable_timing(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> bool {
        let timer = self
            .timer
            .get_or_insert_with(|| crate::timing::Timer::new(device, queue));
        matches!(timer, crate::timing::Timer::Gpu(_))
    }

    /// Times every pass by submitting and waiting after each, even where timestamps exist
    /// (to compare the two, or on drivers whose timestamps are unreliable).
    pub fn enable_wall_clock_timing(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        self.timer = Some(crate::timing::Timer::WallClock(
            crate::timing::WallClockTimer::new(device, queue),
        ));
    }

    /// The time of each pass of the last submitted frame, when timing is enabled. Waits for
    /// the GPU to finish that frame.
    pub fn pass_times(&self, device: &wgpu::Device) -> Option<Result<Vec<crate::timing::PassTime>>> {
        self.timer.as_ref().map(|t| t.read(device))
    }

    /// After a frame rendered into `target` and submitted: while a light's maps are to be
    /// drawn at another resolution ([`crate::MapResolution::FromPenumbra`], which measures its
    /// penumbrae as it renders; [`Shadows::settle`]), renders the frame again (at most three
    /// times), so that one frame shows what a running application settles to.
    pub fn settle(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
    ) -> Result<()> {
        for _ in 0..3 {
            if !self.shadows.settle(device, queue)? {
                break;
            }
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("Renderer::settle"),
            });
            self.render(queue, &mut encoder, scene, camera, target)?;
            queue.submit([encoder.finish()]);
        }
        Ok(())
    }

    /// Renders at least `warmup` untimed frames (more, until they have taken
    /// [`WARMUP_MIN_MS`]: a GPU raises its clock only under sustained load) and then `frames`
    /// timed frames of `scene` into a `width` x `height` target of this renderer's format,
    /// timing every pass ([`Self::enable_timing`]), and returns the timed frames' times.
    /// `before_frame(scene, i)` runs before frame `i` (counting the warm-up): a benchmark turns
    /// the light there so every pass runs.
    #[allow(clippy::too_many_arguments)]
    pub fn time_frames(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &mut GpuScene,
        camera: &Camera,
        (width, height): (u32, u32),
        warmup: usize,
        frames: usize,
        mut before_frame: impl FnMut(&mut GpuScene, usize) -> Result<()>,
    ) -> Result<crate::timing::TimedFrames> {
        super::gpu::check_target_size(device, (width, height))?;
        let target = super::gpu::color_target(
            device,
            "Renderer::time_frames target",
            (width, height),
            self.color_format(),
        );
        let view = target.create_view(&Default::default());
        self.enable_timing(device, queue);
        self.resize(device, width, height);
        let mut timed = crate::timing::TimedFrames::default();
        let warming = std::time::Instant::now();
        let mut warmup = warmup;
        let mut i = 0;
        while i < warmup + frames {
            before_frame(scene, i)?;
            let start = std::time::Instant::now();
            let mut encoder = device.create_command_encoder(&Default::default());
            self.render(queue, &mut encoder, scene, camera, &view)?;
            queue.submit([encoder.finish()]);
            crate::error::wait_for_gpu(device, "waiting for a timed frame")?;
            if i < warmup {
                // The timed frames draw the maps at the resolution they settle to.
                if i == 0 {
                    self.settle(device, queue, scene, camera, &view)?;
                }
                if i + 1 == warmup && warming.elapsed().as_secs_f64() * 1e3 < WARMUP_MIN_MS {
                    warmup += 1;
                }
                i += 1;
                continue;
            }
            i += 1;
            timed.wall_ms.push(start.elapsed().as_secs_f64() * 1e3);
            if let Some(times) = self.pass_times(device) {
                let times = times?;
                timed.pass_sum_ms.push(times.iter().map(|p| p.milliseconds).sum());
                // A pass run once per light counts once per frame, its lights summed.
                let mut frame = std::collections::BTreeMap::<&'static str, f64>::new();
                for p in times {
                    *frame.entry(p.pass).or_default() += p.milliseconds;
                    timed.stages.insert(p.pass, p.stage);
                }
                for (pass, ms) in frame {
                    timed.passes.entry(pass).or_default().push(ms);
                }
            }
        }
        Ok(timed)
    }

    /// Makes this renderer's shadows take their passes' pipelines, shader modules and bind
    /// group layouts from where `other`'s take theirs ([`Shadows::share_pipelines_with`]): two
    /// renderers of one device (a side-by-side comparison, several views) then compile each
    /// shadow pass once between them. Call it before the first frame: the passes made before
    /// keep their own. The renderer's own passes (prepass, composite, forward) stay its own. A
    /// renderer of another device is refused with an error naming `other`.
    pub fn share_pipelines_with(&mut self, other: &Renderer) -> Result<()> {
        self.shadows.share_pipelines_with(&other.shadows)
    }

    /// Has [`Renderer::render`] and the reference's calls report
    /// [`PenumbraError::DeviceLost`] once `loss` has seen the device lost (see
    /// [`crate::DeviceLoss`]; a [`crate::HeadlessGpu`] has one).
    pub fn watch_device_loss(&mut self, loss: crate::device::DeviceLoss) {
        self.shadows.watch_device_loss(loss.clone());
        self.loss = Some(loss);
    }

    /// [`PenumbraError::DeviceLost`] where the watched device is lost.
    fn check_device(&self) -> Result<()> {
        self.loss
            .as_ref()
            .map_or(Ok(()), crate::device::DeviceLoss::check)
    }

    /// What the last frame did.
    pub fn last_report(&self) -> Option<&FrameReport> {
        self.last_report.as_ref()
    }

    /// The [`Shadows`] this renderer drives (the scene's lights, on its own prepass depth).
    pub fn shadows(&self) -> &Shadows {
        &self.shadows
    }

    /// Makes [`Renderer::debug_texture`] give the maps of light `index` of the last frame (0:
    /// the key light, k: `Scene::more_lights[k - 1]`). Where that light is gone, the key
    /// light's are given.
    pub fn set_debug_light(&mut self, index: usize) {
        self.debug_light = index;
    }

    /// An intermediate texture of the last frame, if the current method has it: of the light
    /// [`Renderer::set_debug_light`] chose (default the key light). Under the reference,
    /// [`LightTexture::Visibility`] is the reference's accumulated mean.
    pub fn debug_texture(&self, which: LightTexture) -> Option<&wgpu::Texture> {
        match (which, self.settings.method) {
            (LightTexture::Visibility, ShadowMethod::Reference) => {
                self.reference.as_ref().map(|p| p.visibility_texture())
            }
            _ => self.shadows.light_texture(self.debug_light_id(), which),
        }
    }

    /// The layer of [`Renderer::debug_texture`]'s texture that holds its light's
    /// ([`Shadows::light_texture_layer`]; 0 for the reference's mean).
    pub fn debug_texture_layer(&self, which: LightTexture) -> Option<u32> {
        match (which, self.settings.method) {
            (LightTexture::Visibility, ShadowMethod::Reference) => self.reference.as_ref().map(|_| 0),
            _ => self.shadows.light_texture_layer(self.debug_light_id(), which),
        }
    }

    /// The camera depth of the renderer's own prepass (the depth the lights' screen-space
    /// passes read), once a frame has run it.
    pub fn camera_depth_texture(&self) -> Option<&wgpu::Texture> {
        self.prepass.as_ref().map(|p| p.depth_texture())
    }

    /// The light whose maps [`Renderer::debug_texture`] gives.
    fn debug_light_id(&self) -> LightId {
        match self.debug_light {
            0 => self.light,
            k => self.more.get(k - 1).copied().unwrap_or(self.light),
        }
    }

    /// The receiver mask of the renderer's own depth prepass (R8: 1 where a receiver was
    /// drawn), when it has run.
    pub(crate) fn receiver_mask_texture(&self) -> Option<&wgpu::Texture> {
        self.prepass.as_ref().map(|p| p.receiver_mask_texture())
    }

    /// The visibility texture the last frame composited (resolved: blurred if the method
    /// blurs, indirect attenuation applied; the reference's mean), or `None` for the methods
    /// that shade in one forward pass.
    pub fn composited_visibility(&self) -> Option<&wgpu::Texture> {
        let plan = self.last_report.as_ref()?.plan;
        if !plan.composite {
            None
        } else if plan.reference {
            self.debug_texture(LightTexture::Visibility)
        } else {
            self.shadows.visibility_texture()
        }
    }

    /// The depth shadow map of the last frame: the key light's, at its layer
    /// [`Renderer::debug_texture_layer`] (`LightTexture::ShadowMap`) where the lights' maps
    /// share an array.
    pub fn shadow_map_texture(&self) -> Option<&wgpu::Texture> {
        self.shadows.light_texture(self.light, LightTexture::ShadowMap)
    }

    /// The light's view used by the last frame.
    pub fn light_view(&self) -> Option<&LightView> {
        self.last_report.as_ref().map(|r| &r.light.light_view)
    }

    /// [`Self::allocate`], turning a device's refusal (a format it cannot render to, say) into
    /// an error that names the method instead of a panic.
    fn allocate_checked(&mut self) -> Result<()> {
        let device = self.device.clone();
        let ((), error) = crate::gpu_helpers::scoped(&device, || self.allocate(&device));
        match error {
            None => Ok(()),
            Some(error) => Err(PenumbraError::Gpu {
                during: format!("creating the passes of method `{}`", self.settings.method.name()),
                reason: format!("this device cannot run it: {error}"),
            }),
        }
    }

    /// Creates the renderer's own passes the method may need and drops the rest. The
    /// shadow chain's passes are [`Shadows`]' to allocate.
    fn allocate(&mut self, device: &wgpu::Device) {
        let method = self.settings.method;
        // Several lights are composited, whatever the method.
        let screen = method.is_screen_space() || !self.more.is_empty();
        // Methods that need a light size fall back to the forward pass when it is zero.
        let forward = !screen
            || matches!(
                method,
                ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Pcss
            );
        let (w, h) = (self.size.0.max(1), self.size.1.max(1));
        let layouts = &self.layouts;
        keep(&mut self.prepass, screen, || {
            let mut p = DepthPrepass::new(device, layouts, FRAME_SIZE);
            p.resize(device, w, h);
            p
        });
        if let Some(p) = &mut self.prepass {
            p.bind(device, &self.frame_buffer);
        }
        keep(&mut self.composite, screen, || {
            CompositePass::new(device, layouts, self.color_format, FRAME_SIZE)
        });
        self.composite_source = None;
        keep(&mut self.reference, method == ShadowMethod::Reference, || {
            GroundTruth::new(device, FRAME_SIZE, (w, h))
        });
        if !forward {
            self.forward = None;
            self.forward_source = None;
        }
        if !screen || method == ShadowMethod::Reference {
            self.shadows.set_maps_only(true);
        }
    }

    /// Gives `shadows` the scene's further lights (added, changed or removed to match); when
    /// the frame changes between one light and several, the renderer's own passes follow.
    fn sync_lights(&mut self, device: &wgpu::Device, scene: &GpuScene) -> Result<()> {
        let lights = scene.more_lights();
        let was_single = self.more.is_empty();
        while self.more.len() > lights.len() {
            if let Some(id) = self.more.pop() {
                self.shadows.remove_light(id)?;
            }
        }
        for (k, light) in lights.iter().enumerate() {
            match self.more.get(k) {
                Some(&id) => self.shadows.set_light(id, *light)?,
                None => {
                    let id = self.shadows.add_light(device, *light)?;
                    self.more.push(id);
                }
            }
        }
        if was_single != self.more.is_empty() {
            self.allocate_checked()?;
        }
        Ok(())
    }

    /// Errors unless `target` is a view of a texture of the renderer's size and format that
    /// can be rendered to. The texture's format may also be the sRGB or linear counterpart of
    /// the renderer's: a browser's canvas is `Rgba8Unorm` or `Bgra8Unorm` and is drawn through
    /// a view of its sRGB format (its `view_formats`; wgpu refuses a view of any format the
    /// texture does not list, and a view does not say its own).
    fn check_target(&self, target: &wgpu::TextureView) -> Result<()> {
        let texture = target.texture();
        let fail = |reason: String| Err(PenumbraError::input("render target", reason));
        if (texture.width(), texture.height()) != self.size {
            return fail(format!(
                "it is {}x{}, the renderer {}x{} (call Renderer::resize)",
                texture.width(),
                texture.height(),
                self.size.0,
                self.size.1
            ));
        }
        if texture.format().remove_srgb_suffix() != self.color_format.remove_srgb_suffix() {
            return fail(format!(
                "its format is {:?}, the renderer's {:?} (make the renderer with the target's format)",
                texture.format(),
                self.color_format
            ));
        }
        if !texture.usage().contains(wgpu::TextureUsages::RENDER_ATTACHMENT) || texture.sample_count() != 1 {
            return fail("it needs RENDER_ATTACHMENT usage and one sample".into());
        }
        Ok(())
    }

    /// Records one frame into `target` (a view of a texture of the renderer's color format and
    /// size) and says what it did: the prepass, the light's [`Shadows`] chain on its depth, the
    /// composite; hard shadows in one forward pass. `Ok(None)` while the size is zero; an error
    /// for a target of another size or format.
    pub fn render(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
    ) -> Result<Option<FrameReport>> {
        self.check_device()?;
        if self.size.0 == 0 || self.size.1 == 0 {
            return Ok(None);
        }
        self.check_target(target)?;
        let device = self.device.clone();
        let lit = shadows_settings_lit(&self.settings, scene.lighting().0);
        if *self.shadows.settings() != lit {
            self.shadows.set_settings(&device, lit)?;
        }
        let light = *scene.light();
        self.sync_lights(&device, scene)?;
        let plan = PassPlan::for_lights(&self.settings, &light, 1 + self.more.len());
        let matrices = CameraMatrices::from_camera(camera, self.size.0 as f32 / self.size.1 as f32);
        let casters = scene.casters();
        self.shadows.set_light(self.light, light)?;
        self.shadows.set_maps_only(plan.forward);

        let mut timer = self.timer.take();
        if let Some(t) = &mut timer {
            t.begin(encoder);
        }
        let mut passes = Vec::new();
        let mut mark = |encoder: &mut wgpu::CommandEncoder, label: &'static str, stage: PassStage| {
            passes.push(label);
            if let Some(t) = &mut timer {
                t.mark(encoder, label, stage);
            }
        };
        let result = self.encode_frame(&device, queue, encoder, scene, &matrices, target, plan, &mut mark);
        if let Some(t) = &mut timer {
            t.finish(encoder);
        }
        self.timer = timer;
        let (shadow_maps_rendered, spreads, light_view) = result?;
        let _ = casters;
        // The chain the shadows ran: whether a draw wrote the light's layer is theirs to
        // decide (the device's storage formats).
        let mut plan = plan;
        if plan.shadow_map()
            && !plan.forward
            && let Some(report) = self.shadows.report(self.light)
        {
            plan.chain = report.chain;
        }
        let light = match self.shadows.report(self.light).filter(|_| plan.shadow_map()) {
            Some(report) => *report,
            None => LightReport {
                light: self.light,
                chain: plan.chain,
                shadow_maps_rendered,
                tiles_rendered: 0,
                spreads,
                light_view,
                map_resolution: light_view.tile,
                penumbra_widths: None,
                unheld_caster: None,
            },
        };
        let report = FrameReport { plan, passes, light };
        self.last_report = Some(report.clone());
        Ok(Some(report))
    }

    /// The frame's passes in order; returns whether the maps were rendered, the spreads and
    /// the light's view.
    #[allow(clippy::too_many_arguments)]
    fn encode_frame(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &CameraMatrices,
        target: &wgpu::TextureView,
        plan: PassPlan,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str, PassStage),
    ) -> Result<(bool, DerivedSpreads, LightView)> {
        let casters = scene.casters();
        // Decide the light's frame first (CPU and uniform writes only), so the camera's uniform
        // (prepass, composite, reference) is written before anything is encoded: the
        // wall-clock timer submits after every pass. Without a chain (the reference) the light
        // gets a loose fit.
        if plan.shadow_map() {
            let (depth, mask) = match &self.prepass {
                Some(p) => (p.depth_texture(), Some(p.receiver_mask_texture())),
                // The forward path reads no depth; the maps only need the camera for the fit.
                None => (&self.no_depth, None),
            };
            let view = ViewInputs {
                camera: *camera,
                depth,
                receiver_mask: mask,
            };
            // The debug views read the chosen light's intermediates.
            self.shadows.inspect(Some(self.debug_light_id()));
            self.shadows.prepare(device, queue, casters, &view)?;
        }
        // The report of the frame just prepared.
        let (light_view, spreads) = match self.shadows.report(self.light).filter(|_| plan.shadow_map()) {
            Some(report) => (report.light_view, report.spreads),
            None => self.loose_fit(scene),
        };
        self.write_frame_uniform(queue, scene, camera, &light_view, spreads);

        if plan.depth_prepass
            && let Some(prepass) = &self.prepass
        {
            encoder.push_debug_group("depth prepass");
            prepass.encode(encoder, scene);
            encoder.pop_debug_group();
            mark(encoder, "depth prepass", PassStage::Scene);
        }
        let mut maps_rendered = false;
        if plan.shadow_map() {
            let reports = self.shadows.encode_with_marks(encoder, casters, mark)?;
            maps_rendered = reports.first().is_some_and(|r| r.shadow_maps_rendered);
        }
        let result = (maps_rendered, spreads, light_view);
        if plan.composite {
            // The key light's visibility is layer 0 of the reference's one-layer view.
            // The reference keeps its lights' means in its own array, in the lights' order.
            let source = if plan.reference {
                self.reference
                    .as_mut()
                    .map(|r| r.visibility_array(device, encoder))
            } else {
                self.shadows.visibility().cloned()
            };
            if let Some(composite) = &mut self.composite {
                let mut lights = vec![(*scene.light(), self.light.layer())];
                if plan.reference {
                    lights.extend(scene.more_lights().iter().zip(1..).map(|(l, layer)| (*l, layer)));
                } else {
                    lights.extend(
                        scene
                            .more_lights()
                            .iter()
                            .zip(&self.more)
                            .map(|(l, id)| (*l, id.layer())),
                    );
                }
                composite.set_lights(device, queue, &lights, scene.exposure().scale());
            }
            if let (Some(composite), Some(source)) = (&mut self.composite, source)
                && self.composite_source.as_ref() != Some(&source)
            {
                composite.bind(device, &self.frame_buffer, &source);
                self.composite_source = Some(source);
            }
            if let (Some(composite), Some(prepass)) = (&self.composite, &self.prepass) {
                encoder.push_debug_group("composite");
                composite.encode(encoder, scene, camera.eye(), prepass.depth(), target);
                encoder.pop_debug_group();
                mark(encoder, "composite", PassStage::Scene);
            }
        }
        if plan.forward
            && let Some(texture) = self
                .shadows
                .light_texture(self.light, LightTexture::ShadowMap)
                .cloned()
        {
            // Bound again when the light's maps were made again (the pass is made with them).
            if self.forward_source.as_ref() != Some(&texture) {
                let view = texture.create_view(&Default::default());
                match &mut self.forward {
                    Some(f) => f.set_shadow_map(device, &view),
                    None => {
                        let mut f = ForwardPass::new(device, &self.layouts, self.color_format, &view);
                        f.resize(device, self.size.0, self.size.1);
                        self.forward = Some(f);
                    }
                }
                self.forward_source = Some(texture);
            }
            if let Some(forward) = &mut self.forward {
                forward.shade(device, scene.light());
                encoder.push_debug_group("forward");
                forward.encode(
                    encoder,
                    queue,
                    scene,
                    camera,
                    &result.2,
                    plan.method(),
                    &self.settings.shadow_map,
                    target,
                );
                encoder.pop_debug_group();
                mark(encoder, "forward", PassStage::Scene);
            }
        }
        Ok(result)
    }

    /// Renders the ground truth ([`ShadowMethod::Reference`], which must be the current
    /// method) into `target` from start to end: the camera depth, then for each of the
    /// `ShadowSettings::reference.samples` points on the light a hard shadow map and one
    /// accumulation step, each submitted on its own so memory does not grow with the count,
    /// then the composite. `progress(done, total)` is called after every sample. Blocks until
    /// all samples are in; interactive programs call [`Renderer::render_reference_step`].
    #[allow(clippy::too_many_arguments)]
    pub fn render_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
        mut progress: impl FnMut(u32, u32),
    ) -> Result<Option<FrameReport>> {
        if let Some(r) = &mut self.reference {
            r.restart();
        }
        let total = self.settings.reference.samples;
        if !self.accumulate_reference(device, queue, scene, camera, total, &mut progress)? {
            return Ok(None);
        }
        self.composite_reference(device, queue, scene, camera, target)
    }

    /// Adds up to `max_samples` more light samples to the reference and composites the mean
    /// so far into `target`, so a window can show the ground truth converging while it stays
    /// responsive. The average restarts by itself when the camera, light, scene, size or
    /// settings differ from the previous call. Returns the progress, or `None` when the
    /// target has no pixels. Once every sample is in, further calls only composite.
    #[allow(clippy::too_many_arguments)]
    pub fn render_reference_step(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
        max_samples: u32,
    ) -> Result<Option<ReferenceProgress>> {
        if !self.accumulate_reference(device, queue, scene, camera, max_samples, &mut |_, _| {})? {
            return Ok(None);
        }
        self.composite_reference(device, queue, scene, camera, target)?;
        Ok(self.reference_progress())
    }

    /// How far the reference average has come, when the method is the reference.
    pub fn reference_progress(&self) -> Option<ReferenceProgress> {
        self.reference
            .as_ref()
            .map(|r| r.progress(self.settings.reference.samples))
    }

    /// Accumulates up to `max_samples` samples (restarting the average when its inputs
    /// changed). Returns false when there is nothing to draw into.
    fn accumulate_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
        max_samples: u32,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<bool> {
        if self.settings.method != ShadowMethod::Reference {
            return Err(crate::PenumbraError::setting(
                "method",
                format!(
                    "rendering the reference needs method `reference`, not `{}`",
                    self.settings.method.name()
                ),
            ));
        }
        if self.size.0 == 0 || self.size.1 == 0 {
            return Ok(false);
        }
        let matrices = CameraMatrices::from_camera(camera, self.size.0 as f32 / self.size.1 as f32);
        let (loose, spreads) = self.loose_fit(scene);
        self.write_frame_uniform(queue, scene, &matrices, &loose, spreads);
        let (Some(prepass), Some(reference)) = (&self.prepass, &mut self.reference) else {
            return Ok(false);
        };
        let inputs = SampleInputs {
            device,
            queue,
            scene,
            camera,
            settings: &self.settings,
            size: self.size,
            frame: &self.frame_buffer,
            prepass,
        };
        reference.accumulate(inputs, max_samples, progress)?;
        Ok(true)
    }

    /// Draws the reference's mean so far into `target` (the composite of a normal frame).
    fn composite_reference(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
    ) -> Result<Option<FrameReport>> {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("reference: composite"),
        });
        let report = self.render(queue, &mut encoder, scene, camera, target);
        queue.submit([encoder.finish()]);
        report
    }

    /// Writes the uniform the prepass, composite and reference read.
    /// The light fitted to the scene's bounds alone and the spreads it gives: for the frames
    /// `Shadows` did not plan (the forward path and the reference).
    fn loose_fit(&self, scene: &GpuScene) -> (LightView, DerivedSpreads) {
        let light = *scene.light();
        let loose = LightView::fit(&light, &scene.shadow_bounds());
        let derived = derive_spreads(&light, &loose, &scene.shadow_bounds(), &scene.caster_parts(), 1.0);
        let spreads = crate::shadows::spreads(&self.settings, derived);
        (loose, spreads)
    }

    fn write_frame_uniform(
        &self,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &CameraMatrices,
        light_view: &LightView,
        spreads: DerivedSpreads,
    ) {
        let light = *scene.light();
        queue.write_buffer(
            &self.frame_buffer,
            0,
            bytemuck::bytes_of(&FrameUniform::new(&FrameInputs {
                camera,
                width: self.size.0,
                height: self.size.1,
                light: &light,
                ambient: scene.ambient(),
                light_view,
                settings: &self.settings,
                spreads,
                caster_radius: scene.caster_bounds().radius(),
                receiver_mask: false,
                distance_map: false,
                map_scale: 1.0,
                map_layers: Default::default(),
            })),
        );
    }
}

/// The settings the renderer's [`Shadows`] runs: the reference accumulates its own maps, so
/// its light is given hard-shadow settings.
fn shadows_settings(settings: &ShadowSettings) -> ShadowSettings {
    match settings.method {
        ShadowMethod::Reference => ShadowSettings {
            method: ShadowMethod::Hard,
            ..*settings
        },
        _ => *settings,
    }
}

/// [`shadows_settings`] for a scene lit in `lighting`: with mixed lighting the lightmap holds
/// the indirect light, so the method's indirect-light attenuation is off.
fn shadows_settings_lit(settings: &ShadowSettings, lighting: crate::scene::LightingMode) -> ShadowSettings {
    let mut s = shadows_settings(settings);
    if lighting == crate::scene::LightingMode::Mixed {
        s.penumbra.indirect_weight = 0.0;
    }
    s
}

/// Makes `slot` hold a pass exactly when `wanted`.
fn keep<T>(slot: &mut Option<T>, wanted: bool, make: impl FnOnce() -> T) {
    if !wanted {
        *slot = None;
    } else if slot.is_none() {
        *slot = Some(make());
    }
}

/// Renders one frame of `scene` from `camera` into a new `width` x `height` sRGB texture and
/// returns it as an image. The renderer must have been made for `Rgba8UnormSrgb`.
pub fn render_to_image(
    gpu: &super::gpu::HeadlessGpu,
    renderer: &mut Renderer,
    scene: &GpuScene,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage> {
    render_to_image_with_progress(gpu, renderer, scene, camera, width, height, |_, _| {})
}

/// As [`render_to_image`]; for the reference method `progress(done, total)` is called after
/// every light sample.
pub fn render_to_image_with_progress(
    gpu: &super::gpu::HeadlessGpu,
    renderer: &mut Renderer,
    scene: &GpuScene,
    camera: &Camera,
    width: u32,
    height: u32,
    progress: impl FnMut(u32, u32),
) -> Result<image::RgbaImage> {
    gpu.device_loss.check()?;
    let result = render_to_image_now(gpu, renderer, scene, camera, (width, height), progress);
    // A device lost meanwhile is the cause of whatever else failed (a read-back, say); wgpu
    // tells of the loss when it polls the device.
    if result.is_err() {
        let _ = gpu.device.poll(wgpu::PollType::Poll);
    }
    gpu.device_loss.check()?;
    result
}

fn render_to_image_now(
    gpu: &super::gpu::HeadlessGpu,
    renderer: &mut Renderer,
    scene: &GpuScene,
    camera: &Camera,
    (width, height): (u32, u32),
    progress: impl FnMut(u32, u32),
) -> Result<image::RgbaImage> {
    super::gpu::check_target_size(&gpu.device, (width, height))?;
    let target = super::gpu::color_target(
        &gpu.device,
        "penumbra::render_to_image target",
        (width, height),
        renderer.color_format(),
    );
    let view = target.create_view(&Default::default());
    renderer.resize(&gpu.device, width, height);
    if renderer.settings().method == ShadowMethod::Reference {
        renderer.render_reference(&gpu.device, &gpu.queue, scene, camera, &view, progress)?;
    } else {
        // The encoder is this function's own, so what wgpu finds wrong in the commands
        // (reported at `finish`) comes back as an error too.
        PenumbraError::scoped(
            &gpu.device,
            || "rendering a frame".into(),
            || {
                let mut encoder = gpu
                    .device
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("penumbra::render_to_image"),
                    });
                let report = renderer.render(&gpu.queue, &mut encoder, scene, camera, &view);
                gpu.queue.submit([encoder.finish()]);
                report
            },
        )?;
        // The frame a running application settles to: again at the map resolution its
        // penumbrae ask for (`MapResolution::FromPenumbra`).
        renderer.settle(&gpu.device, &gpu.queue, scene, camera, &view)?;
    }
    let pixels = super::gpu::read_texture_rgba8(&gpu.device, &gpu.queue, &target)?;
    image::RgbaImage::from_raw(width, height, pixels).ok_or_else(|| PenumbraError::Gpu {
        during: "reading back the frame".into(),
        reason: "size mismatch".into(),
    })
}
