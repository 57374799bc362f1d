//! The top-level renderer: runs the method's passes in order for one frame.

use crate::error::Result;
use crate::frame::{DerivedSpreads, FrameInputs, FrameUniform, derive_spreads, is_point_light};
use crate::gpu_scene::{GpuScene, SceneLayouts};
use crate::light_space::{FitInputs, LightView};
use crate::passes::{
    BlurPass, CompositePass, DistanceMapPass, FattenedShadowMapPass, ForwardPass, PcfPass, PcssPass,
    ReferencePass, ShadowMapPass, screen_target,
};
use crate::scene::{Camera, Light};
use crate::settings::{ShadowMapSettings, ShadowMethod, ShadowSettings, SpreadMode};

/// Which passes a frame runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PassPlan {
    /// The method actually drawn: a method that needs a light size falls back to
    /// [`ShadowMethod::Hard`] when the light has none.
    pub method: ShadowMethod,
    pub shadow_map: bool,
    pub fattened_map: bool,
    /// The camera depth prepass (every screen-space method).
    pub depth_prepass: bool,
    /// The prepass also writes the distance map and mask.
    pub distance_map: bool,
    pub pcf: bool,
    pub pcss: bool,
    /// The reference's accumulated visibility is composited (accumulated by
    /// [`Renderer::render_reference`]).
    pub reference: bool,
    pub blur: bool,
    pub composite: bool,
    /// The one-pass lit forward pass (hard and hw2x2).
    pub forward: bool,
}

impl PassPlan {
    /// The passes `settings.method` needs under `light`.
    pub fn new(settings: &ShadowSettings, light: &Light) -> Self {
        let method = match settings.method {
            ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Pcss if is_point_light(light) => {
                ShadowMethod::Hard
            }
            m => m,
        };
        let blur_taps = match method {
            ShadowMethod::Traditional => settings.traditional.blur_taps,
            _ => settings.penumbra.blur_taps,
        };
        let screen = method.is_screen_space();
        PassPlan {
            method,
            shadow_map: true,
            fattened_map: method.uses_distance_map(),
            depth_prepass: screen,
            distance_map: method.uses_distance_map(),
            pcf: matches!(
                method,
                ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Traditional
            ),
            pcss: method == ShadowMethod::Pcss,
            reference: method == ShadowMethod::Reference,
            blur: matches!(
                method,
                ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Traditional
            ) && blur_taps > 1,
            composite: screen,
            forward: !screen,
        }
    }

    /// The names of the passes, in the order they run.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.shadow_map, "shadow map"),
            (self.fattened_map, "fattened shadow map"),
            (self.depth_prepass && self.distance_map, "distance map"),
            (self.depth_prepass && !self.distance_map, "depth prepass"),
            (self.pcf, "pcf"),
            (self.pcss, "pcss"),
            (self.reference, "reference"),
            (self.blur, "blur"),
            (self.composite, "composite"),
            (self.forward, "forward"),
        ]
        .into_iter()
        .filter_map(|(on, name)| on.then_some(name))
        .collect()
    }
}

/// What a frame did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameReport {
    pub plan: PassPlan,
    /// False when the shadow map and fattened map were reused from an earlier frame.
    pub shadow_maps_rendered: bool,
    /// The spreads derived from the light (physical mode) for this frame.
    pub spreads: DerivedSpreads,
    pub light_view: LightView,
}

/// An intermediate texture, for debug views.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DebugTexture {
    /// Depth of the casters from the light.
    ShadowMap,
    /// Depth of the fattened casters from the light.
    FattenedMap,
    /// Camera depth.
    CameraDepth,
    /// RG16F: R = distance to the fattened occluder (world units), G = mask.
    DistanceMap,
    /// Raw PCF or PCSS visibility (R16F).
    Visibility,
    /// Blurred visibility (R16F).
    BlurredVisibility,
}

impl DebugTexture {
    /// Every intermediate texture, in the order the passes make them.
    pub const ALL: [DebugTexture; 6] = [
        DebugTexture::ShadowMap,
        DebugTexture::FattenedMap,
        DebugTexture::CameraDepth,
        DebugTexture::DistanceMap,
        DebugTexture::Visibility,
        DebugTexture::BlurredVisibility,
    ];
}

