//! Frame time of penumbra's shadows against Bevy's own, in one run on one scene (the examples'
//! scene: a sun, a spot and a point light, a box moving every frame), rendered headless.
//!
//! ```sh
//! cargo +nightly run --release -p penumbra-bevy --example bench --ignore-rust-version -- \
//!     [--size 960x640] [--frames 20] [--pictures DIR]
//! ```
//!
//! Each mode renders `--frames` frames after a warm-up; a frame is one `App::update` and a wait
//! for the GPU. The report gives each mode's median frame time and its ratio to penumbra's
//! `ours`. `--pictures DIR` writes each mode's last frame and `side_by_side.png` (penumbra's
//! `ours` | Bevy's PCSS | Bevy's `Gaussian`).

mod common;

use std::path::PathBuf;
use std::time::Instant;

use bevy::light::ShadowFilteringMethod;
use bevy::prelude::*;
use common::{move_box, spawn_scene};
use penumbra_bevy::{PenumbraCamera, PenumbraPlugin, Quality, ShadowMethod};

/// One way of shadowing the scene.
#[derive(Clone, Copy)]
struct Mode {
    name: &'static str,
    /// penumbra's method, or `None` for Bevy's own shadow maps.
    penumbra: Option<ShadowMethod>,
    filtering: ShadowFilteringMethod,
    /// Bevy's experimental PCSS on every light.
    bevy_pcss: bool,
    /// No shadow at all (Bevy's shadow maps off too): the shading's own cost.
    shadows: bool,
    /// The box stands still (penumbra then reuses its light maps; Bevy re-renders its own).
    still: bool,
}

const MODES: [Mode; 8] = [
    Mode {
        name: "penumbra ours",
        penumbra: Some(ShadowMethod::Ours),
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: false,
        shadows: true,
        still: false,
    },
    Mode {
        name: "penumbra pcss",
        penumbra: Some(ShadowMethod::Pcss),
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: false,
        shadows: true,
        still: false,
    },
    Mode {
        name: "bevy hardware2x2",
        penumbra: None,
        filtering: ShadowFilteringMethod::Hardware2x2,
        bevy_pcss: false,
        shadows: true,
        still: false,
    },
    Mode {
        name: "bevy gaussian",
        penumbra: None,
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: false,
        shadows: true,
        still: false,
    },
    Mode {
        name: "bevy pcss",
        penumbra: None,
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: true,
        shadows: true,
        still: false,
    },
    Mode {
        name: "penumbra ours, box still",
        penumbra: Some(ShadowMethod::Ours),
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: false,
        shadows: true,
        still: true,
    },
    Mode {
        name: "bevy pcss, box still",
        penumbra: None,
        filtering: ShadowFilteringMethod::Gaussian,
        bevy_pcss: true,
        shadows: true,
        still: true,
    },
    Mode {
        name: "no shadows",
        penumbra: None,
        filtering: ShadowFilteringMethod::Hardware2x2,
        bevy_pcss: false,
        shadows: false,
        still: false,
    },
];

struct Args {
    size: UVec2,
    frames: usize,
    pictures: Option<PathBuf>,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        size: UVec2::new(960, 640),
        frames: 20,
        pictures: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or(format!("{arg} needs a value"));
        match arg.as_str() {
            "--size" => {
                let v = value()?;
                let (w, h) = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
                    .ok_or(format!("--size {v}: expected WIDTHxHEIGHT"))?;
                if w == 0 || h == 0 || w % 64 != 0 {
                    return Err(format!("--size {v}: the width must be a positive multiple of 64"));
                }
                args.size = UVec2::new(w, h);
            }
            "--frames" => {
                let v = value()?;
                args.frames = v
                    .parse()
                    .ok()
                    .filter(|n| *n > 0)
                    .ok_or(format!("--frames {v}: expected a positive number"))?;
            }
            "--pictures" => args.pictures = Some(PathBuf::from(value()?)),
            _ => {
                return Err(format!(
                    "unknown argument `{arg}` (expected --size, --frames, --pictures)"
                ));
            }
        }
    }
    Ok(args)
}

