//! The settings panel: every setting of the library with its unit, the scene, the light,
//! the intermediate maps, the measurements and the screenshot and settings-file buttons.

use eframe::egui;
use penumbra::debug::DebugView;
use penumbra::{
    CullMode, DepthFormat, DirectionalLight, DiskLight, Light, LightFit, MapResolution, PcfKernel,
    PointLight, Quality, RectLight, ShadowMethod, ShadowSettings, SpotLight, SpreadMode,
};

use crate::app::{BUILT_IN, DemoApp, LightAngles, MapView, built_in_path};

fn method_combo(ui: &mut egui::Ui, id: &str, label: &str, method: &mut ShadowMethod) {
    egui::ComboBox::from_id_salt(id)
        .selected_text(format!("{label}: {}", method.name()))
        .show_ui(ui, |ui| {
            for m in ShadowMethod::ALL {
                ui.selectable_value(method, m, m.name());
            }
        });
}

fn kernel_combo(ui: &mut egui::Ui, id: &str, kernel: &mut PcfKernel) {
    egui::ComboBox::from_id_salt(id)
        .selected_text(format!("PCF kernel {0}x{0}", kernel.side()))
        .show_ui(ui, |ui| {
            for k in [PcfKernel::Pcf3x3, PcfKernel::Pcf4x4, PcfKernel::Pcf5x5] {
                ui.selectable_value(kernel, k, format!("{0}x{0}", k.side()));
            }
        });
}

/// A slider for an odd tap count in [1, 31].
fn odd_taps(ui: &mut egui::Ui, taps: &mut u32, label: &str) {
    let mut half = (*taps / 2) as i32;
    ui.add(
        egui::Slider::new(&mut half, 0..=15)
            .custom_formatter(|h, _| format!("{}", 2 * h as i32 + 1))
            .text(label),
    );
    *taps = 2 * half as u32 + 1;
}

impl DemoApp {
    fn is_open(&self, section: &str) -> bool {
        self.open_sections.iter().any(|s| s == section)
    }

