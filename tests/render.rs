//! Rendering tests on the software adapter: what the pictures must show, and golden images.
//!
//! Golden images live in `tests/golden/`. They are compared with NVIDIA's FLIP perceptual
//! metric; a test passes when the mean FLIP error is at most [`MEAN_FLIP_TOLERANCE`] **and**
//! at most [`BAD_PIXEL_SHARE`] of the pixels have an error above [`BAD_PIXEL_FLIP`]. The second
//! bound is what catches a lost or moved shadow, which covers only a few percent of the image
//! and would hardly move the mean. On failure the actual image and a FLIP heat-map are written
//! to `target/penumbra-test-output/`. Set `PENUMBRA_UPDATE_REFERENCES=1` to rewrite the
//! references (then look at them before committing).

mod common;

use glam::{Mat4, Vec3, Vec4};
use penumbra::{
    AlphaMode, DirectionalLight, Light, Material, Scene, ShadowMethod, ShadowSettings, SpotLight,
    TextureImage, load_scene, scene::primitives,
};

const MEAN_FLIP_TOLERANCE: f32 = 0.01;
const BAD_PIXEL_FLIP: f32 = 0.25;
const BAD_PIXEL_SHARE: f32 = 0.005;

fn settings(method: ShadowMethod) -> ShadowSettings {
    ShadowSettings {
        method,
        ..Default::default()
    }
}

fn compare_with_reference(name: &str, actual: &image::RgbaImage) {
    let reference_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{name}.png"));
    if std::env::var_os("PENUMBRA_UPDATE_REFERENCES").is_some() {
        std::fs::create_dir_all(reference_path.parent().unwrap()).unwrap();
        actual.save(&reference_path).unwrap();
        return;
    }
    let reference = image::open(&reference_path)
        .unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run with PENUMBRA_UPDATE_REFERENCES=1 to create it",
                reference_path.display()
            )
        })
        .to_rgba8();
    assert_eq!(
        reference.dimensions(),
        actual.dimensions(),
        "{name}: size differs from the reference"
    );
    let rgb = |img: &image::RgbaImage| -> Vec<u8> { img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect() };
    let (w, h) = actual.dimensions();
    let error_map = nv_flip::flip(
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(&reference)),
        nv_flip::FlipImageRgb8::with_data(w, h, &rgb(actual)),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let errors = error_map.to_vec();
    let mean = errors.iter().sum::<f32>() / errors.len() as f32;
    let bad = errors.iter().filter(|&&e| e > BAD_PIXEL_FLIP).count() as f32 / errors.len() as f32;
    eprintln!(
        "{name}: mean FLIP {mean:.5}, {:.3}% of pixels above {BAD_PIXEL_FLIP}",
        bad * 100.0
    );
    if mean > MEAN_FLIP_TOLERANCE || bad > BAD_PIXEL_SHARE {
        let out = common::output_dir();
        actual.save(out.join(format!("{name}.actual.png"))).unwrap();
        let heat = error_map.apply_color_lut(&nv_flip::magma_lut());
        image::RgbImage::from_raw(w, h, heat.to_vec())
            .unwrap()
            .save(out.join(format!("{name}.difference.png")))
            .unwrap();
        panic!(
            "{name}: mean FLIP {mean:.4} (tolerance {MEAN_FLIP_TOLERANCE}), {:.2}% of pixels above {BAD_PIXEL_FLIP} \
             (tolerance {:.2}%); actual and difference images in {}",
            bad * 100.0,
            BAD_PIXEL_SHARE * 100.0,
            out.display()
        );
    }
}

/// Renders one golden case and compares it with its reference image.
fn golden(scene: &str, view: usize, method: ShadowMethod) {
    let gpu = common::gpu();
    let loaded = load_scene(&common::asset(&format!("scenes/{scene}.ron"))).unwrap();
    let camera = loaded.view(view).unwrap();
    let image = common::render(&gpu, &loaded, &camera, settings(method), 320, 256);
    compare_with_reference(&format!("{scene}_view{view}_{}", method.name()), &image);
}

