//! Cascaded shadow maps for directional lights.
//!
//! - The penumbra is as wide in world units on both sides of a cascade boundary: a roof's
//!   straight edge 6 units up throws a shadow edge that runs away from the camera across the
//!   first boundary; its 10-90% width, measured on the floor just before the boundary's blend
//!   band and just past the boundary, must agree within 10%.
//! - On the built-in outdoor scene (340 units across) the visibility near the camera is far
//!   closer to the reference with four cascades than with one map.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, DirectionalLight, Light, Material, Quality, Renderer, Scene, ShadowMethod, ShadowSettings,
    load_scene,
    metrics::{VisibilityImage, measure_visibility, visibility_error},
    scene::primitives,
};

/// The direction the sun's light travels: toward +x and down, 0.8 sideways per unit of drop.
const SUN: Vec3 = Vec3::new(0.8, -1.0, 0.0);
/// The roof's edge: x = 0, 6 units up (its slab 0.2 thick), running along z.
const ROOF_HEIGHT: f32 = 6.0;

fn roof_scene() -> Scene {
    let mut scene = Scene {
        light: Light::Directional(DirectionalLight {
            direction: SUN,
            angular_diameter_deg: 5.0,
            color: Vec3::ONE,
            intensity: 1.0,
        }),
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let blue = scene.add_material(Material::colored("roof", [0.3, 0.5, 0.8]));
    let floor = scene.add_mesh(primitives::plane(400.0, 1.0));
    scene.add_instance(floor, grey, Mat4::IDENTITY).caster = false;
    let roof = scene.add_mesh(primitives::cuboid(Vec3::new(60.0, 0.2, 240.0)));
    scene
        .add_instance(
            roof,
            blue,
            Mat4::from_translation(Vec3::new(-30.0, ROOF_HEIGHT, -40.0)),
        )
        .receiver = false;
    scene
}

/// Where the roof's shadow edge lies on the floor (the top face's edge throws the outer one).
fn shadow_edge_x() -> f32 {
    common::shadow_on_floor(Vec3::new(0.0, ROOF_HEIGHT + 0.1, 0.0), SUN).x
}

fn camera() -> Camera {
    let edge = shadow_edge_x();
    Camera {
        fov_y_deg: 40.0,
        near: 0.1,
        far: 300.0,
        ..Camera::look_at(Vec3::new(edge + 3.0, 3.0, 40.0), Vec3::new(edge, 0.0, 0.0))
    }
}

const SIZE: (u32, u32) = (480, 360);

/// The point of the shadow edge on the floor at `distance` from the camera along its view.
fn edge_point_at(camera: &Camera, distance: f32) -> Vec3 {
    // dot(p(z) - eye, forward) is linear in z along the edge.
    let forward = camera.forward();
    let at = |z: f32| (Vec3::new(shadow_edge_x(), 0.0, z) - camera.eye).dot(forward);
    let (a, b) = (at(0.0), at(1.0));
    Vec3::new(shadow_edge_x(), 0.0, (distance - a) / (b - a))
}

/// The 10-90% width (world units along the floor, across the edge) at `distance` from the
/// camera, averaged over five lines 0.1 units apart along the edge.
fn width_at(image: &VisibilityImage, camera: &Camera, distance: f32) -> f32 {
    let edge = edge_point_at(camera, distance);
    let reach = 2.5;
    let profile: Vec<(f32, f32)> = (0..=400)
        .map(|i| {
            let t = reach * (i as f32 / 200.0 - 1.0);
            let v = (-2..=2)
                .map(|k| common::sample_visibility(image, camera, edge + Vec3::new(t, 0.0, k as f32 * 0.1)))
                .sum::<f32>()
                / 5.0;
            (t, v)
        })
        .collect();
    common::width_10_90(&profile).unwrap_or_else(|| panic!("no penumbra found at distance {distance}"))
}

#[test]
fn the_penumbra_keeps_its_width_across_a_cascade_boundary() {
    let gpu = common::gpu();
    let scene = roof_scene();
    let camera = camera();
    let settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    assert_eq!(settings.shadow_map.cascades.count, 4, "four cascades by default");
    // Where the first cascade ends for this view, as the renderer planned it.
    let (_, renderer): (_, Renderer) = common::render_frame(&gpu, &scene, &camera, settings, SIZE);
    let light_view = renderer.last_report().expect("a frame").light.light_view;
    let cascades = light_view.cascades();
    assert_eq!(cascades.len(), 4, "the sun gets four cascades");
    for pair in cascades.windows(2) {
        assert!(pair[0].end < pair[1].end, "cascades end farther and farther");
        assert!(
            pair[0].extent.x < pair[1].extent.x,
            "nearer cascades cover less: {} vs {}",
            pair[0].extent.x,
            pair[1].extent.x
        );
    }
    let first = cascades[0];
    let before = first.blend_start * 0.85;
    let after = first.end * 1.15;
    assert!(
        after < cascades[1].blend_start,
        "the second measurement lies inside cascade 1"
    );
    let mut rows = Vec::new();
    let methods = [ShadowMethod::Reference, ShadowMethod::Ours, ShadowMethod::Pcss];
    for method in methods {
        let mut s = ShadowSettings::preset(method, Quality::Medium);
        s.reference.samples = 96;
        let image = measure_visibility(&gpu, &scene, &camera, s, SIZE).unwrap();
        let (a, b) = (
            width_at(&image, &camera, before),
            width_at(&image, &camera, after),
        );
        println!(
            "{:>9}: width {a:.3} at {before:.1} (cascade 0), {b:.3} at {after:.1} (cascade 1): ratio {:.3}",
            method.name(),
            b / a
        );
        rows.push((method, a, b));
    }
    // The truth: the whole penumbra is 2 tan(2.5 deg) x the ray's length from the roof's edge
    // to the floor, stretched along the floor; a disk light's 10-90% part is 0.687 of it (the
    // chord offsets that leave 10% and 90% of a disk's area on one side: +-0.687 radii).
    let ray = ROOF_HEIGHT * SUN.length() / -SUN.y;
    let across = 2.0 * 2.5f32.to_radians().tan() * ray;
    let along_floor = 0.687 * across * SUN.length() / -SUN.y;
    println!("analytic 10-90% width along the floor: {along_floor:.3}");
    for (method, a, b) in rows {
        if method == ShadowMethod::Reference {
            // The judge itself: close to the analytic width on both sides.
            for w in [a, b] {
                assert!(
                    (w / along_floor - 1.0).abs() < 0.15,
                    "reference width {w:.3} vs analytic {along_floor:.3}"
                );
            }
            continue;
        }
        assert!(
            (b / a - 1.0).abs() <= 0.10,
            "{}: width {a:.3} before the boundary, {b:.3} after it",
            method.name()
        );
    }
}

/// Visibility RMSE over the lower half of the image (the ground nearest the camera).
fn near_rmse(reference: &VisibilityImage, image: &VisibilityImage) -> f32 {
    let h = reference.height;
    let error = visibility_error(&reference.rows(h / 2..h), &image.rows(h / 2..h)).unwrap();
    assert!(
        error.pixels > (reference.width * h / 4) as usize,
        "the lower half is mostly lit ground"
    );
    error.rmse
}

#[test]
fn cascades_sharpen_the_outdoor_scene_near_the_camera() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/outdoor.ron")).unwrap();
    let bounds = scene.bounds();
    let across = (bounds.max - bounds.min).truncate().max_element();
    assert!(across >= 300.0, "the outdoor scene is {across} units across");
    assert!(scene.instances.len() > 100, "many casters");
    let camera = scene.view(0).unwrap();
    let size = (320, 240);
    let mut reference = ShadowSettings::preset(ShadowMethod::Reference, Quality::Medium);
    reference.reference.samples = 48;
    let reference = measure_visibility(&gpu, &scene, &camera, reference, size).unwrap();
    let mut errors = Vec::new();
    for count in [1, 4] {
        let mut s = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
        s.shadow_map.cascades.count = count;
        let image = measure_visibility(&gpu, &scene, &camera, s, size).unwrap();
        let error = near_rmse(&reference, &image);
        println!("{count} cascade(s): RMSE near the camera {error:.4}");
        errors.push(error);
    }
    assert!(
        errors[1] < 0.5 * errors[0],
        "four cascades {:.4} against one map {:.4}",
        errors[1],
        errors[0]
    );
}