    pub fn settings_panel(&mut self, ui: &mut egui::Ui) {
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.heading("penumbra");
            if let Some((text, is_error)) = &self.message {
                let color = if *is_error {
                    egui::Color32::from_rgb(255, 110, 90)
                } else {
                    ui.visuals().text_color()
                };
                ui.colored_label(color, text);
            }
            self.compare_section(ui);
            self.light_section(ui);
            self.method_sections(ui);
            self.shadow_map_section(ui);
            self.view_section(ui);
            self.scene_section(ui);
            self.measure_section(ui);
            self.keep_section(ui);
        });
    }

    fn compare_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Compare")
            .default_open(self.is_open("compare"))
            .show(ui, |ui| {
                ui.checkbox(&mut self.split, "split view (drag the divider)");
                let [left, right] = &mut self.sides;
                method_combo(
                    ui,
                    "left method",
                    if self.split { "left" } else { "method" },
                    &mut left.method,
                );
                if self.split {
                    method_combo(ui, "right method", "right", &mut right.method);
                    ui.add(egui::Slider::new(&mut self.divider, 0.0..=1.0).text("divider (share of width)"));
                }
                ui.horizontal(|ui| {
                    let mut quality = None;
                    egui::ComboBox::from_id_salt("preset")
                        .selected_text("apply quality preset")
                        .show_ui(ui, |ui| {
                            for q in [Quality::Low, Quality::Medium, Quality::High, Quality::Ultra] {
                                if ui.selectable_label(false, q.name()).clicked() {
                                    quality = Some(q);
                                }
                            }
                        });
                    if let Some(q) = quality {
                        let method = self.shared.method;
                        self.shared = ShadowSettings {
                            method,
                            ..ShadowSettings::preset(method, q)
                        };
                        self.say(format!("applied the {} preset", q.name()));
                    }
                    if ui.button("reset to defaults").clicked() {
                        self.reset();
                    }
                });
            });
    }

    fn light_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Light")
            .default_open(self.is_open("light"))
            .show(ui, |ui| {
                let center = self.bounds.center();
                let radius = self.bounds.radius().max(1e-3);
                // Which light the controls below edit; lights added and removed.
                let count = self.lights().len();
                ui.horizontal_wrapped(|ui| {
                    for k in 0..count {
                        let name = if k == 0 {
                            "key".to_string()
                        } else {
                            format!("{}", k + 1)
                        };
                        if ui.selectable_label(self.selected_light == k, name).clicked() {
                            self.select_light(k);
                        }
                    }
                });
                ui.horizontal(|ui| {
                    let room = count < penumbra::MAX_LIGHTS;
                    for kind in ["sun", "spot", "point"] {
                        if ui
                            .add_enabled(room, egui::Button::new(format!("+ {kind}")))
                            .clicked()
                        {
                            self.add_light(kind);
                        }
                    }
                    if ui
                        .add_enabled(self.selected_light > 0, egui::Button::new("remove"))
                        .clicked()
                    {
                        self.remove_light();
                    }
                });
                if count > 1 {
                    ui.label("The maps show the selected light; the error view measures the key light.");
                }
                let mut light = self.light;
                ui.horizontal(|ui| {
                    let (directional, spot, point, rect, disk) = (
                        matches!(light, Light::Directional(_)),
                        matches!(light, Light::Spot(_)),
                        matches!(light, Light::Point(_)),
                        matches!(light, Light::Rect(_)),
                        matches!(light, Light::Disk(_)),
                    );
                    if ui.selectable_label(directional, "directional").clicked() && !directional {
                        light = to_directional(&light);
                    }
                    if ui.selectable_label(spot, "spot").clicked() && !spot {
                        light = to_spot(&light, center, radius);
                    }
                    if ui.selectable_label(point, "point").clicked() && !point {
                        light = to_point(&light, center, radius);
                    }
                    if ui.selectable_label(rect, "rectangle").clicked() && !rect {
                        light = to_area(&light, center, radius, true);
                    }
                    if ui.selectable_label(disk, "disk").clicked() && !disk {
                        light = to_area(&light, center, radius, false);
                    }
                });
                match &mut light {
                    Light::Directional(d) => {
                        ui.add(
                            egui::Slider::new(&mut d.angular_diameter_deg, 0.0..=20.0)
                                .suffix("°")
                                .text("size (angular diameter)"),
                        );
                        ui.add(egui::Slider::new(&mut d.intensity, 0.0..=4.0).text("intensity"));
                    }
                    Light::Spot(s) => {
                        ui.add(
                            egui::Slider::new(&mut s.radius, 0.0..=radius * 0.5)
                                .suffix(" units")
                                .text("size (disk radius)"),
                        );
                        ui.add(
                            egui::Slider::new(&mut s.cone_angle_deg, 5.0..=89.0)
                                .suffix("°")
                                .text("cone half-angle"),
                        );
                        ui.add(egui::Slider::new(&mut s.intensity, 0.0..=4.0).text("intensity"));
                    }
                    Light::Point(p) => {
                        ui.add(
                            egui::Slider::new(&mut p.radius, 0.0..=radius * 0.5)
                                .suffix(" units")
                                .text("size (sphere radius)"),
                        );
                        ui.add(egui::Slider::new(&mut p.intensity, 0.0..=4.0).text("intensity"));
                    }
                    Light::Rect(r) => {
                        ui.add(
                            egui::Slider::new(&mut r.width, 0.0..=radius)
                                .suffix(" units")
                                .text("width"),
                        );
                        ui.add(
                            egui::Slider::new(&mut r.height, 0.0..=radius)
                                .suffix(" units")
                                .text("height"),
                        );
                        ui.add(
                            egui::Slider::new(&mut r.intensity, 0.0..=40.0)
                                .logarithmic(true)
                                .text("luminance (nits)"),
                        );
                    }
                    Light::Disk(d) => {
                        ui.add(
                            egui::Slider::new(&mut d.radius, 0.0..=radius * 0.5)
                                .suffix(" units")
                                .text("size (disk radius)"),
                        );
                        ui.add(
                            egui::Slider::new(&mut d.intensity, 0.0..=40.0)
                                .logarithmic(true)
                                .text("luminance (nits)"),
                        );
                    }
                }
                if light != self.light {
                    self.set_light(light);
                }
                let mut angles = self.angles;
                ui.add(
                    egui::Slider::new(&mut angles.azimuth_deg, -180.0..=180.0)
                        .suffix("°")
                        .text("azimuth"),
                );
                ui.add(
                    egui::Slider::new(&mut angles.elevation_deg, 1.0..=90.0)
                        .suffix("°")
                        .text("elevation"),
                );
                ui.horizontal(|ui| {
                    light_gizmo(ui, &mut angles);
                    ui.vertical(|ui| {
                        ui.label("drag the dot, or Shift + drag in the view");
                        ui.checkbox(&mut self.animate_light, "animate light");
                        ui.add(egui::Slider::new(&mut self.animation_speed, 0.1..=3.0).text("speed"));
                    });
                });
                if angles != self.angles {
                    self.set_angles(angles);
                }
            });
    }

    fn method_sections(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Ours (distance map)")
            .default_open(self.is_open("ours"))
            .show(ui, |ui| {
                let p = &mut self.shared.penumbra;
                let mut manual = matches!(p.spreads, SpreadMode::Manual { .. });
                ui.horizontal(|ui| {
                    ui.radio_value(&mut manual, false, "physical (from the light)");
                    ui.radio_value(&mut manual, true, "manual");
                });
                match (&mut p.spreads, manual) {
                    (SpreadMode::Physical, true) => {
                        p.spreads = SpreadMode::Manual {
                            fatten_distance: 0.1,
                            pcf_spread: 8.0,
                            blur_spread: 8.0,
                        }
                    }
                    (SpreadMode::Manual { .. }, false) => p.spreads = SpreadMode::Physical,
                    _ => {}
                }
                if let SpreadMode::Manual {
                    fatten_distance,
                    pcf_spread,
                    blur_spread,
                } = &mut p.spreads
                {
                    ui.add(
                        egui::Slider::new(fatten_distance, 0.0..=2.0)
                            .logarithmic(true)
                            .suffix(" units")
                            .text("fatten_distance"),
                    );
                    ui.add(
                        egui::Slider::new(pcf_spread, 0.0..=200.0)
                            .logarithmic(true)
                            .suffix(" texels/unit")
                            .text("pcf_spread"),
                    );
                    ui.add(
                        egui::Slider::new(blur_spread, 0.0..=200.0)
                            .logarithmic(true)
                            .suffix(" px/unit")
                            .text("blur_spread"),
                    );
                } else {
                    ui.add(
                        egui::Slider::new(&mut p.pcf_variance_share, 0.0..=1.0)
                            .text("PCF share of the penumbra"),
                    );
                }
                kernel_combo(ui, "ours kernel", &mut p.pcf_kernel);
                ui.add(
                    egui::Slider::new(&mut p.pcf_base_spacing, 0.0..=16.0)
                        .suffix(" texels")
                        .text("PCF base spacing"),
                );
                odd_taps(ui, &mut p.blur_taps, "blur taps");
                ui.checkbox(&mut p.rotate_taps, "rotate PCF taps per pixel");
                ui.checkbox(&mut p.mask_early_out, "mask early-out (no taps outside the mask)");
                ui.checkbox(
                    &mut p.nearest_caster,
                    "beside a shadow, distance to the nearest caster",
                );
                ui.checkbox(
                    &mut p.skip_tiles_facing_away,
                    "skip tiles facing away from the light",
                );
                ui.checkbox(&mut p.skip_umbra_tiles, "skip tiles deep in the umbra");
                ui.checkbox(
                    &mut p.reduced_resolution,
                    "PCF at half resolution where the penumbra is wide",
                );
                ui.checkbox(&mut p.depth_aware_blur, "depth-aware blur");
                // The light's maps: the fattened map drawn or derived, the exit map or none.
                egui::ComboBox::from_label("fattened map")
                    .selected_text(format!("{:?}", p.fattening))
                    .show_ui(ui, |ui| {
                        for (choice, text) in [
                            (penumbra::Fattening::Auto, "Auto (by the casters' triangles)"),
                            (
                                penumbra::Fattening::Geometry,
                                "Geometry (the casters drawn again)",
                            ),
                            (
                                penumbra::Fattening::Dilation,
                                "Dilation (derived from the shadow map)",
                            ),
                        ] {
                            ui.selectable_value(&mut p.fattening, choice, text);
                        }
                    });
                ui.checkbox(&mut p.exit_map, "exit map (the casters' back faces)");
                let draw = &mut self.shared.execution.exit_map_draw;
                egui::ComboBox::from_label("exit map drawn by")
                    .selected_text(format!("{draw:?}"))
                    .show_ui(ui, |ui| {
                        for choice in [
                            penumbra::ExitMapDraw::Auto,
                            penumbra::ExitMapDraw::ShadowMapPass,
                            penumbra::ExitMapDraw::OwnPass,
                        ] {
                            ui.selectable_value(draw, choice, format!("{choice:?}"));
                        }
                    });
                // Lights alike run their PCF and blur as one dispatch each (on a GPU).
                ui.checkbox(
                    &mut self.shared.execution.light_groups,
                    "lights alike run their PCF and blur as one group",
                );
                if self.shared.execution.light_groups {
                    // The group's intermediates per listed tile: screens' worth of tiles its
                    // pool holds (0: a screen a light); fewer, less memory, more rounds.
                    ui.add(
                        egui::Slider::new(&mut self.shared.execution.light_group_pool, 0..=16)
                            .text("group's pool, screens of tiles (0: one a light)"),
                    );
                }
                let p = &mut self.shared.penumbra;
                // Every method's: draws instead of compute passes, to compare their cost.
                ui.checkbox(
                    &mut p.fragment_passes,
                    "screen-space passes as draws, not compute (all methods)",
                );
                ui.add(egui::Slider::new(&mut p.indirect_weight, 0.0..=1.0).text("indirect_weight"));
                // The light's maps at half resolution where its penumbrae are wide.
                let mut from_penumbra = matches!(p.map_resolution, MapResolution::FromPenumbra { .. });
                ui.checkbox(&mut from_penumbra, "coarser light maps where penumbrae are wide");
                p.map_resolution = match (from_penumbra, p.map_resolution) {
                    (false, _) => MapResolution::Configured,
                    (true, MapResolution::FromPenumbra { mut narrowest_texels }) => {
                        ui.add(
                            egui::Slider::new(&mut narrowest_texels, 1.0..=64.0)
                                .logarithmic(true)
                                .suffix(" texels")
                                .text("narrowest penumbra at half resolution"),
                        );
                        MapResolution::FromPenumbra { narrowest_texels }
                    }
                    (true, MapResolution::Configured) => MapResolution::from_penumbra(),
                };
            });
        egui::CollapsingHeader::new("Traditional (PCF + Gaussian)")
            .default_open(self.is_open("traditional"))
            .show(ui, |ui| {
                let t = &mut self.shared.traditional;
                kernel_combo(ui, "traditional kernel", &mut t.pcf_kernel);
                ui.add(
                    egui::Slider::new(&mut t.pcf_spacing, 0.0..=16.0)
                        .suffix(" texels")
                        .text("PCF spacing"),
                );
                odd_taps(ui, &mut t.blur_taps, "blur taps");
                ui.add(
                    egui::Slider::new(&mut t.blur_step, 0.0..=16.0)
                        .suffix(" px")
                        .text("blur step"),
                );
            });
        egui::CollapsingHeader::new("PCSS and reference")
            .default_open(self.is_open("pcss"))
            .show(ui, |ui| {
                let s = &mut self.shared;
                ui.add(
                    egui::Slider::new(&mut s.pcss.blocker_samples, 1..=64).text("PCSS blocker-search taps"),
                );
                ui.add(egui::Slider::new(&mut s.pcss.pcf_samples, 1..=64).text("PCSS filter taps"));
                ui.add(
                    egui::Slider::new(&mut s.reference.samples, 1..=4096)
                        .logarithmic(true)
                        .text("reference light samples"),
                );
            });
    }

    fn shadow_map_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Shadow map")
            .default_open(self.is_open("shadow-map"))
            .show(ui, |ui| {
                let max = self
                    .render_state
                    .device
                    .limits()
                    .max_texture_dimension_2d
                    .min(8192);
                let m = &mut self.shared.shadow_map;
                egui::ComboBox::from_id_salt("resolution")
                    .selected_text(format!("{0}x{0} texels", m.resolution))
                    .show_ui(ui, |ui| {
                        let mut r = 256;
                        while r <= max {
                            ui.selectable_value(&mut m.resolution, r, format!("{r}"));
                            r *= 2;
                        }
                    });
                egui::ComboBox::from_id_salt("depth format")
                    .selected_text(format!("depth {:?}", m.depth_format))
                    .show_ui(ui, |ui| {
                        for f in [DepthFormat::Depth16, DepthFormat::Depth24, DepthFormat::Depth32] {
                            ui.selectable_value(&mut m.depth_format, f, format!("{f:?}"));
                        }
                    });
                ui.add(egui::Slider::new(&mut m.constant_bias, 0..=64).text("constant bias (depth steps)"));
                ui.add(egui::Slider::new(&mut m.slope_bias, 0.0..=16.0).text("slope bias (x depth slope)"));
                ui.add(
                    egui::Slider::new(&mut m.normal_offset, 0.0..=8.0)
                        .suffix(" texels")
                        .text("normal offset"),
                );
                egui::ComboBox::from_id_salt("cull")
                    .selected_text(format!("cull {:?} faces", m.cull_mode))
                    .show_ui(ui, |ui| {
                        for c in [CullMode::None, CullMode::Back, CullMode::Front] {
                            ui.selectable_value(&mut m.cull_mode, c, format!("{c:?}"));
                        }
                    });
                ui.add(egui::Slider::new(&mut m.cascades.count, 1..=4).text("sun cascades"));
                if m.cascades.count > 1 {
                    ui.add(
                        egui::Slider::new(&mut m.cascades.split, 0.0..=1.0).text("split (0 uniform, 1 log)"),
                    );
                    ui.add(egui::Slider::new(&mut m.cascades.blend, 0.0..=0.5).text("blend band"));
                    if m.resolution > penumbra::settings::MAX_CASCADE_RESOLUTION {
                        m.resolution = penumbra::settings::MAX_CASCADE_RESOLUTION;
                    }
                    ui.label(format!(
                        "each cascade {0}x{0} texels (at most {1} with cascades)",
                        m.resolution,
                        penumbra::settings::MAX_CASCADE_RESOLUTION
                    ));
                }
                let mut camera_fit = matches!(m.fit, LightFit::CameraFrustum { .. });
                ui.checkbox(&mut camera_fit, "fit the light to the camera's view");
                if camera_fit {
                    let mut max_distance = match m.fit {
                        LightFit::CameraFrustum { max_distance } => max_distance,
                        LightFit::Scene => 0.0,
                    };
                    ui.add(
                        egui::Slider::new(&mut max_distance, 0.0..=500.0)
                            .logarithmic(true)
                            .max_decimals(1)
                            .text("shadow distance (0: far plane)"),
                    );
                    m.fit = LightFit::CameraFrustum { max_distance };
                } else {
                    m.fit = LightFit::Scene;
                }
                ui.checkbox(&mut m.snap_to_texels, "snap to texels (no shimmer)");
                ui.checkbox(&mut m.clear_by_copy, "clear 16-bit maps by a copy");
            });
    }

    fn view_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Intermediate maps")
            .default_open(self.is_open("maps"))
            .show(ui, |ui| {
                let before = (self.map, self.map_side);
                egui::ComboBox::from_id_salt("map")
                    .selected_text(self.map.name())
                    .show_ui(ui, |ui| {
                        ui.selectable_value(&mut self.map, MapView::Final, MapView::Final.name());
                        for v in DebugView::ALL {
                            ui.selectable_value(&mut self.map, MapView::Debug(v), MapView::Debug(v).name());
                        }
                        ui.selectable_value(&mut self.map, MapView::Error, MapView::Error.name());
                    });
                if matches!(self.map, MapView::Debug(_)) {
                    ui.horizontal(|ui| {
                        ui.label("of");
                        ui.radio_value(&mut self.map_side, 0, self.sides[0].method.name());
                        if self.split {
                            ui.radio_value(&mut self.map_side, 1, self.sides[1].method.name());
                        }
                    });
                }
                if self.map == MapView::Error {
                    ui.label("needs `reference` on one side; shows |visibility - reference|");
                }
                if (self.map, self.map_side) != before {
                    self.map_stale = true;
                }
                ui.add(
                    egui::Slider::new(&mut self.render_scale, 0.25..=1.0)
                        .text("render scale (share of pixels)"),
                );
                ui.checkbox(&mut self.continuous, "redraw every frame (for timing)");
            });
    }

    fn scene_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Scene and camera")
            .default_open(self.is_open("scene"))
            .show(ui, |ui| {
                ui.label(format!(
                    "{} ({} triangles)",
                    self.scene_name,
                    self.gpu_scene.triangle_count()
                ));
                ui.horizontal(|ui| {
                    for (name, file) in BUILT_IN {
                        if ui.button(name).clicked() {
                            self.open_scene(&built_in_path(file));
                        }
                    }
                });
                ui.horizontal(|ui| {
                    ui.add(
                        egui::TextEdit::singleline(&mut self.open_path)
                            .hint_text("path to .obj, .gltf, .glb or .ron"),
                    );
                    if ui.button("open").clicked() {
                        let path = std::path::PathBuf::from(self.open_path.trim());
                        self.open_scene(&path);
                    }
                });
                ui.label("or drop a file on the window");
                ui.horizontal_wrapped(|ui| {
                    ui.label("viewpoints:");
                    let names: Vec<String> = self.scene.views.iter().map(|v| v.name.clone()).collect();
                    for (i, name) in names.iter().enumerate() {
                        if ui.button(name).clicked() {
                            self.go_to_view(i);
                        }
                    }
                });
                ui.label("drag: orbit · right drag: pan · wheel: zoom");
                self.exposure_controls(ui);
                self.lighting_controls(ui);
                self.object_controls(ui);
            });
    }

    /// The camera's exposure for the lights, as an EV100 (a multiplier of 1 is about -0.23).
    fn exposure_controls(&mut self, ui: &mut egui::Ui) {
        let scale = self.gpu_scene.exposure().scale().max(1e-12);
        // The EV100 whose scale this is: scale = 1 / (pi 1.2 2^ev).
        let mut ev100 = -(scale * std::f32::consts::PI * 1.2).log2();
        let before = ev100;
        ui.add(egui::Slider::new(&mut ev100, -4.0..=16.0).text("exposure (EV100)"));
        if ev100 != before
            && let Err(e) = self.gpu_scene.set_exposure(penumbra::Exposure::Ev100(ev100))
        {
            self.complain(format!("exposure: {e}"));
        }
    }

    /// The lighting mode and the lightmaps' exposure, for scenes that have lightmaps.
    fn lighting_controls(&mut self, ui: &mut egui::Ui) {
        use penumbra::LightingMode;
        let modes: Vec<LightingMode> = LightingMode::ALL
            .into_iter()
            .filter(|m| *m == LightingMode::Dynamic || self.gpu_scene.has_lightmaps(*m))
            .collect();
        if modes.len() < 2 {
            return;
        }
        let (mut mode, mut exposure) = self.gpu_scene.lighting();
        let before = (mode, exposure);
        ui.horizontal(|ui| {
            ui.label("lighting:");
            for m in &modes {
                ui.radio_value(&mut mode, *m, m.name());
            }
        });
        ui.label("dynamic: lightmaps off · mixed: lightmap as indirect light · baked: lightmap only");
        ui.add(egui::Slider::new(&mut exposure, 0.0..=4.0).text("lightmap exposure"));
        if (mode, exposure) != before {
            let rs = &self.render_state;
            if let Err(e) = self.gpu_scene.set_lighting(&rs.device, &rs.queue, mode, exposure) {
                self.complain(format!("lighting: {e}"));
            }
        }
        let mut bicubic = self.gpu_scene.lightmap_filter() == penumbra::LightmapFilter::Bicubic;
        if ui
            .checkbox(&mut bicubic, "bicubic lightmap filtering (smooth across texels)")
            .changed()
        {
            let filter = if bicubic {
                penumbra::LightmapFilter::Bicubic
            } else {
                penumbra::LightmapFilter::Bilinear
            };
            let rs = &self.render_state;
            if let Err(e) = self.gpu_scene.set_lightmap_filter(&rs.device, &rs.queue, filter) {
                self.complain(format!("lightmap filter: {e}"));
            }
        }
    }

    /// Moves one of the scene's objects (a dynamic object over baked scenery, for example).
    fn object_controls(&mut self, ui: &mut egui::Ui) {
        if self.scene.instances.is_empty() {
            return;
        }
        let name = |app: &Self, k: usize| {
            let inst = &app.scene.instances[k];
            format!("{k}: {}", app.scene.meshes[inst.mesh].name)
        };
        let k = self.moved_object.min(self.scene.instances.len() - 1);
        let mut chosen = k;
        egui::ComboBox::from_label("object to move")
            .selected_text(name(self, k))
            .show_ui(ui, |ui| {
                for i in 0..self.scene.instances.len() {
                    ui.selectable_value(&mut chosen, i, name(self, i));
                }
            });
        if chosen != k {
            self.moved_object = chosen;
            self.object_offset = glam::Vec3::ZERO;
        }
        let reach = self.bounds.radius().max(1e-3);
        let before = self.object_offset;
        for (axis, value) in ["x", "y", "z"].iter().zip(self.object_offset.as_mut()) {
            ui.add(egui::Slider::new(value, -reach..=reach).text(format!("move {axis}")));
        }
        if self.object_offset != before {
            let original = self.scene.instances[self.moved_object].transform;
            let moved = glam::Mat4::from_translation(self.object_offset) * original;
            if let Err(e) = self
                .gpu_scene
                .set_transform(&self.render_state.queue, self.moved_object, moved)
            {
                self.complain(format!("move: {e}"));
            }
        }
    }

    fn measure_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Measure")
            .default_open(self.is_open("measure"))
            .show(ui, |ui| {
                if let Some(ms) = self.clock.mean_ms() {
                    ui.label(format!(
                        "window: {:.1} FPS ({ms:.1} ms per frame)",
                        1000.0 / ms.max(1e-3)
                    ));
                }
                self.clock.graph(ui);
                let count = if self.split { 2 } else { 1 };
                for side in &self.sides[..count] {
                    let s = &side.stats;
                    ui.label(egui::RichText::new(side.method.name()).strong());
                    if let Some(p) = s.reference {
                        ui.label(format!("{}/{} light samples", p.done, p.total));
                        continue;
                    }
                    ui.label(format!(
                        "GPU {:.2} ms · redraw {:.1} ms wall",
                        s.gpu_ms, s.wall_ms
                    ));
                    egui::Grid::new(format!("passes {}", side.method.name()))
                        .striped(true)
                        .show(ui, |ui| {
                            for p in &s.passes {
                                ui.label(p.pass);
                                ui.label(format!("{:.2} ms", p.milliseconds));
                                ui.end_row();
                            }
                        });
                    if let Some((texels, widths)) = s.maps {
                        ui.label(match widths {
                            Some(w) => format!(
                                "light maps {texels} texels a tile; of {} penumbra pixels {} narrower than {} texels",
                                w.pixels, w.narrower[0], w.limits_texels[0]
                            ),
                            None => format!("light maps {texels} texels a tile"),
                        });
                    }
                    if let Some(m) = &s.mask {
                        ui.label(format!(
                            "mask saved {:.1}% of the shadow-map taps ({} of {} receiver pixels skipped)",
                            m.share * 100.0,
                            m.skipped_pixels,
                            m.receiver_pixels
                        ));
                    }
                }
            });
    }

    fn keep_section(&mut self, ui: &mut egui::Ui) {
        egui::CollapsingHeader::new("Keep")
            .default_open(self.is_open("keep"))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.add(egui::TextEdit::singleline(&mut self.screenshot_path).desired_width(190.0));
                    if ui.button("screenshot").clicked() {
                        let path = std::path::PathBuf::from(self.screenshot_path.trim());
                        self.request_screenshot(ui.ctx(), path);
                    }
                });
                ui.horizontal(|ui| {
                    ui.add(egui::TextEdit::singleline(&mut self.settings_path).desired_width(150.0));
                    if ui.button("save settings").clicked() {
                        self.save_settings();
                    }
                    if ui.button("load").clicked() {
                        self.load_settings();
                    }
                });
            });
    }
}

