//! Lights in physical units: a spot's or point light's candela fall off with the square of the
//! distance, lights add up (the renderer is linear in them), and a glTF file's lights keep
//! their intensities, so dimming them all dims the frame down to its ambient light.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, DirectionalLight, Exposure, GpuScene, Light, Material, PointLight, Renderer, Scene, ShadowMethod,
    ShadowSettings, SpotLight, scene::primitives,
};

const SIZE: (u32, u32) = (160, 120);

use common::linear;

/// The linear luminance of pixel (x, y).
fn luminance(image: &image::RgbaImage, x: u32, y: u32) -> f32 {
    common::linear_luminance(image, (x, y))
}

/// A white floor (a receiver, no caster) and a grey box on it, no ambient light.
fn floor_scene(with_box: bool) -> Scene {
    let mut scene = Scene {
        ambient: Vec3::ZERO,
        ..Default::default()
    };
    let white = scene.add_material(Material::colored("white", [1.0, 1.0, 1.0]));
    let floor = scene.add_mesh(primitives::plane(20.0, 1.0));
    scene.add_instance(floor, white, Mat4::IDENTITY).caster = false;
    if with_box {
        let grey = scene.add_material(Material::colored("grey", [0.5, 0.5, 0.5]));
        let cube = scene.add_mesh(primitives::cuboid(Vec3::splat(0.6)));
        scene.add_instance(cube, grey, Mat4::from_translation(Vec3::new(0.0, 0.3, 0.0)));
    }
    scene
}

fn render(scene: &Scene, camera: &Camera, method: ShadowMethod) -> image::RgbaImage {
    let gpu = common::gpu();
    let settings = ShadowSettings::preset(method, penumbra::Quality::Medium);
    common::render(&gpu, scene, camera, settings, SIZE.0, SIZE.1)
}

fn point(height: f32, intensity: f32) -> Light {
    Light::Point(point_light(height, intensity))
}

fn point_light(height: f32, intensity: f32) -> PointLight {
    PointLight {
        position: Vec3::new(0.0, height, 0.0),
        radius: 0.0,
        color: Vec3::ONE,
        intensity,
        range: None,
    }
}

#[test]
fn a_point_light_twice_as_far_gives_a_quarter_of_the_light() {
    // Looking straight down at the floor's centre, under the light.
    let camera = Camera::look_at(Vec3::new(0.0, 6.0, 0.001), Vec3::ZERO);
    let centre = (SIZE.0 / 2, SIZE.1 / 2);
    let lit = |height: f32| {
        let scene = Scene {
            light: point(height, 0.8),
            ..floor_scene(false)
        };
        let image = render(&scene, &camera, ShadowMethod::Ours);
        image
            .save(common::output_dir().join(format!("light-units-point-{height}.png")))
            .unwrap();
        luminance(&image, centre.0, centre.1)
    };
    let (near, far) = (lit(1.0), lit(2.0));
    eprintln!(
        "floor under a 0.8 cd point light: at 1 {near:.4}, at 2 {far:.4}, ratio {:.4}",
        far / near
    );
    // 0.8 lux at 1 unit on a white floor, exposure 1.
    assert!((near - 0.8).abs() < 0.02, "{near}");
    assert!((far / near - 0.25).abs() < 0.25 * 0.05, "{far} / {near}");
    // A range ends the light: the same light with a range shorter than its height lights
    // nothing, one far longer lights as without one.
    let windowed = |range: f32| {
        let Light::Point(mut p) = point(2.0, 0.8) else {
            unreachable!()
        };
        p.range = Some(range);
        let scene = Scene {
            light: Light::Point(p),
            ..floor_scene(false)
        };
        luminance(&render(&scene, &camera, ShadowMethod::Ours), centre.0, centre.1)
    };
    assert!(windowed(1.5) < 0.002);
    assert!((windowed(200.0) - far).abs() < 0.01);
}

