//! The demo's state and its frame: input, the split view, intermediate maps, screenshots.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use anyhow::{Context, Result};
use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::Vec3;
use penumbra::debug::{DebugView, Legend};
use penumbra::metrics::{VisibilityError, VisibilityImage};
use penumbra::{Aabb, GpuScene, Light, OrbitCamera, Scene, SceneLayouts, ShadowMethod, ShadowSettings};
use serde::{Deserialize, Serialize};

use crate::Startup;
use crate::side::Side;
use crate::stats::FrameClock;

/// What the view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapView {
    /// The final images of the two methods.
    Final,
    /// An intermediate texture of one side.
    Debug(DebugView),
    /// The visibility error of one side against the other, which must be the reference.
    Error,
}

impl MapView {
    pub fn name(self) -> &'static str {
        match self {
            MapView::Final => "final image",
            MapView::Debug(DebugView::ShadowMap) => "shadow map (depth)",
            MapView::Debug(DebugView::FattenedMap) => "fattened map (depth)",
            MapView::Debug(DebugView::Distance) => "distance map",
            MapView::Debug(DebugView::Mask) => "mask",
            MapView::Debug(DebugView::Pcf) => "raw PCF visibility",
            MapView::Debug(DebugView::Blur) => "blurred visibility",
            MapView::Error => "error vs reference",
        }
    }
}

/// How the demo ended, for the exit code of `--screenshot` runs.
#[derive(Clone, Default)]
pub struct Outcome(Arc<Mutex<Option<String>>>);

impl Outcome {
    pub fn fail(&self, message: impl Into<String>) {
        let mut slot = self.0.lock().unwrap_or_else(|e| e.into_inner());
        slot.get_or_insert(message.into());
    }

    pub fn failure(&self) -> Option<String> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

/// The light's direction as the controls see it: where the light is, seen from the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightAngles {
    /// Degrees about +Y; 0 is toward +Z.
    pub azimuth_deg: f32,
    /// Degrees above the horizon, in [1, 90].
    pub elevation_deg: f32,
}

impl LightAngles {
    pub fn of(light: &Light, center: Vec3) -> Self {
        let toward = match light {
            Light::Directional(_) => -light.direction(),
            Light::Spot(s) => (s.position - center).normalize_or(Vec3::Y),
            Light::Point(p) => (p.position - center).normalize_or(Vec3::Y),
            Light::Rect(r) => (r.position - center).normalize_or(Vec3::Y),
            Light::Disk(d) => (d.position - center).normalize_or(Vec3::Y),
        };
        Self {
            azimuth_deg: toward.x.atan2(toward.z).to_degrees(),
            elevation_deg: toward.y.clamp(-1.0, 1.0).asin().to_degrees().clamp(1.0, 90.0),
        }
    }

    /// Unit vector from the scene toward the light.
    pub fn toward(self) -> Vec3 {
        let (az, el) = (self.azimuth_deg.to_radians(), self.elevation_deg.to_radians());
        Vec3::new(el.cos() * az.sin(), el.sin(), el.cos() * az.cos())
    }

    /// `light` turned to these angles (a spot or point light keeps its distance from `center`).
    pub fn apply(self, light: &Light, center: Vec3) -> Light {
        let toward = self.toward();
        match *light {
            Light::Directional(mut d) => {
                d.direction = -toward;
                Light::Directional(d)
            }
            Light::Spot(mut s) => {
                let distance = (s.position - center).length().max(1e-3);
                s.position = center + toward * distance;
                s.direction = -toward;
                Light::Spot(s)
            }
            Light::Point(mut p) => {
                let distance = (p.position - center).length().max(1e-3);
                p.position = center + toward * distance;
                Light::Point(p)
            }
            // Area lights face the centre from where they are put, their sides kept.
            Light::Rect(mut r) => {
                let distance = (r.position - center).length().max(1e-3);
                r.position = center + toward * distance;
                r.direction = -toward;
                Light::Rect(r)
            }
            Light::Disk(mut d) => {
                let distance = (d.position - center).length().max(1e-3);
                d.position = center + toward * distance;
                d.direction = -toward;
                Light::Disk(d)
            }
        }
    }
}

/// What "Save settings" writes: everything a person tunes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SavedSettings {
    pub shadows: ShadowSettings,
    pub left: ShadowMethod,
    pub right: ShadowMethod,
    pub split: bool,
    /// The key light.
    pub light: Light,
    /// The lights beside the key light.
    #[serde(default)]
    pub more_lights: Vec<Light>,
}

/// An intermediate map shown in the view, with its legend.
pub struct MapImage {
    pub texture: egui::TextureHandle,
    pub legend: Option<Legend>,
    /// Error figures, for the error view.
    pub error: Option<VisibilityError>,
}

struct AutoScreenshot {
    path: PathBuf,
    frames: u32,
    requested: bool,
    /// Window sizes to go through first (`--exercise-resize`), one every few frames.
    resizes: Vec<ResizeStep>,
}

#[derive(Debug, Clone, Copy)]
enum ResizeStep {
    Size(f32, f32),
    Minimize(bool),
}