/// One test per golden image, so one failure does not hide the others: every method from the
/// first viewpoint, the method, its baseline and hw2x2 from the other two.
macro_rules! golden_images {
    ($($test:ident: $scene:literal, $view:literal, $method:ident;)*) => {
        $(
            #[test]
            fn $test() {
                golden($scene, $view, ShadowMethod::$method);
            }
        )*
        /// The reference images the cases above compare with.
        const GOLDEN: &[(&str, usize, ShadowMethod)] = &[$(($scene, $view, ShadowMethod::$method)),*];
    };
}

golden_images! {
    teapot_view0_ours: "teapot", 0, Ours;
    teapot_view0_ours_fast: "teapot", 0, OursFast;
    teapot_view0_traditional: "teapot", 0, Traditional;
    teapot_view0_pcss: "teapot", 0, Pcss;
    teapot_view0_hard: "teapot", 0, Hard;
    teapot_view0_hw2x2: "teapot", 0, Hardware2x2;
    teapot_view1_ours: "teapot", 1, Ours;
    teapot_view1_traditional: "teapot", 1, Traditional;
    teapot_view1_hw2x2: "teapot", 1, Hardware2x2;
    teapot_view2_ours: "teapot", 2, Ours;
    teapot_view2_traditional: "teapot", 2, Traditional;
    teapot_view2_hw2x2: "teapot", 2, Hardware2x2;
    character_view0_ours: "character", 0, Ours;
    character_view0_ours_fast: "character", 0, OursFast;
    character_view0_traditional: "character", 0, Traditional;
    character_view0_pcss: "character", 0, Pcss;
    character_view0_hard: "character", 0, Hard;
    character_view0_hw2x2: "character", 0, Hardware2x2;
    character_view1_ours: "character", 1, Ours;
    character_view1_traditional: "character", 1, Traditional;
    character_view1_hw2x2: "character", 1, Hardware2x2;
    character_view2_ours: "character", 2, Ours;
    character_view2_traditional: "character", 2, Traditional;
    character_view2_hw2x2: "character", 2, Hardware2x2;
}

#[test]
fn every_reference_image_has_its_case() {
    let names: Vec<String> = GOLDEN
        .iter()
        .map(|(scene, view, method)| format!("{scene}_view{view}_{}.png", method.name()))
        .collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let mut on_disk: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".png"))
        .collect();
    on_disk.sort();
    let mut expected = names.clone();
    expected.sort();
    assert_eq!(on_disk, expected);
}

fn directional(direction: Vec3) -> Light {
    Light::Directional(DirectionalLight {
        direction,
        angular_diameter_deg: 0.0,
        color: Vec3::ONE,
        intensity: 1.0,
    })
}

/// Asserts that `p` is shadowed in `shadowed` (much darker than with no casters) or lit
/// (the same as with no casters), naming the point in the message.
fn assert_point(
    what: &str,
    shadowed: bool,
    with: &image::RgbaImage,
    without: &image::RgbaImage,
    px: (u32, u32),
) {
    let (a, b) = (common::luminance(with, px), common::luminance(without, px));
    if shadowed {
        assert!(
            a < 0.75 * b && b - a > 0.08,
            "{what} at pixel {px:?} should be in shadow: {a:.3} vs unshadowed {b:.3}"
        );
    } else {
        assert!(
            (a - b).abs() <= 2.0 / 255.0,
            "{what} at pixel {px:?} should be lit: {a:.3} vs unshadowed {b:.3}"
        );
    }
}

