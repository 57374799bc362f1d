//! Several lights in one frame of the convenience renderer: each light's direct light times its
//! own visibility, summed. Rendered with two suns together, a frame must equal the sum of the
//! frames with each sun alone, less the ambient-only frame counted twice (in linear light), for
//! every method, the reference included; the metrics measure the key light alone; lights can
//! be added and removed between frames; misuse is refused with an error naming the lights. The two-sun frames are
//! written to `target/penumbra-test-output/two-suns-<method>.png`.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, DirectionalLight, GpuScene, Light, Material, Renderer, Scene, ShadowMethod, ShadowSettings,
    metrics::measure_visibility, scene::primitives,
};

fn sun(direction: Vec3, intensity: f32) -> Light {
    Light::Directional(DirectionalLight {
        direction,
        angular_diameter_deg: 2.0,
        color: Vec3::ONE,
        intensity,
    })
}

/// The sun whose shadow falls toward +x, and the one whose shadow falls toward -x and +z.
fn suns() -> (Light, Light) {
    (
        sun(Vec3::new(0.7, -1.0, 0.0), 0.45),
        sun(Vec3::new(-0.6, -1.0, 0.4), 0.45),
    )
}

/// A floor and a box standing on it, lit by `key` and `more`.
fn scene(key: Light, more: Vec<Light>) -> Scene {
    let mut scene = Scene {
        light: key,
        more_lights: more,
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let blue = scene.add_material(Material::colored("box", [0.4, 0.6, 0.9]));
    let floor = scene.add_mesh(primitives::plane(12.0, 1.0));
    scene.add_instance(floor, grey, Mat4::IDENTITY).caster = false;
    let cube = scene.add_mesh(primitives::cuboid(Vec3::new(1.0, 1.5, 1.0)));
    scene.add_instance(cube, blue, Mat4::from_translation(Vec3::new(0.0, 0.75, 0.0)));
    scene
}

fn camera() -> Camera {
    Camera::look_at(Vec3::new(0.5, 6.0, 5.0), Vec3::new(0.0, 0.0, 0.0))
}

const SIZE: (u32, u32) = (200, 150);

/// The frame as linear light, one value per pixel and channel.
fn linear(image: &image::RgbaImage) -> Vec<f32> {
    image
        .pixels()
        .flat_map(|p| {
            p.0[..3].iter().map(|&c| {
                let c = c as f32 / 255.0;
                if c <= 0.04045 {
                    c / 12.92
                } else {
                    ((c + 0.055) / 1.055).powf(2.4)
                }
            })
        })
        .collect()
}

#[test]
fn two_lights_add_up_to_each_light_alone() {
    let gpu = common::gpu();
    let (a, b) = suns();
    let camera = camera();
    for method in [
        ShadowMethod::Ours,
        ShadowMethod::Pcss,
        ShadowMethod::Hard,
        ShadowMethod::Reference,
    ] {
        let mut settings = ShadowSettings::preset(method, penumbra::Quality::Medium);
        // The reference averages every light's samples, each light's in its own mean.
        settings.reference.samples = 16;
        let render = |s: &Scene| linear(&common::render(&gpu, s, &camera, settings, SIZE.0, SIZE.1));
        let both_image = common::render(&gpu, &scene(a, vec![b]), &camera, settings, SIZE.0, SIZE.1);
        let name = format!("two-suns-{}.png", method.name());
        both_image.save(common::output_dir().join(name)).unwrap();
        let both = linear(&both_image);
        let only_a = render(&scene(a, vec![]));
        let only_b = render(&scene(b, vec![]));
        let ambient = render(&scene(sun(Vec3::NEG_Y, 0.0), vec![]));
        let mut errors: Vec<f32> = both
            .iter()
            .zip(&only_a)
            .zip(&only_b)
            .zip(&ambient)
            .map(|(((ab, a), b), n)| (ab + n - a - b).abs())
            .collect();
        errors.sort_by(f32::total_cmp);
        let mean = errors.iter().sum::<f32>() / errors.len() as f32;
        let p99 = errors[errors.len() * 99 / 100];
        eprintln!(
            "{}: mean |error| {mean:.5}, median {:.5}, 99th percentile {p99:.5}, max {:.5}",
            method.name(),
            errors[errors.len() / 2],
            errors[errors.len() - 1]
        );
        // Four 8-bit sRGB frames: each rounds by up to about 0.003 in linear light at these
        // levels. A light left out or shaded with another's visibility errs by 0.1 or more.
        assert!(mean < 0.005, "{}: mean error {mean}", method.name());
        assert!(p99 < 0.012, "{}: 99th percentile {p99}", method.name());
        // Each sun's shadow is in the frame: pixels that one sun leaves dark (its shadow) while
        // the other lights them, both ways round.
        let in_shadow_of = |dark: &[f32], lit: &[f32]| {
            (0..ambient.len())
                .filter(|&i| dark[i] < ambient[i] + 0.01 && lit[i] > ambient[i] + 0.1)
                .count()
        };
        let (shadow_a, shadow_b) = (in_shadow_of(&only_a, &only_b), in_shadow_of(&only_b, &only_a));
        assert!(
            shadow_a > 300 && shadow_b > 300,
            "{}: {shadow_a} values in a's shadow only, {shadow_b} in b's",
            method.name()
        );
    }
}

#[test]
fn lights_are_added_and_removed_between_frames_and_metrics_measure_the_key_light() {
    let gpu = common::gpu();
    let (a, b) = suns();
    let camera = camera();
    let settings = ShadowSettings::preset(ShadowMethod::Ours, penumbra::Quality::Medium);
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let mut gpu_scene =
        GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene(a, vec![])).unwrap();
    let frame = |renderer: &mut Renderer, s: &GpuScene| {
        penumbra::render_to_image(&gpu, renderer, s, &camera, SIZE.0, SIZE.1).unwrap()
    };
    let alone = frame(&mut renderer, &gpu_scene);
    gpu_scene.set_more_lights(vec![b, b]).unwrap();
    let three = frame(&mut renderer, &gpu_scene);
    assert_ne!(alone, three, "the added lights changed nothing");
    assert_eq!(renderer.shadows().light_ids().len(), 3);
    // The debug textures are the chosen light's: another sun, another shadow map; a light
    // that is not there gives the key light's.
    let map = |renderer: &mut Renderer, light: usize| {
        renderer.set_debug_light(light);
        let texture = renderer.debug_texture(penumbra::LightTexture::ShadowMap).unwrap();
        let layer = renderer
            .debug_texture_layer(penumbra::LightTexture::ShadowMap)
            .unwrap();
        common::read_layer_f32(&gpu, texture, layer).0
    };
    let (key_map, second_map, missing_map) = (
        map(&mut renderer, 0),
        map(&mut renderer, 1),
        map(&mut renderer, 9),
    );
    assert_ne!(key_map, second_map);
    assert_eq!(key_map, missing_map);
    renderer.set_debug_light(0);
    gpu_scene.set_more_lights(vec![]).unwrap();
    let again = frame(&mut renderer, &gpu_scene);
    assert_eq!(renderer.shadows().light_ids().len(), 1);
    assert_eq!(
        alone, again,
        "removing the lights did not restore the one-light frame"
    );

    // The metrics measure the key light's visibility, whatever else lights the scene.
    let with_b = measure_visibility(&gpu, &scene(a, vec![b]), &camera, settings, SIZE).unwrap();
    let without = measure_visibility(&gpu, &scene(a, vec![]), &camera, settings, SIZE).unwrap();
    assert_eq!(with_b.visibility, without.visibility);
    let mut reference = ShadowSettings {
        method: ShadowMethod::Reference,
        ..Default::default()
    };
    reference.reference.samples = 8;
    let with_b = measure_visibility(&gpu, &scene(a, vec![b]), &camera, reference, SIZE).unwrap();
    let without = measure_visibility(&gpu, &scene(a, vec![]), &camera, reference, SIZE).unwrap();
    assert_eq!(with_b.visibility, without.visibility);
}

#[test]
fn misuse_of_several_lights_is_refused_with_a_clear_error() {
    let gpu = common::gpu();
    let (a, b) = suns();
    // More than MAX_LIGHTS.
    let crowded = scene(a, vec![b; penumbra::MAX_LIGHTS]);
    let err = crowded.validate().unwrap_err().to_string();
    assert!(err.contains("lights") && err.contains("at most 16"), "{err}");
    let settings = ShadowSettings::preset(ShadowMethod::Ours, penumbra::Quality::Medium);
    let renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
    let mut gpu_scene =
        GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene(a, vec![])).unwrap();
    let err = gpu_scene
        .set_more_lights(vec![b; penumbra::MAX_LIGHTS])
        .unwrap_err()
        .to_string();
    assert!(err.contains("at most 16"), "{err}");
    // An invalid further light names its field.
    let bad = sun(Vec3::ZERO, 1.0);
    assert!(gpu_scene.set_more_lights(vec![b, bad]).is_err());
    assert!(scene(a, vec![bad]).validate().is_err());
}
