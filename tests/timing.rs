//! Per-pass timings: with GPU timestamps, and with the submit-and-wait fallback. Both name the
//! passes the frame ran, in order, with positive times; the frame's image is the same.

mod common;

use penumbra::timing::PassStage;
use penumbra::{GpuScene, Renderer, ShadowMethod, ShadowSettings, load_scene};

#[test]
fn both_timers_time_every_pass_the_frame_ran() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let settings = ShadowSettings {
        method: ShadowMethod::Ours,
        ..Default::default()
    };
    let mut images = Vec::new();
    for wall_clock in [false, true] {
        let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
        if wall_clock {
            renderer.enable_wall_clock_timing(&gpu.device, &gpu.queue);
        } else {
            assert!(
                renderer.enable_timing(&gpu.device, &gpu.queue),
                "lavapipe has timestamp queries"
            );
        }
        let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
        images.push(penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 160, 120).unwrap());
        let times = renderer.pass_times(&gpu.device).unwrap().unwrap();
        let names: Vec<&str> = times.iter().map(|t| t.pass).collect();
        assert_eq!(
            names,
            renderer.last_report().unwrap().passes,
            "wall clock: {wall_clock}"
        );
        // Each pass is timed with its stage: the maps from the light, the chain over the
        // screen, the renderer's own passes over the scene.
        for t in &times {
            let expected = match t.pass {
                "shadow map" | "fattened shadow map" | "exit map" => PassStage::LightSpace,
                "depth prepass" | "composite" | "forward" => PassStage::Scene,
                _ => PassStage::ScreenSpace,
            };
            assert_eq!(t.stage, expected, "{}", t.pass);
        }
        assert!(
            times
                .iter()
                .all(|t| t.milliseconds > 0.0 && t.milliseconds.is_finite()),
            "{times:?}"
        );
    }
    assert_eq!(images[0], images[1], "timing must not change the frame");
}

/// `Renderer::time_frames` (the benchmark's loop): one entry per timed frame after the
/// warm-up, every pass named, the maps drawn each frame when the light turns; a size with no
/// pixels or past the device's limit is an error naming the size.
#[test]
fn time_frames_times_each_frame_and_refuses_impossible_sizes() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let mut renderer = Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        ShadowSettings::default(),
    )
    .unwrap();
    let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let light = scene.light;
    let mut calls = 0;
    let timed = renderer
        .time_frames(
            &gpu.device,
            &gpu.queue,
            &mut gpu_scene,
            &camera,
            (96, 72),
            2,
            3,
            |s, i| {
                calls += 1;
                s.set_light(light.turned(glam::Quat::from_rotation_y(i as f32 * 0.01)))
            },
        )
        .unwrap();
    assert_eq!(calls, 5, "before_frame runs before every frame, warm-up included");
    assert_eq!((timed.wall_ms.len(), timed.pass_sum_ms.len()), (3, 3));
    for pass in [
        "shadow map",
        "fattened shadow map",
        "distance map",
        "pcf",
        "blur",
        "composite",
    ] {
        let times = timed
            .passes
            .get(pass)
            .unwrap_or_else(|| panic!("{pass} missing: {:?}", timed.passes.keys()));
        assert_eq!(times.len(), 3, "{pass}");
        assert!(times.iter().all(|t| *t > 0.0), "{pass}: {times:?}");
    }
    let limit = gpu.device.limits().max_texture_dimension_2d;
    for size in [(0, 72), (limit + 1, 8)] {
        let error = renderer
            .time_frames(
                &gpu.device,
                &gpu.queue,
                &mut gpu_scene,
                &camera,
                size,
                0,
                1,
                |_, _| Ok(()),
            )
            .unwrap_err()
            .to_string();
        assert!(error.contains("size"), "{size:?}: {error}");
    }
}

/// A frame with `MAX_LIGHTS` lights, every one's chain whole: each pass it ran is timed (the
/// timer once held 32 timestamps, and sixteen lights' last passes and the lit pass went
/// untimed without a word).
#[test]
fn every_pass_of_sixteen_lights_is_timed() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let center = scene.bounds().center();
    let reach = scene.bounds().radius();
    scene.more_lights = (1..penumbra::MAX_LIGHTS)
        .map(|k| {
            let turn = glam::Quat::from_rotation_y((k as f32 * 22.5).to_radians());
            let position = center + turn * glam::Vec3::new(reach, 1.5 * reach, reach);
            penumbra::Light::Spot(penumbra::SpotLight {
                position,
                direction: center - position,
                cone_angle_deg: 45.0,
                radius: 0.02 * reach,
                color: glam::Vec3::ONE,
                intensity: 1.0,
                range: None,
            })
        })
        .collect();
    let settings = ShadowSettings {
        method: ShadowMethod::Ours,
        ..Default::default()
    };
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    assert!(renderer.enable_timing(&gpu.device, &gpu.queue));
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 96, 80).unwrap();
    let times = renderer.pass_times(&gpu.device).unwrap().unwrap();
    let names: Vec<&str> = times.iter().map(|t| t.pass).collect();
    let ran = &renderer.last_report().unwrap().passes;
    assert_eq!(&names, ran);
    // Every light's screen-space chain, and the lit pass last.
    let count = |name: &str| names.iter().filter(|&&n| n == name).count();
    assert_eq!(count("distance map"), penumbra::MAX_LIGHTS, "{names:?}");
    assert!(names.len() > 32, "{} passes", names.len());
    assert_eq!(names.last(), Some(&"composite"), "{names:?}");
}