#[test]
fn teapot_shadows_the_floor_beside_it_and_nothing_else() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let (w, h) = (400, 320);
    let lit_only = common::without_casters(&scene);
    for method in ShadowMethod::ALL {
        let with = common::render(&gpu, &scene, &camera, settings(method), w, h);
        let without = common::render(&gpu, &lit_only, &camera, settings(method), w, h);
        let d = scene.light.direction();
        // The rim's center is inside the teapot: the floor point it projects to is in shadow.
        let under = common::shadow_on_floor(Vec3::new(0.0, 2.4, 0.0), d);
        let px = common::project(&camera, w, h, under).expect("shadow point on screen");
        assert_point(
            &format!("{}: floor behind the teapot", method.name()),
            true,
            &with,
            &without,
            px,
        );
        // Floor points toward the light from the teapot are not occluded by anything.
        for p in [
            Vec3::new(-3.0, 0.0, 4.0),
            Vec3::new(3.5, 0.0, 4.5),
            Vec3::new(-5.0, 0.0, 0.5),
        ] {
            let px = common::project(&camera, w, h, p).expect("lit point on screen");
            assert_point(
                &format!("{}: open floor {p}", method.name()),
                false,
                &with,
                &without,
                px,
            );
        }
        // Shadows only ever remove light.
        for (a, b) in with.pixels().zip(without.pixels()) {
            assert!(
                a[0] <= b[0].saturating_add(1) && a[1] <= b[1].saturating_add(1),
                "{}: a shadow brightened a pixel",
                method.name()
            );
        }
    }
}

#[test]
fn moving_the_light_moves_the_shadow() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let (w, h) = (400, 320);
    let without = common::render(
        &gpu,
        &common::without_casters(&scene),
        &camera,
        settings(ShadowMethod::Hard),
        w,
        h,
    );
    let right = Vec3::new(0.9, -0.75, 0.45);
    let left = Vec3::new(-0.9, -0.75, 0.45);
    let top = Vec3::new(0.0, 2.4, 0.0);
    let right_spot = common::project(&camera, w, h, common::shadow_on_floor(top, right.normalize())).unwrap();
    let left_spot = common::project(&camera, w, h, common::shadow_on_floor(top, left.normalize())).unwrap();
    scene.light = directional(right);
    let lit_from_left = common::render(&gpu, &scene, &camera, settings(ShadowMethod::Hard), w, h);
    scene.light = directional(left);
    let lit_from_right = common::render(&gpu, &scene, &camera, settings(ShadowMethod::Hard), w, h);
    // `without` has the default light; compare each render against its own unshadowed twin.
    let _ = without;
    let twin = |light: Vec3| {
        let mut s = common::without_casters(&scene);
        s.light = directional(light);
        common::render(&gpu, &s, &camera, settings(ShadowMethod::Hard), w, h)
    };
    let (twin_right, twin_left) = (twin(right), twin(left));
    assert_point(
        "light toward +x: shadow on the right",
        true,
        &lit_from_left,
        &twin_right,
        right_spot,
    );
    assert_point(
        "light toward +x: left floor lit",
        false,
        &lit_from_left,
        &twin_right,
        left_spot,
    );
    assert_point(
        "light toward -x: shadow on the left",
        true,
        &lit_from_right,
        &twin_left,
        left_spot,
    );
    assert_point(
        "light toward -x: right floor lit",
        false,
        &lit_from_right,
        &twin_left,
        right_spot,
    );
}

#[test]
fn spot_light_casts_a_perspective_shadow() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let position = Vec3::new(-4.0, 8.0, 2.0);
    scene.light = Light::Spot(SpotLight {
        position,
        direction: Vec3::new(0.0, 1.0, 0.0) - position,
        cone_angle_deg: 45.0,
        radius: 0.0,
        color: Vec3::ONE,
        // Candela: about 1.2 lux at the teapot, 10 units away.
        intensity: 120.0,
        range: None,
    });
    let camera = scene.view(0).unwrap();
    let (w, h) = (400, 320);
    let (with, without) = common::render_with_and_without_casters(
        &gpu,
        &scene,
        &camera,
        settings(ShadowMethod::Hardware2x2),
        w,
        h,
    );
    // A floor point whose path to the light passes through the inside of the teapot's body
    // (radius 1.7 < 2 at height 1.2), on the side the camera sees.
    let through = Vec3::new(1.6, 1.2, 0.6);
    let under = common::shadow_on_floor(through, (through - position).normalize());
    assert_point(
        "spot: floor behind the teapot",
        true,
        &with,
        &without,
        common::project(&camera, w, h, under).unwrap(),
    );
    assert_point(
        "spot: floor in front",
        false,
        &with,
        &without,
        common::project(&camera, w, h, Vec3::new(-2.0, 0.0, 4.0)).unwrap(),
    );
}

