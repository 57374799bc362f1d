//! Headless renderer: draws a scene file, or any OBJ/glTF model set on a floor, to a PNG.
//!
//! ```text
//! cargo run --release --example render -- --scene assets/scenes/teapot.ron --view 0 \
//!     --size 1280x1024 --method hard --out out.png
//! ```

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Parser;
use penumbra::debug::DebugView;
use penumbra::timing::TimedFrames;
use penumbra::{
    DevicePath, ExitFaces, ExitMapDraw, Fattening, GpuScene, HeadlessGpu, Light, MapResolution, Quality,
    Renderer, ShadowMethod, ShadowSettings, TilePixels,
};

#[derive(Parser)]
#[command(about = "Render a penumbra scene (or an OBJ/glTF model on a floor) to a PNG, headless")]
struct Args {
    /// A scene file (.ron) or a model (.obj, .gltf, .glb).
    #[arg(long)]
    scene: PathBuf,
    /// Index of the scene's viewpoint (models get three orbit views: 0, 1, 2).
    #[arg(long, default_value_t = 0)]
    view: usize,
    /// Output size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x1024")]
    size: String,
    /// Shadow method: ours, ours-fast, traditional, pcss, hard or hw2x2.
    #[arg(long, default_value = "ours")]
    method: String,
    /// Light samples for `--method reference` (1..=4096); defaults to the preset's.
    #[arg(long)]
    samples: Option<u32>,
    /// Quality preset: low, medium, high or ultra.
    #[arg(long, default_value = "medium")]
    quality: String,
    /// The key light's size: angular diameter in degrees (directional), radius in world units (spot,
    /// point, disk), or a rectangle's width in world units (its height keeps the sides' ratio).
    /// Defaults to the scene's.
    #[arg(long)]
    light_size: Option<f32>,
    /// Shadow map resolution in texels (power of two, 64..=8192).
    #[arg(long, default_value_t = 2048)]
    shadow_map: u32,
    /// Cascades of a directional light's map, 1..=4 (spot lights use one)
    #[arg(long, default_value_t = 4)]
    cascades: u32,
    /// `ours`: leave out the nearest-caster search beside a shadow
    /// (`PenumbraSettings::nearest_caster`), to compare its cost and its error.
    #[arg(long)]
    no_nearest_caster: bool,
    /// `ours`: how the fattened map is made (`PenumbraSettings::fattening`): auto (by the
    /// casters' triangles), geometry (the casters drawn again, pushed out) or dilation (derived
    /// from the shadow map in compute).
    #[arg(long, default_value = "auto")]
    fattening: String,
    /// `ours`: leave out the exit map (`PenumbraSettings::exit_map`), to compare its cost and
    /// its error.
    #[arg(long)]
    no_exit_map: bool,
    /// `ours`: list the tiles deep in the umbra apart, the passes writing 0 there without taps
    /// (`PenumbraSettings::skip_umbra_tiles`), to compare their cost and the frame.
    #[arg(long)]
    umbra_tiles: bool,
    /// `ours`: PCF at half resolution where the penumbra is wide
    /// (`PenumbraSettings::reduced_resolution`), to compare its cost and its error.
    #[arg(long)]
    reduced_resolution: bool,
    /// `ours`: the screen-space passes as draws (`PenumbraSettings::fragment_passes`) instead
    /// of compute passes over the tile list, to compare their cost.
    #[arg(long)]
    fragment_passes: bool,
    /// How the compute path clears its intermediates (`ExecutionSettings::clears`): auto,
    /// compute or render (the same frame; to compare their cost).
    #[arg(long, default_value = "auto")]
    clears: String,
    /// How the tile classification tests a tile's pixels (`ExecutionSettings::tile_pixels`):
    /// auto, workgroup or loop.
    #[arg(long, default_value = "auto")]
    tile_pixels: String,
    /// `ours`: the distance map in a compute pass of its own, not read by the variable PCF's
    /// (`ExecutionSettings::distance_in_pcf` off).
    #[arg(long)]
    distance_apart: bool,
    /// Draws write the lights' visibility layers, not the compute passes
    /// (`ExecutionSettings::compute_layer_writes` off).
    #[arg(long)]
    draw_layer_writes: bool,
    /// The light maps cleared by their passes, not by a copy (`ShadowMapSettings::clear_by_copy`
    /// off).
    #[arg(long)]
    map_clears_by_pass: bool,
    /// `ours`: the exit map tests every fragment's side (`ExitFaces::Fragment`) instead of
    /// culling by winding.
    #[arg(long)]
    exit_faces_by_fragment: bool,
    /// `ours`: which pass makes the exit map (`ExecutionSettings::exit_map_draw`): auto (by
    /// the casters' triangles), shadow-map (kept by the shadow map's pass) or own (a pass of
    /// its own), to compare their cost.
    #[arg(long, default_value = "auto")]
    exit_map_draw: String,
    /// `ours`: the narrowest penumbra, in texels, the light's maps may be coarsened to
    /// (`MapResolution::FromPenumbra`); 0 keeps the maps at `--shadow-map` texels
    /// (`MapResolution::Configured`). Default: the preset's.
    #[arg(long)]
    narrowest_texels: Option<f32>,
    /// Also render the ground-truth reference with this many light samples, print the
    /// visibility error (RMSE, penumbra RMSE, max) and FLIP, and write OUT.heat.png (the
    /// visibility error) next to the output.
    #[arg(long)]
    compare_to_reference: Option<u32>,
    /// Write an intermediate texture instead of the final image: shadow-map, fattened-map,
    /// distance, mask, pcf or blur (false color where it helps).
    #[arg(long)]
    debug_view: Option<String>,
    /// Lighting mode: dynamic, mixed or baked (default: the scene file's)
    #[arg(long)]
    lighting: Option<String>,
    /// Lightmap exposure (default: the scene file's)
    #[arg(long)]
    exposure: Option<f32>,
    /// The camera's exposure for the lights as an EV100 (Bevy's and Filament's: 9.7 is Bevy's
    /// default camera); default: the scene file's, or 9.7 for a model file's own lights
    #[arg(long)]
    ev100: Option<f32>,
    /// Output PNG.
    #[arg(long, default_value = "out.png")]
    out: PathBuf,
    /// Also time this many frames (after one warm-up) and print the median frame time and the
    /// median of each pass (GPU timestamps where the adapter has them, else wall clock with a
    /// submit per pass). The key light turns 0.01 degrees a frame, as in the benchmark, so every
    /// pass runs; with --still-light it stays, and the light-space maps are kept.
    #[arg(long)]
    time: Option<usize>,
    /// With --time: keep the light still (only the camera's screen-space passes run).
    #[arg(long)]
    still_light: bool,
}

