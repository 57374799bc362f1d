//! The distance-map method's light maps at a resolution chosen from its penumbrae
//! (`MapResolution::FromPenumbra`; the default is the configured resolution): a box floating high under a large spot light
//! throws only wide penumbrae, and its maps go to half the configured resolution with the
//! penumbra as wide as before; under a small light a box standing on the floor throws narrow
//! penumbrae, and its maps stay at the configured resolution; the configured
//! setting, the draws and the other methods never move.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, GpuScene, LightReport, MapResolution, Material, Renderer, Scene, ShadowMethod, ShadowSettings,
    SpotLight, metrics::VisibilityImage, scene::primitives,
};

/// The spot light, to the box's -x side: the box's shadow falls toward +x.
const SPOT: Vec3 = Vec3::new(-3.0, 6.0, 0.0);
const SIZE: (u32, u32) = (320, 240);

/// A floor and a unit box whose bottom is `height` up, centred over the origin, under a spot
/// light of radius `radius` six units above the floor and three to the box's -x side.
fn scene(height: f32, radius: f32) -> Scene {
    let mut scene = Scene {
        light: penumbra::Light::Spot(SpotLight {
            position: SPOT,
            direction: Vec3::new(1.5, 0.0, 0.0) - SPOT,
            cone_angle_deg: 50.0,
            radius,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        }),
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let blue = scene.add_material(Material::colored("box", [0.3, 0.5, 0.8]));
    let floor = scene.add_mesh(primitives::plane(16.0, 1.0));
    scene.add_instance(floor, grey, Mat4::IDENTITY).caster = false;
    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    scene
        .add_instance(
            cube,
            blue,
            Mat4::from_translation(Vec3::new(0.0, height + 0.5, 0.0)),
        )
        .receiver = false;
    scene
}

/// Looking straight down from 8 units up at the floor around `x` on the x axis.
fn camera_over(x: f32) -> Camera {
    Camera {
        eye: Vec3::new(x, 8.0, 0.0),
        target: Vec3::new(x, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_deg: 40.0,
        near: 1.0,
        far: 12.0,
    }
}

/// Over the floating box's shadow, which centres on (3, 0, 0) and ends near x = 5.4.
fn camera() -> Camera {
    camera_over(4.5)
}

/// One frame from `camera` through `render_to_image` (which renders again while the map
/// resolution moves) and the key light's report after it.
fn frame_from(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    settings: ShadowSettings,
    camera: &Camera,
) -> (image::RgbaImage, LightReport) {
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), scene).unwrap();
    let image = penumbra::render_to_image(gpu, &mut renderer, &gpu_scene, camera, SIZE.0, SIZE.1).unwrap();
    let id = renderer.last_report().expect("a frame").light.light;
    let report = *renderer.shadows().report(id).expect("the key light's report");
    (image, report)
}

fn frame(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    settings: ShadowSettings,
) -> (image::RgbaImage, LightReport) {
    frame_from(gpu, scene, settings, &camera())
}

fn ours() -> ShadowSettings {
    let mut s = ShadowSettings::preset(ShadowMethod::Ours, penumbra::Quality::Medium);
    s.penumbra.map_resolution = MapResolution::from_penumbra();
    s
}

/// The default.
fn configured() -> ShadowSettings {
    let s = ShadowSettings::preset(ShadowMethod::Ours, penumbra::Quality::Medium);
    assert_eq!(s.penumbra.map_resolution, MapResolution::Configured);
    s
}

/// The 10-90% width (world units) of the floating box's shadow's far edge, along +x from the
/// shadow's centre, averaged over three lines.
fn edge_width(image: &VisibilityImage) -> f32 {
    let camera = camera();
    let widths: Vec<f32> = [-0.2f32, 0.0, 0.2]
        .iter()
        .map(|&z| {
            let profile: Vec<(f32, f32)> = (0..=400)
                .map(|i| {
                    let x = 3.0 + 0.01 * i as f32;
                    (x, common::sample_visibility(image, &camera, Vec3::new(x, 0.0, z)))
                })
                .collect();
            common::width_10_90(&profile).expect("the profile crosses the edge")
        })
        .collect();
    widths.iter().sum::<f32>() / widths.len() as f32
}