pub struct DemoApp {
    pub(crate) render_state: RenderState,
    pub(crate) layouts: SceneLayouts,
    pub(crate) scene: Scene,
    pub(crate) scene_name: String,
    pub(crate) gpu_scene: GpuScene,
    pub(crate) bounds: Aabb,
    pub(crate) orbit: OrbitCamera,
    /// The light the controls edit: the key light, or one of the scene's further lights.
    pub(crate) light: Light,
    /// Which: 0 the key light, k the scene's further light k - 1.
    pub(crate) selected_light: usize,
    /// The instance the "move" sliders move, and by how much (world units).
    pub(crate) moved_object: usize,
    pub(crate) object_offset: glam::Vec3,
    pub(crate) angles: LightAngles,
    pub(crate) animate_light: bool,
    pub(crate) animation_speed: f32,
    animation_time: f32,
    animation_base: LightAngles,
    pub(crate) shared: ShadowSettings,
    pub(crate) sides: [Side; 2],
    pub(crate) split: bool,
    /// Divider position across the view, in [0, 1].
    pub(crate) divider: f32,
    pub(crate) map: MapView,
    /// Which side the intermediate maps come from.
    pub(crate) map_side: usize,
    map_image: Option<MapImage>,
    pub(crate) map_stale: bool,
    /// Pixels with direct light, for the error view, and what they were computed for.
    #[allow(clippy::type_complexity)]
    direct_mask: Option<((penumbra::Camera, Light, (u32, u32)), Vec<bool>)>,
    pub(crate) render_scale: f32,
    pub(crate) continuous: bool,
    pub(crate) open_sections: Vec<String>,
    pub(crate) clock: FrameClock,
    pub(crate) open_path: String,
    pub(crate) settings_path: String,
    pub(crate) screenshot_path: String,
    pub(crate) message: Option<(String, bool)>,
    screenshot: Arc<Mutex<Option<Arc<egui::ColorImage>>>>,
    screenshot_target: Option<PathBuf>,
    auto: Option<AutoScreenshot>,
    outcome: Outcome,
    frames: u64,
    /// Window frames, drawn view or not.
    ui_frames: u64,
    view_rect_px: [f32; 4],
    divider_px: f32,
}

/// The built-in scenes, shipped in `assets/scenes`.
pub const BUILT_IN: [(&str, &str); 4] = [
    ("teapot", "teapot.ron"),
    ("character", "character.ron"),
    ("outdoor", "outdoor.ron"),
    ("room", "room.ron"),
];

pub fn built_in_path(file: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/scenes")
        .join(file)
}

impl DemoApp {
    pub fn new(cc: &eframe::CreationContext<'_>, startup: Startup, outcome: Outcome) -> Result<Self> {
        let render_state = cc
            .wgpu_render_state
            .clone()
            .context("eframe started without its wgpu renderer")?;
        let info = render_state.adapter.get_info();
        eprintln!(
            "adapter: {} ({:?}, {:?})",
            info.name, info.backend, info.device_type
        );
        let args = &startup.args;
        let scene_path = args.scene.clone().unwrap_or_else(|| built_in_path(BUILT_IN[0].1));
        let mut scene = penumbra::load_scene(&scene_path)?;
        for warning in &scene.warnings {
            eprintln!("warning: {}: {warning}", scene_path.display());
        }
        if let Some(name) = &args.lighting {
            scene.lighting = penumbra::LightingMode::ALL
                .into_iter()
                .find(|m| m.name() == name)
                .with_context(|| format!("--lighting {name}: expected dynamic, mixed or baked"))?;
        }
        let layouts = SceneLayouts::new(&render_state.device);
        let gpu_scene = GpuScene::new(&render_state.device, &render_state.queue, &layouts, &scene)?;
        let camera = scene.view(args.view).context("--view")?;
        let mut shared = ShadowSettings::preset(startup.methods[0], startup.quality);
        if let Some(samples) = args.samples {
            shared.reference.samples = samples;
        }
        let mut split = !args.single;
        let mut methods = startup.methods;
        let mut light = scene.light;
        let mut more_lights = scene.more_lights.clone();
        if let Some(saved) = startup.saved.clone() {
            shared = saved.shadows;
            methods = [saved.left, saved.right];
            split = saved.split;
            light = saved.light;
            more_lights = saved.more_lights;
        }
        shared.method = methods[0];
        shared
            .validate(Some(render_state.device.limits().max_texture_dimension_2d))
            .context("settings")?;
        let bounds = gpu_scene.bounds();
        let angles = LightAngles::of(&light, bounds.center());
        let mut app = Self {
            layouts,
            scene_name: scene_path.display().to_string(),
            scene,
            gpu_scene,
            bounds,
            orbit: OrbitCamera::from_camera(&camera),
            light,
            selected_light: 0,
            moved_object: 0,
            object_offset: glam::Vec3::ZERO,
            angles,
            animate_light: args.animate_light,
            animation_speed: 1.0,
            animation_time: 0.0,
            animation_base: angles,
            shared,
            sides: [Side::new(methods[0]), Side::new(methods[1])],
            split,
            divider: 0.5,
            map: startup.map.unwrap_or(MapView::Final),
            map_side: 0,
            map_image: None,
            map_stale: true,
            direct_mask: None,
            render_scale: args.render_scale,
            continuous: false,
            open_sections: args
                .open_sections
                .split(',')
                .map(|s| s.trim().to_string())
                .collect(),
            clock: FrameClock::new(),
            open_path: String::new(),
            settings_path: "penumbra-demo-settings.ron".into(),
            screenshot_path: "penumbra-screenshot.png".into(),
            message: None,
            screenshot: Arc::default(),
            screenshot_target: None,
            auto: args.screenshot.clone().map(|path| AutoScreenshot {
                path,
                frames: args.frames,
                requested: false,
                resizes: if args.exercise_resize {
                    let (w, h) = startup.window;
                    vec![
                        ResizeStep::Size(400.0, 300.0),
                        ResizeStep::Size(1.0, 1.0),
                        ResizeStep::Minimize(true),
                        ResizeStep::Minimize(false),
                        ResizeStep::Size(w * 0.5, h),
                        ResizeStep::Size(w, h),
                    ]
                } else {
                    Vec::new()
                },
            }),
            outcome,
            frames: 0,
            ui_frames: 0,
            view_rect_px: [0.0; 4],
            divider_px: 0.0,
            render_state,
        };
        app.gpu_scene.set_light(light)?;
        app.gpu_scene
            .set_more_lights(more_lights)
            .context("saved settings' lights")?;
        Ok(app)
    }