fn main() {
    let args = parse_args().unwrap_or_else(|e| {
        eprintln!("bench: {e}");
        std::process::exit(2)
    });
    let mut headless = common::Headless::new(args.size, |app| {
        // Bevy's render diagnostics: each pass's GPU time where the device has timestamp
        // queries (penumbra's passes are the `penumbra` span).
        app.add_plugins((PenumbraPlugin, bevy::render::diagnostic::RenderDiagnosticsPlugin))
            .add_systems(Update, move_box);
    });
    let camera = headless.camera(Vec3::new(-6.0, 7.0, 9.0), Vec3::new(0.0, 0.5, 0.0));
    let world = headless.app.world_mut();
    world.run_system_cached(spawn_scene).expect("the scene spawns");
    let camera = world.spawn((camera, PenumbraCamera::default())).id();
    // The lights as the scene made them (their shadow flags are switched per mode).
    if let Some(dir) = &args.pictures {
        std::fs::create_dir_all(dir).unwrap_or_else(|e| {
            eprintln!("bench: cannot make {}: {e}", dir.display());
            std::process::exit(2)
        });
    }

    println!(
        "penumbra-bevy bench: {}x{}, {} frames a mode, the examples' scene (sun, spot, point, a moving box)",
        args.size.x, args.size.y, args.frames
    );
    let mut times = Vec::new();
    let mut frames = Vec::new();
    let mut spans = Vec::new();
    for mode in MODES {
        set_mode(&mut headless.app, camera, mode);
        if mode.still {
            headless.app.insert_resource(common::BoxPoseAt(1.0));
        }
        // At least 6 frames and half a second: a GPU raises its clock only under sustained load.
        let warming = Instant::now();
        for i in 0.. {
            if i >= 6 && warming.elapsed().as_secs_f64() >= 0.5 {
                break;
            }
            headless.frame();
        }
        clear_render_diagnostics(&mut headless.app);
        let mut samples: Vec<f64> = (0..args.frames)
            .map(|_| {
                let start = Instant::now();
                headless.frame();
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        samples.sort_by(f64::total_cmp);
        let median = samples[samples.len() / 2];
        times.push(median);
        spans.push(gpu_spans(&headless.app));
        headless.app.insert_resource(common::BoxPoseAt(1.0));
        let frame = headless.render(5);
        headless.app.world_mut().remove_resource::<common::BoxPoseAt>();
        if let Some(dir) = &args.pictures {
            let path = dir.join(format!("{}.png", mode.name.replace([' ', ','], "_")));
            frame
                .save(&path)
                .unwrap_or_else(|e| eprintln!("bench: cannot write {}: {e}", path.display()));
        }
        frames.push(frame);
        let messages = headless
            .app
            .world()
            .resource::<penumbra_bevy::PenumbraDiagnostics>()
            .messages();
        if !messages.is_empty() {
            eprintln!("bench: the plugin reported {messages:?}");
        }
    }
    let ours = times[0];
    println!("| mode | median frame (ms) | / penumbra ours |");
    println!("|---|---|---|");
    for (mode, t) in MODES.iter().zip(&times) {
        println!("| {} | {t:.1} | {:.2} |", mode.name, t / ours);
    }
    // GPU time per span of Bevy's render diagnostics, mean over each mode's timed frames.
    println!();
    println!(
        "GPU ms per render span (Bevy's render diagnostics, mean over the timed frames; `penumbra` is the plugin's passes):"
    );
    for (mode, spans) in MODES.iter().zip(&spans) {
        if spans.is_empty() {
            println!(
                "- {}: no GPU timings (the device has no timestamp queries)",
                mode.name
            );
            continue;
        }
        let list: Vec<String> = spans.iter().map(|(name, ms)| format!("{name} {ms:.3}")).collect();
        println!("- {}: {}", mode.name, list.join(", "));
    }
    if let Some(dir) = &args.pictures {
        let pick = |name: &str| &frames[MODES.iter().position(|m| m.name == name).expect("a mode")];
        let parts = [pick("penumbra ours"), pick("bevy pcss"), pick("bevy gaussian")];
        let (w, h) = (args.size.x, args.size.y);
        let mut side = image::RgbaImage::new(3 * w, h);
        for (i, part) in parts.iter().enumerate() {
            image::imageops::replace(&mut side, *part, (i as u32 * w) as i64, 0);
        }
        let path = dir.join("side_by_side.png");
        side.save(&path)
            .unwrap_or_else(|e| eprintln!("bench: cannot write {}: {e}", path.display()));
        println!("pictures in {}", dir.display());
    }
}

/// Forgets what Bevy's render diagnostics measured so far.
fn clear_render_diagnostics(app: &mut App) {
    let mut store = app
        .world_mut()
        .resource_mut::<bevy::diagnostic::DiagnosticsStore>();
    for diagnostic in store.iter_mut() {
        diagnostic.clear_history();
    }
}

/// The mean GPU time (ms) of each span Bevy's render diagnostics measured since they were
/// cleared, by its path below `render/`.
fn gpu_spans(app: &App) -> Vec<(String, f64)> {
    let store = app.world().resource::<bevy::diagnostic::DiagnosticsStore>();
    let mut spans: Vec<(String, f64)> = store
        .iter()
        .filter_map(|d| {
            let path = d.path().as_str();
            let name = path.strip_prefix("render/")?.strip_suffix("/elapsed_gpu")?;
            Some((name.to_string(), d.average()?))
        })
        .collect();
    spans.sort_by(|a, b| a.0.cmp(&b.0));
    spans
}

/// Switches the camera and the lights to `mode`.
fn set_mode(app: &mut App, camera: Entity, mode: Mode) {
    let world = app.world_mut();
    {
        let mut entity = world.entity_mut(camera);
        entity.insert(mode.filtering);
        let mut penumbra = entity.get_mut::<PenumbraCamera>().expect("the camera");
        match mode.penumbra {
            Some(method) => *penumbra = PenumbraCamera::new(method, Quality::Medium),
            None => penumbra.enabled = false,
        }
    }
    let mut suns = world.query::<&mut DirectionalLight>();
    for mut sun in suns.iter_mut(world) {
        sun.shadow_maps_enabled = mode.shadows;
        // Bevy's PCSS search radius in world units (about the 3-degree sun's penumbra here).
        sun.soft_shadow_size = mode.bevy_pcss.then_some(0.2);
    }
    let mut spots = world.query::<&mut SpotLight>();
    for mut spot in spots.iter_mut(world) {
        spot.shadow_maps_enabled = mode.shadows;
        spot.soft_shadows_enabled = mode.bevy_pcss;
    }
    let mut points = world.query::<&mut PointLight>();
    for mut point in points.iter_mut(world) {
        point.shadow_maps_enabled = mode.shadows;
        point.soft_shadows_enabled = mode.bevy_pcss;
    }
}