/// The maps hold the cascades the view uses: the teapot's view 0 uses two, side by side in a
/// 2 x 1 atlas (the exit map the same at half the texels, the fattened map at half or, derived,
/// at a quarter); the roof's view uses
/// four in 2 x 2. A renderer whose view goes from one layout to the other makes its maps again
/// and draws what a new renderer draws.
#[test]
fn the_maps_hold_the_cascades_the_view_uses() {
    use penumbra::{GpuScene, LightTexture, light_space::AtlasGrid};
    let gpu = common::gpu();
    let settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    let tile = settings.shadow_map.resolution;
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let teapot_camera = teapot.view(0).unwrap();
    let sizes = |renderer: &Renderer| {
        let report = renderer.last_report().expect("a frame").light;
        let shadows = renderer.shadows();
        let size = |which| {
            let t = shadows.light_texture(report.light, which).expect("the map");
            (t.width(), t.height())
        };
        (
            report.light_view.grid,
            report.light_view.cascades().len(),
            size(LightTexture::ShadowMap),
            size(LightTexture::FattenedMap),
            size(LightTexture::ExitMap),
        )
    };
    // The fattened map: drawn at half the shadow map's texels a side, derived at a quarter
    // (`Fattening::Dilation`, which `Fattening::Auto` takes from its count of caster triangles).
    let triangles = {
        let renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
        let scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &teapot).unwrap();
        scene.casters().caster_triangle_count()
    };
    let fattened = if settings.penumbra.fattening.derived(triangles) {
        (tile / 2, tile / 4)
    } else {
        (tile, tile / 2)
    };
    let (_, renderer) = common::render_frame(&gpu, &teapot, &teapot_camera, settings, SIZE);
    assert_eq!(
        sizes(&renderer),
        (
            AtlasGrid { cols: 2, rows: 1 },
            2,
            (2 * tile, tile),
            fattened,
            (tile, tile / 2)
        )
    );
    let (_, renderer) = common::render_frame(&gpu, &roof_scene(), &camera(), settings, SIZE);
    let (grid, count, shadow_map, ..) = sizes(&renderer);
    assert_eq!(
        (grid, count, shadow_map),
        (AtlasGrid::square(2), 4, (2 * tile, 2 * tile))
    );

    // The teapot seen from view 0, then from far back (one cascade): the maps go from 2 x 1
    // to one tile, and the frame is the one a new renderer draws.
    let far = Camera {
        eye: teapot_camera.target + (teapot_camera.eye - teapot_camera.target) * 4.0,
        far: teapot_camera.far * 4.0,
        ..teapot_camera
    };
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &teapot).unwrap();
    penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &teapot_camera, SIZE.0, SIZE.1).unwrap();
    assert_eq!(sizes(&renderer).0, AtlasGrid { cols: 2, rows: 1 });
    let reused = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &far, SIZE.0, SIZE.1).unwrap();
    let (grid, count, shadow_map, ..) = sizes(&renderer);
    assert_eq!((grid, count, shadow_map), (AtlasGrid::SINGLE, 1, (tile, tile)));
    let (fresh, _) = common::render_frame(&gpu, &teapot, &far, settings, SIZE);
    let differing = reused
        .pixels()
        .zip(fresh.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0.iter()).any(|(x, y)| x.abs_diff(*y) > 1))
        .count();
    assert_eq!(
        differing, 0,
        "the reused renderer's frame differs from a new one's"
    );
    // And the far view has the teapot's shadow on the floor below it.
    let visibility = measure_visibility(&gpu, &teapot, &far, settings, SIZE).unwrap();
    let shadowed = visibility
        .visibility
        .iter()
        .flatten()
        .filter(|&&v| v < 0.2)
        .count();
    assert!(shadowed > 100, "no shadow from far back ({shadowed} pixels)");
}