    pub(crate) fn camera(&self) -> penumbra::Camera {
        self.orbit.camera(&self.bounds)
    }

    pub(crate) fn say(&mut self, text: impl Into<String>) {
        self.message = Some((text.into(), false));
    }

    pub(crate) fn complain(&mut self, text: impl Into<String>) {
        let text = text.into();
        eprintln!("error: {text}");
        if self.auto.is_some() {
            self.outcome.fail(text.clone());
        }
        self.message = Some((text, true));
    }

    /// Loads a scene file or model; on failure the current scene stays and the error is shown.
    pub(crate) fn open_scene(&mut self, path: &Path) {
        let loaded = penumbra::load_scene(path).and_then(|scene| {
            let gpu = GpuScene::new(
                &self.render_state.device,
                &self.render_state.queue,
                &self.layouts,
                &scene,
            )?;
            Ok((scene, gpu))
        });
        match loaded {
            Ok((scene, gpu_scene)) => {
                let camera = scene.view(0).unwrap_or_default();
                self.bounds = gpu_scene.bounds();
                self.orbit = OrbitCamera::from_camera(&camera);
                self.light = scene.light;
                self.selected_light = 0;
                self.moved_object = 0;
                self.object_offset = glam::Vec3::ZERO;
                self.angles = LightAngles::of(&self.light, self.bounds.center());
                self.animation_base = self.angles;
                self.scene_name = path.display().to_string();
                let warnings = scene.warnings.len();
                self.scene = scene;
                self.gpu_scene = gpu_scene;
                for side in &mut self.sides {
                    side.invalidate();
                }
                self.map_stale = true;
                self.say(format!(
                    "opened {} ({} triangles{})",
                    path.display(),
                    self.gpu_scene.triangle_count(),
                    if warnings > 0 {
                        format!(", {warnings} warnings: see the terminal")
                    } else {
                        String::new()
                    }
                ));
                for w in &self.scene.warnings {
                    eprintln!("warning: {}: {w}", path.display());
                }
            }
            Err(e) => self.complain(format!("cannot open {}: {e}", path.display())),
        }
    }

    /// Jumps to the scene's viewpoint `index`.
    pub(crate) fn go_to_view(&mut self, index: usize) {
        match self.scene.view(index) {
            Ok(camera) => self.orbit = OrbitCamera::from_camera(&camera),
            Err(e) => self.complain(e.to_string()),
        }
    }

    /// Sets the selected light (validated) on the scene.
    pub(crate) fn set_light(&mut self, light: Light) {
        let result = match self.selected_light {
            0 => self.gpu_scene.set_light(light),
            k => {
                let mut more = self.gpu_scene.more_lights().to_vec();
                if let Some(slot) = more.get_mut(k - 1) {
                    *slot = light;
                }
                self.gpu_scene.set_more_lights(more)
            }
        };
        match result {
            Ok(()) => self.light = light,
            Err(e) => self.complain(format!("light: {e}")),
        }
    }

    /// Every light of the scene, the key light first.
    pub(crate) fn lights(&self) -> Vec<Light> {
        std::iter::once(*self.gpu_scene.light())
            .chain(self.gpu_scene.more_lights().iter().copied())
            .collect()
    }

    /// Makes light `index` (0: the key light) the one the controls edit.
    pub(crate) fn select_light(&mut self, index: usize) {
        let lights = self.lights();
        let Some(light) = lights.get(index) else { return };
        self.selected_light = index;
        // The maps follow the selected light.
        self.map_stale = true;
        self.light = *light;
        self.angles = LightAngles::of(light, self.bounds.center());
        self.animation_base = self.angles;
    }

