//! A blocker a few centimetres from a small light: the room's lamp under its shade, isolated.
//!
//! A sphere light of radius R = 3 cm hangs 1.2 m above the floor; a thin plate `D` below it
//! covers everything on one side of the line z = 0 (its edge lies right under the light). A
//! wall at x = 0.4 stands beside it. Every receiver point sees the light's sphere as a disk cut
//! by the plate's edge along z, so across the edge (along z) the penumbra's full width is
//! `2 R d / D'` with `d / D' = (H - y) / (H - h) - 1` for a receiver at height `y`, the plate at
//! `h` and the light at `H`, whatever x; its 10-90% part is 0.687 of that. With D = 6 cm that
//! ratio is 19 on the floor, where the room's is 20-30; earlier accuracy tests stayed at 1-3.
//!
//! That small-angle width is a guide only: across penumbrae this wide the rays tilt, and the
//! plate is 4 mm thick; the exact profile, integrated here on the CPU over the sphere's disk of
//! directions, is about 11% wider. The reference must agree with the exact width within 5%, and `ours` with the
//! reference within 10%.
//!
//! Measured along z at fixed points: on the floor (the -y cube face), on the wall low down (a
//! ray 66 degrees off the wall's normal, the -y face), on the wall at 45 degrees down from the
//! light (the boundary between the -y and +x faces) and higher up (the +x face). A second test
//! holds `ours` to 0.8x `pcss`' penumbra RMSE in the room itself.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, Material, Quality, Scene, ShadowMethod, ShadowSettings, metrics::measure_visibility,
    scene::primitives,
};

const LIGHT_HEIGHT: f32 = 1.2;
const RADIUS: f32 = 0.03;
/// The wall's plane, x = WALL (facing -x).
const WALL: f32 = 0.4;

fn scene(gap: f32) -> Scene {
    let (mut scene, grey) = common::point_light_over_floor(LIGHT_HEIGHT, RADIUS, 8.0);
    let brass = scene.add_material(Material::colored("shade", [0.75, 0.6, 0.3]));
    // The wall ends below the plate, so the scene's centre (where the metrics' exposure puts 1
    // on a surface facing the light) is not at the light.
    let wall = scene.add_mesh(primitives::cuboid(Vec3::new(0.02, 1.3, 6.0)));
    scene
        .add_instance(
            wall,
            grey,
            Mat4::from_translation(Vec3::new(WALL + 0.01, 0.65, 0.0)),
        )
        .caster = false;
    let (min, max) = plate(gap);
    let plate = scene.add_mesh(primitives::cuboid(max - min));
    scene
        .add_instance(plate, brass, Mat4::from_translation((min + max) / 2.0))
        .receiver = false;
    scene
}

/// The plate's box: 4 mm thick, its lower face `gap` below the light's centre, from x = -1.5 to
/// just short of the wall, z from -1.5 to 0 (its edge right under the light).
fn plate(gap: f32) -> (Vec3, Vec3) {
    let bottom = LIGHT_HEIGHT - gap;
    (
        Vec3::new(-1.5, bottom, -1.5),
        Vec3::new(WALL - 0.02, bottom + 0.004, 0.0),
    )
}

/// The exact visibility at `p` (normal `n`), independent of the renderer
/// ([`common::exact_sphere_visibility`]).
fn exact_visibility(p: Vec3, n: Vec3, gap: f32) -> f32 {
    let light = Vec3::new(0.0, LIGHT_HEIGHT, 0.0);
    common::exact_sphere_visibility(light, RADIUS, &[plate(gap)], p, n)
}

/// The small-angle 10-90% width along z at a receiver of height `y`, the plate `gap` below
/// the light: `0.687 2 R d / D`. Only a guide (see the module's docs).
fn analytic(y: f32, gap: f32) -> f32 {
    0.687 * 2.0 * RADIUS * ((LIGHT_HEIGHT - y) / gap - 1.0)
}

/// A place to measure: a point on the line z = 0 of a receiver and the camera that sees it.
struct Spot {
    name: &'static str,
    point: Vec3,
    camera: Camera,
}

fn spots() -> Vec<Spot> {
    let camera = |eye: Vec3, target: Vec3| Camera {
        fov_y_deg: 60.0,
        near: 0.05,
        far: 20.0,
        ..Camera::look_at(eye, target)
    };
    vec![
        Spot {
            name: "floor",
            point: Vec3::new(-0.5, 0.0, 0.0),
            camera: camera(Vec3::new(-0.5, 1.0, 1.6), Vec3::new(-0.5, 0.0, 0.0)),
        },
        Spot {
            name: "wall, low (66 degrees)",
            point: Vec3::new(WALL, 0.3, 0.0),
            camera: camera(Vec3::new(-0.9, 0.3, 0.9), Vec3::new(WALL, 0.3, 0.0)),
        },
        Spot {
            name: "wall, between two faces",
            point: Vec3::new(WALL, LIGHT_HEIGHT - WALL, 0.0),
            camera: camera(Vec3::new(-0.9, 0.8, 0.9), Vec3::new(WALL, 0.8, 0.0)),
        },
        Spot {
            name: "wall, high",
            point: Vec3::new(WALL, 0.95, 0.0),
            camera: camera(Vec3::new(-0.9, 0.95, 0.9), Vec3::new(WALL, 0.95, 0.0)),
        },
    ]
}