/// How far a progressive reference has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceProgress {
    /// Light samples averaged so far.
    pub done: u32,
    /// Light samples the settings ask for.
    pub total: u32,
}

impl ReferenceProgress {
    pub fn is_complete(&self) -> bool {
        self.done >= self.total
    }
}

/// What a progressive reference's average depends on.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ReferenceKey {
    camera: Camera,
    light: Light,
    scene: (u64, u64),
    size: (u32, u32),
    settings: ShadowSettings,
}

/// What decides whether the shadow maps can be reused.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ShadowKey {
    scene: (u64, u64),
    light: Light,
    light_view: [f32; 16],
    shadow_map: ShadowMapSettings,
    fatten_distance: Option<f32>,
}

/// Owns the passes and their targets. Made once per output format; [`Renderer::resize`] when
/// the output size changes, [`Renderer::set_settings`] when settings change. Passes the
/// current method does not use are not allocated.
pub struct Renderer {
    settings: ShadowSettings,
    color_format: wgpu::TextureFormat,
    layouts: SceneLayouts,
    frame_buffer: wgpu::Buffer,
    /// A 1x1 zero distance map for methods without one.
    no_distance: (wgpu::Texture, wgpu::TextureView),
    shadow_map: ShadowMapPass,
    fattened_map: Option<FattenedShadowMapPass>,
    forward: Option<ForwardPass>,
    distance_map: Option<DistanceMapPass>,
    pcf: Option<PcfPass>,
    pcss: Option<PcssPass>,
    reference: Option<ReferencePass>,
    blur: Option<BlurPass>,
    composite: Option<CompositePass>,
    size: (u32, u32),
    shadow_key: Option<ShadowKey>,
    reference_key: Option<ReferenceKey>,
    last_report: Option<FrameReport>,
    timer: Option<crate::timing::Timer>,
}

const FRAME_SIZE: usize = size_of::<FrameUniform>();

