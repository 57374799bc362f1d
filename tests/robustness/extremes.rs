//! Numerical stability at the extremes: the same scene at very different scales, extreme sizes
//! and settings, odd geometry, and random settings and light directions (proptest).

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::metrics::measure_visibility;
use penumbra::scene::primitives;
use penumbra::{
    Camera, CascadeSettings, CullMode, DepthFormat, DirectionalLight, ExitFaces, Light, LightFit, Material,
    PcfKernel, PcssSettings, PenumbraSettings, Scene, ShadowMapSettings, ShadowMethod, ShadowSettings,
    SpreadMode, TraditionalSettings, load_scene,
};
use proptest::prelude::*;
use proptest::test_runner::{Config as ProptestConfig, TestRunner};

/// `scene` and `camera` scaled by `s` about the origin: geometry, camera distances and a spot
/// light's position and radius. (A directional light's angle does not scale.)
fn scaled(scene: &Scene, camera: &Camera, s: f32) -> (Scene, Camera) {
    let mut scene = scene.clone();
    for instance in &mut scene.instances {
        instance.transform = Mat4::from_scale(Vec3::splat(s)) * instance.transform;
    }
    if let Light::Spot(spot) = &mut scene.light {
        spot.position *= s;
        spot.radius *= s;
    }
    let camera = Camera {
        eye: camera.eye * s,
        target: camera.target * s,
        near: camera.near * s,
        far: camera.far * s,
        ..*camera
    };
    (scene, camera)
}

/// The teapot scene at 1e-3, 1 and 1e4 world units per unit gives the same picture: every
/// setting in world units is derived from the light (physical spreads) or is in texels, pixels
/// or depth steps.
#[test]
fn scaled_scenes_render_the_same_image() {
    let gpu = common::gpu();
    let base = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = base.view(0).unwrap();
    let (w, h) = (320, 240);
    for method in [ShadowMethod::Ours, ShadowMethod::Traditional, ShadowMethod::Pcss] {
        let settings = ShadowSettings {
            method,
            ..Default::default()
        };
        let reference = common::render(&gpu, &base, &camera, settings, w, h);
        for s in [1e-3f32, 1e4] {
            let (scene, cam) = scaled(&base, &camera, s);
            let image = common::render(&gpu, &scene, &cam, settings, w, h);
            let (mean, map) = penumbra::metrics::flip(&reference, &image).unwrap();
            let file = format!("scale_{}_{s:e}", method.name());
            image
                .save(common::output_dir().join(format!("{file}.png")))
                .unwrap();
            eprintln!("{} at scale {s:e}: mean FLIP {mean:.4}", method.name());
            if mean >= 0.01 {
                map.save(common::output_dir().join(format!("{file}_flip.png")))
                    .unwrap();
            }
            assert!(
                mean < 0.01,
                "{} at scale {s:e}: mean FLIP {mean:.4}",
                method.name()
            );
        }
    }
    // Spreads set by hand in world units do not scale, so the same check sees a difference.
    let manual = ShadowSettings {
        penumbra: penumbra::PenumbraSettings {
            spreads: SpreadMode::Manual {
                fatten_distance: 0.3,
                pcf_spread: 4.0,
                blur_spread: 12.0,
            },
            ..Default::default()
        },
        ..Default::default()
    };
    let reference = common::render(&gpu, &base, &camera, manual, w, h);
    let (scene, cam) = scaled(&base, &camera, 1e-3);
    let image = common::render(&gpu, &scene, &cam, manual, w, h);
    let (mean, _) = penumbra::metrics::flip(&reference, &image).unwrap();
    eprintln!("manual spreads at scale 1e-3: mean FLIP {mean:.4}");
    assert!(
        mean > 0.01,
        "unscaled manual spreads changed nothing ({mean:.4}): the check is blind"
    );
}

/// Renders one frame and checks every intermediate texture the method made (finite values,
/// visibility in [0, 1]) and that the final image is not flat. Returns the image and the
/// (blurred, where there is one) visibility.
fn check_frame(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    settings: ShadowSettings,
    size: (u32, u32),
    what: &str,
) -> (image::RgbaImage, Option<Vec<f32>>) {
    let (image, visibility) = common::finite_frame(gpu, scene, camera, settings, size, what);
    assert_not_flat(&image, what);
    (image, visibility)
}

