//! `cargo bench`: frame time of every shadow method on the project's scenes, from every
//! viewpoint, at 800x600 and 1280x1024, measured in one run so the methods can be compared as
//! ratios. Frames are timed by submitting and waiting for the GPU (wall clock), after warm-up.
//!
//! `PENUMBRA_BENCH=quick` measures one viewpoint per scene with fewer frames.

use std::time::Instant;

use penumbra::{GpuScene, HeadlessGpu, Renderer, ShadowMethod, ShadowSettings};

/// A configuration's name and the median frame times (ms) of ours, traditional and pcss.
type Run = (String, f64, f64, f64);

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> anyhow::Result<()> {
    let quick = std::env::var("PENUMBRA_BENCH").is_ok_and(|v| v == "quick");
    let (warmup, frames, views) = if quick { (2, 5, 1) } else { (5, 30, 3) };
    let gpu = HeadlessGpu::new()?;
    println!(
        "penumbra bench on {} ({} mode)",
        gpu.describe(),
        if quick { "quick" } else { "full" }
    );
    println!(
        "{:<10} {:>4} {:>10} {:>8} {:>10} {:>7}",
        "scene", "view", "size", "method", "median ms", "fps"
    );
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    // One row per configuration: its name and the median frame times of ours, traditional, pcss.
    let mut runs: Vec<Run> = Vec::new();
    for name in ["teapot", "character"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/scenes/{name}.ron"));
        let scene = penumbra::load_scene(&path)?;
        for (width, height) in [(800u32, 600u32), (1280, 1024)] {
            let target = gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("bench target"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            });
            let view = target.create_view(&Default::default());
            for v in 0..views {
                let camera = scene.view(v)?;
                let mut ms_of = std::collections::HashMap::new();
                for method in ShadowMethod::REAL_TIME {
                    let settings = ShadowSettings {
                        method,
                        ..Default::default()
                    };
                    let mut renderer = Renderer::new(&gpu.device, format, settings)?;
                    let timed = renderer.enable_timing(&gpu.device, &gpu.queue);
                    let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
                    renderer.resize(&gpu.device, width, height);
                    let mut times = Vec::new();
                    let mut pass_ms: std::collections::BTreeMap<&'static str, Vec<f64>> = Default::default();
                    for i in 0..warmup + frames {
                        // Nudge the light so every frame renders every pass, shadow maps included.
                        gpu_scene.set_light(nudged(&scene.light, i))?;
                        let start = Instant::now();
                        let mut encoder = gpu.device.create_command_encoder(&Default::default());
                        renderer.render(&gpu.queue, &mut encoder, &gpu_scene, &camera, &view);
                        gpu.queue.submit([encoder.finish()]);
                        gpu.device.poll(wgpu::PollType::Wait {
                            submission_index: None,
                            timeout: None,
                        })?;
                        if i >= warmup {
                            times.push(start.elapsed().as_secs_f64() * 1e3);
                            if let Some(passes) = renderer.pass_times(&gpu.device) {
                                for p in passes? {
                                    pass_ms.entry(p.pass).or_default().push(p.milliseconds);
                                }
                            }
                        }
                    }
                    let ms = median(times);
                    let passes = if timed {
                        pass_ms
                            .into_iter()
                            .map(|(pass, v)| format!("{pass} {:.2}", median(v)))
                            .collect::<Vec<_>>()
                            .join(", ")
                    } else {
                        "no timestamp queries on this device".to_string()
                    };
                    println!(
                        "{name:<10} {v:>4} {:>10} {:>11} {ms:>10.2} {:>7.1}   {passes}",
                        format!("{width}x{height}"),
                        method.name(),
                        1e3 / ms
                    );
                    ms_of.insert(method, ms);
                }
                runs.push((
                    format!("{name} view {v} {width}x{height}"),
                    ms_of[&ShadowMethod::Ours],
                    ms_of[&ShadowMethod::Traditional],
                    ms_of[&ShadowMethod::Pcss],
                ));
            }
        }
    }
    println!();
    println!(
        "{:<32} {:>18} {:>12}",
        "configuration", "ours/traditional", "ours/pcss"
    );
    for (what, ours, traditional, pcss) in &runs {
        println!("{what:<32} {:>18.3} {:>12.3}", ours / traditional, ours / pcss);
    }
    let mean = |f: &dyn Fn(&Run) -> f64| runs.iter().map(f).sum::<f64>() / runs.len() as f64;
    println!(
        "mean frame-time ratio: ours/traditional {:.3}, ours/pcss {:.3} over {} configurations (frame times; \
         the light moves a little every frame, so every pass runs every frame)",
        mean(&|r| r.1 / r.2),
        mean(&|r| r.1 / r.3),
        runs.len()
    );
    Ok(())
}

/// `light` turned by a hundredth of a degree per frame, so the shadow maps must be re-rendered.
fn nudged(light: &penumbra::Light, frame: usize) -> penumbra::Light {
    let turn = glam::Quat::from_rotation_y((frame as f32 * 0.01).to_radians());
    match *light {
        penumbra::Light::Directional(l) => penumbra::Light::Directional(penumbra::DirectionalLight {
            direction: turn * l.direction,
            ..l
        }),
        penumbra::Light::Spot(l) => penumbra::Light::Spot(penumbra::SpotLight {
            direction: turn * l.direction,
            ..l
        }),
    }
}