    /// Adds a light of `kind` ("sun", "spot" or "point") like the key light, a quarter turn
    /// around the scene, and selects it.
    pub(crate) fn add_light(&mut self, kind: &str) {
        let center = self.bounds.center();
        let radius = self.bounds.radius().max(1e-3);
        let like = match kind {
            "spot" => crate::panel::to_spot(&self.light, center, radius),
            "point" => crate::panel::to_point(&self.light, center, radius),
            _ => crate::panel::to_directional(&self.light),
        };
        let mut angles = LightAngles::of(&like, center);
        angles.azimuth_deg = (angles.azimuth_deg + 90.0 + 180.0).rem_euclid(360.0) - 180.0;
        let mut more = self.gpu_scene.more_lights().to_vec();
        more.push(angles.apply(&like, center));
        match self.gpu_scene.set_more_lights(more) {
            Ok(()) => {
                let last = self.gpu_scene.more_lights().len();
                self.select_light(last);
            }
            Err(e) => self.complain(format!("light: {e}")),
        }
    }

    /// Removes the selected light (not the key light) and selects the one before it.
    pub(crate) fn remove_light(&mut self) {
        let k = self.selected_light;
        if k == 0 {
            return;
        }
        let mut more = self.gpu_scene.more_lights().to_vec();
        if k - 1 < more.len() {
            more.remove(k - 1);
        }
        match self.gpu_scene.set_more_lights(more) {
            Ok(()) => self.select_light(k - 1),
            Err(e) => self.complain(format!("light: {e}")),
        }
    }

    pub(crate) fn set_angles(&mut self, angles: LightAngles) {
        self.angles = angles;
        let light = angles.apply(&self.light, self.bounds.center());
        self.set_light(light);
    }

    /// Back to the defaults: settings, methods, light and viewpoint of the scene.
    pub(crate) fn reset(&mut self) {
        self.shared = ShadowSettings::default();
        self.sides[0].method = ShadowMethod::Ours;
        self.sides[1].method = ShadowMethod::Traditional;
        self.split = true;
        self.divider = 0.5;
        self.animate_light = false;
        if let Err(e) = self.gpu_scene.set_more_lights(self.scene.more_lights.clone()) {
            self.complain(format!("light: {e}"));
        }
        self.selected_light = 0;
        self.light = self.scene.light;
        self.angles = LightAngles::of(&self.light, self.bounds.center());
        self.animation_base = self.angles;
        let light = self.light;
        self.set_light(light);
        self.go_to_view(0);
        self.map = MapView::Final;
        self.say("settings reset to the defaults");
    }

    pub(crate) fn saved_settings(&self) -> SavedSettings {
        SavedSettings {
            shadows: self.shared,
            left: self.sides[0].method,
            right: self.sides[1].method,
            split: self.split,
            light: *self.gpu_scene.light(),
            more_lights: self.gpu_scene.more_lights().to_vec(),
        }
    }

    pub(crate) fn save_settings(&mut self) {
        let path = PathBuf::from(&self.settings_path);
        self.save_settings_to(&path);
    }

    fn save_settings_to(&mut self, path: &Path) {
        let text = ron::ser::to_string_pretty(&self.saved_settings(), ron::ser::PrettyConfig::default());
        match text
            .map_err(anyhow::Error::from)
            .and_then(|t| std::fs::write(path, t).with_context(|| format!("cannot write {}", path.display())))
        {
            Ok(()) => self.say(format!("saved settings to {}", path.display())),
            Err(e) => self.complain(format!("{e:#}")),
        }
    }

    pub(crate) fn load_settings(&mut self) {
        let path = PathBuf::from(&self.settings_path);
        let loaded = read_settings(&path).and_then(|saved| {
            saved
                .shadows
                .validate(Some(self.render_state.device.limits().max_texture_dimension_2d))
                .with_context(|| format!("{}", path.display()))?;
            saved
                .light
                .validate()
                .with_context(|| format!("{}", path.display()))?;
            Ok(saved)
        });
        match loaded {
            Ok(saved) => {
                self.shared = saved.shadows;
                self.sides[0].method = saved.left;
                self.sides[1].method = saved.right;
                self.split = saved.split;
                if let Err(e) = self.gpu_scene.set_more_lights(saved.more_lights) {
                    self.complain(format!("{}: {e}", path.display()));
                }
                self.select_light(0);
                self.set_light(saved.light);
                self.select_light(0);
                self.say(format!("loaded settings from {}", path.display()));
            }
            Err(e) => self.complain(format!("{e:#}")),
        }
    }

    pub(crate) fn request_screenshot(&mut self, ctx: &egui::Context, path: PathBuf) {
        let slot = self.screenshot.clone();
        let repaint = ctx.clone();
        self.screenshot_target = Some(path);
        ctx.request_screenshot(move |image| {
            *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(image);
            repaint.request_repaint();
        });
    }

