//! The interactive demo: see, tune and compare penumbra's soft shadows live.
//!
//! `cargo run --release --example demo` opens a window (eframe with its wgpu renderer). The
//! library renders each side of the view into its own texture, exactly as an embedding engine
//! would, and egui shows the textures. `--screenshot PATH --frames N` renders N frames, saves
//! the window's image (and PATH with a `.json` extension describing where the 3D view is) and
//! exits, for tests and for people without a display.

mod app;
mod panel;
mod side;
mod stats;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result, bail};
use clap::Parser;
use penumbra::debug::DebugView;
use penumbra::{Quality, ShadowMethod};

#[derive(Parser, Debug, Clone)]
#[command(about = "Interactive soft-shadow demo: compare, tune and inspect penumbra's methods")]
pub struct Args {
    /// A scene file (.ron) or a model (.obj, .gltf, .glb); defaults to the built-in teapot scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Index of the scene's viewpoint to start from.
    #[arg(long, default_value_t = 0)]
    pub view: usize,
    /// The two methods of the split view, LEFT,RIGHT: ours, ours-fast, traditional, pcss, hard,
    /// hw2x2 or reference.
    #[arg(long, default_value = "ours,traditional")]
    pub split: String,
    /// Show one method over the whole view (the split's left one) instead of a split view.
    #[arg(long)]
    pub single: bool,
    /// Quality preset to start from: low, medium, high or ultra.
    #[arg(long, default_value = "medium")]
    pub quality: String,
    /// Light samples of the reference (1..=4096).
    #[arg(long)]
    pub samples: Option<u32>,
    /// Show an intermediate map instead of the final image: shadow-map, fattened-map, distance,
    /// mask, pcf, blur, or error (against the reference, which must be one of the two sides).
    #[arg(long)]
    pub map: Option<String>,
    /// Start with the light animation on.
    #[arg(long)]
    pub animate_light: bool,
    /// Lighting mode of a scene with lightmaps: dynamic, mixed or baked (default: the scene
    /// file's).
    #[arg(long)]
    pub lighting: Option<String>,
    /// Start with these settings (a file written by the demo's "Save settings").
    #[arg(long)]
    pub settings: Option<PathBuf>,
    /// Sections of the settings panel open at start, comma-separated: compare, light, ours,
    /// traditional, pcss, shadow-map, maps, scene, measure, keep.
    #[arg(long, default_value = "compare,light,ours,maps,scene,measure,keep")]
    pub open_sections: String,
    /// Window size in points, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x800")]
    pub size: String,
    /// Share of the window's pixels the 3D view renders, in [0.25, 1] (the software adapter
    /// is slow; lower it for a smoother window).
    #[arg(long, default_value_t = 1.0)]
    pub render_scale: f32,
    /// Render `--frames` frames, save the window's image to this PNG (with PATH.json, where the
    /// view is, and PATH.settings.ron, the settings it ran with) and exit.
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Before the screenshot, shrink the window to nothing, minimize it and restore it (a
    /// check that resizing, to zero included, is handled).
    #[arg(long)]
    pub exercise_resize: bool,
    /// Frames to render before `--screenshot` is taken (at least 1).
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
}

/// What the command line asked for, checked.
#[derive(Debug, Clone)]
pub struct Startup {
    pub args: Args,
    pub methods: [ShadowMethod; 2],
    pub quality: Quality,
    pub map: Option<app::MapView>,
    pub window: (f32, f32),
    /// The `--settings` file, read.
    pub saved: Option<app::SavedSettings>,
}

fn parse_args(args: Args) -> Result<Startup> {
    let (left, right) = args.split.split_once(',').with_context(|| {
        format!(
            "--split {}: expected LEFT,RIGHT, for example ours,traditional",
            args.split
        )
    })?;
    let methods = [
        ShadowMethod::from_name(left.trim()).context("--split")?,
        ShadowMethod::from_name(right.trim()).context("--split")?,
    ];
    let quality = Quality::from_name(&args.quality).context("--quality")?;
    let map = match args.map.as_deref() {
        None => None,
        Some("error") => Some(app::MapView::Error),
        Some(name) => Some(app::MapView::Debug(DebugView::from_name(name).context("--map")?)),
    };
    let window = args
        .size
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.trim().parse::<f32>().ok()?, h.trim().parse::<f32>().ok()?)))
        .filter(|(w, h)| *w >= 200.0 && *h >= 150.0 && w.is_finite() && h.is_finite())
        .with_context(|| format!("--size {}: expected WIDTHxHEIGHT of at least 200x150", args.size))?;
    if !(0.25..=1.0).contains(&args.render_scale) {
        bail!("--render-scale {}: must be in [0.25, 1]", args.render_scale);
    }
    if args.frames == 0 {
        bail!("--frames 0: at least one frame must be rendered before the screenshot");
    }
    if let Some(samples) = args.samples
        && !(1..=4096).contains(&samples)
    {
        bail!("--samples {samples}: must be in 1..=4096");
    }
    let saved = match &args.settings {
        Some(path) => {
            let saved = app::read_settings(path)?;
            saved
                .shadows
                .validate(None)
                .with_context(|| format!("{}", path.display()))?;
            saved
                .light
                .validate()
                .with_context(|| format!("{}", path.display()))?;
            Some(saved)
        }
        None => None,
    };
    Ok(Startup {
        saved,
        args,
        methods,
        quality,
        map,
        window,
    })
}

