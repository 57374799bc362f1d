//! Shadow-map hygiene at the extremes: a light grazing the floor, where depth precision and
//! biases are tested hardest.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::metrics::measure_visibility;
use penumbra::scene::primitives;
use penumbra::{Camera, DepthFormat, DirectionalLight, Light, Material, Scene, ShadowMethod, ShadowSettings};

/// A unit cube standing on a 40-unit floor that casts shadows too (so it could shadow itself:
/// acne), lit by a sun `elevation_deg` above the horizon from +X.
fn grazing_scene(elevation_deg: f32) -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_mesh(primitives::plane(40.0, 1.0));
    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    let gray = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let red = scene.add_material(Material::colored("cube", [0.8, 0.3, 0.2]));
    scene.add_instance(floor, gray, Mat4::IDENTITY);
    scene.add_instance(cube, red, Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)));
    let el = elevation_deg.to_radians();
    scene.light = Light::Directional(DirectionalLight {
        direction: -Vec3::new(el.cos(), el.sin(), 0.0),
        angular_diameter_deg: 0.5,
        color: Vec3::ONE,
        intensity: 1.0,
    });
    scene.ambient = Vec3::splat(0.05);
    scene
}

/// Whether the ray from floor point `p` toward the light passes within `margin` of the cube.
fn near_cube_shadow(p: Vec3, toward: Vec3, margin: f32) -> bool {
    let (lo, hi) = (
        Vec3::new(-0.5, 0.0, -0.5) - margin,
        Vec3::new(0.5, 1.0, 0.5) + margin,
    );
    let (mut t0, mut t1) = (0.0f32, f32::MAX);
    for axis in 0..3 {
        if toward[axis].abs() < 1e-9 {
            if p[axis] < lo[axis] || p[axis] > hi[axis] {
                return false;
            }
            continue;
        }
        let a = (lo[axis] - p[axis]) / toward[axis];
        let b = (hi[axis] - p[axis]) / toward[axis];
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

const GRAZING_CAMERA: Camera = Camera {
    eye: Vec3::new(-10.0, 14.0, 14.0),
    target: Vec3::new(-6.0, 0.0, 0.0),
    up: Vec3::Y,
    fov_y_deg: 50.0,
    near: 0.5,
    far: 80.0,
};

/// Share of the floor points away from the cube's shadow that `settings` shadows wrongly
/// (visibility below 0.8), and the visibility just behind the cube at its base.
fn grazing_acne(gpu: &penumbra::HeadlessGpu, settings: ShadowSettings) -> (f32, usize, Vec<f32>) {
    let scene = grazing_scene(3.0);
    let toward = -scene.light.direction();
    let camera = GRAZING_CAMERA;
    let (w, h) = (480, 360);
    let v = measure_visibility(gpu, &scene, &camera, settings, (w, h)).unwrap();
    let at =
        |p: Vec3| common::project(&camera, w, h, p).and_then(|(x, y)| v.visibility[(y * w + x) as usize]);
    let (mut lit, mut wrong) = (0usize, 0usize);
    for i in 0..120 {
        for j in 0..120 {
            let p = Vec3::new(
                -19.0 + 38.0 * i as f32 / 119.0,
                0.0,
                -19.0 + 38.0 * j as f32 / 119.0,
            );
            if near_cube_shadow(p, toward, 0.6) {
                continue;
            }
            if let Some(visibility) = at(p) {
                lit += 1;
                if visibility < 0.8 {
                    wrong += 1;
                }
            }
        }
    }
    let contact = [-0.3f32, 0.0, 0.3]
        .iter()
        .filter_map(|z| at(Vec3::new(-0.58, 0.0, *z)))
        .collect();
    (wrong as f32 / lit.max(1) as f32, lit, contact)
}

/// Without any bias the same check finds acne, so it can fail.
#[test]
fn grazing_light_without_bias_shows_acne() {
    let gpu = common::gpu();
    let mut settings = ShadowSettings {
        method: ShadowMethod::Hard,
        ..Default::default()
    };
    settings.shadow_map.constant_bias = 0;
    settings.shadow_map.slope_bias = 0.0;
    settings.shadow_map.normal_offset = 0.0;
    let (share, lit, _) = grazing_acne(&gpu, settings);
    eprintln!(
        "no bias: {:.2}% of {lit} lit floor points wrongly shadowed",
        share * 100.0
    );
    assert!(
        share > 0.01,
        "no acne without bias ({:.3}%): the check is blind",
        share * 100.0
    );
}

/// The 16-bit map is tested too: the near and far planes fitted to the clipped scene keep its
/// 65536 depth steps on what the map covers.
#[test]
fn grazing_light_gives_no_acne_and_the_shadow_touches_its_caster() {
    let gpu = common::gpu();
    let methods = [
        ShadowMethod::Hard,
        ShadowMethod::Hardware2x2,
        ShadowMethod::Ours,
        ShadowMethod::Traditional,
        ShadowMethod::Pcss,
    ];
    let formats = [DepthFormat::Depth32, DepthFormat::Depth16];
    for (method, format) in formats.iter().flat_map(|f| methods.map(|m| (m, *f))) {
        let mut settings = ShadowSettings {
            method,
            ..Default::default()
        };
        settings.shadow_map.depth_format = format;
        let (share, lit, contact) = grazing_acne(&gpu, settings);
        let wrong = (share * lit as f32).round();
        eprintln!(
            "{} {format:?}: {wrong} of {lit} lit floor points wrongly shadowed ({:.3}%), contact visibility {contact:?}",
            method.name(),
            share * 100.0
        );
        assert!(lit > 5000, "too few floor points measured ({lit})");
        assert!(
            share < 0.001,
            "{}: acne on {:.3}% of the lit floor",
            method.name(),
            share * 100.0
        );
        assert!(
            contact.len() == 3 && contact.iter().all(|v| *v < 0.5),
            "{}: the shadow does not touch the cube: {contact:?}",
            method.name()
        );
    }
}

/// A 60-unit floor and, out of the camera's view, a fence of thin posts whose striped shadow
/// falls across the part of the floor the camera sees.
fn fence_scene() -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_mesh(primitives::plane(60.0, 1.0));
    let post = scene.add_mesh(primitives::cuboid(Vec3::new(0.23, 5.0, 0.23)));
    let gray = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let wood = scene.add_material(Material::colored("post", [0.5, 0.4, 0.3]));
    scene.add_instance(floor, gray, Mat4::IDENTITY);
    for k in -25..=25 {
        let x = k as f32 * 0.61;
        scene.add_instance(post, wood, Mat4::from_translation(Vec3::new(x, 2.5, 5.5)));
    }
    scene.light = Light::Directional(DirectionalLight {
        direction: Vec3::new(0.15, -1.0, -1.0),
        angular_diameter_deg: 0.5,
        color: Vec3::ONE,
        intensity: 1.0,
    });
    scene.ambient = Vec3::splat(0.05);
    scene
}

/// A camera 10 units above the floor looking straight down, moved `dx` along x.
fn top_down(dx: f32) -> Camera {
    Camera {
        eye: Vec3::new(dx, 10.0, 0.0),
        target: Vec3::new(dx, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_deg: 40.0,
        near: 1.0,
        far: 12.0,
    }
}

/// Renders the fence from `top_down(0)` and from `top_down` one pixel further along x, and
/// counts the floor pixels whose visibility differs after undoing the one-pixel shift.
fn shimmer(gpu: &penumbra::HeadlessGpu, settings: ShadowSettings) -> (usize, usize) {
    let (w, h) = (320, 240);
    let scene = fence_scene();
    let pixel = 10.0 * 2.0 * (20.0f32).to_radians().tan() / h as f32;
    let a = measure_visibility(gpu, &scene, &top_down(0.0), settings, (w, h)).unwrap();
    let b = measure_visibility(gpu, &scene, &top_down(pixel), settings, (w, h)).unwrap();
    let name = format!(
        "shimmer_{}_{}.png",
        settings.method.name(),
        if settings.shadow_map.snap_to_texels {
            "snapped"
        } else {
            "free"
        }
    );
    let gray = image::GrayImage::from_fn(w, h, |x, y| {
        image::Luma([(a.visibility[(y * w + x) as usize].unwrap_or(0.0) * 255.0) as u8])
    });
    gray.save(common::output_dir().join(name)).unwrap();
    let (mut compared, mut changed) = (0, 0);
    // Leave a border where screen-space filters see the image's edge.
    for y in 16..h - 16 {
        for x in 16..w - 16 {
            let (Some(va), Some(vb)) = (
                a.visibility[(y * w + x) as usize],
                b.visibility[(y * w + x - 1) as usize],
            ) else {
                continue;
            };
            compared += 1;
            if (va - vb).abs() > 0.02 {
                changed += 1;
            }
        }
    }
    (compared, changed)
}

/// A camera move of one pixel (0.43 shadow-map texels here) leaves a static shadow where it
/// was when the light's map moves in whole texels, and makes its edges crawl when it does not.
/// (PCSS and, by default, ours rotate their taps by a per-pixel noise that is anchored to the
/// screen, so a one-pixel move changes their noise whatever the map does: ours is tested with
/// the rotation off.)
#[test]
fn sub_texel_camera_moves_do_not_make_shadows_shimmer() {
    let gpu = common::gpu();
    for method in [
        ShadowMethod::Hard,
        ShadowMethod::Hardware2x2,
        ShadowMethod::Traditional,
        ShadowMethod::Ours,
    ] {
        let mut settings = ShadowSettings {
            method,
            ..Default::default()
        };
        settings.penumbra.rotate_taps = false;
        settings.shadow_map.resolution = 256;
        let (compared, snapped) = shimmer(&gpu, settings);
        settings.shadow_map.snap_to_texels = false;
        let (_, free) = shimmer(&gpu, settings);
        eprintln!(
            "{}: {snapped} of {compared} floor pixels changed with snapping, {free} without",
            method.name()
        );
        assert!(compared > 40_000, "{compared} floor pixels compared");
        assert!(
            snapped as f32 <= compared as f32 * 1e-4,
            "{}: {snapped} pixels changed with snapping",
            method.name()
        );
        assert!(
            free as f32 > compared as f32 * 5e-3,
            "{}: only {free} pixels changed without snapping: the test cannot see shimmer",
            method.name()
        );
    }
}
