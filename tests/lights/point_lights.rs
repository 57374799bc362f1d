//! Point lights: a sphere of radius R, shadowed through a cube of six maps.
//!
//! Two thin plates hang over a floor with their edges on the line z = 0 under a point light
//! 3 units up. Seen across the edge (along z) every floor point sees the light's sphere as a
//! disk of radius R around the same spot, so the penumbra's full width is `2 R h / (H - h)`
//! for a plate `h` up and the light `H` up, whatever x; its 10-90% part is 0.687 of that.
//! - `ours`' 10-90% width within 10% of that analytic width under the high plate and the low
//!   one (contact hardening: the low plate's shadow is four times sharper);
//! - no seam at the cube faces: the high plate's shadow edge crosses the boundary between the
//!   -y face and the +x face (floor points with x = H); the widths on both sides agree within
//!   10%, and the lit floor beside the edge and the umbra inside it stay lit and dark across
//!   the boundary, with no line.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, Light, Material, Quality, Scene, ShadowMethod, ShadowSettings,
    metrics::{VisibilityImage, measure_visibility},
    scene::primitives,
};

const LIGHT_HEIGHT: f32 = 3.0;
const RADIUS: f32 = 0.3;
/// The plates: (height, x range); both span z in [-2, 0].
const HIGH: (f32, (f32, f32)) = (1.5, (-1.0, 6.0));
const LOW: (f32, (f32, f32)) = (0.6, (-6.0, -1.5));

fn scene() -> Scene {
    let (mut scene, _) = common::point_light_over_floor(LIGHT_HEIGHT, RADIUS, 30.0);
    let blue = scene.add_material(Material::colored("plate", [0.3, 0.5, 0.8]));
    for (h, (x0, x1)) in [HIGH, LOW] {
        let plate = scene.add_mesh(primitives::cuboid(Vec3::new(x1 - x0, 0.04, 2.0)));
        scene
            .add_instance(
                plate,
                blue,
                Mat4::from_translation(Vec3::new((x0 + x1) / 2.0, h, -1.0)),
            )
            .receiver = false;
    }
    scene
}

/// The analytic 10-90% width across a plate's edge on the floor.
fn analytic(h: f32) -> f32 {
    0.687 * 2.0 * RADIUS * h / (LIGHT_HEIGHT - h)
}

fn looking_down_at(x: f32, span: f32) -> Camera {
    Camera {
        fov_y_deg: 40.0,
        near: 0.1,
        far: 50.0,
        ..Camera::look_at(Vec3::new(x, span, 0.3 * span), Vec3::new(x, 0.0, 0.0))
    }
}

/// The 10-90% width across the edge (along +z, from the umbra into the light) at `x`,
/// averaged over five profiles 0.04 apart along x; `reach` each way from z = 0 (the camera
/// sees the floor under the plate only a little way past its edge).
fn width_at(image: &VisibilityImage, camera: &Camera, x: f32, reach: f32) -> f32 {
    let profile: Vec<(f32, f32)> = (0..=400)
        .map(|i| {
            let t = reach * (i as f32 / 200.0 - 1.0);
            let v = (-2..=2)
                .map(|k| common::sample_visibility(image, camera, Vec3::new(x + k as f32 * 0.04, 0.0, t)))
                .sum::<f32>()
                / 5.0;
            (t, v)
        })
        .collect();
    common::width_10_90(&profile).unwrap_or_else(|| panic!("no penumbra at x = {x}"))
}

fn settings(method: ShadowMethod) -> ShadowSettings {
    let mut s = ShadowSettings::preset(method, Quality::Medium);
    s.reference.samples = 96;
    s
}

const SIZE: (u32, u32) = (400, 300);