impl Renderer {
    /// Creates the passes `settings.method` needs for drawing into targets of `color_format`.
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
        let shadow_map = ShadowMapPass::new(device, &layouts, &settings.shadow_map);
        let frame_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("Renderer::frame"),
            size: FRAME_SIZE as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let no_distance = screen_target(
            device,
            "Renderer::no_distance_map",
            1,
            1,
            DistanceMapPass::DISTANCE_FORMAT,
        );
        let mut renderer = Self {
            settings,
            color_format,
            layouts,
            frame_buffer,
            no_distance,
            shadow_map,
            fattened_map: None,
            forward: None,
            distance_map: None,
            pcf: None,
            pcss: None,
            reference: None,
            blur: None,
            composite: None,
            size: (0, 0),
            shadow_key: None,
            reference_key: None,
            last_report: None,
            timer: None,
        };
        renderer.allocate_checked(device)?;
        Ok(renderer)
    }

    /// The layouts a [`GpuScene`] must be made with to be drawn by this renderer.
    pub fn layouts(&self) -> &SceneLayouts {
        &self.layouts
    }

    pub fn settings(&self) -> &ShadowSettings {
        &self.settings
    }

    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.color_format
    }

    /// Applies new settings: recreates the shadow maps when their resolution, format, bias or
    /// culling change, allocates the passes a new method needs and drops the others.
    pub fn set_settings(&mut self, device: &wgpu::Device, settings: ShadowSettings) -> Result<()> {
        settings.validate(Some(device.limits().max_texture_dimension_2d))?;
        if settings.shadow_map != *self.shadow_map.settings() {
            self.shadow_map = ShadowMapPass::new(device, &self.layouts, &settings.shadow_map);
            self.fattened_map = None;
            self.forward = None;
            self.shadow_key = None;
        }
        self.settings = settings;
        self.allocate_checked(device)
    }

    /// Sets the output size. A zero width or height (a minimized window) is accepted: frames
    /// are then skipped until a non-zero size is set again.
    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        if self.size == (width, height) {
            return;
        }
        self.size = (width, height);
        if width > 0 && height > 0 {
            self.resize_targets(device);
        }
    }

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

    /// What the last frame did.
    pub fn last_report(&self) -> Option<&FrameReport> {
        self.last_report.as_ref()
    }

    /// An intermediate texture of the last frame, if the current method has it.
    pub fn debug_texture(&self, which: DebugTexture) -> Option<&wgpu::Texture> {
        match which {
            DebugTexture::ShadowMap => Some(self.shadow_map.texture()),
            DebugTexture::FattenedMap => self.fattened_map.as_ref().map(|p| p.texture()),
            DebugTexture::CameraDepth => self.distance_map.as_ref().map(|p| p.depth_texture()),
            DebugTexture::DistanceMap => self
                .distance_map
                .as_ref()
                .filter(|_| self.settings.method.uses_distance_map())
                .map(|p| p.distance_texture()),
            DebugTexture::Visibility => self
                .pcf
                .as_ref()
                .map(|p| p.visibility_texture())
                .or_else(|| self.pcss.as_ref().map(|p| p.visibility_texture()))
                .or_else(|| self.reference.as_ref().map(|p| p.visibility_texture())),
            DebugTexture::BlurredVisibility => self.blur.as_ref().map(|p| p.blurred_texture()),
        }
    }

    /// The visibility texture the last frame composited (blurred if the method blurs), or
    /// `None` for the methods that shade in one forward pass.
    pub fn composited_visibility(&self) -> Option<&wgpu::Texture> {
        let plan = self.last_report.as_ref()?.plan;
        if !plan.composite {
            return None;
        }
        if plan.blur {
            self.debug_texture(DebugTexture::BlurredVisibility)
        } else {
            self.debug_texture(DebugTexture::Visibility)
        }
    }

    /// The depth shadow map.
    pub fn shadow_map(&self) -> &wgpu::TextureView {
        self.shadow_map.view()
    }

    pub fn shadow_map_texture(&self) -> &wgpu::Texture {
        self.shadow_map.texture()
    }

    /// The light's view used by the last frame.
    pub fn light_view(&self) -> Option<&LightView> {
        self.last_report.as_ref().map(|r| &r.light_view)
    }

    /// [`Self::allocate`], turning a device's refusal (a format it cannot render to, say) into
    /// an error that names the method instead of a panic.
    fn allocate_checked(&mut self, device: &wgpu::Device) -> Result<()> {
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        self.allocate(device);
        match pollster::block_on(scope.pop()) {
            None => Ok(()),
            Some(error) => Err(crate::PenumbraError::Gpu {
                during: format!("creating the passes of method `{}`", self.settings.method.name()),
                reason: format!("this device cannot run it: {error}"),
            }),
        }
    }

    /// Creates the passes the method needs (for any light size) and drops the rest, then
    /// re-points every pass at its inputs.
    fn allocate(&mut self, device: &wgpu::Device) {
        let method = self.settings.method;
        let screen = method.is_screen_space();
        let distance = method.uses_distance_map();
        let uses_pcf = matches!(
            method,
            ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Traditional
        );
        // Methods that need a light size fall back to the forward pass when it is zero.
        let forward = !screen
            || matches!(
                method,
                ShadowMethod::Ours | ShadowMethod::OursFast | ShadowMethod::Pcss
            );
        let layouts = &self.layouts;
        let settings = self.settings.shadow_map;
        keep(&mut self.fattened_map, distance, || {
            FattenedShadowMapPass::new(device, layouts, &settings)
        });
        keep(&mut self.distance_map, screen, || {
            DistanceMapPass::new(device, layouts, FRAME_SIZE)
        });
        keep(&mut self.pcf, uses_pcf, || PcfPass::new(device, FRAME_SIZE));
        keep(&mut self.pcss, method == ShadowMethod::Pcss, || {
            PcssPass::new(device, FRAME_SIZE)
        });
        keep(&mut self.reference, method == ShadowMethod::Reference, || {
            ReferencePass::new(device, FRAME_SIZE)
        });
        let blur_taps = match method {
            ShadowMethod::Traditional => self.settings.traditional.blur_taps,
            _ => self.settings.penumbra.blur_taps,
        };
        keep(&mut self.blur, uses_pcf && blur_taps > 1, || {
            BlurPass::new(device, FRAME_SIZE)
        });
        keep(&mut self.composite, screen, || {
            CompositePass::new(device, layouts, self.color_format, FRAME_SIZE)
        });
        let shadow_view = self.shadow_map.view();
        keep(&mut self.forward, forward, || {
            ForwardPass::new(device, layouts, self.color_format, shadow_view)
        });
        self.resize_targets(device);
    }

    /// Recreates screen-sized targets and rebuilds every bind group.
    fn resize_targets(&mut self, device: &wgpu::Device) {
        let (w, h) = (self.size.0.max(1), self.size.1.max(1));
        for_each_pass_mut(self, |pass| match pass {
            AnyPass::Distance(p) => p.resize(device, w, h),
            AnyPass::Pcf(p) => p.resize(device, w, h),
            AnyPass::Pcss(p) => p.resize(device, w, h),
            AnyPass::Reference(p) => p.resize(device, w, h),
            AnyPass::Blur(p) => p.resize(device, w, h),
            AnyPass::Forward(p) => p.resize(device, w, h),
        });
        self.rebind(device);
    }

    fn rebind(&mut self, device: &wgpu::Device) {
        let frame = &self.frame_buffer;
        let shadow_map = self.shadow_map.view();
        let fattened = self.fattened_map.as_ref().map_or(shadow_map, |f| f.view());
        if let Some(d) = &mut self.distance_map {
            d.bind(device, frame, fattened);
        }
        let distance_view = match (&self.distance_map, self.settings.method.uses_distance_map()) {
            (Some(d), true) => d.distance_map(),
            _ => &self.no_distance.1,
        };
        let Some(depth) = self.distance_map.as_ref().map(|d| d.depth()) else {
            if let Some(f) = &mut self.forward {
                f.set_shadow_map(device, shadow_map);
            }
            return;
        };
        if let Some(p) = &mut self.pcf {
            p.bind(device, frame, depth, distance_view, shadow_map);
        }
        if let Some(p) = &mut self.pcss {
            p.bind(device, frame, depth, shadow_map);
        }
        if let Some(p) = &mut self.reference {
            p.bind(device, frame, depth, shadow_map);
        }
        let raw = self
            .pcf
            .as_ref()
            .map(|p| p.visibility())
            .or_else(|| self.pcss.as_ref().map(|p| p.visibility()))
            .or_else(|| self.reference.as_ref().map(|p| p.visibility()));
        if let (Some(b), Some(raw)) = (&mut self.blur, raw) {
            b.bind(device, frame, depth, distance_view, raw);
        }
        let blur_taps = match self.settings.method {
            ShadowMethod::Traditional => self.settings.traditional.blur_taps,
            _ => self.settings.penumbra.blur_taps,
        };
        let composited = match &self.blur {
            Some(b) if blur_taps > 1 => Some(b.blurred()),
            _ => raw,
        };
        if let (Some(c), Some(v)) = (&mut self.composite, composited) {
            c.bind(device, frame, v, distance_view);
        }
        if let Some(f) = &mut self.forward {
            f.set_shadow_map(device, shadow_map);
        }
    }

    /// Records one frame into `target` (a view of a texture of the renderer's color format and
    /// size) and says what it did. Reads like the method: shadow map, fattened map, distance
    /// map, PCF, blur, composite; the other methods run the subset they need.
    pub fn render(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        camera: &Camera,
        target: &wgpu::TextureView,
    ) -> Option<FrameReport> {
        if self.size.0 == 0 || self.size.1 == 0 {
            return None;
        }
        let light = *scene.light();
        let plan = PassPlan::new(&self.settings, &light);
        // Fit once to find the depth range (and so the widest penumbra), then fit the sides
        // to the casters widened by that penumbra.
        let loose = LightView::fit(&light, &scene.shadow_bounds());
        let spreads = self.spreads(&light, &loose, scene);
        let sm = &self.settings.shadow_map;
        let light_view = LightView::fit_with(&FitInputs {
            light: &light,
            casters: scene.caster_bounds(),
            casters_and_receivers: scene.shadow_bounds(),
            parts: scene.shadow_parts(),
            margin: spreads.fatten_distance * 2.0,
            fit: sm.fit,
            camera: Some((camera, self.size.0 as f32 / self.size.1 as f32)),
            resolution: sm.resolution,
            snap_to_texels: sm.snap_to_texels,
        });
        self.write_frame_uniform(queue, scene, camera, &light_view, spreads);

        // The shadow maps depend on the light, the casters and the light's window, which
        // follows the camera only with the camera fit (and then in whole texels).
        let key = ShadowKey {
            scene: scene.revision(),
            light,
            light_view: light_view.view_projection.to_cols_array(),
            shadow_map: self.settings.shadow_map,
            fatten_distance: plan.fattened_map.then_some(spreads.fatten_distance),
        };
        let shadow_maps_rendered = self.shadow_key != Some(key);
        let mut timer = self.timer.take();
        if let Some(t) = &mut timer {
            t.begin(encoder);
        }
        let mut mark = |encoder: &mut wgpu::CommandEncoder, label: &'static str| {
            if let Some(t) = &mut timer {
                t.mark(encoder, label);
            }
        };
        if shadow_maps_rendered {
            encoder.push_debug_group("shadow map");
            self.shadow_map.encode(encoder, queue, scene, &light_view);
            encoder.pop_debug_group();
            mark(encoder, "shadow map");
            if let (true, Some(fattened)) = (plan.fattened_map, &self.fattened_map) {
                encoder.push_debug_group("fattened shadow map");
                fattened.encode(encoder, queue, scene, &light_view, spreads.fatten_distance);
                encoder.pop_debug_group();
                mark(encoder, "fattened shadow map");
            }
            self.shadow_key = Some(key);
        }
        if let (true, Some(distance)) = (plan.depth_prepass, &self.distance_map) {
            encoder.push_debug_group(if plan.distance_map {
                "distance map"
            } else {
                "depth prepass"
            });
            distance.encode(encoder, scene, plan.distance_map);
            encoder.pop_debug_group();
            mark(encoder, "distance map");
        }
        if let (true, Some(pcf)) = (plan.pcf, &self.pcf) {
            encoder.push_debug_group("pcf");
            pcf.encode(encoder);
            encoder.pop_debug_group();
            mark(encoder, "pcf");
        }
        if let (true, Some(pcss)) = (plan.pcss, &self.pcss) {
            encoder.push_debug_group("pcss");
            pcss.encode(encoder);
            encoder.pop_debug_group();
            mark(encoder, "pcss");
        }
        if let (true, Some(blur)) = (plan.blur, &self.blur) {
            encoder.push_debug_group("blur");
            let taps = match plan.method {
                ShadowMethod::Traditional => self.settings.traditional.blur_taps,
                _ => self.settings.penumbra.blur_taps,
            };
            blur.encode(encoder, queue, taps);
            encoder.pop_debug_group();
            mark(encoder, "blur");
        }
        if let (true, Some(composite), Some(distance)) = (plan.composite, &self.composite, &self.distance_map)
        {
            encoder.push_debug_group("composite");
            composite.encode(encoder, scene, distance.depth(), target);
            encoder.pop_debug_group();
            mark(encoder, "composite");
        }
        if let (true, Some(forward)) = (plan.forward, &self.forward) {
            encoder.push_debug_group("forward");
            forward.encode(
                encoder,
                queue,
                scene,
                camera,
                &light_view,
                plan.method,
                &self.settings.shadow_map,
                target,
            );
            encoder.pop_debug_group();
            mark(encoder, "forward");
        }
        if let Some(t) = &mut timer {
            t.finish(encoder);
        }
        self.timer = timer;
        let report = FrameReport {
            plan,
            shadow_maps_rendered,
            spreads,
            light_view,
        };
        self.last_report = Some(report);
        Some(report)
    }

    /// Renders the ground truth ([`ShadowMethod::Reference`], which must be the current
    /// method) into `target` from start to end: the camera depth, then for each of the
    /// [`crate::ReferenceSettings::samples`] points on the light a hard shadow map and one
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
        self.reference_key = None;
        let total = self.settings.reference.samples;
        if !self.accumulate_reference(device, queue, scene, camera, total, &mut progress)? {
            return Ok(None);
        }
        Ok(self.composite_reference(device, queue, scene, camera, target))
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
        self.composite_reference(device, queue, scene, camera, target);
        Ok(self.reference_progress())
    }

    /// How far the reference average has come, when the method is the reference.
    pub fn reference_progress(&self) -> Option<ReferenceProgress> {
        self.reference.as_ref().map(|r| ReferenceProgress {
            done: r.accumulated(),
            total: self.settings.reference.samples,
        })
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
        let light = *scene.light();
        let total = self.settings.reference.samples;
        let key = ReferenceKey {
            camera: *camera,
            light,
            scene: scene.revision(),
            size: self.size,
            settings: self.settings,
        };
        let restart = self.reference_key.as_ref() != Some(&key);
        let loose = LightView::fit(&light, &scene.shadow_bounds());
        let spreads = self.spreads(&light, &loose, scene);
        self.write_frame_uniform(queue, scene, camera, &loose, spreads);
        let (Some(distance), Some(reference)) = (&self.distance_map, &mut self.reference) else {
            return Ok(false);
        };
        if restart {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reference: depth prepass"),
            });
            distance.encode(&mut encoder, scene, false);
            queue.submit([encoder.finish()]);
            reference.reset();
            self.reference_key = Some(key);
        }
        let first = reference.accumulated();
        let last = first.saturating_add(max_samples).min(total);
        for k in first..last {
            let sample = crate::light_samples::light_sample(&light, k, total);
            let view = LightView::fit_casters(&sample, &scene.caster_bounds(), &scene.shadow_bounds(), 0.0);
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reference: sample"),
            });
            self.shadow_map.encode(&mut encoder, queue, scene, &view);
            reference.accumulate(&mut encoder, queue, &view);
            queue.submit([encoder.finish()]);
            if k % 16 == 15 {
                device
                    .poll(wgpu::PollType::Wait {
                        submission_index: None,
                        timeout: None,
                    })
                    .map_err(|e| crate::PenumbraError::Gpu {
                        during: "rendering the reference".into(),
                        reason: e.to_string(),
                    })?;
            }
            progress(k + 1, total);
        }
        if last > first {
            // The shadow map now holds the last sample's, and the mean sits in the other target.
            self.shadow_key = None;
            self.rebind(device);
        }
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
    ) -> Option<FrameReport> {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("reference: composite"),
        });
        let report = self.render(queue, &mut encoder, scene, camera, target);
        queue.submit([encoder.finish()]);
        report
    }

    /// Writes the uniform every screen-space pass reads.
    fn write_frame_uniform(
        &self,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        camera: &Camera,
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
            })),
        );
    }

    /// The fatten distance and penumbra scale for this frame: derived from the light in
    /// physical mode, the user's in manual mode.
    fn spreads(&self, light: &Light, light_view: &LightView, scene: &GpuScene) -> DerivedSpreads {
        let derived = derive_spreads(
            light,
            light_view,
            &scene.shadow_bounds(),
            self.settings.shadow_map.resolution,
        );
        match self.settings.penumbra.spreads {
            SpreadMode::Physical => derived,
            SpreadMode::Manual { fatten_distance, .. } => DerivedSpreads {
                fatten_distance,
                ..derived
            },
        }
    }
}

