//! One side of the split view: a penumbra renderer drawing one method into its own texture,
//! which egui shows. Nothing is recreated per frame: the target only when the view's size
//! changes, the renderer's passes only when a setting that needs them changes.

use std::time::Instant;

use eframe::egui;
use penumbra::debug::MaskSavings;
use penumbra::timing::PassTime;
use penumbra::{
    Camera, GpuScene, Light, ReferenceProgress, Renderer, SceneLayouts, ShadowMethod, ShadowSettings,
};

/// The format the sides render in; egui samples it as sRGB.
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Everything a frame's image depends on: when it is unchanged, the side is not redrawn.
#[derive(Debug, Clone, Copy, PartialEq)]
struct FrameKey {
    camera: Camera,
    light: Light,
    settings: ShadowSettings,
    size: (u32, u32),
    scene: (u64, u64, u64),
    lighting: (penumbra::LightingMode, f32),
    lightmap_filter: penumbra::LightmapFilter,
    exposure: penumbra::Exposure,
}

struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

/// What the last redraw measured.
#[derive(Debug, Clone, Default)]
pub struct SideStats {
    /// Per-pass GPU times of the last redraw.
    pub passes: Vec<PassTime>,
    /// Their sum, in milliseconds.
    pub gpu_ms: f32,
    /// Wall time of the last redraw on the CPU side (encode, submit and wait), milliseconds.
    pub wall_ms: f32,
    /// The mask's savings (distance-map methods), measured every few redraws.
    pub mask: Option<MaskSavings>,
    /// The key light's maps: texels a tile as drawn, and the penumbra widths measured.
    pub maps: Option<(u32, Option<penumbra::PenumbraWidths>)>,
    /// The reference's progress, when this side shows it.
    pub reference: Option<ReferenceProgress>,
    /// Redraws so far.
    pub redraws: u64,
}

pub struct Side {
    pub method: ShadowMethod,
    renderer: Option<Renderer>,
    target: Option<Target>,
    texture_id: Option<egui::TextureId>,
    key: Option<FrameKey>,
    /// Light samples the reference takes per frame; adapted to keep frames near 60 ms.
    reference_batch: u32,
    pub stats: SideStats,
}

impl Side {
    pub fn new(method: ShadowMethod) -> Self {
        Self {
            method,
            renderer: None,
            target: None,
            texture_id: None,
            key: None,
            reference_batch: 4,
            stats: SideStats::default(),
        }
    }

    pub fn renderer(&self) -> Option<&Renderer> {
        self.renderer.as_ref()
    }

    /// Whose intermediate maps the map views show: light `index` (0: the key light).
    pub fn set_debug_light(&mut self, index: usize) {
        if let Some(r) = &mut self.renderer {
            r.set_debug_light(index);
        }
    }

    pub fn texture_id(&self) -> Option<egui::TextureId> {
        self.texture_id
    }

    /// Forgets the last image so the next [`Side::draw`] redraws.
    pub fn invalidate(&mut self) {
        self.key = None;
    }

    /// The settings this side runs: the shared ones with its own method.
    pub fn settings_for(&self, shared: &ShadowSettings) -> ShadowSettings {
        ShadowSettings {
            method: self.method,
            ..*shared
        }
    }