#[test]
fn alpha_masked_casters_cast_only_where_opaque() {
    let gpu = common::gpu();
    // A sun of 2 degrees: with none, `ours` would draw hard shadows (the forward pass).
    let mut scene = Scene {
        light: Light::Directional(DirectionalLight {
            direction: Vec3::NEG_Y,
            angular_diameter_deg: 2.0,
            color: Vec3::ONE,
            intensity: 1.0,
        }),
        ..Default::default()
    };
    // A 4x1 texture: left half transparent, right half opaque.
    let mut rgba = Vec::new();
    for alpha in [0u8, 0, 255, 255] {
        rgba.extend_from_slice(&[230, 60, 60, alpha]);
    }
    scene.textures.push(TextureImage::from_rgba8("half", 4, 1, rgba));
    let card_material = scene.add_material(Material {
        name: "card".into(),
        base_color: Vec4::ONE,
        base_color_texture: Some(0),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Default::default()
    });
    let floor_material = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let card = scene.add_mesh(primitives::cuboid(Vec3::new(2.0, 0.02, 2.0)));
    let floor = scene.add_mesh(primitives::plane(12.0, 1.0));
    scene.add_instance(
        card,
        card_material,
        Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0)),
    );
    scene.add_instance(floor, floor_material, Mat4::IDENTITY).caster = false;
    let camera = penumbra::Camera::look_at(Vec3::new(0.0, 0.6, 6.0), Vec3::new(0.0, 0.3, 0.0));
    let (w, h) = (320, 256);
    // Hard shadows draw the card in their forward pass; `ours` in the renderer's depth prepass,
    // whose masked instances have a pipeline of their own (the others neither read a texture
    // nor discard), and in its composite.
    for method in [ShadowMethod::Hard, ShadowMethod::Ours] {
        let (with, without) =
            common::render_with_and_without_casters(&gpu, &scene, &camera, settings(method), w, h);
        let left = common::project(&camera, w, h, Vec3::new(-0.5, 0.0, 0.5)).unwrap();
        let right = common::project(&camera, w, h, Vec3::new(0.5, 0.0, 0.5)).unwrap();
        assert_point(
            &format!("{method:?}: floor under the transparent half"),
            false,
            &with,
            &without,
            left,
        );
        assert_point(
            &format!("{method:?}: floor under the opaque half"),
            true,
            &with,
            &without,
            right,
        );
        // From above, through the card's transparent half: the floor as it is with no card
        // (green, unlike the background).
        let above = penumbra::Camera::look_at(Vec3::new(-0.5, 4.0, 0.6), Vec3::new(-0.5, 0.0, 0.5));
        let mut green = scene.clone();
        green.materials[floor_material].base_color = Vec4::new(0.2, 0.6, 0.2, 1.0);
        let mut bare = green.clone();
        bare.instances.retain(|i| i.mesh != card);
        let through = common::render(&gpu, &green, &above, settings(method), w, h);
        let floor_only = common::render(&gpu, &bare, &above, settings(method), w, h);
        let (x, y) = common::project(&above, w, h, Vec3::new(-0.5, 0.0, 0.5)).unwrap();
        let (a, b) = (through.get_pixel(x, y).0, floor_only.get_pixel(x, y).0);
        let off = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
        assert!(
            b[1] > b[0] + 40,
            "{method:?}: the floor is not green from above: {b:?}"
        );
        assert!(
            off <= 8,
            "{method:?}: through the transparent half {a:?}, the floor alone {b:?}"
        );
    }
}