/// A top view of the sky: the dot is where the light is (center: overhead, rim: horizon).
fn light_gizmo(ui: &mut egui::Ui, angles: &mut LightAngles) {
    let size = 96.0;
    let (rect, response) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::click_and_drag());
    let painter = ui.painter_at(rect);
    let center = rect.center();
    let radius = size * 0.5 - 4.0;
    painter.circle_filled(center, radius, ui.visuals().extreme_bg_color);
    painter.circle_stroke(center, radius, ui.visuals().widgets.noninteractive.bg_stroke);
    painter.circle_stroke(
        center,
        radius * 0.5,
        ui.visuals().widgets.noninteractive.bg_stroke,
    );
    if let Some(p) = response.interact_pointer_pos()
        && (response.dragged() || response.clicked())
    {
        let v = (p - center) / radius;
        let r = v.length().min(1.0);
        angles.elevation_deg = r.acos().to_degrees().clamp(1.0, 90.0);
        if r > 1e-3 {
            angles.azimuth_deg = v.x.atan2(v.y).to_degrees();
        }
    }
    let (az, el) = (angles.azimuth_deg.to_radians(), angles.elevation_deg.to_radians());
    let dot = center + egui::vec2(az.sin(), az.cos()) * el.cos() * radius;
    painter.circle_filled(dot, 6.0, egui::Color32::from_rgb(255, 210, 80));
}

