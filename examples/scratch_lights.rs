// SCRATCH, not committed.
use penumbra::*;
fn sized_light(scene: &Scene, kind: &str, k: usize, apart_deg: f32, size: f32) -> Light {
    let center = scene.bounds().center();
    let reach = scene.bounds().radius().max(1e-3);
    let turn = glam::Quat::from_rotation_y((k as f32 * apart_deg).to_radians());
    match (kind, scene.light) {
        ("sun", Light::Directional(l)) => Light::Directional(DirectionalLight {
            direction: turn * l.direction,
            angular_diameter_deg: l.angular_diameter_deg * size,
            ..l
        }),
        ("spot", _) => {
            let position = center + turn * glam::Vec3::new(reach, 1.5 * reach, reach);
            Light::Spot(SpotLight {
                position,
                direction: center - position,
                cone_angle_deg: 45.0,
                radius: 0.02 * reach * size,
                color: glam::Vec3::ONE,
                intensity: 1.0,
                range: None,
            })
        }
        ("point", _) => Light::Point(PointLight {
            position: center + turn * glam::Vec3::new(0.6 * reach, 1.2 * reach, 0.6 * reach),
            radius: 0.02 * reach * size,
            color: glam::Vec3::ONE,
            intensity: 1.0,
            range: None,
        }),
        (_, other) => other,
    }
}
fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let kind = args.get(1).map(|s| s.as_str()).unwrap_or("spot");
    let gpu = HeadlessGpu::new()?;
    let base = load_scene(std::path::Path::new("assets/scenes/teapot.ron"))?;
    let camera = base.view(0)?;
    // each light alone: k, size
    let umbra = args.get(2).is_some();
    for (k, size) in [
        (0usize, 1.0f32),
        (0, 0.25),
        (1, 1.0),
        (1, 0.25),
        (2, 0.25),
        (3, 0.25),
    ] {
        let mut scene = base.clone();
        scene.light = sized_light(&base, kind, k, 90.0, size);
        scene.more_lights = vec![];
        let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
        settings.penumbra.skip_umbra_tiles = umbra;
        let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings)?;
        let mut gs = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
        let timed = renderer.time_frames(
            &gpu.device,
            &gpu.queue,
            &mut gs,
            &camera,
            (1280, 1024),
            2,
            7,
            |_, _| Ok(()),
        )?;
        let ms = timed.pass_medians();
        let p = |n: &str| ms.get(n).copied().unwrap_or(0.0);
        let rep = renderer.last_report().unwrap();
        let tiles = debug::tile_share(&gpu.device, &gpu.queue, &renderer)?;
        let away = debug::facing_away_share(&gpu.device, &gpu.queue, &renderer)?;
        let um = debug::umbra_share(&gpu.device, &gpu.queue, &renderer)?;
        println!("  tile share {tiles:?} facing away {away:?} umbra {um:?}");
        println!(
            "{kind} k={k} size x{size}: dm {:.2} pcf {:.2} blur {:.2} sum {:.2} ms; tiles {} of {}",
            p("distance map"),
            p("pcf"),
            p("blur"),
            p("distance map") + p("pcf") + p("blur"),
            rep.light.tiles_rendered,
            (1280 / 16) * (1024 / 16)
        );
    }
    Ok(())
}