/// Blended materials (glTF `BLEND`): drawn over the floor with their alpha, casting where their
/// alpha is at least 0.5, for the screen-space method and the forward path alike.
#[test]
fn blended_surfaces_show_what_lies_behind_and_cast_only_where_alpha_is_half_or_more() {
    let gpu = common::gpu();
    let mut scene = Scene {
        light: directional(Vec3::NEG_Y),
        ambient: Vec3::splat(0.1),
        ..Default::default()
    };
    let glass = |name: &str, rgb: [f32; 3], alpha: f32| Material {
        name: name.into(),
        base_color: Vec4::new(rgb[0], rgb[1], rgb[2], alpha),
        alpha_mode: AlphaMode::Blend,
        ..Default::default()
    };
    let faint = scene.add_material(glass("faint red", [1.0, 0.1, 0.1], 0.3));
    let dense = scene.add_material(glass("dense blue", [0.1, 0.1, 1.0], 0.8));
    let floor_material = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let card = scene.add_mesh(primitives::cuboid(Vec3::new(1.5, 0.02, 1.5)));
    let floor = scene.add_mesh(primitives::plane(12.0, 1.0));
    scene.add_instance(card, faint, Mat4::from_translation(Vec3::new(-1.2, 1.0, 0.0)));
    scene.add_instance(card, dense, Mat4::from_translation(Vec3::new(1.2, 1.0, 0.0)));
    scene.add_instance(floor, floor_material, Mat4::IDENTITY).caster = false;
    let camera = penumbra::Camera::look_at(Vec3::new(0.0, 5.0, 5.0), Vec3::ZERO);
    let (w, h) = (320, 256);
    for method in [ShadowMethod::Ours, ShadowMethod::Hard] {
        let (with, without) =
            common::render_with_and_without_casters(&gpu, &scene, &camera, settings(method), w, h);
        with.save(common::output_dir().join(format!("blended-{}.png", method.name())))
            .unwrap();
        let at = |x: f32, y: f32, z: f32| common::project(&camera, w, h, Vec3::new(x, y, z)).unwrap();
        // On the cards, seen from above: their colour over the lit floor's grey.
        let red = with.get_pixel(at(-1.2, 1.02, 0.0).0, at(-1.2, 1.02, 0.0).1).0;
        let blue = with.get_pixel(at(1.2, 1.02, 0.0).0, at(1.2, 1.02, 0.0).1).0;
        let floor = with.get_pixel(at(0.0, 0.0, 2.5).0, at(0.0, 0.0, 2.5).1).0;
        eprintln!(
            "{}: faint red card {red:?}, dense blue card {blue:?}, open floor {floor:?}",
            method.name()
        );
        assert!(
            red[0] > red[2] + 40 && red[2] > 60,
            "{}: the faint card hides the floor: {red:?}",
            method.name()
        );
        assert!(blue[2] > blue[0] + 50, "{}: {blue:?}", method.name());
        // Beside the cards (seen past their edges) the floor under the faint card is lit, under
        // the dense one shadowed.
        let under = |x: f32| {
            let p = at(x, 0.0, 0.6);
            (common::luminance(&with, p), common::luminance(&without, p))
        };
        let (faint_with, faint_without) = under(-1.2);
        let (dense_with, dense_without) = under(1.2);
        eprintln!(
            "{}: floor under the faint card {faint_with:.3} ({faint_without:.3} without casters), under the dense one {dense_with:.3} ({dense_without:.3})",
            method.name()
        );
        assert!(
            (faint_with - faint_without).abs() < 0.02,
            "{}: the faint card casts",
            method.name()
        );
        assert!(
            dense_with < 0.6 * dense_without,
            "{}: the dense card casts no shadow",
            method.name()
        );
    }
}