/// Neither one color nor all dark or all bright.
fn assert_not_flat(image: &image::RgbaImage, what: &str) {
    let first = *image.get_pixel(0, 0);
    assert!(
        image.pixels().any(|p| *p != first),
        "{what}: the frame is one color {first:?}"
    );
    let luma = |p: &image::Rgba<u8>| (p[0] as u32 + p[1] as u32 + p[2] as u32) / 3;
    let (dark, bright) = image
        .pixels()
        .fold((255, 0), |(lo, hi), p| (lo.min(luma(p)), hi.max(luma(p))));
    assert!(
        bright > 40 && dark < 220,
        "{what}: luma only in [{dark}, {bright}]"
    );
}

/// Shares of the visibility texels that are shadowed (< 0.1) and lit (> 0.9).
fn shadowed_and_lit(visibility: &[f32]) -> (f32, f32) {
    let n = visibility.len().max(1) as f32;
    (
        visibility.iter().filter(|v| **v < 0.1).count() as f32 / n,
        visibility.iter().filter(|v| **v > 0.9).count() as f32 / n,
    )
}

/// Shadow maps from 256 to 8192 texels a side, each depth format: no NaN, the teapot's shadow
/// is there.
#[test]
fn shadow_map_sizes_from_256_to_8192() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    for resolution in [256, 1024, 4096, 8192] {
        for format in [DepthFormat::Depth16, DepthFormat::Depth32] {
            let mut settings = ShadowSettings::default();
            settings.shadow_map.resolution = resolution;
            settings.shadow_map.depth_format = format;
            if resolution > penumbra::settings::MAX_CASCADE_RESOLUTION {
                // Four 8192-texel cascades are refused, naming the setting; one map is not.
                let refused = settings.validate(None).unwrap_err().to_string();
                assert!(refused.contains("shadow_map.resolution"), "{refused}");
                settings.shadow_map.cascades.count = 1;
            }
            let what = format!("{resolution} texels, {format:?}");
            let (_, visibility) = check_frame(&gpu, &scene, &camera, settings, (200, 150), &what);
            let (shadowed, lit) = shadowed_and_lit(&visibility.unwrap());
            eprintln!(
                "{what}: {:.1}% shadowed, {:.1}% lit",
                shadowed * 100.0,
                lit * 100.0
            );
            assert!(
                shadowed > 0.01 && lit > 0.3,
                "{what}: {shadowed} shadowed, {lit} lit"
            );
        }
    }
}

/// A unit cube standing on a floor and another floating 60 units above it, under a sun that
/// throws their shadows toward +x (the floating cube's near x = 5).
fn standing_and_floating(degrees: f32) -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_mesh(primitives::plane(40.0, 1.0));
    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    let gray = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let red = scene.add_material(Material::colored("cube", [0.8, 0.3, 0.2]));
    scene.add_instance(floor, gray, Mat4::IDENTITY).caster = false;
    scene.add_instance(cube, red, Mat4::from_translation(Vec3::new(-2.0, 0.5, 0.0)));
    scene.add_instance(cube, red, Mat4::from_translation(Vec3::new(-25.0, 60.5, 0.0)));
    scene.light = Light::Directional(DirectionalLight {
        direction: Vec3::new(0.5, -1.0, 0.0),
        angular_diameter_deg: degrees,
        color: Vec3::ONE,
        intensity: 1.0,
    });
    scene
}