#[test]
fn a_floating_boxs_wide_penumbra_takes_half_the_resolution_and_keeps_its_width() {
    let gpu = common::gpu();
    let scene = scene(2.5, 0.6);
    let (_, report) = frame(&gpu, &scene, ours());
    let configured_tile = ours().shadow_map.resolution;
    let widths = report
        .penumbra_widths
        .expect("the compute path measures its penumbrae");
    println!(
        "floating box: {widths:?}, maps at {} texels",
        report.map_resolution
    );
    assert!(
        widths.pixels > 1000,
        "{widths:?}: the penumbra covers many pixels"
    );
    assert_eq!(
        report.map_resolution,
        configured_tile / 2,
        "{widths:?}: no penumbra is narrow, the maps go to half"
    );
    // As wide as at the configured resolution, and as the reference's.
    let measure =
        |settings| penumbra::metrics::measure_visibility(&gpu, &scene, &camera(), settings, SIZE).unwrap();
    // The box's shadow is there: dark at its centre, lit far from it.
    let visibility = measure(ours());
    let at = |x: f32| common::sample_visibility(&visibility, &camera(), Vec3::new(x, 0.0, 0.0));
    assert!(
        at(3.0) < 0.2 && at(7.2) > 0.95,
        "{} at the shadow's centre, {} far from it",
        at(3.0),
        at(7.2)
    );
    let mut reference_settings = ours();
    reference_settings.method = ShadowMethod::Reference;
    reference_settings.reference.samples = 128;
    let (half, full, reference) = (
        edge_width(&visibility),
        edge_width(&measure(configured())),
        edge_width(&measure(reference_settings)),
    );
    println!("10-90% width: half resolution {half:.3}, configured {full:.3}, reference {reference:.3}");
    assert!(
        (half / full - 1.0).abs() < 0.05,
        "half resolution {half:.3} against {full:.3} at the configured one"
    );
    assert!(
        (half / reference - 1.0).abs() < 0.15,
        "half resolution {half:.3} against the reference's {reference:.3}"
    );
}

#[test]
fn a_small_lights_narrow_penumbrae_keep_the_configured_resolution() {
    let gpu = common::gpu();
    let (_, report) = frame_from(&gpu, &scene(0.0, 0.03), ours(), &camera_over(1.5));
    let widths = report.penumbra_widths.expect("measured");
    println!(
        "box on the floor, small light: {widths:?}, maps at {} texels",
        report.map_resolution
    );
    assert_eq!(report.map_resolution, ours().shadow_map.resolution, "{widths:?}");
    let narrow = widths.narrower[1] as f32 / widths.pixels as f32;
    assert!(narrow > 0.05, "{widths:?}: the penumbrae are narrow");
}

#[test]
fn the_configured_setting_the_draws_and_the_other_methods_keep_the_resolution() {
    let gpu = common::gpu();
    let scene = scene(2.5, 0.6);
    let configured_tile = ours().shadow_map.resolution;
    let (_, report) = frame(&gpu, &scene, configured());
    assert_eq!(report.map_resolution, configured_tile);
    assert_eq!(report.penumbra_widths, None, "nothing is measured");

    let mut draws = ours();
    draws.penumbra.fragment_passes = true;
    assert!(matches!(
        draws.penumbra.map_resolution,
        MapResolution::FromPenumbra { .. }
    ));
    let (_, report) = frame(&gpu, &scene, draws);
    assert_eq!(report.map_resolution, configured_tile);
    assert_eq!(report.penumbra_widths, None);

    let mut pcss = ours();
    pcss.method = ShadowMethod::Pcss;
    let (_, report) = frame(&gpu, &scene, pcss);
    assert_eq!(report.map_resolution, configured_tile);
    assert_eq!(report.penumbra_widths, None);
}

#[test]
fn a_narrowest_width_out_of_range_is_refused_by_name() {
    let mut s = ours();
    s.penumbra.map_resolution = MapResolution::FromPenumbra {
        narrowest_texels: 0.0,
    };
    let e = s.validate(None).unwrap_err().to_string();
    assert!(e.contains("penumbra.map_resolution.narrowest_texels"), "{e}");
}