#[test]
fn real_models_render_with_shadows() {
    let gpu = common::gpu();
    for file in ["teapot.obj", "spot.obj", "Fox.glb", "CornellBox.glb"] {
        let scene = load_scene(&common::models().join(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let (w, h) = (256, 192);
        let (with, without) = common::render_with_and_without_casters(
            &gpu,
            &scene,
            &camera,
            settings(ShadowMethod::Hardware2x2),
            w,
            h,
        );
        if std::env::var_os("PENUMBRA_SAVE_RENDERS").is_some() {
            with.save(common::output_dir().join(format!("{file}.png")))
                .unwrap();
        }
        let lum: Vec<f32> = with
            .pixels()
            .map(|p| (0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32) / 255.0)
            .collect();
        let mean = lum.iter().sum::<f32>() / lum.len() as f32;
        let std_dev = (lum.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / lum.len() as f32).sqrt();
        assert!(
            std_dev > 0.04,
            "{file}: the image is nearly one color (std dev {std_dev})"
        );
        let darkened = with
            .pixels()
            .zip(without.pixels())
            .filter(|(a, b)| (a[1] as f32) < 0.8 * b[1] as f32)
            .count() as f32
            / (w * h) as f32;
        assert!(
            darkened > 0.005,
            "{file}: no visible shadow ({:.2}% of pixels darkened)",
            darkened * 100.0
        );
    }
}

#[test]
fn zero_sized_targets_are_rejected_or_skipped() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let mut renderer = penumbra::Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        ShadowSettings::default(),
    )
    .unwrap();
    let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let camera = scene.view(0).unwrap();
    let err = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 0, 10).unwrap_err();
    assert!(err.to_string().contains("size"), "{err}");
    // A minimized window: resizing to zero and back works and frames are skipped meanwhile.
    renderer.resize(&gpu.device, 0, 0);
    let image = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 64, 48).unwrap();
    assert_eq!(image.dimensions(), (64, 48));
}

#[test]
fn every_depth_format_and_cull_mode_renders_the_shadow() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let (w, h) = (320, 256);
    let without = common::render(
        &gpu,
        &common::without_casters(&scene),
        &camera,
        settings(ShadowMethod::Hard),
        w,
        h,
    );
    let under = common::shadow_on_floor(Vec3::new(0.0, 2.4, 0.0), scene.light.direction());
    let px = common::project(&camera, w, h, under).unwrap();
    let open = common::project(&camera, w, h, Vec3::new(-3.0, 0.0, 4.0)).unwrap();
    for format in [
        penumbra::DepthFormat::Depth16,
        penumbra::DepthFormat::Depth24,
        penumbra::DepthFormat::Depth32,
    ] {
        for cull in [
            penumbra::CullMode::None,
            penumbra::CullMode::Back,
            penumbra::CullMode::Front,
        ] {
            let mut s = settings(ShadowMethod::Hard);
            s.shadow_map.depth_format = format;
            s.shadow_map.cull_mode = cull;
            s.shadow_map.resolution = 1024;
            let with = common::render(&gpu, &scene, &camera, s, w, h);
            let what = format!("{format:?}/{cull:?}");
            assert_point(&format!("{what}: shadow"), true, &with, &without, px);
            assert_point(&format!("{what}: open floor"), false, &with, &without, open);
        }
    }
}

/// Share of pixels that are partly shadowed: darker than unshadowed, but clearly lighter than
/// the darkest shadow in the image.
fn partly_shadowed_share(with: &image::RgbaImage, without: &image::RgbaImage) -> f32 {
    let ratios: Vec<f32> = with
        .pixels()
        .zip(without.pixels())
        .filter(|(_, b)| b[1] > 20)
        .map(|(a, b)| a[1] as f32 / b[1] as f32)
        .collect();
    let darkest = ratios.iter().cloned().fold(1.0, f32::min);
    let partial = ratios.iter().filter(|&&r| r > darkest + 0.1 && r < 0.95).count();
    partial as f32 / ratios.len() as f32
}

#[test]
fn hardware_pcf_grades_the_edges_that_hard_shadows_cut() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    // Only the floor receives: there the shadowed / unshadowed ratio is the visibility alone
    // (on the curved teapot it would also vary with the angle to the light).
    for instance in &mut scene.instances {
        instance.receiver = !instance.caster;
    }
    let camera = scene.view(2).unwrap();
    let (w, h) = (400, 320);
    let mut shares = Vec::new();
    for method in [ShadowMethod::Hard, ShadowMethod::Hardware2x2] {
        let mut s = settings(method);
        // A coarse map makes each shadow-map texel span several pixels.
        s.shadow_map.resolution = 256;
        let (with, without) = common::render_with_and_without_casters(&gpu, &scene, &camera, s, w, h);
        shares.push(partly_shadowed_share(&with, &without));
    }
    let (hard, pcf) = (shares[0], shares[1]);
    assert!(
        hard < 0.0005,
        "hard shadows should be all or nothing per pixel: {:.3}% partial",
        hard * 100.0
    );
    assert!(
        pcf > 0.002 && pcf > 5.0 * hard,
        "2x2 PCF should grade its edges: {:.3}% partial vs hard {:.3}%",
        pcf * 100.0,
        hard * 100.0
    );
}

