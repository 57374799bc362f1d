//! Penumbrae against the ground truth: on a scene of the kind an independent renderer checked
//! (a floor; a thin plate touching it at one end and rising to 1.5 units; a box floating 1 unit
//! up; a pillar and a scanned mesh standing on the floor), under a spot light of disk radius
//! 0.25, under a sphere light of that radius and a 0.8 x 0.2 rectangle light in its place and
//! under a 4-degree sun, `ours`'
//! 10-90% penumbra widths must be within 15% of the reference's at contact and far from it
//! (one exception under the sphere light, below), and its mean signed error in each half of
//! the penumbra within +-0.03.
//!
//! Widths are measured along a line on the floor that crosses one shadow edge, from the umbra
//! into full light, with a camera looking straight down at that edge. The visibility is the
//! one `penumbra::metrics` measures, read bilinearly, averaged over five parallel lines.
//!
//! `PENUMBRA_TRUTH_METHODS=ours,pcss,traditional` prints the same table for other methods
//! (nothing is asserted on them).

use crate::common;

use glam::{Mat4, Quat, Vec3};
use penumbra::{
    Camera, DirectionalLight, Light, Material, PointLight, RectLight, Scene, ShadowMethod, ShadowSettings,
    SpotLight,
    metrics::{VisibilityImage, measure_visibility},
    scene::primitives,
};

/// The direction the sun's light travels: down and toward +z, 0.8 units sideways per unit of
/// drop, so shadows fall on the +z side of their casters.
const SUN: Vec3 = Vec3::new(0.0, -1.0, 0.8);

/// Where the plate's lower face touches the floor and how it rises: along x from -3.5 (height
/// 0) to +0.5 (height 1.5), |z + 2| < 0.4.
const PLATE_X: (f32, f32) = (-3.5, 0.5);
const PLATE_Z: f32 = -2.0;
const PLATE_HALF_WIDTH: f32 = 0.4;
/// The floating box: a unit cube whose bottom is 1 unit up.
const BOX_CENTER: Vec3 = Vec3::new(2.5, 1.5, -2.5);
/// The pillar standing on the floor: 0.4 x 2.5 x 0.4.
const PILLAR_CENTER: Vec3 = Vec3::new(-1.0, 1.25, 1.0);
const PILLAR_HALF: f32 = 0.2;

#[derive(Clone, Copy)]
enum Lamp {
    Spot,
    Sun,
    /// A sphere light of the spot's radius where the spot is: its map is a cube of faces.
    Sphere,
    /// A rectangle light 0.8 x 0.2 where the spot is, facing as it does, its long side along x:
    /// its map is a cube of faces, its penumbrae four times as wide across edges along z as
    /// across edges along x.
    Rect,
}

impl Lamp {
    fn name(self) -> &'static str {
        match self {
            Lamp::Spot => "spot r=0.25",
            Lamp::Sun => "sun 4deg",
            Lamp::Sphere => "sphere r=0.25",
            Lamp::Rect => "rect 0.8x0.2",
        }
    }

    fn light(self) -> Light {
        match self {
            Lamp::Sun => Light::Directional(DirectionalLight {
                direction: SUN,
                angular_diameter_deg: 4.0,
                color: Vec3::ONE,
                intensity: 1.0,
            }),
            Lamp::Sphere => Light::Point(PointLight {
                position: self.spot_position(),
                radius: 0.25,
                color: Vec3::ONE,
                intensity: 1.0,
                range: None,
            }),
            Lamp::Rect => Light::Rect(RectLight {
                position: self.spot_position(),
                direction: -self.spot_position() + Vec3::new(0.0, 0.0, 0.5),
                // Its height in the plane of +y and its direction; its width along x.
                up: Vec3::Y,
                width: 0.8,
                height: 0.2,
                color: Vec3::ONE,
                intensity: 1.0,
                range: None,
            }),
            Lamp::Spot => Light::Spot(SpotLight {
                position: self.spot_position(),
                direction: -self.spot_position() + Vec3::new(0.0, 0.0, 0.5),
                cone_angle_deg: 50.0,
                radius: 0.25,
                color: Vec3::ONE,
                intensity: 1.0,
                range: None,
            }),
        }
    }

    fn spot_position(self) -> Vec3 {
        Vec3::new(0.0, 6.0, -4.8)
    }

    /// Where the ray from the light's center through `p` meets the floor.
    fn shadow_of(self, p: Vec3) -> Vec3 {
        let d = match self {
            Lamp::Sun => SUN,
            Lamp::Spot | Lamp::Sphere | Lamp::Rect => p - self.spot_position(),
        };
        common::shadow_on_floor(p, d)
    }
}