/// True when a window system is reachable (Linux and the BSDs need X11 or Wayland).
fn display_available() -> bool {
    if cfg!(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "openbsd"
    )) {
        std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty())
            || std::env::var_os("WAYLAND_DISPLAY").is_some_and(|d| !d.is_empty())
    } else {
        true
    }
}

const NO_DISPLAY: &str = "the demo needs a display, and neither DISPLAY nor WAYLAND_DISPLAY is set.\n\
    Run it under X11 or Wayland, or inside a virtual display:\n\
    \x20   xvfb-run -a -s \"-screen 0 1280x1024x24\" cargo run --release --example demo -- --screenshot shot.png\n\
    or render without a window: cargo run --release --example render -- --scene assets/scenes/teapot.ron --out out.png";

fn main() -> ExitCode {
    let startup = match parse_args(Args::parse()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e:#}");
            return ExitCode::from(2);
        }
    };
    if !display_available() {
        eprintln!("error: {NO_DISPLAY}");
        return ExitCode::from(2);
    }
    let outcome = app::Outcome::default();
    let (w, h) = startup.window;
    let options = eframe::NativeOptions {
        viewport: eframe::egui::ViewportBuilder::default()
            .with_title("penumbra: soft shadows")
            .with_inner_size([w, h])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: wgpu_configuration(),
        ..Default::default()
    };
    let app_outcome = outcome.clone();
    let result = eframe::run_native(
        "penumbra demo",
        options,
        Box::new(move |cc| {
            let app = app::DemoApp::new(cc, startup, app_outcome)
                .map_err(|e| -> Box<dyn std::error::Error + Send + Sync> { format!("{e:#}").into() })?;
            Ok(Box::new(app))
        }),
    );
    if let Err(e) = result {
        eprintln!("error: cannot run the demo's window: {e}");
        if e.to_string().contains("xlib") {
            // winit opens the X11 libraries at run time; a minimal system lacks some of them.
            eprintln!(
                "hint: the X11 window needs libX11, libXcursor, libXi and libxkbcommon-x11 (Debian: sudo apt-get install libxcursor1 libxi6 libxkbcommon-x11-0)"
            );
        }
        eprintln!(
            "hint: the headless renderer needs no window: cargo run --release --example render -- --scene assets/scenes/teapot.ron --out out.png"
        );
        return ExitCode::FAILURE;
    }
    match outcome.failure() {
        Some(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
        None => ExitCode::SUCCESS,
    }
}

/// eframe's wgpu set-up with penumbra's device wishes: its instance flags (no DEBUG on Mesa's
/// lavapipe, which crashes in debug labels) and its features (timestamps for the per-pass times).
fn wgpu_configuration() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuConfiguration, WgpuSetup, WgpuSetupCreateNew};
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.instance_descriptor.flags = penumbra::instance_flags();
    setup.device_descriptor = std::sync::Arc::new(|adapter| {
        let mut descriptor = penumbra::device_descriptor(adapter);
        // egui wants surfaces up to 8192 pixels wide.
        descriptor.required_limits.max_texture_dimension_2d = descriptor
            .required_limits
            .max_texture_dimension_2d
            .max(8192)
            .min(adapter.limits().max_texture_dimension_2d);
        descriptor.label = Some("penumbra demo device");
        descriptor
    });
    WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(setup),
        ..Default::default()
    }
}