/// Lights from a point to nearly a hemisphere, spot lights as wide as the scene, camera
/// near/far ratios of 1e6, and casters touching the floor or floating 60 units above it.
#[test]
fn extreme_light_sizes_depth_ranges_and_caster_heights() {
    let gpu = common::gpu();
    let methods = [
        ShadowMethod::Ours,
        ShadowMethod::OursFast,
        ShadowMethod::Traditional,
        ShadowMethod::Pcss,
    ];
    let top = Camera::look_at(Vec3::new(0.0, 12.0, 9.0), Vec3::new(0.0, 0.0, 0.0));
    for degrees in [0.0, 0.01, 3.0, 20.0, 89.9] {
        for method in methods {
            let settings = ShadowSettings {
                method,
                ..Default::default()
            };
            let what = format!("{} under a {degrees} degree sun", method.name());
            let scene = standing_and_floating(degrees);
            let (_, visibility) = check_frame(&gpu, &scene, &top, settings, (160, 120), &what);
            // Beside the standing cube's base the floor is in shadow. Checked up to 20 degrees
            // (PCSS: 0.01): PCSS's 16 blocker taps spread over a search region as wide as the
            // light's size times the whole depth range (60 units here), so it loses this
            // contact shadow. (Ours lost it above 3 degrees while its distance was taken to
            // the fattened occluder.)
            let checked = if method == ShadowMethod::Pcss { 0.01 } else { 20.0 };
            if degrees <= checked {
                let v = measure_visibility(&gpu, &scene, &top, settings, (160, 120)).unwrap();
                let (x, y) = common::project(&top, 160, 120, Vec3::new(-1.3, 0.0, 0.0)).unwrap();
                let contact = v.visibility[(y * 160 + x) as usize];
                // (The baseline's fixed screen-space blur reaches 0.5 units here.)
                let limit = if method == ShadowMethod::Traditional {
                    0.6
                } else {
                    0.25
                };
                assert!(
                    contact.is_some_and(|c| c < limit),
                    "{what}: visibility {contact:?} at the standing cube's base"
                );
            }
            // At size 0 the renderer shades hard shadows in its forward pass: no visibility.
            let forward = penumbra::PassPlan::new(&settings, &scene.light).forward;
            assert!(visibility.is_some() || forward, "{what}: no visibility texture");
        }
    }
    // The standing cube alone: the depth range is short, so the fattened casters are close to
    // the real ones and the contact shadow survives wide lights. (The fattened casters reach
    // beyond the casters' own depth range; a fit that forgot this clipped them and lost the
    // whole shadow of ours at 5.4 degrees.)
    for degrees in [1.0, 5.4, 10.0] {
        let mut scene = standing_and_floating(degrees);
        scene.instances.truncate(2);
        for method in [ShadowMethod::Ours, ShadowMethod::OursFast, ShadowMethod::Pcss] {
            let settings = ShadowSettings {
                method,
                ..Default::default()
            };
            let v = measure_visibility(&gpu, &scene, &top, settings, (160, 120)).unwrap();
            let (x, y) = common::project(&top, 160, 120, Vec3::new(-1.3, 0.0, 0.0)).unwrap();
            let contact = v.visibility[(y * 160 + x) as usize];
            assert!(
                contact.is_some_and(|c| c < 0.25),
                "{} under a {degrees} degree sun, standing cube alone: visibility {contact:?} at its base",
                method.name()
            );
        }
    }
    // A spot light whose radius is larger than its height.
    let mut spot_scene = standing_and_floating(1.0);
    for radius in [0.0, 30.0] {
        spot_scene.light = Light::Spot(penumbra::SpotLight {
            position: Vec3::new(0.0, 20.0, 0.0),
            direction: Vec3::NEG_Y,
            cone_angle_deg: 50.0,
            radius,
            color: Vec3::ONE,
            intensity: 3.0,
            range: None,
        });
        for method in methods {
            let settings = ShadowSettings {
                method,
                ..Default::default()
            };
            let what = format!("{} under a spot light of radius {radius}", method.name());
            check_frame(&gpu, &spot_scene, &top, settings, (160, 120), &what);
        }
    }
    // Camera near/far ratios of 1e6, near the eye and far out: the shadows stay where they
    // are with an ordinary range.
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = teapot.view(0).unwrap();
    let ordinary = measure_visibility(&gpu, &teapot, &camera, ShadowSettings::default(), (200, 150)).unwrap();
    for (near, far) in [(1e-4, 100.0), (1.0, 1e6)] {
        let wide = Camera { near, far, ..camera };
        for method in methods {
            let settings = ShadowSettings {
                method,
                ..Default::default()
            };
            let what = format!("{} with near {near} far {far}", method.name());
            check_frame(&gpu, &teapot, &wide, settings, (200, 150), &what);
        }
        let v = measure_visibility(&gpu, &teapot, &wide, ShadowSettings::default(), (200, 150)).unwrap();
        let (mut both, mut differ) = (0, 0);
        for (a, b) in ordinary.visibility.iter().zip(&v.visibility) {
            if let (Some(a), Some(b)) = (a, b) {
                both += 1;
                if (a - b).abs() > 0.2 {
                    differ += 1;
                }
            }
        }
        eprintln!(
            "near {near} far {far}: {differ} of {both} pixels differ by more than 0.2 from near 0.05 far 200"
        );
        assert!(both > 15_000, "{both} pixels compared");
        assert!(
            (differ as f32) < both as f32 * 0.005,
            "near {near} far {far}: {differ} of {both} pixels differ"
        );
    }
}