fn parse_size(text: &str) -> Result<(u32, u32)> {
    let parse = || -> Option<(u32, u32)> {
        let (w, h) = text.split_once(['x', 'X'])?;
        Some((w.trim().parse().ok()?, h.trim().parse().ok()?))
    };
    match parse() {
        Some((w, h)) if w > 0 && h > 0 => Ok((w, h)),
        Some(_) => bail!("--size {text}: width and height must be at least 1"),
        None => bail!("--size {text}: expected WIDTHxHEIGHT, for example 1280x1024"),
    }
}

fn main() -> Result<()> {
    let args = Args::parse();
    let (width, height) = parse_size(&args.size)?;
    let method = ShadowMethod::from_name(&args.method).context("--method")?;
    let quality = Quality::from_name(&args.quality).context("--quality")?;
    let mut settings = ShadowSettings::preset(method, quality);
    settings.shadow_map.resolution = args.shadow_map;
    settings.shadow_map.cascades.count = args.cascades;
    settings.penumbra.nearest_caster = !args.no_nearest_caster;
    settings.penumbra.reduced_resolution = args.reduced_resolution;
    settings.penumbra.fattening = match args.fattening.as_str() {
        "auto" => Fattening::Auto,
        "geometry" => Fattening::Geometry,
        "dilation" => Fattening::Dilation,
        other => anyhow::bail!("--fattening: unknown `{other}`; choose auto, geometry or dilation"),
    };
    settings.penumbra.exit_map = !args.no_exit_map;
    settings.penumbra.skip_umbra_tiles = args.umbra_tiles;
    settings.penumbra.fragment_passes = args.fragment_passes;
    settings.execution.clears = match args.clears.as_str() {
        "auto" => DevicePath::Auto,
        "compute" => DevicePath::Compute,
        "render" => DevicePath::RenderPass,
        other => bail!("--clears: unknown value {other:?} (auto, compute or render)"),
    };
    settings.execution.tile_pixels = match args.tile_pixels.as_str() {
        "auto" => TilePixels::Auto,
        "workgroup" => TilePixels::Workgroup,
        "loop" => TilePixels::Loop,
        other => bail!("--tile-pixels: unknown value {other:?} (auto, workgroup or loop)"),
    };
    settings.execution.distance_in_pcf = !args.distance_apart;
    settings.execution.compute_layer_writes = !args.draw_layer_writes;
    settings.shadow_map.clear_by_copy = !args.map_clears_by_pass;
    if args.exit_faces_by_fragment {
        settings.shadow_map.exit_faces = ExitFaces::Fragment;
    }
    settings.execution.exit_map_draw = match args.exit_map_draw.as_str() {
        "auto" => ExitMapDraw::Auto,
        "shadow-map" => ExitMapDraw::ShadowMapPass,
        "own" => ExitMapDraw::OwnPass,
        other => bail!("--exit-map-draw: unknown value {other:?} (auto, shadow-map or own)"),
    };
    settings.penumbra.map_resolution = match args.narrowest_texels {
        None => settings.penumbra.map_resolution,
        Some(t) if t <= 0.0 => MapResolution::Configured,
        Some(narrowest_texels) => MapResolution::FromPenumbra { narrowest_texels },
    };
    if let Some(samples) = args.samples {
        settings.reference.samples = samples;
    }
    settings.validate(None).context("--shadow-map")?;
    if let Some(frames) = args.time
        && (frames == 0 || method == ShadowMethod::Reference)
    {
        bail!("--time {frames}: expected at least 1 frame of a real-time method");
    }

    let debug_view = args
        .debug_view
        .as_deref()
        .map(DebugView::from_name)
        .transpose()
        .context("--debug-view")?;
    let mut scene = penumbra::load_scene(&args.scene)?;
    if let Some(size) = args.light_size {
        match &mut scene.light {
            Light::Directional(l) => l.angular_diameter_deg = size,
            Light::Spot(l) => l.radius = size,
            Light::Point(l) => l.radius = size,
            Light::Disk(l) => l.radius = size,
            Light::Rect(l) => {
                let ratio = if l.width > 0.0 { l.height / l.width } else { 1.0 };
                l.width = size;
                l.height = size * ratio;
            }
        }
        scene.light.validate().context("--light-size")?;
    }
    for warning in &scene.warnings {
        eprintln!("warning: {}: {warning}", args.scene.display());
    }
    if let Some(name) = &args.lighting {
        scene.lighting = penumbra::LightingMode::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .with_context(|| format!("--lighting {name}: expected dynamic, mixed or baked"))?;
    }
    if let Some(exposure) = args.exposure {
        scene.lightmap_exposure = exposure;
    }
    scene.validate_lightmaps().context("--exposure")?;
    if let Some(ev100) = args.ev100 {
        scene.exposure = penumbra::Exposure::Ev100(ev100);
        scene.exposure.validate().context("--ev100")?;
    }
    let camera = scene.view(args.view).context("--view")?;
    // The raw PCF view reads `ours`' visibility before the blur, kept apart only when asked.
    settings.execution.raw_visibility |= debug_view == Some(DebugView::Pcf);
    let gpu = HeadlessGpu::new()?;
    eprintln!("adapter: {}", gpu.describe());
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings)?;
    let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
    let mut image = if method == ShadowMethod::Reference {
        render_reference_with_progress(&gpu, &mut renderer, &gpu_scene, &camera, width, height)?
    } else {
        penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, width, height)?
    };
    if let Some(view) = debug_view {
        image = penumbra::debug::debug_image(&gpu.device, &gpu.queue, &renderer, view)?;
    }
    image
        .save(&args.out)
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    if let Some(samples) = args.compare_to_reference {
        compare_to_reference(&gpu, &scene, &camera, settings, samples, &image, &args.out)?;
    }
    // The key light's penumbra widths, as measured after the frame (`MapResolution::FromPenumbra`).
    if let Some(report) = renderer
        .last_report()
        .and_then(|r| renderer.shadows().report(r.light.light))
        && let Some(widths) = report.penumbra_widths
    {
        eprintln!(
            "maps: {} texels a tile; {} penumbra pixels, narrower than {:?} texels: {:?}",
            report.map_resolution, widths.pixels, widths.limits_texels, widths.narrower
        );
    }
    if let Some(reach) = renderer
        .last_report()
        .and_then(|r| r.light.light_view.shadow_reach)
    {
        eprintln!(
            "warning: the key light's maps end {reach:.1} units from it, before the scene's farthest part              (a caster lies near the light while the scene reaches far): receivers beyond get no shadow;              give the light a range"
        );
    }
    if let Some(unheld) = renderer.last_report().and_then(|r| r.light.unheld_caster) {
        eprintln!(
            "warning: a caster {:.3} units across at {:.1} units from the camera is narrower than a texel of the \
             sun's map ({:.3} units): its shadow is lost; give the sun a shadow distance \
             (shadow_map.fit: CameraFrustum(max_distance: ...)) or a finer map",
            unheld.size, unheld.view_distance, unheld.texel
        );
    }
    if renderer
        .last_report()
        .is_some_and(|r| r.plan.chain.distance_map())
        && debug_view.is_none()
    {
        let saved = penumbra::debug::mask_savings(&gpu.device, &gpu.queue, &renderer)?;
        eprintln!(
            "mask: {} of {} receiver pixels ({:.1}%) took no shadow-map taps; {} taps saved",
            saved.skipped_pixels,
            saved.receiver_pixels,
            saved.share * 100.0,
            saved.taps_saved
        );
    }
    if let Some(frames) = args.time {
        let light = scene.light;
        time_frames(
            &gpu,
            &mut renderer,
            &mut gpu_scene,
            &camera,
            (width, height),
            frames,
            |i| {
                (!args.still_light)
                    .then(|| light.turned(glam::Quat::from_rotation_y((i as f32 * 0.01).to_radians())))
            },
        )?;
    }
    eprintln!(
        "wrote {} ({width}x{height}, {} triangles, method {}, view {})",
        args.out.display(),
        gpu_scene.triangle_count(),
        method.name(),
        args.view
    );
    Ok(())
}