    /// Saves a screenshot that has arrived.
    fn receive_screenshot(&mut self, ctx: &egui::Context) {
        let Some(image) = self.screenshot.lock().unwrap_or_else(|e| e.into_inner()).take() else {
            return;
        };
        let Some(path) = self.screenshot_target.take() else {
            return;
        };
        let [w, h] = image.size;
        let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
        let saved = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
            .context("screenshot has the wrong size")
            .and_then(|img| {
                img.save(&path)
                    .with_context(|| format!("cannot write {}", path.display()))
            });
        match saved {
            Ok(()) => {
                self.say(format!("saved {} ({w}x{h})", path.display()));
                eprintln!("wrote {} ({w}x{h})", path.display());
            }
            Err(e) => self.complain(format!("{e:#}")),
        }
        if self.auto.is_some() {
            let layout = serde_json::json!({
                "width": w,
                "height": h,
                "view": self.view_rect_px,
                "divider": self.divider_px,
                "split": self.split,
                "left": self.sides[0].method.name(),
                "right": self.sides[1].method.name(),
                "map": self.map.name(),
                "frames": self.frames,
                "lights": self.lights().len(),
            });
            let json = path.with_extension("json");
            if let Err(e) = std::fs::write(&json, layout.to_string()) {
                self.complain(format!("cannot write {}: {e}", json.display()));
            }
            // The settings it ran with, loadable with --settings (the same file "Save" writes).
            self.save_settings_to(&path.with_extension("settings.ron"));
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    /// Files dropped on the window: a scene or model opens, a settings file (.ron with
    /// `shadows`) loads.
    fn handle_dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        for path in dropped {
            self.open_path = path.display().to_string();
            self.open_scene(&path);
        }
    }

    fn animate(&mut self, ctx: &egui::Context) {
        if !self.animate_light {
            return;
        }
        let dt = ctx.input(|i| i.stable_dt).min(0.1);
        self.animation_time += dt * self.animation_speed;
        let t = self.animation_time;
        // Sweep the light from high to low and around, so shadows stretch away from their
        // contacts and the penumbra widens with the distance, then tightens again.
        let angles = LightAngles {
            azimuth_deg: self.animation_base.azimuth_deg + 50.0 * (0.37 * t).sin(),
            elevation_deg: (45.0 + 30.0 * t.sin()).clamp(5.0, 85.0),
        };
        self.set_angles(angles);
        ctx.request_repaint();
    }

    /// Mouse in the 3D view: left drag orbits (or moves the divider when grabbed near it),
    /// right drag pans, Shift + left drag or middle drag moves the light, the wheel zooms.
    fn handle_view_input(&mut self, ui: &egui::Ui, response: &egui::Response, rect: egui::Rect) {
        let divider_x = rect.left() + self.divider * rect.width();
        let near_divider =
            |p: egui::Pos2| self.split && self.map == MapView::Final && (p.x - divider_x).abs() < 8.0;
        if response.hovered()
            && let Some(p) = response.hover_pos()
            && near_divider(p)
        {
            ui.ctx().set_cursor_icon(egui::CursorIcon::ResizeHorizontal);
        }
        let grabbed_id = response.id.with("divider");
        let mut dragging_divider = ui.ctx().data(|d| d.get_temp::<bool>(grabbed_id)).unwrap_or(false);
        if response.drag_started_by(egui::PointerButton::Primary)
            && let Some(p) = response.interact_pointer_pos()
        {
            dragging_divider = near_divider(p - response.drag_delta());
        }
        if response.drag_stopped() {
            dragging_divider = false;
        }
        ui.ctx().data_mut(|d| d.insert_temp(grabbed_id, dragging_divider));
        let delta = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Primary) {
            if dragging_divider {
                if let Some(p) = response.interact_pointer_pos() {
                    self.divider = ((p.x - rect.left()) / rect.width()).clamp(0.0, 1.0);
                }
            } else if shift {
                self.drag_light(delta);
            } else {
                self.orbit.rotate(-delta.x * 0.4, delta.y * 0.4);
            }
        }
        if response.dragged_by(egui::PointerButton::Middle) {
            self.drag_light(delta);
        }
        if response.dragged_by(egui::PointerButton::Secondary) {
            let scale = (self.orbit.fov_y_deg.to_radians() * 0.5).tan() * 2.0 / rect.height().max(1.0);
            self.orbit.pan(-delta.x * scale, delta.y * scale);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.orbit.zoom((-scroll * 0.002).exp());
            }
        }
    }

    fn drag_light(&mut self, delta: egui::Vec2) {
        let mut angles = self.angles;
        angles.azimuth_deg -= delta.x * 0.4;
        angles.elevation_deg = (angles.elevation_deg - delta.y * 0.3).clamp(1.0, 90.0);
        self.animation_base = angles;
        self.set_angles(angles);
    }

    /// Redraws the sides that need it; returns whether any did.
    fn draw_sides(&mut self, size: (u32, u32)) -> bool {
        let camera = self.camera();
        let count = if self.split || self.map == MapView::Error {
            2
        } else {
            1
        };
        let mut drew = false;
        // The raw PCF view reads `ours`' visibility before the blur, kept apart only when asked.
        let mut shared = self.shared;
        shared.execution.raw_visibility |= self.map == MapView::Debug(DebugView::Pcf);
        for i in 0..count {
            let measure_mask = self.sides[i].stats.redraws.is_multiple_of(15);
            let (left, right) = self.sides.split_at_mut(1);
            let (side, other) = if i == 0 {
                (&mut left[0], &right[0])
            } else {
                (&mut right[0], &left[0])
            };
            let result = side.draw(
                &self.render_state,
                &self.layouts,
                &self.gpu_scene,
                &camera,
                &shared,
                size,
                self.continuous,
                measure_mask,
                other.renderer(),
            );
            self.sides[i].set_debug_light(self.selected_light);
            match result {
                Ok(d) => drew |= d,
                Err(e) => {
                    let name = self.sides[i].method.name();
                    self.complain(format!("{name}: {e}"));
                    // Fall back to what worked before: the method's defaults.
                    self.sides[i].reset_renderer();
                    self.sides[i].method = if i == 0 {
                        ShadowMethod::Ours
                    } else {
                        ShadowMethod::Traditional
                    };
                }
            }
        }
        drew
    }

    /// The view: both sides' images split at the divider (or one side's intermediate map).
    fn view(&mut self, ui: &mut egui::Ui) {
        let rect = ui.available_rect_before_wrap();
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        self.handle_view_input(ui, &response, rect);
        let ppp = ui.ctx().pixels_per_point();
        let size = (
            (rect.width() * ppp * self.render_scale).round().max(0.0) as u32,
            (rect.height() * ppp * self.render_scale).round().max(0.0) as u32,
        );
        let max = self.render_state.device.limits().max_texture_dimension_2d;
        let size = (size.0.min(max), size.1.min(max));
        self.view_rect_px = [
            rect.left() * ppp,
            rect.top() * ppp,
            rect.width() * ppp,
            rect.height() * ppp,
        ];
        self.divider_px = (rect.left() + self.divider * rect.width()) * ppp;
        if size.0 == 0 || size.1 == 0 {
            return;
        }
        let drew = self.draw_sides(size);
        self.frames += 1;
        if drew {
            self.map_stale = true;
        }
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, egui::Color32::from_gray(20));
        if self.map != MapView::Final {
            self.update_map(ui.ctx());
            self.paint_map(&painter, rect);
        } else {
            self.paint_final(&painter, rect);
        }
        if let Some(progress) = self
            .sides
            .iter()
            .filter_map(|s| s.stats.reference)
            .find(|p| !p.is_complete())
        {
            painter.text(
                rect.left_bottom() + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                format!("reference: {}/{} light samples", progress.done, progress.total),
                egui::FontId::proportional(14.0),
                egui::Color32::YELLOW,
            );
            ui.ctx().request_repaint();
        }
    }

    fn paint_final(&self, painter: &egui::Painter, rect: egui::Rect) {
        let white = egui::Color32::WHITE;
        let full = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        let label = |pos: egui::Pos2, align: egui::Align2, text: &str| {
            let galley = painter.layout_no_wrap(text.to_string(), egui::FontId::proportional(16.0), white);
            let at = align.anchor_size(pos, galley.size());
            painter.rect_filled(at.expand(4.0), 3.0, egui::Color32::from_black_alpha(140));
            painter.galley(at.min, galley, white);
        };
        if !self.split {
            if let Some(id) = self.sides[0].texture_id() {
                painter.image(id, rect, full, white);
            }
            label(
                rect.left_top() + egui::vec2(10.0, 10.0),
                egui::Align2::LEFT_TOP,
                self.sides[0].method.name(),
            );
            return;
        }
        let x = rect.left() + self.divider * rect.width();
        let (left, right) = (
            egui::Rect::from_min_max(rect.min, egui::pos2(x, rect.bottom())),
            egui::Rect::from_min_max(egui::pos2(x, rect.top()), rect.max),
        );
        if let Some(id) = self.sides[0].texture_id() {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(self.divider, 1.0));
            painter.image(id, left, uv, white);
        }
        if let Some(id) = self.sides[1].texture_id() {
            let uv = egui::Rect::from_min_max(egui::pos2(self.divider, 0.0), egui::pos2(1.0, 1.0));
            painter.image(id, right, uv, white);
        }
        painter.line_segment(
            [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
            egui::Stroke::new(2.0, egui::Color32::from_rgb(255, 200, 60)),
        );
        label(
            rect.left_top() + egui::vec2(10.0, 10.0),
            egui::Align2::LEFT_TOP,
            self.sides[0].method.name(),
        );
        label(
            rect.right_top() + egui::vec2(-10.0, 10.0),
            egui::Align2::RIGHT_TOP,
            self.sides[1].method.name(),
        );
    }

    /// Reads the chosen intermediate map back when the image changed.
    fn update_map(&mut self, ctx: &egui::Context) {
        if !self.map_stale {
            return;
        }
        // While the reference converges, refresh the error map every few frames only.
        let converging = self
            .sides
            .iter()
            .any(|s| s.stats.reference.is_some_and(|p| !p.is_complete()));
        if converging
            && self.map == MapView::Error
            && !self.frames.is_multiple_of(8)
            && self.map_image.is_some()
        {
            return;
        }
        self.map_stale = false;
        let result = match self.map {
            MapView::Final => return,
            MapView::Debug(view) => self.debug_map(view),
            MapView::Error => self.error_map(),
        };
        match result {
            Ok((image, legend, error)) => {
                let size = [image.width() as usize, image.height() as usize];
                let color = egui::ColorImage::from_rgba_unmultiplied(size, image.as_raw());
                match &mut self.map_image {
                    Some(map) => {
                        map.texture.set(color, egui::TextureOptions::LINEAR);
                        map.legend = legend;
                        map.error = error;
                    }
                    None => {
                        self.map_image = Some(MapImage {
                            texture: ctx.load_texture(
                                "intermediate map",
                                color,
                                egui::TextureOptions::LINEAR,
                            ),
                            legend,
                            error,
                        })
                    }
                }
                if self.message.as_ref().is_some_and(|(_, is_error)| *is_error) {
                    self.message = None;
                }
            }
            Err(e) => {
                self.map_image = None;
                self.message = Some((e, true));
            }
        }
    }

    #[allow(clippy::type_complexity)]
    fn debug_map(
        &self,
        view: DebugView,
    ) -> Result<(image::RgbaImage, Option<Legend>, Option<VisibilityError>), String> {
        let side = &self.sides[self.map_side.min(1)];
        let renderer = side.renderer().ok_or("the side has not rendered yet")?;
        let d = penumbra::debug::debug_image_with_legend(
            &self.render_state.device,
            &self.render_state.queue,
            renderer,
            view,
        )
        .map_err(|e| format!("{}: {e}", side.method.name()))?;
        Ok((d.image, d.legend, None))
    }

    /// The visibility error of the non-reference side against the reference side.
    #[allow(clippy::type_complexity)]
    fn error_map(&mut self) -> Result<(image::RgbaImage, Option<Legend>, Option<VisibilityError>), String> {
        let reference = self
            .sides
            .iter()
            .position(|s| s.method == ShadowMethod::Reference)
            .ok_or("the error view needs `reference` on one side of the split")?;
        let test = &self.sides[1 - reference];
        if test.method == ShadowMethod::Reference {
            return Err("the error view needs a method other than `reference` on the other side".into());
        }
        let read = |side: &Side| -> Result<VisibilityImage, String> {
            let renderer = side.renderer().ok_or("a side has not rendered yet")?;
            let texture = renderer.composited_visibility().ok_or_else(|| {
                format!(
                    "`{}` shades in one forward pass and keeps no visibility texture to compare",
                    side.method.name()
                )
            })?;
            let (values, channels) =
                penumbra::read_texture_f32(&self.render_state.device, &self.render_state.queue, texture)
                    .map_err(|e| e.to_string())?;
            Ok(VisibilityImage {
                width: texture.width(),
                height: texture.height(),
                visibility: values
                    .chunks_exact(channels as usize)
                    .map(|px| Some(px[0]))
                    .collect(),
            })
        };
        let mut r = read(&self.sides[reference])?;
        let mut t = read(test)?;
        if (r.width, r.height) != (t.width, t.height) {
            return Err("the sides have not both rendered at this size yet".into());
        }
        // Measure only where direct light falls, as penumbra::metrics does: surfaces facing
        // away from the light are dark whatever their visibility.
        // The key light's, as the metrics measure it.
        let key = (self.camera(), *self.gpu_scene.light(), (r.width, r.height));
        if self.direct_mask.as_ref().is_none_or(|(k, _)| *k != key) {
            let mut scene = self.scene.clone();
            scene.light = key.1;
            let mask = penumbra::metrics::direct_light_mask(
                &self.render_state.device,
                &self.render_state.queue,
                &scene,
                &key.0,
                self.shared,
                key.2,
            )
            .map_err(|e| e.to_string())?;
            self.direct_mask = Some((key, mask));
        }
        if let Some((_, mask)) = &self.direct_mask {
            for image in [&mut r, &mut t] {
                for (v, lit) in image.visibility.iter_mut().zip(mask) {
                    if !lit {
                        *v = None;
                    }
                }
            }
        }
        let error = penumbra::metrics::visibility_error(&r, &t).map_err(|e| e.to_string())?;
        let legend = Legend {
            low: 0.0,
            high: 0.5,
            unit: "absolute visibility error",
        };
        Ok((
            penumbra::metrics::error_heat_map(&r, &t),
            Some(legend),
            Some(error),
        ))
    }

    fn paint_map(&self, painter: &egui::Painter, rect: egui::Rect) {
        let Some(map) = &self.map_image else {
            return;
        };
        let [w, h] = map.texture.size();
        let aspect = w as f32 / h.max(1) as f32;
        let fit = if rect.width() / rect.height() > aspect {
            egui::vec2(rect.height() * aspect, rect.height())
        } else {
            egui::vec2(rect.width(), rect.width() / aspect)
        };
        let image_rect = egui::Rect::from_center_size(rect.center(), fit);
        let full = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        painter.image(map.texture.id(), image_rect, full, egui::Color32::WHITE);
        let side = self.sides[self.map_side.min(1)].method.name();
        let title = match self.map {
            MapView::Error => format!(
                "{}: {}",
                self.map.name(),
                self.sides
                    .iter()
                    .find(|s| s.method != ShadowMethod::Reference)
                    .map_or("", |s| s.method.name())
            ),
            _ => format!("{} of {side}", self.map.name()),
        };
        painter.text(
            rect.left_top() + egui::vec2(10.0, 10.0),
            egui::Align2::LEFT_TOP,
            title,
            egui::FontId::proportional(16.0),
            egui::Color32::WHITE,
        );
        if let Some(e) = &map.error {
            painter.text(
                rect.left_top() + egui::vec2(10.0, 32.0),
                egui::Align2::LEFT_TOP,
                format!(
                    "RMSE {:.4}, penumbra RMSE {:.4}, max {:.3}",
                    e.rmse, e.penumbra_rmse, e.max_abs
                ),
                egui::FontId::proportional(14.0),
                egui::Color32::WHITE,
            );
        }
        if let Some(legend) = map.legend {
            paint_legend(painter, rect, legend, self.map == MapView::Error);
        }
    }
}