/// A mesh with degenerate triangles (a repeated index, three collinear points), duplicated
/// vertices and NaN and zero normals, a one-triangle mesh, an empty scene and a camera inside
/// a caster all render with finite values everywhere; a NaN position is rejected by name.
#[test]
fn odd_geometry_renders_or_is_rejected() {
    let gpu = common::gpu();
    let methods = [
        ShadowMethod::Ours,
        ShadowMethod::Traditional,
        ShadowMethod::Pcss,
        ShadowMethod::Hardware2x2,
    ];
    let top = Camera::look_at(Vec3::new(0.0, 8.0, 6.0), Vec3::ZERO);

    // Two quads' worth of a tent, every vertex listed twice, plus a repeated-index triangle and
    // a collinear one; normals: some NaN, some zero.
    let p = [
        Vec3::new(-1.0, 0.0, -1.0),
        Vec3::new(1.0, 0.0, -1.0),
        Vec3::new(0.0, 1.5, 0.0),
        Vec3::new(-1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
    ];
    let mut positions: Vec<Vec3> = p.iter().chain(p.iter()).copied().collect();
    positions.extend([Vec3::ZERO, Vec3::new(0.5, 0.5, 0.5), Vec3::ONE]);
    let mut normals = vec![Vec3::Y; positions.len()];
    normals[0] = Vec3::NAN;
    normals[3] = Vec3::ZERO;
    normals[7] = Vec3::new(f32::INFINITY, 0.0, 0.0);
    let indices = vec![0, 2, 1, 3, 4, 7, 5, 8, 6, 1, 2, 4, 0, 0, 2, 10, 11, 12];
    let (tent, repairs) =
        penumbra::Mesh::new_with_report("tent", positions, Some(normals), None, indices).unwrap();
    assert_eq!(repairs.repaired_normals, 3, "{repairs:?}");
    assert!(
        tent.normals
            .iter()
            .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-3)
    );

    let mut scene = standing_and_floating(1.0);
    let mesh = scene.add_mesh(tent);
    let material = scene.add_material(Material::colored("tent", [0.3, 0.6, 0.3]));
    scene.add_instance(mesh, material, Mat4::from_translation(Vec3::new(2.0, 0.0, 1.0)));
    let one = scene.add_mesh(
        penumbra::Mesh::new(
            "one triangle",
            vec![
                Vec3::new(-1.0, 1.0, 2.0),
                Vec3::new(0.0, 1.0, 2.0),
                Vec3::new(-0.5, 1.0, 3.0),
            ],
            None,
            None,
            vec![0, 1, 2],
        )
        .unwrap(),
    );
    scene.add_instance(one, material, Mat4::IDENTITY);
    for method in methods {
        let settings = ShadowSettings {
            method,
            ..Default::default()
        };
        check_frame(
            &gpu,
            &scene,
            &top,
            settings,
            (160, 120),
            &format!("{} with odd meshes", method.name()),
        );
        // From inside the standing cube (its faces are drawn from both sides).
        let inside = Camera::look_at(Vec3::new(-2.0, 0.5, 0.0), Vec3::new(3.0, 0.0, 0.0));
        common::finite_frame(
            &gpu,
            &scene,
            &inside,
            settings,
            (160, 120),
            &format!("{} inside a caster", method.name()),
        );
        // An empty scene: only the background.
        let (image, _) = common::finite_frame(
            &gpu,
            &Scene::default(),
            &top,
            settings,
            (64, 48),
            &format!("{} empty scene", method.name()),
        );
        let first = *image.get_pixel(0, 0);
        assert!(
            image.pixels().all(|p| *p == first),
            "{}: an empty scene drew something",
            method.name()
        );
    }

    let err = penumbra::Mesh::new(
        "broken",
        vec![Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 0.0), Vec3::ONE],
        None,
        None,
        vec![0, 1, 2],
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("broken") && err.contains("not finite"), "{err}");
}

fn property_cases(default: u32) -> u32 {
    std::env::var("PENUMBRA_PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn runner(cases: u32) -> TestRunner {
    TestRunner::new(ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    })
}

fn kernel() -> impl Strategy<Value = PcfKernel> {
    prop::sample::select(vec![PcfKernel::Pcf3x3, PcfKernel::Pcf4x4, PcfKernel::Pcf5x5])
}

fn odd_taps() -> impl Strategy<Value = u32> {
    (0u32..16).prop_map(|k| 2 * k + 1)
}