fn settings(method: ShadowMethod) -> ShadowSettings {
    let mut s = ShadowSettings::preset(method, Quality::Medium);
    s.reference.samples = 128;
    s
}

const SIZE: (u32, u32) = (400, 300);

/// The 10-90% width along z through `point`, from the umbra (z < 0) into the light, of the
/// visibility `at` gives, averaged over five profiles 1 cm apart across it (along the
/// receiver); `reach` each way.
fn width_at(at: impl Fn(Vec3) -> f32, point: Vec3, across: Vec3, reach: f32) -> Option<f32> {
    let profile: Vec<(f32, f32)> = (0..=400)
        .map(|i| {
            let t = reach * (i as f32 / 200.0 - 1.0);
            let v = (-2..=2)
                .map(|k| at(point + Vec3::Z * t + across * (0.01 * k as f32)))
                .sum::<f32>()
                / 5.0;
            (t, v)
        })
        .collect();
    common::width_10_90(&profile)
}

/// A place's widths: its name, the small-angle and the exact width, and each method's.
struct Widths {
    name: &'static str,
    small_angle: f32,
    exact: f32,
    methods: Vec<f32>,
}

/// Widths on every spot for `methods`, with the plate `gap` below the light.
fn measure(gpu: &penumbra::HeadlessGpu, gap: f32, methods: &[ShadowMethod]) -> Vec<Widths> {
    let scene = scene(gap);
    spots()
        .into_iter()
        .map(|spot| {
            let small_angle = analytic(spot.point.y, gap);
            let reach = 0.8 * small_angle / 0.687;
            let (across, normal) = if spot.point.y == 0.0 {
                (Vec3::X, Vec3::Y)
            } else {
                (Vec3::Y, Vec3::NEG_X)
            };
            let exact = width_at(|p| exact_visibility(p, normal, gap), spot.point, across, reach)
                .expect("the exact profile crosses the penumbra");
            let profiles = std::env::var_os("PENUMBRA_NEAR_PROFILES").is_some();
            if profiles {
                let line: Vec<String> = (-8..=8)
                    .map(|i| {
                        let t = reach * i as f32 / 8.0;
                        format!("{:.2}", exact_visibility(spot.point + Vec3::Z * t, normal, gap))
                    })
                    .collect();
                println!("{} {:>10} {}", spot.name, "exact", line.join(" "));
            }
            let widths = methods
                .iter()
                .map(|&method| {
                    let image =
                        measure_visibility(gpu, &scene, &spot.camera, settings(method), SIZE).unwrap();
                    let at = |p| common::sample_visibility(&image, &spot.camera, p);
                    if profiles {
                        let line: Vec<String> = (-8..=8)
                            .map(|i| format!("{:.2}", at(spot.point + Vec3::Z * (reach * i as f32 / 8.0))))
                            .collect();
                        println!("{} {:>10} {}", spot.name, method.name(), line.join(" "));
                    }
                    width_at(at, spot.point, across, reach)
                        .unwrap_or_else(|| panic!("{}: {} has no penumbra there", spot.name, method.name()))
                })
                .collect();
            Widths {
                name: spot.name,
                small_angle,
                exact,
                methods: widths,
            }
        })
        .collect()
}