fn truth_scene(lamp: Lamp) -> Scene {
    let mut scene = Scene {
        light: lamp.light(),
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let blue = scene.add_material(Material::colored("casters", [0.3, 0.5, 0.8]));
    let floor = scene.add_mesh(primitives::plane(16.0, 1.0));
    scene.add_instance(floor, grey, Mat4::IDENTITY).caster = false;

    let (x0, x1) = PLATE_X;
    let rise = 1.5f32;
    let thickness = 0.04;
    let length = ((x1 - x0).powi(2) + rise * rise).sqrt();
    let plate = scene.add_mesh(primitives::cuboid(Vec3::new(
        length,
        thickness,
        2.0 * PLATE_HALF_WIDTH,
    )));
    let tilt = (rise / (x1 - x0)).atan();
    // Rotate about z, then place so the lower face's -x end rests on the floor at x0.
    let rotation = Quat::from_rotation_z(tilt);
    let lower_end = rotation * Vec3::new(-length / 2.0, -thickness / 2.0, 0.0);
    let center = Vec3::new(x0, 0.0, PLATE_Z) - lower_end;
    scene
        .add_instance(plate, blue, Mat4::from_rotation_translation(rotation, center))
        .receiver = false;

    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    scene
        .add_instance(cube, blue, Mat4::from_translation(BOX_CENTER))
        .receiver = false;

    let pillar = scene.add_mesh(primitives::cuboid(Vec3::new(
        2.0 * PILLAR_HALF,
        2.0 * PILLAR_CENTER.y,
        2.0 * PILLAR_HALF,
    )));
    scene
        .add_instance(pillar, blue, Mat4::from_translation(PILLAR_CENTER))
        .receiver = false;

    // The scanned cow, about 1.5 units long, standing on the floor.
    let model = penumbra::load_model(&common::models().join("spot.obj")).unwrap();
    let bounds = model.bounds();
    let scale = 1.5 / bounds.size().max_element();
    let place = Mat4::from_translation(Vec3::new(2.0, -bounds.min.y * scale, 1.5))
        * Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2)
        * Mat4::from_scale(Vec3::splat(scale));
    scene.add_model(&model, place, Some(blue), true, false);
    scene
}

/// The height of the plate's lower face above the floor at `x`.
fn plate_height(x: f32) -> f32 {
    1.5 * (x - PLATE_X.0) / (PLATE_X.1 - PLATE_X.0)
}

/// One shadow edge to measure: the occluder's edge point that casts it, the direction on the
/// floor toward the lit side, and how far either side of the hard edge the profile reaches.
struct Edge {
    name: &'static str,
    /// `true` where the distance to the occluder is small.
    contact: bool,
    occluder: Vec3,
    toward_light: Vec3,
    reach: f32,
}