pub(crate) fn to_directional(light: &Light) -> Light {
    let (direction, radius, color, intensity) = match *light {
        Light::Directional(_) => return *light,
        Light::Spot(s) => (s.direction, s.radius, s.color, s.intensity),
        Light::Point(p) => (
            -p.position.normalize_or(glam::Vec3::Y),
            p.radius,
            p.color,
            p.intensity,
        ),
        Light::Rect(_) | Light::Disk(_) => (
            light.direction(),
            light.enclosing_radius(),
            light.color(),
            light.far_intensity(),
        ),
    };
    let distance = 10.0f32.max(radius);
    Light::Directional(DirectionalLight {
        direction,
        angular_diameter_deg: (2.0 * (radius / distance).atan()).to_degrees().min(20.0),
        color,
        intensity,
    })
}

/// A point light where `light` shines from: a spot's place, or above the scene toward a sun
/// (its size kept as the radius a sun's angle gives at that distance).
pub(crate) fn to_point(light: &Light, center: glam::Vec3, radius: f32) -> Light {
    match *light {
        Light::Point(_) => *light,
        Light::Rect(_) | Light::Disk(_) => Light::Point(PointLight {
            position: light.position().unwrap_or(center),
            radius: light.enclosing_radius(),
            color: light.color(),
            intensity: light.far_intensity(),
            range: light.range(),
        }),
        Light::Spot(s) => Light::Point(PointLight {
            position: s.position,
            radius: s.radius,
            color: s.color,
            intensity: s.intensity,
            range: None,
        }),
        Light::Directional(d) => {
            let distance = radius * 1.5;
            Light::Point(PointLight {
                position: center - light.direction() * distance,
                radius: distance * (d.angular_diameter_deg.to_radians() * 0.5).tan(),
                color: d.color,
                intensity: d.intensity,
                range: None,
            })
        }
    }
}

