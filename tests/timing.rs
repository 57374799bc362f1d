//! Per-pass timings: with GPU timestamps, and with the submit-and-wait fallback. Both name the
//! passes the frame ran, in order, with positive times; the frame's image is the same.

mod common;

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
            renderer.last_report().unwrap().plan.names(),
            "wall clock: {wall_clock}"
        );
        assert!(
            times
                .iter()
                .all(|t| t.milliseconds > 0.0 && t.milliseconds.is_finite()),
            "{times:?}"
        );
    }
    assert_eq!(images[0], images[1], "timing must not change the frame");
}