fn edges(lamp: Lamp) -> Vec<Edge> {
    let plate_edge = |x: f32| {
        // The +z long edge of the plate's lower face.
        Vec3::new(x, plate_height(x), PLATE_Z + PLATE_HALF_WIDTH)
    };
    let pillar_edge = |h: f32| {
        // The pillar's +x, +z vertical edge.
        Vec3::new(PILLAR_CENTER.x + PILLAR_HALF, h, PILLAR_CENTER.z + PILLAR_HALF)
    };
    // Where the shadow lies beside its caster (the plate and the box), the profile stays off
    // the caster's own image: at most 0.7 of the way from the hard edge back to the point
    // under the occluder's edge. (The pillar's profiles run across its shadow's side.)
    let clear = |mut edge: Edge| {
        let under = Vec3::new(edge.occluder.x, 0.0, edge.occluder.z);
        let gap = (lamp.shadow_of(edge.occluder) - under).dot(edge.toward_light);
        if gap > 1e-3 {
            edge.reach = edge.reach.min(0.7 * gap);
        }
        edge
    };
    let edges = vec![
        Edge {
            name: "plate, contact end",
            contact: true,
            occluder: plate_edge(-3.0),
            toward_light: Vec3::Z,
            reach: 0.12,
        },
        Edge {
            name: "plate, far end",
            contact: false,
            occluder: plate_edge(0.2),
            toward_light: Vec3::Z,
            reach: 0.5,
        },
        Edge {
            name: "box, far edge",
            contact: false,
            occluder: BOX_CENTER + Vec3::new(0.0, 0.5, 0.5),
            toward_light: Vec3::Z,
            reach: 0.6,
        },
        Edge {
            name: "pillar, near its foot",
            contact: true,
            occluder: pillar_edge(0.35),
            toward_light: Vec3::X,
            reach: 0.12,
        },
        Edge {
            name: "pillar, top",
            contact: false,
            occluder: pillar_edge(2.2),
            toward_light: Vec3::X,
            reach: 0.18,
        },
    ];
    // The rectangle is 0.8 wide along x where the spot's disk is 0.5 across: profiles along x
    // (across the pillar's edges) reach as much farther.
    let wider = |mut edge: Edge| {
        if matches!(lamp, Lamp::Rect) && edge.toward_light == Vec3::X {
            edge.reach *= 0.8 / 0.5;
        }
        edge
    };
    edges.into_iter().map(wider).map(clear).collect()
}

/// A camera straight above `center`, `span` world units across vertically.
fn camera_above(center: Vec3, span: f32) -> Camera {
    let height = 4.0;
    Camera {
        eye: center + Vec3::Y * height,
        target: center,
        up: Vec3::NEG_Z,
        fov_y_deg: 2.0 * (span / 2.0 / height).atan().to_degrees(),
        near: 1.0,
        far: 8.0,
    }
}

const SIZE: (u32, u32) = (320, 240);

/// The visibility profile across `edge`, averaged over five parallel lines, as (offset from the
/// hard edge toward the light, visibility).
fn profile(image: &VisibilityImage, camera: &Camera, hard_edge: Vec3, edge: &Edge) -> Vec<(f32, f32)> {
    let along = Vec3::Y.cross(edge.toward_light).normalize() * (edge.reach * 0.08);
    (0..=400)
        .map(|i| {
            let t = edge.reach * (i as f32 / 200.0 - 1.0);
            let p = hard_edge + edge.toward_light * t;
            let v = (-2..=2)
                .map(|k| common::sample_visibility(image, camera, p + along * k as f32))
                .sum::<f32>()
                / 5.0;
            (t, v)
        })
        .collect()
}