#[test]
fn the_frame_lit_by_several_lights_is_the_sum_of_the_frames_lit_by_each() {
    let camera = Camera::look_at(Vec3::new(3.0, 4.0, 5.0), Vec3::ZERO);
    let lights = [
        Light::Directional(DirectionalLight {
            direction: Vec3::new(0.5, -1.0, 0.3),
            angular_diameter_deg: 2.0,
            color: Vec3::new(1.0, 0.9, 0.8),
            intensity: 0.25,
        }),
        Light::Spot(SpotLight {
            position: Vec3::new(-1.5, 2.5, 1.0),
            direction: Vec3::new(0.6, -1.0, -0.4),
            cone_angle_deg: 40.0,
            radius: 0.1,
            color: Vec3::new(0.6, 0.8, 1.0),
            intensity: 1.2,
            range: Some(12.0),
        }),
        Light::Point(PointLight {
            position: Vec3::new(1.5, 1.5, -1.0),
            radius: 0.05,
            color: Vec3::ONE,
            intensity: 0.6,
            range: None,
        }),
    ];
    let ambient = Vec3::splat(0.05);
    let with = |lights: &[Light]| {
        let (key, more) = lights.split_first().unwrap();
        Scene {
            light: *key,
            more_lights: more.to_vec(),
            ambient,
            ..floor_scene(true)
        }
    };
    let dark = |l: &Light| l.with_intensity(0.0);
    let all = render(&with(&lights), &camera, ShadowMethod::Ours);
    all.save(common::output_dir().join("light-units-three-lights.png"))
        .unwrap();
    let each: Vec<image::RgbaImage> = lights
        .iter()
        .map(|l| render(&with(&[*l]), &camera, ShadowMethod::Ours))
        .collect();
    let ambient_only = render(&with(&[dark(&lights[0])]), &camera, ShadowMethod::Ours);
    let (mut close, mut lit, mut worst) = (0, 0, 0.0f32);
    let total = SIZE.0 * SIZE.1;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let sum: f32 =
                each.iter().map(|i| luminance(i, x, y)).sum::<f32>() - 2.0 * luminance(&ambient_only, x, y);
            let whole = luminance(&all, x, y);
            let error = (whole - sum).abs();
            worst = worst.max(error);
            if error < 0.01 {
                close += 1;
            }
            if whole > luminance(&ambient_only, x, y) + 0.05 {
                lit += 1;
            }
        }
    }
    eprintln!("{close} of {total} pixels within 0.01 of the sum, worst {worst:.4}; {lit} lit");
    assert!(lit > total / 4, "the lights must light the frame");
    assert!(close as f32 > 0.99 * total as f32);
}

#[test]
fn dimming_every_light_of_a_gltf_file_a_millionfold_leaves_only_the_ambient() {
    let path = common::models().join("MixedLightingExample/MixedLightingExample.gltf");
    let model = penumbra::load_model(&path).unwrap();
    let scene = Scene::showcase(&model).unwrap();
    assert_eq!(scene.exposure, Exposure::Ev100(Exposure::EV100_DEFAULT));
    let camera = scene.view(0).unwrap();
    let scaled = |factor: f32| {
        let mut scene = scene.clone();
        for l in std::iter::once(&mut scene.light).chain(&mut scene.more_lights) {
            *l = l.with_intensity(l.intensity() * factor);
        }
        render(&scene, &camera, ShadowMethod::Ours)
    };
    let (full, dimmed, off) = (scaled(1.0), scaled(1e-6), scaled(0.0));
    full.save(common::output_dir().join("light-units-gltf.png"))
        .unwrap();
    let differing = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 1))
            .count()
    };
    // The file's sun (2049 lux at EV100 9.7) lights the frame; a millionth of it does not.
    assert!(differing(&full, &off) > 1000, "the file's lights must show");
    assert_eq!(
        differing(&dimmed, &off),
        0,
        "a millionth of the file's lights must not show"
    );
}