/// Times `frames` frames after one warm-up (`light(i)`, when some, is set before frame `i`) and
/// prints the median frame time and each pass's median.
fn time_frames(
    gpu: &HeadlessGpu,
    renderer: &mut Renderer,
    scene: &mut GpuScene,
    camera: &penumbra::Camera,
    size: (u32, u32),
    frames: usize,
    light: impl Fn(usize) -> Option<Light>,
) -> Result<()> {
    let timed = renderer.time_frames(
        &gpu.device,
        &gpu.queue,
        scene,
        camera,
        size,
        1,
        frames,
        |scene, i| match light(i) {
            Some(l) => scene.set_light(l),
            None => Ok(()),
        },
    )?;
    let per_pass: Vec<String> = timed
        .pass_medians()
        .into_iter()
        .map(|(pass, ms)| format!("{pass} {ms:.2}"))
        .collect();
    println!(
        "time: {frames} frames, median {:.2} ms; per pass (ms): {}",
        TimedFrames::median(&timed.pass_sum_ms),
        per_pass.join(", ")
    );
    Ok(())
}

/// The reference, with a progress bar on the terminal while its samples accumulate.
fn render_reference_with_progress(
    gpu: &HeadlessGpu,
    renderer: &mut Renderer,
    scene: &GpuScene,
    camera: &penumbra::Camera,
    width: u32,
    height: u32,
) -> Result<image::RgbaImage> {
    let bar = indicatif::ProgressBar::new(renderer.settings().reference.samples as u64).with_style(
        indicatif::ProgressStyle::with_template("reference {bar:40} {pos}/{len} light samples, {eta} left")
            .expect("valid template"),
    );
    let image =
        penumbra::render_to_image_with_progress(gpu, renderer, scene, camera, width, height, |done, _| {
            bar.set_position(done as u64)
        })?;
    bar.finish_and_clear();
    Ok(image)
}