/// A color bar with its end values, at the bottom right of the view.
fn paint_legend(painter: &egui::Painter, rect: egui::Rect, legend: Legend, heat: bool) {
    let bar = egui::Rect::from_min_size(
        rect.right_bottom() + egui::vec2(-270.0, -46.0),
        egui::vec2(240.0, 14.0),
    );
    painter.rect_filled(
        bar.expand2(egui::vec2(8.0, 26.0)),
        4.0,
        egui::Color32::from_black_alpha(160),
    );
    let steps = 48;
    for k in 0..steps {
        let t = k as f32 / (steps - 1) as f32;
        let [r, g, b] = if heat {
            penumbra::metrics::heat_color(t * 0.5)
        } else {
            penumbra::debug::false_color(t)
        };
        let x0 = bar.left() + bar.width() * k as f32 / steps as f32;
        let x1 = bar.left() + bar.width() * (k + 1) as f32 / steps as f32;
        painter.rect_filled(
            egui::Rect::from_min_max(egui::pos2(x0, bar.top()), egui::pos2(x1 + 0.5, bar.bottom())),
            0.0,
            egui::Color32::from_rgb(r, g, b),
        );
    }
    let color = egui::Color32::WHITE;
    let font = egui::FontId::proportional(12.0);
    painter.text(
        bar.left_bottom() + egui::vec2(0.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{:.3}", legend.low),
        font.clone(),
        color,
    );
    painter.text(
        bar.right_bottom() + egui::vec2(0.0, 2.0),
        egui::Align2::RIGHT_TOP,
        format!("{:.3}", legend.high),
        font.clone(),
        color,
    );
    painter.text(
        bar.center_top() - egui::vec2(0.0, 2.0),
        egui::Align2::CENTER_BOTTOM,
        legend.unit,
        font,
        color,
    );
}

pub fn read_settings(path: &Path) -> Result<SavedSettings> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    ron::from_str(&text).with_context(|| format!("{} is not a demo settings file", path.display()))
}

