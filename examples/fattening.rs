//! What the distance-map method's fattened map and exit map buy, against the reference: each
//! benchmark view (the teapot's and the character's three, the room's desk under its lamp) with
//! `ours` medium in five forms, the fattened map drawn (`Fattening::Geometry`) or derived from
//! the shadow map (`Fattening::Dilation`), with and without the exit map
//! (`PenumbraSettings::exit_map`), and derived with the exit map kept by the shadow map's pass
//! (`ExitMapDraw::ShadowMapPass`: one geometry pass a light). Prints a markdown table of the penumbra RMSE, the RMSE, and
//! the geometry passes a light's maps take, and the share of pixels each form's mask leaves
//! out where the reference has a penumbra (the mask must leave out none).
//!
//! ```text
//! cargo run --release --example fattening -- [--samples 256] [--size 400x320] [--scenes teapot,character,room]
//! ```

use anyhow::{Context, Result};
use clap::Parser;
use penumbra::metrics::{self, VisibilityImage};
use penumbra::{ExitMapDraw, Fattening, HeadlessGpu, Quality, ShadowMethod, ShadowSettings};

#[derive(Parser)]
#[command(about = "The fattened map's and the exit map's forms against the reference")]
struct Args {
    /// Light samples of the reference.
    #[arg(long, default_value_t = 256)]
    samples: u32,
    /// The measured images' size, WIDTHxHEIGHT (the benchmark's accuracy run: 400x320).
    #[arg(long, default_value = "400x320")]
    size: String,
    /// The scenes of `assets/scenes` to measure, comma-separated (the room: its desk view).
    #[arg(long, default_value = "teapot,character,room")]
    scenes: String,
    /// Also write each view's reference and each form's error heat map (red: too dark, blue: too
    /// light) as PNGs into this folder.
    #[arg(long)]
    dump: Option<std::path::PathBuf>,
}

/// The forms measured: the fattening, and the exit map's pass (none: no exit map).
type Form = (Fattening, Option<ExitMapDraw>);

const FORMS: [Form; 5] = [
    (Fattening::Geometry, Some(ExitMapDraw::OwnPass)),
    (Fattening::Geometry, None),
    (Fattening::Dilation, Some(ExitMapDraw::OwnPass)),
    (Fattening::Dilation, Some(ExitMapDraw::ShadowMapPass)),
    (Fattening::Dilation, None),
];

fn form_name((fattening, exit): Form) -> String {
    let f = match fattening {
        Fattening::Auto => "auto",
        Fattening::Geometry => "drawn",
        Fattening::Dilation => "derived",
    };
    let exit = match exit {
        None => "",
        Some(ExitMapDraw::ShadowMapPass) => " + exit map kept",
        Some(_) => " + exit map",
    };
    format!("{f}{exit}")
}

fn settings_of((fattening, exit): Form) -> ShadowSettings {
    let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    settings.penumbra.fattening = fattening;
    settings.penumbra.exit_map = exit.is_some();
    settings.execution.exit_map_draw = exit.unwrap_or_default();
    settings
}

/// The passes that draw the casters from the light when its maps are redrawn
/// (`Chain::light_maps` on a device that keeps the exit map in the shadow map's pass): the
/// shadow map's, the drawn fattened map's and the exit map's own.
fn geometry_passes((fattening, exit): Form) -> u32 {
    1 + (fattening == Fattening::Geometry) as u32 + (exit == Some(ExitMapDraw::OwnPass)) as u32
}

/// The share of the reference's penumbra pixels (visibility strictly between 0.02 and 0.98)
/// where `image` says no shadow can fall (its mask 0: fully lit, as the method leaves it).
fn missed_penumbra(reference: &VisibilityImage, image: &VisibilityImage) -> f32 {
    let mut penumbra = 0usize;
    let mut missed = 0usize;
    for (r, m) in reference.visibility.iter().zip(&image.visibility) {
        let (Some(r), Some(m)) = (r, m) else { continue };
        if *r > 0.02 && *r < 0.98 {
            penumbra += 1;
            if *m >= 0.999 && *r < 0.9 {
                missed += 1;
            }
        }
    }
    missed as f32 / penumbra.max(1) as f32
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (w, h) = args
        .size
        .split_once('x')
        .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
        .context("--size: expected WIDTHxHEIGHT")?;
    let gpu = HeadlessGpu::new()?;
    let assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    println!(
        "Device: {}. `ours` medium, {w}x{h}, against a {}-sample reference.\n",
        gpu.describe(),
        args.samples
    );
    print!("| scene | view |");
    for form in FORMS {
        print!(" {} |", form_name(form));
    }
    println!();
    println!("|---|---|{}", "---|".repeat(FORMS.len()));
    for name in args.scenes.split(',') {
        let scene = penumbra::load_scene(&assets.join(format!("{name}.ron")))
            .with_context(|| format!("--scenes: {name}"))?;
        let views = if name == "room" { 1 } else { 3 };
        for view in 0..views {
            let camera = scene.view(view)?;
            let mut reference = ShadowSettings::preset(ShadowMethod::Reference, Quality::Medium);
            reference.reference.samples = args.samples;
            let reference = metrics::measure_visibility(&gpu, &scene, &camera, reference, (w, h))?;
            print!("| {name} | {view} |");
            for form in FORMS {
                let image = metrics::measure_visibility(&gpu, &scene, &camera, settings_of(form), (w, h))?;
                let error = metrics::visibility_error(&reference, &image)?;
                let missed = missed_penumbra(&reference, &image);
                if let Some(dir) = &args.dump {
                    std::fs::create_dir_all(dir)?;
                    let form = form_name(form).replace(" + ", "-").replace(' ', "-");
                    metrics::error_heat_map(&reference, &image)
                        .save(dir.join(format!("{name}-{view}-{form}.png")))?;
                }
                print!(
                    " {:.4} (RMSE {:.4}, missed {:.2}%) |",
                    error.penumbra_rmse,
                    error.rmse,
                    missed * 100.0
                );
            }
            println!();
        }
    }
    println!("\nGeometry passes per light when its maps are drawn:");
    for form in FORMS {
        println!("- {}: {}", form_name(form), geometry_passes(form));
    }
    Ok(())
}