    /// Brings the renderer and target up to date and redraws when anything the image depends
    /// on changed (or `force`). Returns whether it drew. A reference keeps adding light
    /// samples, a batch per call, until it is complete.
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
        render_state: &eframe::egui_wgpu::RenderState,
        layouts: &SceneLayouts,
        scene: &GpuScene,
        camera: &Camera,
        shared: &ShadowSettings,
        size: (u32, u32),
        force: bool,
        measure_mask: bool,
        other: Option<&Renderer>,
    ) -> Result<bool, penumbra::PenumbraError> {
        let (device, queue) = (&render_state.device, &render_state.queue);
        if size.0 == 0 || size.1 == 0 {
            return Ok(false);
        }
        let settings = self.settings_for(shared);
        match &mut self.renderer {
            Some(r) => {
                if *r.settings() != settings {
                    r.set_settings(device, settings)?;
                }
            }
            None => {
                let mut r = Renderer::with_layouts(device, COLOR_FORMAT, settings, layouts.clone())?;
                // The other side's shadow passes serve this one too: each is compiled once.
                if let Some(other) = other {
                    r.share_pipelines_with(other)?;
                }
                r.enable_timing(device, queue);
                self.renderer = Some(r);
            }
        }
        self.ensure_target(render_state, size);
        let key = FrameKey {
            camera: *camera,
            light: *scene.light(),
            settings,
            size,
            scene: scene.revision(),
            lighting: scene.lighting(),
            lightmap_filter: scene.lightmap_filter(),
            exposure: scene.exposure(),
        };
        let reference_pending = self.stats.reference.is_some_and(|p| !p.is_complete());
        let unchanged = self.key == Some(key);
        if unchanged && !force && !(self.method == ShadowMethod::Reference && reference_pending) {
            return Ok(false);
        }
        let (Some(renderer), Some(target)) = (&mut self.renderer, &self.target) else {
            return Ok(false);
        };
        renderer.resize(device, size.0, size.1);
        let start = Instant::now();
        if self.method == ShadowMethod::Reference {
            let progress = renderer.render_reference_step(
                device,
                queue,
                scene,
                camera,
                &target.view,
                self.reference_batch,
            )?;
            self.stats.reference = progress;
            self.stats.passes.clear();
            self.stats.gpu_ms = 0.0;
            device
                .poll(wgpu::PollType::Wait {
                    submission_index: None,
                    timeout: None,
                })
                .map_err(|e| penumbra::PenumbraError::Gpu {
                    during: "waiting for the reference".into(),
                    reason: e.to_string(),
                })?;
            // Aim for about 60 ms of samples per frame so the window stays responsive.
            let ms = start.elapsed().as_secs_f32() * 1e3;
            self.reference_batch = if ms < 30.0 {
                (self.reference_batch * 2).min(256)
            } else if ms > 90.0 {
                (self.reference_batch / 2).max(1)
            } else {
                self.reference_batch
            };
        } else {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("demo side"),
            });
            renderer.render(queue, &mut encoder, scene, camera, &target.view)?;
            queue.submit([encoder.finish()]);
            // Again while the light's maps move to the resolution its penumbrae ask for
            // (`MapResolution::FromPenumbra`): the side shows what it settles to.
            renderer.settle(device, queue, scene, camera, &target.view)?;
            self.stats.reference = None;
            if let Some(times) = renderer.pass_times(device) {
                self.stats.passes = times?;
                self.stats.gpu_ms = self.stats.passes.iter().map(|p| p.milliseconds as f32).sum();
            }
        }
        self.stats.wall_ms = start.elapsed().as_secs_f32() * 1e3;
        self.stats.redraws += 1;
        self.stats.maps = renderer
            .last_report()
            .and_then(|r| renderer.shadows().report(r.light.light))
            .map(|r| (r.map_resolution, r.penumbra_widths));
        let has_mask = renderer
            .last_report()
            .is_some_and(|r| r.plan.chain.distance_map());
        if !has_mask {
            self.stats.mask = None;
        } else if measure_mask || self.stats.mask.is_none() {
            self.stats.mask = Some(penumbra::debug::mask_savings(device, queue, renderer)?);
        }
        self.key = Some(key);
        Ok(true)
    }

    /// Makes the target match `size`, registering it with egui (or re-pointing egui's
    /// texture at the new one).
    fn ensure_target(&mut self, render_state: &eframe::egui_wgpu::RenderState, size: (u32, u32)) {
        if self
            .target
            .as_ref()
            .is_some_and(|t| (t.texture.width(), t.texture.height()) == size)
        {
            return;
        }
        let device = &render_state.device;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("demo side target"),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COLOR_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let mut egui_renderer = render_state.renderer.write();
        match self.texture_id {
            Some(id) => egui_renderer.update_egui_texture_from_wgpu_texture(
                device,
                &view,
                wgpu::FilterMode::Linear,
                id,
            ),
            None => {
                self.texture_id =
                    Some(egui_renderer.register_native_texture(device, &view, wgpu::FilterMode::Linear))
            }
        }
        self.target = Some(Target { texture, view });
        self.key = None;
    }

    /// Drops the renderer (for example when the scene changes its layouts' owner) but keeps
    /// the egui texture registration.
    pub fn reset_renderer(&mut self) {
        self.renderer = None;
        self.key = None;
        self.stats = SideStats::default();
    }
}