/// Renders the reference, measures this method's error against it and writes the heat map.
fn compare_to_reference(
    gpu: &HeadlessGpu,
    scene: &penumbra::Scene,
    camera: &penumbra::Camera,
    settings: ShadowSettings,
    samples: u32,
    image: &image::RgbaImage,
    out: &std::path::Path,
) -> Result<()> {
    use penumbra::metrics;
    let size = image.dimensions();
    let mut reference_settings = ShadowSettings {
        method: ShadowMethod::Reference,
        ..settings
    };
    reference_settings.reference.samples = samples;
    reference_settings
        .validate(None)
        .context("--compare-to-reference")?;
    eprintln!("measuring against a {samples}-sample reference...");
    let reference = metrics::measure_visibility(gpu, scene, camera, reference_settings, size)?;
    let measured = metrics::measure_visibility(gpu, scene, camera, settings, size)?;
    let error = metrics::visibility_error(&reference, &measured)?;
    let mut renderer = Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        reference_settings,
    )?;
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), scene)?;
    let reference_image =
        render_reference_with_progress(gpu, &mut renderer, &gpu_scene, camera, size.0, size.1)?;
    let (flip, _) = metrics::flip(&reference_image, image)?;
    println!(
        "{}: visibility RMSE {:.4}, penumbra RMSE {:.4} ({} penumbra pixels), max error {:.3}, mean FLIP {:.4}",
        settings.method.name(),
        error.rmse,
        error.penumbra_rmse,
        error.penumbra_pixels,
        error.max_abs,
        flip
    );
    let heat_path = out.with_extension("heat.png");
    metrics::error_heat_map(&reference, &measured)
        .save(&heat_path)
        .with_context(|| format!("cannot write {}", heat_path.display()))?;
    eprintln!("wrote {}", heat_path.display());
    Ok(())
}