struct Measured {
    /// (edge name, contact, reference width, method width)
    widths: Vec<(&'static str, bool, f32, Option<f32>)>,
    /// Mean signed error (method - reference) where the reference is in (0.02, 0.5] and in
    /// (0.5, 0.98), over every edge's view and the overview.
    inner: f32,
    outer: f32,
}

/// Summed signed error (method - reference) and pixel counts where the reference is in
/// (0.02, 0.5] (the inner half of the penumbra) and in (0.5, 0.98) (the outer half).
fn signed_error_halves(reference: &VisibilityImage, image: &VisibilityImage) -> [f64; 4] {
    let mut sums = [0.0f64; 4];
    for (r, t) in reference.visibility.iter().zip(&image.visibility) {
        let (Some(r), Some(t)) = (r, t) else { continue };
        let half = if *r > 0.02 && *r <= 0.5 {
            0
        } else if *r > 0.5 && *r < 0.98 {
            2
        } else {
            continue;
        };
        sums[half] += (t - r) as f64;
        sums[half + 1] += 1.0;
    }
    sums
}

fn settings(method: ShadowMethod) -> ShadowSettings {
    ShadowSettings::preset(method, penumbra::Quality::Medium)
}

/// The 10-90% width across the edge named `edge` in the reference and in `ours` with `settings`.
fn widths_across(
    gpu: &penumbra::HeadlessGpu,
    lamp: Lamp,
    edge: &str,
    settings: &[ShadowSettings],
) -> (f32, Vec<Option<f32>>) {
    let edge = edges(lamp)
        .into_iter()
        .find(|e| e.name == edge)
        .expect("an edge of that name");
    let edge = &edge;
    let scene = truth_scene(lamp);
    let hard = lamp.shadow_of(edge.occluder);
    let camera = camera_above(hard, edge.reach * 3.0);
    let width = |s: ShadowSettings| {
        let image = measure_visibility(gpu, &scene, &camera, s, SIZE).unwrap();
        common::width_10_90(&profile(&image, &camera, hard, edge))
    };
    let reference = width(self::settings(ShadowMethod::Reference)).expect("a reference penumbra");
    (reference, settings.iter().map(|s| width(*s)).collect())
}

fn measure(
    gpu: &penumbra::HeadlessGpu,
    lamp: Lamp,
    methods: &[ShadowMethod],
) -> Vec<(ShadowMethod, Measured)> {
    let scene = truth_scene(lamp);
    let mut results: Vec<(ShadowMethod, Measured)> = methods
        .iter()
        .map(|&m| {
            (
                m,
                Measured {
                    widths: vec![],
                    inner: 0.0,
                    outer: 0.0,
                },
            )
        })
        .collect();
    let mut sums = vec![[0.0f64; 4]; methods.len()];
    let save = std::env::var_os("PENUMBRA_SAVE_RENDERS").is_some();
    let mut views: Vec<(Camera, Option<&Edge>)> = vec![];
    let all_edges = edges(lamp);
    for edge in &all_edges {
        let hard = lamp.shadow_of(edge.occluder);
        views.push((camera_above(hard, edge.reach * 3.0), Some(edge)));
    }
    views.push((
        Camera {
            eye: Vec3::new(0.0, 9.0, 7.0),
            target: Vec3::new(0.0, 0.0, -0.5),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 1.0,
            far: 30.0,
        },
        None,
    ));
    for (view, (camera, edge)) in views.iter().enumerate() {
        let reference =
            measure_visibility(gpu, &scene, camera, settings(ShadowMethod::Reference), SIZE).unwrap();
        let ref_profile = edge.map(|e| profile(&reference, camera, lamp.shadow_of(e.occluder), e));
        let ref_width = ref_profile.as_ref().map(|p| {
            common::width_10_90(p).unwrap_or_else(|| {
                panic!(
                    "{}: the reference profile across {} does not go from umbra to light: {:?}",
                    lamp.name(),
                    edge.unwrap().name,
                    p.iter().step_by(40).collect::<Vec<_>>()
                )
            })
        });
        for (index, &method) in methods.iter().enumerate() {
            let image = measure_visibility(gpu, &scene, camera, settings(method), SIZE).unwrap();
            if save {
                // 16-bit, so an independent renderer's image can be compared with them
                // (`tools/mitsuba_truth.py`; no direct light measured: 0).
                let dump = |img: &VisibilityImage, name: &str| {
                    let pixels = img
                        .visibility
                        .iter()
                        .map(|v| v.map_or(0, |v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16))
                        .collect();
                    image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(img.width, img.height, pixels)
                        .unwrap()
                        .save(common::output_dir().join(format!("truth_{}_{view}_{name}.png", lamp as u8)))
                        .unwrap();
                };
                dump(&image, method.name());
                dump(&reference, "reference");
                save_view(lamp, view, camera);
            }
            let halves = signed_error_halves(&reference, &image);
            if std::env::var_os("PENUMBRA_TRUTH_PROFILES").is_some() {
                eprintln!(
                    "{} view {view}: inner {:+.4} ({} px) outer {:+.4} ({} px)",
                    method.name(),
                    halves[0] / halves[1].max(1.0),
                    halves[1],
                    halves[2] / halves[3].max(1.0),
                    halves[3]
                );
            }
            for (sum, h) in sums[index].iter_mut().zip(halves) {
                *sum += h;
            }
            if let (Some(edge), Some(ref_width)) = (edge, ref_width) {
                let prof = profile(&image, camera, lamp.shadow_of(edge.occluder), edge);
                if std::env::var_os("PENUMBRA_TRUTH_PROFILES").is_some() {
                    let r = ref_profile.as_ref().unwrap();
                    eprintln!(
                        "{} {}: {}",
                        method.name(),
                        edge.name,
                        r.iter()
                            .zip(&prof)
                            .step_by(20)
                            .map(|((t, a), (_, b))| format!("{t:+.3}:{a:.2}/{b:.2}"))
                            .collect::<Vec<_>>()
                            .join(" ")
                    );
                }
                let width = common::width_10_90(&prof);
                results[index]
                    .1
                    .widths
                    .push((edge.name, edge.contact, ref_width, width));
            }
        }
    }
    for (index, (_, m)) in results.iter_mut().enumerate() {
        let s = sums[index];
        m.inner = (s[0] / s[1].max(1.0)) as f32;
        m.outer = (s[2] / s[3].max(1.0)) as f32;
    }
    results
}

/// With `PENUMBRA_SAVE_RENDERS`: the scene as two OBJ files (the floor, the casters) and the
/// view and light as JSON, for `tools/mitsuba_truth.py` to render with the dumped images.
fn save_view(lamp: Lamp, view: usize, camera: &Camera) {
    let dir = common::output_dir();
    let scene = truth_scene(lamp);
    for (name, casters) in [("floor", false), ("casters", true)] {
        let mut obj = String::new();
        let mut base = 1;
        for instance in scene.instances.iter().filter(|i| i.caster == casters) {
            let mesh = &scene.meshes[instance.mesh];
            for p in &mesh.positions {
                let p = instance.transform.transform_point3(*p);
                obj += &format!("v {} {} {}\n", p.x, p.y, p.z);
            }
            for t in mesh.indices.chunks_exact(3) {
                obj += &format!("f {} {} {}\n", t[0] + base, t[1] + base, t[2] + base);
            }
            base += mesh.positions.len() as u32;
        }
        std::fs::write(dir.join(format!("truth_{}_{name}.obj", lamp as u8)), obj).unwrap();
    }
    let light = match scene.light {
        Light::Directional(l) => serde_json::json!({
            "kind": "sun", "direction": l.direction.to_array(), "angular_diameter_deg": l.angular_diameter_deg,
        }),
        Light::Spot(l) => serde_json::json!({
            "kind": "spot", "position": l.position.to_array(), "direction": l.direction.to_array(), "radius": l.radius,
        }),
        Light::Point(l) => serde_json::json!({
            "kind": "point", "position": l.position.to_array(), "radius": l.radius,
        }),
        Light::Rect(_) | Light::Disk(_) => {
            let a = scene.light.area().unwrap();
            let kind = if matches!(scene.light, Light::Rect(_)) {
                "rect"
            } else {
                "disk"
            };
            serde_json::json!({
                "kind": kind, "position": a.center.to_array(), "u": a.u.to_array(), "v": a.v.to_array(),
                "facing": a.facing.to_array(),
            })
        }
    };
    let json = serde_json::json!({
        "lamp": lamp.name(),
        "size": [SIZE.0, SIZE.1],
        "camera": {
            "eye": camera.eye.to_array(), "target": camera.target.to_array(), "up": camera.up.to_array(),
            "fov_y_deg": camera.fov_y_deg,
        },
        "light": light,
    });
    std::fs::write(
        dir.join(format!("truth_{}_{view}.json", lamp as u8)),
        serde_json::to_string_pretty(&json).unwrap(),
    )
    .unwrap();
}

fn methods_to_print() -> Vec<ShadowMethod> {
    let mut methods = vec![ShadowMethod::Ours];
    if let Ok(list) = std::env::var("PENUMBRA_TRUTH_METHODS") {
        methods = list
            .split(',')
            .map(|name| ShadowMethod::from_name(name.trim()).unwrap())
            .collect();
        if !methods.contains(&ShadowMethod::Ours) {
            methods.insert(0, ShadowMethod::Ours);
        }
    }
    methods
}

fn check(lamp: Lamp) {
    let gpu = common::gpu();
    let results = measure(&gpu, lamp, &methods_to_print());
    let mut failures = vec![];
    for (method, m) in &results {
        for (edge, contact, reference, width) in &m.widths {
            let ratio = width.map(|w| w / reference);
            eprintln!(
                "{} {:<12} {:<22} reference {:.4}  method {}  ratio {}",
                lamp.name(),
                method.name(),
                edge,
                reference,
                width.map_or("none".into(), |w| format!("{w:.4}")),
                ratio.map_or("-".into(), |r| format!("{r:.3}")),
            );
            // Under the sphere light the plate's contact end is a penumbra of 0.02 units on a
            // cube face whose texels are 0.012 there (a spot's map is fitted to the view): it
            // reads 0.84x the reference's (whose faces have twice the texels), and is held to
            // 25%.
            let tolerance = if matches!(lamp, Lamp::Sphere) && *edge == "plate, contact end" {
                0.25
            } else {
                0.15
            };
            if *method == ShadowMethod::Ours && !ratio.is_some_and(|r| (r - 1.0).abs() <= tolerance) {
                failures.push(format!(
                    "{edge} ({}): width {width:?} against the reference's {reference:.4}",
                    if *contact { "contact" } else { "far" }
                ));
            }
        }
        eprintln!(
            "{} {:<12} mean signed error: inner half {:+.4}, outer half {:+.4}",
            lamp.name(),
            method.name(),
            m.inner,
            m.outer
        );
        if *method == ShadowMethod::Ours {
            for (half, e) in [("inner", m.inner), ("outer", m.outer)] {
                if e.abs() > 0.03 {
                    failures.push(format!("mean signed error in the {half} half {e:+.4}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}: {}", lamp.name(), failures.join("; "));
}

#[test]
fn ours_matches_the_reference_under_a_spot_light() {
    check(Lamp::Spot);
}

#[test]
fn ours_matches_the_reference_under_a_sun() {
    check(Lamp::Sun);
}

/// A point light's cube: each face's near plane must lie in front of every caster along that
/// face's axis (the box's far edge read 0.76x when the near plane clipped the fattened box's
/// top, 40 degrees off the lower face's axis), and the taps must follow the face's stretch off
/// its axis.
#[test]
fn ours_matches_the_reference_under_a_sphere_light() {
    check(Lamp::Sphere);
}

/// A rectangle light where the spot is: the same edges, each as soft as the rectangle's extent
/// across it.
#[test]
fn ours_matches_the_reference_under_a_rectangle_light() {
    check(Lamp::Rect);
}

/// Beside a thick caster's foot under a spot light, the light's rays pass nearest the caster's
/// near corner, while the fattened surface stands for its light-facing side, higher up: the
/// distance there comes from the nearest caster texel of the real shadow map
/// (`PenumbraSettings::nearest_caster`). Without it the penumbra is half again too wide.
#[test]
fn beside_a_thick_casters_foot_the_distance_is_to_its_nearest_corner() {
    let gpu = common::gpu();
    let with = settings(ShadowMethod::Ours);
    let mut without = with;
    without.penumbra.nearest_caster = false;
    let (reference, widths) = widths_across(&gpu, Lamp::Spot, "pillar, near its foot", &[with, without]);
    let ratios: Vec<f32> = widths
        .iter()
        .map(|w| w.expect("a penumbra") / reference)
        .collect();
    eprintln!(
        "pillar's foot, spot: reference {reference:.4}, ratio with the search {:.3}, without {:.3}",
        ratios[0], ratios[1]
    );
    assert!((ratios[0] - 1.0).abs() <= 0.15, "with the search: {ratios:?}");
    assert!(
        ratios[1] > 1.3,
        "without the search the fattened surface's distance rules: {ratios:?}"
    );
}

/// The one-pass form (the fattened map derived from the shadow map, `Fattening::Dilation`, and
/// the exit map kept by the shadow map's pass, `ExitMapDraw::ShadowMapPass`: what the defaults
/// give from 500,000 caster triangles) at the rectangle light's contact end, a penumbra 0.0128
/// wide: within 15% of the reference, as `ours_matches_the_reference_under_a_rectangle_light`
/// holds the drawn map. Beside the shadow its distance is at most the derived map's least
/// depth's, as the drawn map's is at most the fattened surface's; without that cap the nearest
/// caster in angle was a part of the plate farther up and the width read 1.21x.
#[test]
fn the_one_pass_form_keeps_a_contact_penumbra_under_a_rectangle_light() {
    let gpu = common::gpu();
    let mut one_pass = settings(ShadowMethod::Ours);
    one_pass.penumbra.fattening = penumbra::Fattening::Dilation;
    one_pass.execution.exit_map_draw = penumbra::ExitMapDraw::ShadowMapPass;
    let (reference, widths) = widths_across(&gpu, Lamp::Rect, "plate, contact end", &[one_pass]);
    let ratio = widths[0].expect("a penumbra") / reference;
    eprintln!("plate's contact end, rectangle light, one pass: reference {reference:.4}, ratio {ratio:.3}");
    assert!((ratio - 1.0).abs() <= 0.15, "ratio {ratio:.3}");
}

/// A point light's cube face magnifies what lies off its axis along the radius (by 1 / cos of
/// the angle): PCF's taps, spaced in world units across the light, are mapped into the face
/// with that stretch, not with the face's scale at its axis. With PCF making the whole penumbra
/// (`pcf_variance_share` 1), the plate's far end under a sphere light where the spot stands
/// (its rays 43 degrees off the lower face's axis there) reads within 10% of the reference
/// (0.885x with the axis's scale). The whole truth check under this light is
/// `ours_matches_the_reference_under_a_sphere_light`.
#[test]
fn pcf_taps_follow_a_cube_face_off_its_axis() {
    let gpu = common::gpu();
    let mut pcf_only = settings(ShadowMethod::Ours);
    pcf_only.penumbra.pcf_variance_share = 1.0;
    let (reference, widths) = widths_across(&gpu, Lamp::Sphere, "plate, far end", &[pcf_only]);
    let ratio = widths[0].expect("a penumbra") / reference;
    eprintln!("plate's far end, sphere light, PCF alone: reference {reference:.4}, ratio {ratio:.3}");
    assert!((ratio - 1.0).abs() <= 0.1, "ratio {ratio:.3}");
}

/// The distance map holds the distance to the caster itself, not to its fattened copy: just
/// inside the plate's shadow under the sun, the distance along the light from the plate's lower
/// face to the floor (before, the fatten distance, 0.27 here, came on top: 0.51 against 0.24 at
/// the contact end).
#[test]
fn distances_are_measured_to_the_true_occluder() {
    let gpu = common::gpu();
    let lamp = Lamp::Sun;
    let scene = truth_scene(lamp);
    for edge in edges(lamp).iter().filter(|e| e.name.starts_with("plate")) {
        let hard = lamp.shadow_of(edge.occluder);
        let camera = camera_above(hard, edge.reach * 3.0);
        let (_, renderer) = common::render_frame(&gpu, &scene, &camera, settings(ShadowMethod::Ours), SIZE);
        let (d, channels) = common::read_f32(
            &gpu,
            renderer
                .debug_texture(penumbra::LightTexture::DistanceMap)
                .unwrap(),
        );
        // A quarter of the profile inside the shadow: the ray meets the plate a little further
        // up the slope than the edge point.
        let inside = hard - edge.toward_light * (edge.reach * 0.25);
        let (px, py) = common::project(&camera, SIZE.0, SIZE.1, inside).unwrap();
        let k = ((py * SIZE.0 + px) * channels) as usize;
        let (distance, mask) = penumbra::debug::distance_and_mask(&d[k..k + channels as usize]);
        assert_eq!(mask, 1.0, "{}: not inside the mask", edge.name);
        let along = SUN.length() / -SUN.y;
        let expected = edge.occluder.y * along;
        assert!(
            (distance / expected - 1.0).abs() < 0.1,
            "{}: distance {distance:.4}, the plate lies {expected:.4} away along the light",
            edge.name,
        );
    }
}