/// Any settings inside their documented ranges.
fn any_settings() -> impl Strategy<Value = ShadowSettings> {
    let shadow_map = (
        prop::sample::select(vec![256u32, 512, 1024, 2048]),
        prop::sample::select(vec![
            DepthFormat::Depth16,
            DepthFormat::Depth24,
            DepthFormat::Depth32,
        ]),
        (0i32..64, 0.0f32..=16.0, 0.0f32..=8.0),
        prop::sample::select(vec![CullMode::None, CullMode::Back, CullMode::Front]),
        prop_oneof![
            Just(LightFit::Scene),
            (0.0f32..60.0).prop_map(|max_distance| LightFit::CameraFrustum { max_distance })
        ],
        (any::<bool>(), 1u32..=4, 0.0f32..=1.0, 0.0f32..=0.5),
        (any::<bool>(), any::<bool>()),
    )
        .prop_map(
            |(
                resolution,
                depth_format,
                (constant_bias, slope_bias, normal_offset),
                cull_mode,
                fit,
                (snap, count, split, blend),
                (clear_by_copy, exit_faces_by_fragment),
            )| {
                ShadowMapSettings {
                    resolution,
                    depth_format,
                    constant_bias,
                    slope_bias,
                    normal_offset,
                    cull_mode,
                    fit,
                    snap_to_texels: snap,
                    cascades: CascadeSettings {
                        count,
                        split,
                        blend,
                        ..Default::default()
                    },
                    clear_by_copy,
                    exit_faces: if exit_faces_by_fragment {
                        ExitFaces::Fragment
                    } else {
                        ExitFaces::Winding
                    },
                }
            },
        );
    let spreads = prop_oneof![
        Just(SpreadMode::Physical),
        (0.0f32..5.0, 0.0f32..50.0, 0.0f32..50.0).prop_map(|(fatten_distance, pcf_spread, blur_spread)| {
            SpreadMode::Manual {
                fatten_distance,
                pcf_spread,
                blur_spread,
            }
        })
    ];
    let penumbra = (
        spreads,
        kernel(),
        0.0f32..=16.0,
        0.0f32..=1.0,
        (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>()),
        odd_taps(),
        0.0f32..=1.0,
    )
        .prop_map(
            |(
                spreads,
                pcf_kernel,
                pcf_base_spacing,
                pcf_variance_share,
                (rotate, mask, aware, nearest),
                blur_taps,
                indirect,
            )| {
                PenumbraSettings {
                    spreads,
                    pcf_kernel,
                    pcf_base_spacing,
                    pcf_variance_share,
                    rotate_taps: rotate,
                    mask_early_out: mask,
                    nearest_caster: nearest,
                    // Either way (the strategy has no boolean to spare).
                    tiles: if rotate {
                        penumbra::TileClassification::On
                    } else {
                        penumbra::TileClassification::Off
                    },
                    skip_tiles_facing_away: !mask,
                    // Either way, as the tiles turned away.
                    skip_umbra_tiles: mask,
                    reduced_resolution: rotate,
                    blur_taps,
                    depth_aware_blur: aware,
                    // Draws or compute passes (reduced resolution is draws either way).
                    fragment_passes: nearest && mask,
                    indirect_weight: indirect,
                    // Either way: coarser maps where the penumbrae allow, or never.
                    map_resolution: if aware {
                        penumbra::MapResolution::FromPenumbra {
                            narrowest_texels: 4.0,
                        }
                    } else {
                        penumbra::MapResolution::Configured
                    },
                    // Either way: the fattened map drawn or derived, with the exit map or
                    // without.
                    fattening: if mask != aware {
                        penumbra::Fattening::Dilation
                    } else {
                        penumbra::Fattening::Geometry
                    },
                    exit_map: rotate || !nearest,
                }
            },
        );
    let traditional = (kernel(), 0.0f32..=16.0, odd_taps(), 0.0f32..=16.0).prop_map(
        |(pcf_kernel, pcf_spacing, blur_taps, blur_step)| TraditionalSettings {
            pcf_kernel,
            pcf_spacing,
            blur_taps,
            blur_step,
        },
    );
    (
        prop::sample::select(ShadowMethod::REAL_TIME.to_vec()),
        shadow_map,
        penumbra,
        traditional,
        (1u32..=64, 1u32..=64),
    )
        .prop_map(
            |(method, shadow_map, penumbra, traditional, (blocker_samples, pcf_samples))| ShadowSettings {
                method,
                shadow_map,
                penumbra,
                traditional,
                pcss: PcssSettings {
                    blocker_samples,
                    pcf_samples,
                },
                ..Default::default()
            },
        )
}

