//! The ground-truth reference checks itself: it converges to hard shadows for a tiny light, it
//! has converged (doubling the samples changes it less than any method's error), and its
//! penumbra matches the analytic width `2 R d / D`.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::metrics::{measure_visibility, visibility_error};
use penumbra::{
    Camera, GpuScene, Light, LightTexture, Material, Renderer, Scene, ShadowMethod, ShadowSettings,
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
    // 25 of the 26869 pixels differ by more than 0.5: hard edges a pixel apart on the floor,
    // and 7 teapot pixels whose triangle faces away from the sun (smooth shading lights them),
    // which the reference reads 0 as rays do (`tests/accuracy/ray_traced_reference.rs`) and hard's
    // normal offset reads lit. Those 7 took the RMSE from about 0.026 to 0.030.
    assert!(
        e.rmse < 0.035,
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

/// A thin plate of `size` centred at `center` (a caster, not a receiver) over a floor `floor`
/// units square (a receiver, not a caster), under `light`.
fn plate_over_a_floor(light: Light, size: Vec3, center: Vec3, floor: f32) -> Scene {
    let mut scene = Scene {
        light,
        ..Default::default()
    };
    let material = scene.add_material(Material::colored("grey", [0.8, 0.8, 0.8]));
    let plate = scene.add_mesh(primitives::cuboid(size));
    scene
        .add_instance(plate, material, Mat4::from_translation(center))
        .receiver = false;
    let floor = scene.add_mesh(primitives::plane(floor, 1.0));
    scene.add_instance(floor, material, Mat4::IDENTITY).caster = false;
    scene
}

/// The reference's own visibility texture (values, channels per pixel) for `scene` from
/// `camera` with `samples` light samples.
fn reference_visibility(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    size: (u32, u32),
    samples: u32,
) -> (Vec<f32>, u32) {
    let mut renderer = Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        settings(ShadowMethod::Reference, samples),
    )
    .unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), scene).unwrap();
    penumbra::render_to_image(gpu, &mut renderer, &gpu_scene, camera, size.0, size.1).unwrap();
    penumbra::read_texture_f32(
        &gpu.device,
        &gpu.queue,
        renderer.debug_texture(LightTexture::Visibility).unwrap(),
    )
    .unwrap()
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
    let light = Light::Spot(SpotLight {
        position: Vec3::new(0.0, light_height, 0.0),
        direction: Vec3::NEG_Y,
        cone_angle_deg: 50.0,
        radius,
        color: Vec3::ONE,
        intensity: 1.0,
        range: None,
    });
    let scene = plate_over_a_floor(
        light,
        Vec3::new(2.0, 0.001, 2.0),
        Vec3::new(0.0, plate_height, 0.0),
        12.0,
    );
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
    let (visibility, channels) = reference_visibility(&gpu, &scene, &camera, size, 512);
    // Across the plate's edge at x = 1, along the floor's x axis at z = 0 (the plate hides
    // nothing there: it is seen edge-on from above at x > 1).
    let sample = |x: f32| {
        let (px, py) = common::project(&camera, size.0, size.1, Vec3::new(x, 0.0, 0.2)).expect("on screen");
        visibility[((py * size.0 + px) * channels) as usize]
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

/// The visibility a floor point `x` (normal +y) has of a sphere light (`center`, `radius`) past
/// the straight edge of a plate at height `plate_height` that covers every x below `edge_x`:
/// the unoccluded share of the disk the sphere shows from `x` (a cone of half-angle
/// asin(R / d), uniformly bright in solid angle), each direction weighted by the receiver's
/// cosine. Integrated on a polar grid over the cone, independently of the reference's samples.
fn sphere_past_an_edge(
    x: glam::DVec3,
    center: glam::DVec3,
    radius: f64,
    plate_height: f64,
    edge_x: f64,
) -> f64 {
    let axis = (center - x).normalize();
    let alpha = (radius / (center - x).length()).asin();
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let (rings, spokes) = (160, 320);
    let (mut lit, mut total) = (0.0, 0.0);
    for i in 0..rings {
        let theta = alpha * (i as f64 + 0.5) / rings as f64;
        for j in 0..spokes {
            let phi = std::f64::consts::TAU * (j as f64 + 0.5) / spokes as f64;
            let w = axis * theta.cos() + (e1 * phi.cos() + e2 * phi.sin()) * theta.sin();
            // Solid angle of the cell, times the receiver's cosine.
            let weight = theta.sin() * w.y.max(0.0);
            let at_plate = x + w * ((plate_height - x.y) / w.y);
            total += weight;
            if at_plate.x >= edge_x {
                lit += weight;
            }
        }
    }
    lit / total
}

/// Under a sphere light the reference's visibility, pixel by pixel across a straight edge's
/// penumbra, is the analytic share of the disk the sphere shows each floor point, within 0.01
/// on average in each half of the penumbra (and 0.02 at any pixel). The receivers lie 34
/// degrees off the direction from the light to the middle of the view: the reference that
/// sampled one disk facing the view (before issue 28) was foreshortened there by cos 34 =
/// 0.83, its penumbra too steep: mean error -0.039 in the inner half, +0.041 in the outer,
/// 0.071 at worst (now +0.0005, +0.0004 and 0.009).
#[test]
fn a_sphere_lights_penumbra_is_the_share_of_its_disk_each_point_sees() {
    let gpu = common::gpu();
    let (light_height, radius, plate_height) = (3.0f32, 0.3f32, 1.0f32);
    // The plate covers x < 4/3 (under the light too); its shadow edge lies at x = 2 on the
    // floor, 34 degrees off the vertical from the light.
    let edge_x = 4.0 / 3.0;
    let center = Vec3::new(0.0, light_height, 0.0);
    let light = Light::Point(penumbra::PointLight {
        position: center,
        radius,
        color: Vec3::ONE,
        intensity: 1.0,
        range: None,
    });
    // The plate's top face at `plate_height`: the rays toward the light, up and to the left,
    // pass the plate's top corner last.
    let scene = plate_over_a_floor(
        light,
        Vec3::new(6.0, 0.002, 8.0),
        Vec3::new(edge_x - 3.0, plate_height - 0.001, 0.0),
        30.0,
    );
    // Straight down onto the floor beside the edge, framing just the strip the test reads
    // (x in [1.6, 2.4], |z| <= 0.5, with a margin): 110 pixels a unit. (It framed the whole
    // floor under the light at 480 x 360 before, 98 pixels a unit, and took 101 of the
    // accuracy tests' 400 s.)
    let camera = Camera {
        eye: Vec3::new(2.0, 6.0, 0.0),
        target: Vec3::new(2.0, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_deg: 11.0,
        near: 2.0,
        far: 8.0,
    };
    let size = (128u32, 128u32);
    let (visibility, channels) = reference_visibility(&gpu, &scene, &camera, size, 1024);
    // Each pixel's floor point, from its centre's ray.
    let to_world = camera
        .view_projection(size.0 as f32 / size.1 as f32)
        .inverse()
        .as_dmat4();
    let floor_point = |px: u32, py: u32| {
        let ndc_x = (px as f64 + 0.5) / size.0 as f64 * 2.0 - 1.0;
        let ndc_y = 1.0 - (py as f64 + 0.5) / size.1 as f64 * 2.0;
        let a = to_world.project_point3(glam::DVec3::new(ndc_x, ndc_y, 0.25));
        let b = to_world.project_point3(glam::DVec3::new(ndc_x, ndc_y, 0.75));
        a + (b - a) * (-a.y / (b.y - a.y))
    };
    let eye = camera.eye.as_dvec3();
    let (mut sums, mut worst) = ([0.0f64; 4], 0.0f64);
    let mut lit_beyond = 0usize;
    for py in 0..size.1 {
        for px in 0..size.0 {
            let x = floor_point(px, py);
            // Only the floor beside the edge, seen past the plate, away from the plate's ends.
            let over_plate = eye + (x - eye) * ((eye.y - plate_height as f64) / eye.y);
            if x.x < 1.6 || x.x > 2.4 || x.z.abs() > 0.5 || over_plate.x < edge_x as f64 + 0.01 {
                continue;
            }
            let truth = sphere_past_an_edge(
                x,
                center.as_dvec3(),
                radius as f64,
                plate_height as f64,
                edge_x as f64,
            );
            let v = visibility[((py * size.0 + px) * channels) as usize] as f64;
            if truth >= 0.999 {
                lit_beyond += (v > 0.99) as usize;
            }
            if truth <= 0.02 || truth >= 0.98 {
                continue;
            }
            let half = if truth <= 0.5 { 0 } else { 2 };
            sums[half] += v - truth;
            sums[half + 1] += 1.0;
            worst = worst.max((v - truth).abs());
        }
    }
    let inner = sums[0] / sums[1].max(1.0);
    let outer = sums[2] / sums[3].max(1.0);
    eprintln!(
        "sphere light past an edge: mean signed error inner half {inner:+.4} ({} px), outer half {outer:+.4} ({} px), largest {worst:.4}; {lit_beyond} px fully lit beyond",
        sums[1], sums[3]
    );
    assert!(
        sums[1] > 500.0 && sums[3] > 500.0,
        "too few penumbra pixels: {sums:?}"
    );
    assert!(lit_beyond > 500, "the floor past the penumbra is not lit");
    assert!(
        inner.abs() <= 0.01 && outer.abs() <= 0.01,
        "mean signed error: inner half {inner:+.4}, outer half {outer:+.4}"
    );
    assert!(worst <= 0.02, "largest error {worst:.4}");
}