pub(crate) fn to_spot(light: &Light, center: glam::Vec3, radius: f32) -> Light {
    match *light {
        Light::Spot(_) => *light,
        Light::Rect(_) | Light::Disk(_) => Light::Spot(SpotLight {
            position: light.position().unwrap_or(center),
            direction: light.direction(),
            cone_angle_deg: 60.0,
            radius: light.enclosing_radius(),
            color: light.color(),
            intensity: light.far_intensity(),
            range: light.range(),
        }),
        Light::Point(p) => Light::Spot(SpotLight {
            position: p.position,
            direction: center - p.position,
            cone_angle_deg: 60.0,
            radius: p.radius,
            color: p.color,
            intensity: p.intensity,
            range: None,
        }),
        Light::Directional(d) => {
            let distance = radius * 2.5;
            let toward = -light.direction();
            Light::Spot(SpotLight {
                position: center + toward * distance,
                direction: -toward,
                cone_angle_deg: (radius * 1.3 / distance).atan().to_degrees().clamp(5.0, 89.0),
                radius: distance * (d.angular_diameter_deg.to_radians() * 0.5).tan(),
                color: d.color,
                intensity: d.intensity,
                range: None,
            })
        }
    }
}

/// A rectangle (`rect`) or disk light where `light` shines from, facing `center`: a spot's or
/// point light's place, or above the scene toward a sun. Its size gives the disk's radius or
/// the rectangle's width (its height a quarter of that), and its luminance gives the same light
/// far along its axis (`Light::far_intensity`).
pub(crate) fn to_area(light: &Light, center: glam::Vec3, radius: f32, rect: bool) -> Light {
    let (position, size) = match *light {
        Light::Directional(d) => {
            let distance = radius * 1.5;
            (
                center - light.direction() * distance,
                distance * (d.angular_diameter_deg.to_radians() * 0.5).tan(),
            )
        }
        _ => (light.position().unwrap_or(center), light.enclosing_radius()),
    };
    let size = size.max(radius * 0.02);
    let direction = (center - position).normalize_or(glam::Vec3::NEG_Y);
    let (color, far) = (light.color(), light.far_intensity());
    if rect {
        let (width, height) = (2.0 * size, 0.5 * size);
        Light::Rect(RectLight {
            position,
            direction,
            up: glam::Vec3::ZERO,
            width,
            height,
            color,
            intensity: far / (width * height),
            range: light.range(),
        })
    } else {
        Light::Disk(DiskLight {
            position,
            direction,
            radius: size,
            color,
            intensity: far / (std::f32::consts::PI * size * size),
            range: light.range(),
        })
    }
}