/// A surface that gives off light shows it with every light off and no ambient light, through
/// the composite (`ours`) and the forward path (`hard`) alike; the rest of the frame stays dark.
#[test]
fn an_emissive_surface_is_bright_with_every_light_off() {
    let camera = Camera::look_at(Vec3::new(3.0, 4.0, 5.0), Vec3::ZERO);
    let mut scene = Scene {
        light: Light::Directional(DirectionalLight {
            direction: Vec3::new(0.5, -1.0, 0.3),
            angular_diameter_deg: 2.0,
            color: Vec3::ONE,
            intensity: 0.0,
        }),
        ..floor_scene(true)
    };
    let glowing = scene.add_material(Material {
        emissive: Vec3::new(1.0, 0.5, 0.2),
        ..Material::colored("panel", [0.5, 0.5, 0.5])
    });
    scene.instances[1].material = glowing;
    let cube_top = common::project(&camera, SIZE.0, SIZE.1, Vec3::new(0.0, 0.6, 0.0)).unwrap();
    let floor = common::project(&camera, SIZE.0, SIZE.1, Vec3::new(-2.0, 0.0, 2.0)).unwrap();
    for method in [ShadowMethod::Ours, ShadowMethod::Hard] {
        let image = render(&scene, &camera, method);
        image
            .save(common::output_dir().join(format!("emissive-{}.png", method.name())))
            .unwrap();
        let top = image.get_pixel(cube_top.0, cube_top.1).0;
        let lit = [linear(top[0]), linear(top[1]), linear(top[2])];
        eprintln!(
            "{}: the emissive box {lit:?}, the floor {:?}",
            method.name(),
            image.get_pixel(floor.0, floor.1).0
        );
        for (got, want) in lit.iter().zip([1.0, 0.5, 0.2]) {
            assert!((got - want).abs() < 0.02, "{}: {lit:?}", method.name());
        }
        assert!(image.get_pixel(floor.0, floor.1).0[..3].iter().all(|c| *c <= 2));
    }
    // An emissive texture (sRGB) multiplies the emissive light: a red one leaves only red.
    scene.textures.push(penumbra::TextureImage {
        name: "red".into(),
        width: 1,
        height: 1,
        rgba8: vec![255, 0, 0, 255],
    });
    scene.materials[glowing].emissive_texture = Some(scene.textures.len() - 1);
    let image = render(&scene, &camera, ShadowMethod::Ours);
    let top = image.get_pixel(cube_top.0, cube_top.1).0;
    assert!(top[0] == 255 && top[1] <= 2 && top[2] <= 2, "{top:?}");
}

/// The irradiance at a point `h` below one corner of an `a` x `b` rectangle of luminance 1
/// parallel to it (the classic corner form factor times π).
fn corner_irradiance(a: f32, b: f32, h: f32) -> f32 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    0.5 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan())
}