#[test]
fn a_blocker_six_centimetres_from_the_light_throws_a_penumbra_as_wide_as_the_truth() {
    let gpu = common::gpu();
    let methods = [ShadowMethod::Reference, ShadowMethod::Ours, ShadowMethod::Pcss];
    let results = measure(&gpu, 0.06, &methods);
    for w in &results {
        println!(
            "{}: small-angle {:.3}, exact {:.3}; {}",
            w.name,
            w.small_angle,
            w.exact,
            methods
                .iter()
                .zip(&w.methods)
                .map(|(m, x)| format!("{} {x:.3} ({:.2}x)", m.name(), x / w.exact))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    for w in &results {
        let (reference, ours) = (w.methods[0], w.methods[1]);
        assert!(
            (reference / w.exact - 1.0).abs() <= 0.05,
            "{}: the reference's width {reference:.3} against the exact {:.3}",
            w.name,
            w.exact
        );
        // Low on the wall, which the light grazes (66 degrees), ours was 0.83-0.87x while the
        // blur made half the penumbra's variance: its kernel, drawn long along the light on
        // the screen, took in receivers nearer the light. With PCF making three quarters
        // (`pcf_variance_share` 0.75) it is 0.96x.
        assert!(
            (ours / reference - 1.0).abs() <= 0.10,
            "{}: ours' width {ours:.3} against the reference's {reference:.3}",
            w.name
        );
    }
}

/// The room's desk view, the lamp's visibility against the reference: `ours`' penumbra RMSE at
/// most 0.8x `pcss`' (what the benchmark's "Room" table measures), and the widths across the
/// shade's shadow edge on the wall ([`wall_widths`]). Before the fixes of issue 38
/// it was 0.200 against 0.103: the fatten distance came from the casters' union box, which held
/// the bulb, and was 2.8 mm; the blur's depth weights cut it short on the walls.
#[test]
fn the_rooms_lamp_against_pcss() {
    let gpu = common::gpu();
    let scene = penumbra::load_scene(&common::asset("scenes/room.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let size = (480, 384);
    let reference =
        measure_visibility(&gpu, &scene, &camera, settings(ShadowMethod::Reference), size).unwrap();
    let images: Vec<_> = [ShadowMethod::Ours, ShadowMethod::Pcss, ShadowMethod::Hard]
        .into_iter()
        .map(|method| measure_visibility(&gpu, &scene, &camera, settings(method), size).unwrap())
        .collect();
    wall_widths(&reference, &images[0], &images[1], &camera);
    let error = |method| {
        let index = [ShadowMethod::Ours, ShadowMethod::Pcss, ShadowMethod::Hard]
            .iter()
            .position(|m| *m == method)
            .unwrap();
        let image = &images[index];
        let error = penumbra::metrics::visibility_error(&reference, image).unwrap();
        if std::env::var_os("PENUMBRA_SAVE_RENDERS").is_some() {
            penumbra::metrics::error_heat_map(&reference, image)
                .save(common::output_dir().join(format!("room_heat_{}.png", method.name())))
                .unwrap();
        }
        error.penumbra_rmse
    };
    let (ours, pcss, hard) = (
        error(ShadowMethod::Ours),
        error(ShadowMethod::Pcss),
        error(ShadowMethod::Hard),
    );
    println!("room, view 0, penumbra RMSE: ours {ours:.4}, pcss {pcss:.4}, hard {hard:.4}");
    assert!(ours <= 0.8 * pcss, "ours {ours:.4} against pcss {pcss:.4}");
}

/// The 10-90% widths across the shade's shadow edge on the wall behind the desk (z = -1.5),
/// along vertical lines from the dark above to the lit below, for `ours` and `pcss` against the
/// reference, held to issue 38's 10%. Measured (480x384, 128 samples): `ours` 0.93-0.99x the
/// reference's on the six lines, `pcss` 0.85-0.99x. With the silhouette search inside a shadow
/// reaching 48 shadow-map texels, `ours` was 0.82-0.87x: the shade's rim lies hundreds of
/// texels from the wall's pixels. Reaching 256 (`INSIDE_REACH_TEXELS` in
/// shaders/distance_map.wgsl) made it 0.97-1.12x, and PCF making three quarters of the
/// penumbra's variance (`pcf_variance_share` 0.75, was 0.5) 0.93-0.99x.
fn wall_widths(
    reference: &penumbra::metrics::VisibilityImage,
    ours: &penumbra::metrics::VisibilityImage,
    pcss: &penumbra::metrics::VisibilityImage,
    camera: &Camera,
) {
    // The lines miss the shade (x = -0.55 +- 0.12) and the monitor (up to y = 1.27).
    for x in [-1.1f32, -0.9, -0.7, -0.4, -0.2, 0.0] {
        // The visibility at height y on the line, where the pixels around it show the wall.
        let at = |image: &penumbra::metrics::VisibilityImage, y: f32| {
            let p = Vec3::new(x, y, -1.5);
            let (px, py) = common::project(camera, image.width, image.height, p)?;
            let measured = |dx: u32, dy: u32| {
                image.visibility[((py + dy - 1) * image.width + px + dx - 1) as usize].is_some()
            };
            ((0..3).all(|dy| (0..3).all(|dx| measured(dx, dy))))
                .then(|| common::sample_visibility(image, camera, p))
        };
        // From y = 2.5 down to 1.1, 5 mm apart: rising from the shade's shadow into the light.
        let width = |image| {
            let profile: Vec<(f32, f32)> = (0..=280)
                .filter_map(|i| {
                    let t = 0.005 * i as f32;
                    at(image, 2.5 - t).map(|v| (t, v))
                })
                .collect();
            common::width_10_90(&profile)
        };
        let (r, o, p) = (width(reference), width(ours), width(pcss));
        println!("wall behind the desk, x = {x}: 10-90% width reference {r:?}, ours {o:?}, pcss {p:?}");
        let (r, o) = (
            r.expect("the reference crosses the shade's shadow edge"),
            o.expect("ours crosses the shade's shadow edge"),
        );
        assert!(
            (0.90..=1.10).contains(&(o / r)),
            "x = {x}: ours' width {o:.3} against the reference's {r:.3}"
        );
    }
}