#[test]
fn empty_and_one_triangle_scenes_render() {
    let gpu = common::gpu();
    let camera = penumbra::Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::ZERO);
    let empty = Scene::default();
    let image = common::render(&gpu, &empty, &camera, settings(ShadowMethod::Hardware2x2), 64, 48);
    let background = *image.get_pixel(0, 0);
    assert!(
        image.pixels().all(|p| *p == background),
        "an empty scene shows only the background"
    );

    let mut one = Scene::default();
    let mesh = one.add_mesh(
        penumbra::Mesh::new(
            "tri",
            vec![
                Vec3::new(-1.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            None,
            None,
            vec![0, 1, 2],
        )
        .unwrap(),
    );
    let material = one.add_material(Material::colored("white", [1.0, 1.0, 1.0]));
    one.add_instance(mesh, material, Mat4::IDENTITY);
    let image = common::render(&gpu, &one, &camera, settings(ShadowMethod::Hardware2x2), 64, 48);
    assert!(image.pixels().any(|p| *p != background), "the triangle is drawn");
}

/// What the device compiled so far: render and compute pipelines, shader modules.
fn compiled(device: &wgpu::Device) -> [isize; 3] {
    let hal = device.get_internal_counters().hal;
    [
        hal.render_pipelines.read(),
        hal.compute_pipelines.read(),
        hal.shader_modules.read(),
    ]
}

/// Two renderers of one device (the demo's two sides) share their shadow passes' pipelines when
/// asked: the second's first frame compiles nothing (its own passes were made with it), and it
/// draws the same image. Without the call that frame compiles the shadow passes again.
#[test]
fn renderers_that_share_pipelines_compile_the_shadow_passes_once() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let format = wgpu::TextureFormat::Rgba8UnormSrgb;
    let first_renderer = || penumbra::Renderer::new(&gpu.device, format, ShadowSettings::default()).unwrap();
    let mut first = first_renderer();
    let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, first.layouts(), &scene).unwrap();
    let image = penumbra::render_to_image(&gpu, &mut first, &gpu_scene, &camera, 96, 72).unwrap();
    let grown = |second: &mut penumbra::Renderer| {
        let before = compiled(&gpu.device);
        let second_image = penumbra::render_to_image(&gpu, second, &gpu_scene, &camera, 96, 72).unwrap();
        let after = compiled(&gpu.device);
        (
            std::array::from_fn::<isize, 3, _>(|k| after[k] - before[k]),
            second_image,
        )
    };
    let mut shared = penumbra::Renderer::with_layouts(
        &gpu.device,
        format,
        ShadowSettings::default(),
        first.layouts().clone(),
    )
    .unwrap();
    shared.share_pipelines_with(&first).unwrap();
    let (with_sharing, shared_image) = grown(&mut shared);
    let mut apart = penumbra::Renderer::with_layouts(
        &gpu.device,
        format,
        ShadowSettings::default(),
        first.layouts().clone(),
    )
    .unwrap();
    let (without, apart_image) = grown(&mut apart);
    println!(
        "compiled by a second renderer (render, compute, modules): sharing {with_sharing:?}, apart {without:?}"
    );
    assert!(
        shared_image == image && apart_image == image,
        "the renderers drew different images"
    );
    assert_eq!(
        with_sharing,
        [0, 0, 0],
        "a sharing renderer compiled pipelines or modules"
    );
    assert!(
        without[0] >= 4 && without[1] >= 4,
        "apart, the second renderer compiled {without:?} against {with_sharing:?} sharing"
    );
}
