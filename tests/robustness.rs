//! Shadow-map hygiene at the extremes: a light grazing the floor, where depth precision and
//! biases are tested hardest.

mod common;

use glam::{Mat4, Vec3};
use penumbra::metrics::measure_visibility;
use penumbra::scene::primitives;
use penumbra::{Camera, DirectionalLight, Light, Material, Scene, ShadowMethod, ShadowSettings};

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

#[test]
fn grazing_light_gives_no_acne_and_the_shadow_touches_its_caster() {
    let gpu = common::gpu();
    for method in [
        ShadowMethod::Hard,
        ShadowMethod::Hardware2x2,
        ShadowMethod::Ours,
        ShadowMethod::Traditional,
        ShadowMethod::Pcss,
    ] {
        let settings = ShadowSettings {
            method,
            ..Default::default()
        };
        let (share, lit, contact) = grazing_acne(&gpu, settings);
        let wrong = (share * lit as f32).round();
        eprintln!(
            "{}: {wrong} of {lit} lit floor points wrongly shadowed ({:.3}%), contact visibility {contact:?}",
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