#[test]
fn penumbra_widths_follow_the_sphere_and_harden_toward_contact() {
    let gpu = common::gpu();
    let scene = scene();
    let mut widths = Vec::new();
    for (name, (h, (x0, x1))) in [("high", HIGH), ("low", LOW)] {
        let x = (x0 + x1) / 2.0;
        let camera = looking_down_at(x, 2.5 + 4.0 * analytic(h));
        let truth = analytic(h);
        for method in [ShadowMethod::Reference, ShadowMethod::Ours, ShadowMethod::Pcss] {
            let image = measure_visibility(&gpu, &scene, &camera, settings(method), SIZE).unwrap();
            let w = width_at(&image, &camera, x, truth / 0.687);
            println!(
                "{name} plate (h = {h}): {:>9} width {w:.4}, analytic {truth:.4}, ratio {:.3}",
                method.name(),
                w / truth
            );
            if method == ShadowMethod::Ours {
                widths.push(w);
            }
            if method != ShadowMethod::Pcss {
                assert!(
                    (w / truth - 1.0).abs() <= 0.10,
                    "{name} plate, {}: width {w:.4} against the analytic {truth:.4}",
                    method.name()
                );
            }
        }
    }
    assert!(
        widths[1] * 3.0 < widths[0],
        "the lower plate's shadow is sharper: {widths:?}"
    );
}

#[test]
fn no_seam_where_the_shadow_crosses_cube_faces() {
    let gpu = common::gpu();
    let scene = scene();
    // Floor points with x = H lie on the boundary of the -y and +x faces.
    let boundary = LIGHT_HEIGHT;
    let camera = looking_down_at(boundary, 3.5);
    let truth = analytic(HIGH.0);
    let image = measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Ours), SIZE).unwrap();
    let sides: Vec<f32> = [boundary - 0.5, boundary, boundary + 0.5]
        .iter()
        .map(|&x| width_at(&image, &camera, x, truth / 0.687))
        .collect();
    println!("widths at x = H - 0.5, H, H + 0.5: {sides:?} (analytic {truth:.4})");
    for w in &sides {
        assert!(
            (w / sides[0] - 1.0).abs() <= 0.10,
            "widths across the faces: {sides:?}"
        );
    }
    // Along the edge, beside it in the light and inside the umbra, across the boundary.
    let half = 0.5 * truth / 0.687;
    for i in 0..=80 {
        let x = boundary - 0.8 + 1.6 * i as f32 / 80.0;
        let lit = common::sample_visibility(&image, &camera, Vec3::new(x, 0.0, half + 0.15));
        let dark = common::sample_visibility(&image, &camera, Vec3::new(x, 0.0, -half - 0.15));
        assert!(lit > 0.95, "a seam in the light at x = {x}: {lit}");
        assert!(dark < 0.05, "a seam in the umbra at x = {x}: {dark}");
    }
}

#[test]
fn the_room_has_a_shaded_lamp_a_monitor_and_a_ceiling_panel() {
    let gpu = common::gpu();
    let scene = penumbra::load_scene(&common::asset("scenes/room.ron")).unwrap();
    assert!(
        matches!(scene.light, Light::Point(_)),
        "the desk lamp is the key light"
    );
    assert!(
        matches!(scene.more_lights.as_slice(), [Light::Spot(_), Light::Rect(_)]),
        "the monitor is a spot, the ceiling panel a rectangle: {:?}",
        scene.more_lights
    );
    let camera = scene.view(0).unwrap();
    let image = measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Ours), SIZE).unwrap();
    let at = |p: Vec3| {
        let (x, y) = common::project(&camera, SIZE.0, SIZE.1, p).expect("in view");
        image.visibility[(y * SIZE.0 + x) as usize].expect("lit by the lamp")
    };
    // The shade hides the wall above the lamp; the wall beside and below it is lit.
    let above = at(Vec3::new(-0.55, 2.0, -1.49));
    let beside = at(Vec3::new(-1.0, 1.0, -1.49));
    println!("wall above the lamp {above:.3}, beside it {beside:.3}");
    assert!(above < 0.2, "the shade's shadow above the lamp: {above}");
    assert!(beside > 0.8, "the wall beside the lamp: {beside}");
}
