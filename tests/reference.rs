//! The ground-truth reference checks itself: it converges to hard shadows for a tiny light, it
//! has converged (doubling the samples changes it less than any method's error), and its
//! penumbra matches the analytic width `2 R d / D`.

mod common;

use glam::{Mat4, Vec3};
use penumbra::metrics::{measure_visibility, visibility_error};
use penumbra::{
    Camera, DebugTexture, GpuScene, Light, Material, Renderer, Scene, ShadowMethod, ShadowSettings,
    SpotLight, load_scene, scene::primitives,
};

fn settings(method: ShadowMethod, samples: u32) -> ShadowSettings {
    let mut s = ShadowSettings {
        method,
        ..Default::default()
    };
    s.reference.samples = samples;
    s
}

#[test]
fn a_tiny_light_converges_to_hard_shadows() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    if let Light::Directional(l) = &mut scene.light {
        l.angular_diameter_deg = 0.01;
    }
    let camera = scene.view(0).unwrap();
    let size = (240, 192);
    let hard = measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Hard, 1), size).unwrap();
    let reference =
        measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Reference, 16), size).unwrap();
    let e = visibility_error(&reference, &hard).unwrap();
    eprintln!("tiny light: reference vs hard {e:?}");
    assert!(e.pixels > 10_000);
    assert!(
        e.rmse < 0.03,
        "reference with a 0.01 degree light differs from hard: {e:?}"
    );
}

#[test]
fn doubling_the_samples_changes_less_than_any_method_errs() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let size = (240, 192);
    let reference =
        |n| measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Reference, n), size).unwrap();
    let (half, full) = (reference(128), reference(256));
    let convergence = visibility_error(&full, &half).unwrap();
    eprintln!("reference 128 vs 256 samples: {convergence:?}");
    for method in ShadowMethod::REAL_TIME {
        let image = measure_visibility(&gpu, &scene, &camera, settings(method, 1), size).unwrap();
        let e = visibility_error(&full, &image).unwrap();
        eprintln!("{}: {e:?}", method.name());
        assert!(
            convergence.rmse < e.rmse,
            "doubling the reference's samples changed it by {} RMSE, more than {}'s error {}",
            convergence.rmse,
            method.name(),
            e.rmse
        );
    }
}

/// Fraction of a uniform disk on the far side of a line at signed distance `t` radii from its
/// center.
fn disk_fraction(t: f32) -> f32 {
    let t = t.clamp(-1.0, 1.0);
    (t.acos() - t * (1.0 - t * t).sqrt()) / std::f32::consts::PI
}

#[test]
fn penumbra_under_a_square_plate_matches_2_r_d_over_d() {
    let gpu = common::gpu();
    // A 2 x 2 plate 1 unit above the floor, a spot light of radius 0.4 four units above it.
    let (plate_height, light_height, radius) = (1.0f32, 5.0f32, 0.4f32);
    let mut scene = Scene {
        light: Light::Spot(SpotLight {
            position: Vec3::new(0.0, light_height, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 50.0,
            radius,
            color: Vec3::ONE,
            intensity: 1.0,
        }),
        ..Default::default()
    };
    let material = scene.add_material(Material::colored("grey", [0.8, 0.8, 0.8]));
    let plate = scene.add_mesh(primitives::cuboid(Vec3::new(2.0, 0.001, 2.0)));
    scene
        .add_instance(
            plate,
            material,
            Mat4::from_translation(Vec3::new(0.0, plate_height, 0.0)),
        )
        .receiver = false;
    let floor = scene.add_mesh(primitives::plane(12.0, 1.0));
    scene.add_instance(floor, material, Mat4::IDENTITY).caster = false;
    // Looking up from under the floor would hide it; look down past the plate's edge instead.
    let camera = Camera {
        eye: Vec3::new(1.25, 6.0, 0.0),
        target: Vec3::new(1.25, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_deg: 20.0,
        near: 3.0,
        far: 8.0,
    };
    let size = (800u32, 800u32);
    let mut renderer = Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        settings(ShadowMethod::Reference, 512),
    )
    .unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, size.0, size.1).unwrap();
    let (visibility, _) = penumbra::read_texture_f32(
        &gpu.device,
        &gpu.queue,
        renderer.debug_texture(DebugTexture::Visibility).unwrap(),
    )
    .unwrap();
    // Across the plate's edge at x = 1, along the floor's x axis at z = 0 (the plate hides
    // nothing there: it is seen edge-on from above at x > 1).
    let sample = |x: f32| {
        let (px, py) = common::project(&camera, size.0, size.1, Vec3::new(x, 0.0, 0.2)).expect("on screen");
        visibility[(py * size.0 + px) as usize]
    };
    let xs: Vec<f32> = (0..=1000).map(|i| 1.0 + i as f32 * 0.0005).collect();
    let first_above = |level: f32| xs.iter().copied().find(|&x| sample(x) >= level).unwrap();
    assert!(
        sample(1.05) < 0.05 && sample(1.49) > 0.95,
        "the edge is not where expected"
    );
    let measured = first_above(0.9) - first_above(0.1);
    // Analytic: full width 2 R d / D, with d = plate to floor and D = light to plate, projected
    // onto the floor. The 10%-90% part of a disk's edge is 2 t radii wide, f(t) = 0.1.
    let (d, big_d) = (plate_height, light_height - plate_height);
    let full_width = 2.0 * radius * d / big_d;
    let t = (0..=10_000)
        .map(|i| i as f32 / 10_000.0)
        .find(|&t| disk_fraction(t) <= 0.1)
        .unwrap();
    let expected = full_width * t;
    eprintln!("10-90% penumbra: measured {measured:.4}, analytic {expected:.4} (full width {full_width:.4})");
    assert!(
        (measured / expected - 1.0).abs() < 0.05,
        "measured {measured:.4} vs analytic {expected:.4}"
    );
}