/// Makes `slot` hold a pass exactly when `wanted`.
fn keep<T>(slot: &mut Option<T>, wanted: bool, make: impl FnOnce() -> T) {
    if !wanted {
        *slot = None;
    } else if slot.is_none() {
        *slot = Some(make());
    }
}

enum AnyPass<'a> {
    Distance(&'a mut DistanceMapPass),
    Pcf(&'a mut PcfPass),
    Pcss(&'a mut PcssPass),
    Reference(&'a mut ReferencePass),
    Blur(&'a mut BlurPass),
    Forward(&'a mut ForwardPass),
}

/// Calls `f` on every allocated pass with screen-sized targets.
fn for_each_pass_mut(r: &mut Renderer, mut f: impl FnMut(AnyPass)) {
    if let Some(p) = &mut r.distance_map {
        f(AnyPass::Distance(p));
    }
    if let Some(p) = &mut r.pcf {
        f(AnyPass::Pcf(p));
    }
    if let Some(p) = &mut r.pcss {
        f(AnyPass::Pcss(p));
    }
    if let Some(p) = &mut r.reference {
        f(AnyPass::Reference(p));
    }
    if let Some(p) = &mut r.blur {
        f(AnyPass::Blur(p));
    }
    if let Some(p) = &mut r.forward {
        f(AnyPass::Forward(p));
    }
}