impl eframe::App for DemoApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.clock.tick();
        self.receive_screenshot(&ctx);
        self.handle_dropped_files(&ctx);
        self.animate(&ctx);
        egui::Panel::right("settings")
            .default_size(340.0)
            .resizable(true)
            .show(ui, |ui| self.settings_panel(ui));
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| self.view(ui));
        if self.continuous {
            ctx.request_repaint();
        }
        self.drive_auto_screenshot(&ctx);
    }
}

impl DemoApp {
    /// `--screenshot`: after the frames asked for (and any reference complete), take it.
    fn drive_auto_screenshot(&mut self, ctx: &egui::Context) {
        self.ui_frames += 1;
        let ui_frames = self.ui_frames;
        let Some(auto) = &mut self.auto else {
            return;
        };
        ctx.request_repaint();
        if auto.requested {
            return;
        }
        if !auto.resizes.is_empty() {
            // One step every five window frames, so each size is seen for a while.
            if ui_frames.is_multiple_of(5) {
                let step = auto.resizes.remove(0);
                eprintln!("exercise: {step:?}");
                ctx.send_viewport_cmd(match step {
                    ResizeStep::Size(w, h) => egui::ViewportCommand::InnerSize(egui::vec2(w, h)),
                    ResizeStep::Minimize(on) => egui::ViewportCommand::Minimized(on),
                });
            }
            return;
        }
        let converging = self
            .sides
            .iter()
            .any(|s| s.stats.reference.is_some_and(|p| !p.is_complete()));
        let ready = self.frames >= auto.frames as u64 && !converging && !self.map_stale;
        let too_long = ui_frames > auto.frames as u64 + 20_000;
        if too_long {
            self.outcome
                .fail("the screenshot never became ready (a reference that does not finish?)");
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        }
        if ready || (self.map == MapView::Final && self.frames >= auto.frames as u64 && !converging) {
            let path = auto.path.clone();
            if let Some(a) = &mut self.auto {
                a.requested = true;
            }
            self.request_screenshot(ctx, path);
        }
    }
}