/// Area lights light a surface as Lambert's formula says: under a rectangle's centre and under
/// one of its corners, and on a disk's axis, the frame's linear value is the albedo times
/// the exact irradiance (closed forms, independent of the shader's polygon integral), and
/// nothing behind the light's plane is lit.
#[test]
fn area_lights_give_the_exact_irradiance() {
    use penumbra::{DiskLight, RectLight};
    let (height, width, depth) = (1.5f32, 2.0f32, 1.0f32);
    let camera = Camera {
        fov_y_deg: 60.0,
        ..Camera::look_at(Vec3::new(0.0, 2.5, 0.001), Vec3::ZERO)
    };
    let at = |image: &image::RgbaImage, p: Vec3| {
        let (x, y) = common::project(&camera, SIZE.0, SIZE.1, p).expect("in view");
        luminance(image, x, y)
    };
    let mut scene = floor_scene(false);
    scene.exposure = Exposure::Multiplier(1.0);
    let luminance_nits = 0.5;
    scene.light = Light::Rect(RectLight {
        position: Vec3::new(0.0, height, 0.0),
        direction: Vec3::NEG_Y,
        up: Vec3::Z,
        width,
        height: depth,
        color: Vec3::ONE,
        intensity: luminance_nits,
        range: None,
    });
    let rect = render(&scene, &camera, ShadowMethod::Hard);
    rect.save(common::output_dir().join("light-units-rect.png"))
        .unwrap();
    // Under the centre: four corners of (w/2) x (d/2) rectangles.
    let centre = 4.0 * corner_irradiance(width / 2.0, depth / 2.0, height) * luminance_nits;
    // Under a corner (x = w/2, z = d/2): the whole rectangle from its corner.
    let corner = corner_irradiance(width, depth, height) * luminance_nits;
    let measured_centre = at(&rect, Vec3::ZERO);
    let measured_corner = at(&rect, Vec3::new(width / 2.0, 0.0, depth / 2.0));
    eprintln!(
        "rectangle: centre {measured_centre:.4} (exact {centre:.4}), corner {measured_corner:.4} (exact {corner:.4})"
    );
    assert!((measured_centre / centre - 1.0).abs() < 0.02);
    assert!((measured_corner / corner - 1.0).abs() < 0.02);
    // The lit passes leave the area lights' shading out until a light with an area is shaded:
    // one renderer that first lights the floor with a point light, then with the rectangle,
    // then with the point light again, must give what fresh renderers give (for the forward
    // pass and for the composite).
    for method in [ShadowMethod::Hard, ShadowMethod::Ours] {
        let gpu = common::gpu();
        let settings = ShadowSettings::preset(method, penumbra::Quality::Medium);
        let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
        // A point light with a size, so that `ours` shades it in the composite too.
        let point_scene = Scene {
            light: Light::Point(PointLight {
                radius: 0.1,
                ..point_light(height, 4.0)
            }),
            ..scene.clone()
        };
        let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &point_scene).unwrap();
        let mut frame = |gpu_scene: &GpuScene| {
            penumbra::render_to_image(&gpu, &mut renderer, gpu_scene, &camera, SIZE.0, SIZE.1).unwrap()
        };
        let first = frame(&gpu_scene);
        gpu_scene.set_light(scene.light).unwrap();
        let switched = frame(&gpu_scene);
        gpu_scene.set_light(point_scene.light).unwrap();
        let back = frame(&gpu_scene);
        let fresh_rect = render(&scene, &camera, method);
        let fresh_point = render(&point_scene, &camera, method);
        assert!(
            switched == fresh_rect,
            "{}: the rectangle after a point light",
            method.name()
        );
        assert!(
            back == fresh_point && first == fresh_point,
            "{}: the point light",
            method.name()
        );
        assert!(
            switched != first,
            "{}: the rectangle lights as the point light did",
            method.name()
        );
    }
    // Facing up, the floor below is behind it: unlit.
    if let Light::Rect(r) = &mut scene.light {
        r.direction = Vec3::Y;
    }
    let behind = render(&scene, &camera, ShadowMethod::Hard);
    assert!(
        at(&behind, Vec3::ZERO) < 0.002,
        "behind the light: {}",
        at(&behind, Vec3::ZERO)
    );
    // A disk on its axis: E = L π R² / (h² + R²).
    let radius = 0.8;
    scene.light = Light::Disk(DiskLight {
        position: Vec3::new(0.0, height, 0.0),
        direction: Vec3::NEG_Y,
        radius,
        color: Vec3::ONE,
        intensity: luminance_nits,
        range: None,
    });
    let disk = render(&scene, &camera, ShadowMethod::Ours);
    let exact = luminance_nits * std::f32::consts::PI * radius * radius / (height * height + radius * radius);
    let measured = at(&disk, Vec3::ZERO);
    eprintln!("disk: on its axis {measured:.4} (exact {exact:.4})");
    assert!((measured / exact - 1.0).abs() < 0.02);
}