/// A sun from any direction at least 2 degrees above the horizon, 0 to 30 degrees wide, or a
/// spot light above the scene.
fn any_light() -> impl Strategy<Value = Light> {
    let sun = (0.0f32..360.0, 2.0f32..90.0, 0.0f32..30.0).prop_map(|(azimuth, elevation, degrees)| {
        let (a, e) = (azimuth.to_radians(), elevation.to_radians());
        Light::Directional(DirectionalLight {
            direction: -Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin()),
            angular_diameter_deg: degrees,
            color: Vec3::ONE,
            intensity: 1.0,
        })
    });
    let spot =
        (-5.0f32..5.0, 4.0f32..30.0, 10.0f32..80.0, 0.0f32..3.0).prop_map(|(x, height, cone, radius)| {
            Light::Spot(penumbra::SpotLight {
                position: Vec3::new(x, height, 2.0),
                direction: Vec3::new(-x * 0.1, -1.0, -0.1),
                cone_angle_deg: cone,
                radius,
                color: Vec3::ONE,
                intensity: 2.0,
                range: None,
            })
        });
    prop_oneof![3 => sun, 1 => spot]
}

/// Random settings (every field inside its range) and random lights: the settings validate,
/// and every intermediate value is finite, every visibility in [0, 1].
#[test]
fn random_settings_and_lights_keep_every_value_finite() {
    let gpu = common::gpu();
    let top = Camera::look_at(Vec3::new(0.0, 8.0, 6.0), Vec3::new(0.0, 0.5, 0.0));
    let mut runner = runner(property_cases(24));
    runner
        .run(&(any_settings(), any_light()), |(settings, light)| {
            prop_assert!(settings.validate(None).is_ok(), "{:?}", settings.validate(None));
            let mut scene = standing_and_floating(1.0);
            scene.light = light;
            let what = format!("{settings:?} under {light:?}");
            common::finite_frame(&gpu, &scene, &top, settings, (96, 72), &what);
            Ok(())
        })
        .unwrap();
}

/// Pixels in a penumbra (visibility strictly between 0.05 and 0.95).
fn penumbra_pixels(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    camera: &Camera,
    method: ShadowMethod,
) -> usize {
    let settings = ShadowSettings {
        method,
        ..Default::default()
    };
    let v = measure_visibility(gpu, scene, camera, settings, (160, 120)).unwrap();
    v.visibility
        .iter()
        .flatten()
        .filter(|v| **v > 0.05 && **v < 0.95)
        .count()
}

/// A wider light never narrows the penumbrae: for random sun directions and sizes, doubling the
/// sun's angle gives at least as many penumbra pixels around a cube standing on the floor (5%
/// slack for noise), for ours and PCSS.
#[test]
fn penumbrae_grow_with_the_light() {
    let gpu = common::gpu();
    let top = Camera::look_at(Vec3::new(0.0, 8.0, 6.0), Vec3::new(0.0, 0.5, 0.0));
    let mut runner = runner(property_cases(8));
    runner
        .run(
            &(0.0f32..360.0, 30.0f32..80.0, 0.3f32..4.0),
            |(azimuth, elevation, degrees)| {
                let (a, e) = (azimuth.to_radians(), elevation.to_radians());
                let direction = -Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin());
                let mut counts = Vec::new();
                for method in [ShadowMethod::Ours, ShadowMethod::Pcss] {
                    let at = |size: f32| {
                        let mut scene = standing_and_floating(size);
                        // Only the standing cube: a floating caster's shadow fades out of the
                        // count as the light widens (it has no umbra left), as it should.
                        scene.instances.truncate(2);
                        if let Light::Directional(l) = &mut scene.light {
                            l.direction = direction;
                        }
                        penumbra_pixels(&gpu, &scene, &top, method)
                    };
                    let (narrow, wide) = (at(degrees), at(degrees * 2.0));
                    counts.push((method.name(), narrow, wide));
                    prop_assert!(
                        wide as f32 >= narrow as f32 * 0.95 - 3.0,
                        "{}: {narrow} penumbra pixels at {degrees} degrees, {wide} at twice that",
                        method.name()
                    );
                }
                eprintln!("{degrees:.2} degrees: {counts:?}");
                Ok(())
            },
        )
        .unwrap();
}
