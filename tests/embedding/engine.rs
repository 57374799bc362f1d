//! The engine example (`examples/engine.rs`): its own meshes, camera, depth and lit shader,
//! with penumbra's shadows for two lights through the public embedding API.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use glam::{Mat4, Vec3, Vec4};
use penumbra::{Camera, GpuScene, Instance, Light, Material, Mesh, Renderer, Scene, ShadowSettings};

const SIZE: (u32, u32) = (320, 240);

#[derive(serde::Deserialize)]
struct Description {
    eye: Vec3,
    target: Vec3,
    fov_y_deg: f32,
    near: f32,
    far: f32,
    lights: Vec<Light>,
    model: Option<PathBuf>,
    model_transform: Mat4,
    floor_size: f32,
}

struct Run {
    frame: image::RgbaImage,
    /// Each light's visibility, row-major.
    layers: Vec<Vec<f32>>,
    description: Description,
}

fn model() -> PathBuf {
    common::models().join("spot.obj")
}

fn run_engine(name: &str, frames: u32) -> Run {
    let dir = common::scratch_dir(&format!("engine-{name}"));
    let out = dir.join("frame.png");
    let output = Command::new(common::example_exe("engine"))
        .arg("--model")
        .arg(model())
        .args([
            "--frames",
            &frames.to_string(),
            "--size",
            &format!("{}x{}", SIZE.0, SIZE.1),
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "engine example failed:\n{stderr}");
    let layers = (0..2)
        .map(|k| {
            let image = image::open(out.with_extension(format!("light{k}.png")))
                .unwrap()
                .to_luma16();
            assert_eq!(image.dimensions(), SIZE);
            image.pixels().map(|p| p[0] as f32 / 65535.0).collect()
        })
        .collect();
    Run {
        frame: image::open(&out).unwrap().to_rgba8(),
        layers,
        description: serde_json::from_str(&std::fs::read_to_string(out.with_extension("json")).unwrap())
            .unwrap(),
    }
}

/// The model's parts merged in model space, as the example builds them.
fn model_mesh(path: &Path) -> Mesh {
    let model = penumbra::load_model(path).unwrap();
    let parts: Vec<Mesh> = model
        .parts
        .iter()
        .map(|p| model.meshes[p.mesh].transformed(&p.transform).unwrap())
        .collect();
    Mesh::merge("model", &parts).unwrap()
}

fn camera(d: &Description) -> Camera {
    Camera {
        eye: d.eye,
        target: d.target,
        up: Vec3::Y,
        fov_y_deg: d.fov_y_deg,
        near: d.near,
        far: d.far,
    }
}

/// The pixel where world point `p` lands.
fn pixel_of(d: &Description, p: Vec3) -> (u32, u32) {
    let view_proj = camera(d).view_projection(SIZE.0 as f32 / SIZE.1 as f32);
    let clip = view_proj * Vec4::new(p.x, p.y, p.z, 1.0);
    let ndc = clip.truncate() / clip.w;
    assert!(
        ndc.x.abs() < 0.95 && ndc.y.abs() < 0.95,
        "{p} is not well inside the frame"
    );
    (
        ((ndc.x * 0.5 + 0.5) * SIZE.0 as f32) as u32,
        ((0.5 - ndc.y * 0.5) * SIZE.1 as f32) as u32,
    )
}

/// Where the model's centre throws its shadow on the floor (y = 0) under `light`.
fn shadow_of_centre(d: &Description, light: &Light) -> Vec3 {
    let centre = d
        .model_transform
        .transform_point3(model_mesh(&model()).bounds.center());
    match light {
        Light::Directional(sun) => centre + sun.direction * (-centre.y / sun.direction.y),
        _ => {
            let position = light.position().unwrap();
            position + (centre - position) * (position.y / (position.y - centre.y))
        }
    }
}

fn at(layer: &[f32], (x, y): (u32, u32)) -> f32 {
    layer[(y * SIZE.0 + x) as usize]
}

/// Mean visibility in a 5x5 block around a pixel.
fn around(layer: &[f32], (x, y): (u32, u32)) -> f32 {
    let mut sum = 0.0;
    for dy in -2i32..=2 {
        for dx in -2i32..=2 {
            sum += at(layer, ((x as i32 + dx) as u32, (y as i32 + dy) as u32));
        }
    }
    sum / 25.0
}

/// Centroid (x) of the pixels a layer shadows below 0.5.
fn shadow_centroid_x(layer: &[f32]) -> f32 {
    let (mut sum, mut count) = (0.0, 0);
    for (i, v) in layer.iter().enumerate() {
        if *v < 0.5 {
            sum += (i as u32 % SIZE.0) as f32;
            count += 1;
        }
    }
    assert!(count > 50, "only {count} shadowed pixels");
    sum / count as f32
}

#[test]
fn each_light_shadows_where_it_must_and_the_moving_mesh_moves_its_shadows() {
    let first = run_engine("first", 1);
    let last = run_engine("last", 8);
    for run in [&first, &last] {
        let d = &run.description;
        for (k, light) in d.lights.iter().enumerate() {
            let layer = &run.layers[k];
            let shadow = pixel_of(d, shadow_of_centre(d, light));
            let dark = around(layer, shadow);
            assert!(
                dark < 0.35,
                "light {k}: visibility {dark} where the model's centre casts its shadow"
            );
            // The open floor in front sees both lights.
            for corner in [Vec3::new(-1.5, 0.0, 1.8), Vec3::new(1.5, 0.0, 1.8)] {
                let lit = around(layer, pixel_of(d, corner));
                assert!(
                    lit > 0.95,
                    "light {k}: visibility {lit} on the open floor at {corner}"
                );
            }
            let shadowed = layer.iter().filter(|v| **v < 0.5).count() as f32 / layer.len() as f32;
            assert!(
                (0.002..0.3).contains(&shadowed),
                "light {k}: {shadowed} of the frame shadowed"
            );
        }
    }
    // The lit frame follows the visibility: where the sun's shadow fell in the first run, the
    // moved model no longer shadows it, and the engine's frame is brighter there.
    let luminance = |run: &Run, (x, y): (u32, u32)| {
        let p = run.frame.get_pixel(x, y);
        (p[0] as f32 + p[1] as f32 + p[2] as f32) / 3.0
    };
    let d = &first.description;
    let p = pixel_of(d, shadow_of_centre(d, &d.lights[0]));
    assert!(at(&first.layers[0], p) < 0.2 && at(&last.layers[0], p) > 0.95);
    // (The spot may light it more in the last run, never less: both terms brighten the frame.)
    let (spot_before, spot_after) = (at(&first.layers[1], p), at(&last.layers[1], p));
    assert!(
        spot_after > spot_before - 0.05,
        "the spot's shadow moved onto it: {spot_before} -> {spot_after}"
    );
    let (before, after) = (luminance(&first, p), luminance(&last, p));
    assert!(
        after > before + 20.0,
        "frame at the sun's first shadow: {before} -> {after}"
    );
    // The model moved +1.75 along x between the runs: both shadows follow it.
    for k in 0..2 {
        let (a, b) = (
            shadow_centroid_x(&first.layers[k]),
            shadow_centroid_x(&last.layers[k]),
        );
        assert!(b > a + 20.0, "light {k}: shadow centroid x {a} -> {b} px");
    }
}

#[test]
fn the_engine_path_and_the_renderer_path_give_the_same_visibility() {
    let run = run_engine("compare", 3);
    let d = &run.description;
    assert_eq!(d.model.as_deref(), Some(model().as_path()));
    let gpu = common::gpu();
    for (k, light) in d.lights.iter().enumerate() {
        let mut scene = Scene {
            light: *light,
            ..Default::default()
        };
        let material = scene.add_material(Material::default());
        let model_mesh = scene.add_mesh(model_mesh(&model()));
        let floor = scene.add_mesh(penumbra::scene::primitives::plane(d.floor_size, 1.0));
        scene.instances.push(Instance {
            mesh: model_mesh,
            material,
            transform: d.model_transform,
            caster: true,
            receiver: true,
        });
        scene.instances.push(Instance {
            mesh: floor,
            material,
            transform: Mat4::IDENTITY,
            caster: false,
            receiver: true,
        });
        let mut renderer = Renderer::new(
            &gpu.device,
            wgpu::TextureFormat::Rgba8UnormSrgb,
            ShadowSettings::default(),
        )
        .unwrap();
        let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
        penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera(d), SIZE.0, SIZE.1).unwrap();
        let texture = renderer.composited_visibility().unwrap();
        let (renderer_visibility, _) = penumbra::read_texture_f32(&gpu.device, &gpu.queue, texture).unwrap();
        let engine = &run.layers[k];
        assert_eq!(renderer_visibility.len(), engine.len());
        let differences: Vec<f32> = renderer_visibility
            .iter()
            .zip(engine)
            .map(|(a, b)| (a - b).abs())
            .collect();
        let mean = differences.iter().sum::<f32>() / differences.len() as f32;
        let large = differences.iter().filter(|e| **e > 0.1).count() as f32 / differences.len() as f32;
        let shadowed = engine.iter().filter(|v| **v < 0.5).count();
        eprintln!(
            "light {k}: mean |engine - renderer| {mean:.5}, {:.3}% of pixels differ by more than 0.1, \
             {shadowed} shadowed pixels",
            large * 100.0
        );
        assert!(shadowed > 100, "light {k}: the comparison needs a shadow");
        assert!(mean < 0.001, "light {k}: mean difference {mean}");
        assert!(
            large < 0.0005,
            "light {k}: {large} of the pixels differ by more than 0.1"
        );
    }
}
