//! The distance-map method and the methods beside it: contact hardening, penumbra width against
//! the light's size, the conservative mask, numerical stability, the fattened map, pass
//! planning and shadow-map reuse.

mod common;

use glam::{Mat4, Quat, Vec3};
use penumbra::{
    Camera, DirectionalLight, Fattening, GpuScene, HeadlessGpu, Light, LightTexture, Material, Renderer,
    Scene, ShadowMethod, ShadowSettings, SpreadMode, load_scene, scene::primitives,
};

fn settings(method: ShadowMethod) -> ShadowSettings {
    ShadowSettings {
        method,
        ..Default::default()
    }
}

fn sun(direction: Vec3, degrees: f32) -> Light {
    Light::Directional(DirectionalLight {
        direction,
        angular_diameter_deg: degrees,
        color: Vec3::ONE,
        intensity: 1.0,
    })
}

use common::{read_f32 as read, render_frame};

/// A floor with a long bar lying tilted above it: touching the floor at x = -2, 1.5 units up
/// at x = +2, 0.6 wide (|z| < 0.3). The sun shines down and toward +z (0.8 units sideways per
/// unit of drop), so the bar's +z shadow edge lies at z = 0.3 + 0.8 h(x), beside the bar, and
/// the distance from bar to floor grows along it. The camera looks straight down.
const SIDEWAYS: f32 = 0.8;

/// Height of the tilted bar's lower face above the floor at `x`.
fn bar_height(x: f32) -> f32 {
    1.5 * (x + 2.0) / 4.0
}

fn tilted_bar_scene(light_degrees: f32) -> (Scene, Camera) {
    let mut scene = Scene {
        light: sun(Vec3::new(0.0, -1.0, SIDEWAYS), light_degrees),
        ..Default::default()
    };
    let floor_material = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let bar_material = scene.add_material(Material::colored("bar", [0.3, 0.5, 0.8]));
    let floor = scene.add_mesh(primitives::plane(12.0, 1.0));
    scene.add_instance(floor, floor_material, Mat4::IDENTITY).caster = false;
    let length = (4.0f32 * 4.0 + 1.5 * 1.5).sqrt();
    let bar = scene.add_mesh(primitives::cuboid(Vec3::new(length, 0.05, 0.6)));
    let tilt = Quat::from_rotation_z((1.5f32 / 4.0).atan());
    // The bar's lower face touches the floor at x = -2.
    let transform = Mat4::from_rotation_translation(tilt, Vec3::new(0.0, 0.75 + 0.03, 0.0));
    scene.add_instance(bar, bar_material, transform).receiver = false;
    let camera = Camera {
        eye: Vec3::new(0.0, 12.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        fov_y_deg: 30.0,
        near: 5.0,
        far: 20.0,
    };
    (scene, camera)
}

/// 10%-90% width (world units, along z on the floor) of the bar's +z shadow edge at `x`,
/// from the visibility the frame composited. Starts beside the bar inside the shadow and must
/// end in full light.
fn edge_width(what: &str, visibility: &[f32], camera: &Camera, (w, h): (u32, u32), x: f32) -> f32 {
    let sample = |z: f32| {
        let (px, py) = common::project(camera, w, h, Vec3::new(x, 0.0, z)).expect("on screen");
        visibility[(py * w + px) as usize]
    };
    let edge = 0.3 + SIDEWAYS * bar_height(x);
    // Halfway between the bar's edge and the shadow's edge, or 0.3 inside the shadow.
    let start = (edge - 0.3).max((0.3 + edge) / 2.0);
    let zs: Vec<f32> = (0..=800).map(|i| start + i as f32 * 0.001).collect();
    assert!(
        sample(start) < 0.1,
        "{what}, x = {x}: z = {start} should be in shadow, visibility {}",
        sample(start)
    );
    assert!(
        sample(*zs.last().unwrap()) > 0.9,
        "{what}, x = {x}: the far side should be lit"
    );
    let first_above = |level: f32| zs.iter().copied().find(|&z| sample(z) >= level).unwrap();
    let width = first_above(0.9) - first_above(0.1);
    assert!(width > 0.0, "{what}, x = {x}: no penumbra at all");
    width
}

fn bar_edge_widths(gpu: &HeadlessGpu, method: ShadowMethod, degrees: f32) -> (f32, f32) {
    let (scene, camera) = tilted_bar_scene(degrees);
    let size = (900, 900);
    let (image, renderer) = render_frame(gpu, &scene, &camera, settings(method), size);
    if std::env::var_os("PENUMBRA_SAVE_RENDERS").is_some() {
        image
            .save(common::output_dir().join(format!("bar_{}_{degrees}.png", method.name())))
            .unwrap();
    }
    let (visibility, channels) = read(
        gpu,
        renderer.composited_visibility().expect("screen-space method"),
    );
    assert_eq!(channels, 1);
    let what = format!("{} at {degrees} degrees", method.name());
    let widths = (
        edge_width(&what, &visibility, &camera, size, -1.2),
        edge_width(&what, &visibility, &camera, size, 1.6),
    );
    eprintln!(
        "{what}: 10-90% penumbra {:.4} at the contact end, {:.4} at the far end",
        widths.0, widths.1
    );
    widths
}

#[test]
fn penumbrae_harden_at_contact_with_ours_and_pcss_but_not_traditional() {
    let gpu = common::gpu();
    for method in [ShadowMethod::Ours, ShadowMethod::Pcss, ShadowMethod::OursFast] {
        let (near, far) = bar_edge_widths(&gpu, method, 6.0);
        assert!(
            far >= 2.0 * near,
            "{}: far-end penumbra {far:.4} should be at least twice the contact end's {near:.4}",
            method.name()
        );
    }
    let (near, far) = bar_edge_widths(&gpu, ShadowMethod::Traditional, 6.0);
    assert!(
        (far / near - 1.0).abs() <= 0.25,
        "traditional: penumbra should be about constant, got {near:.4} near and {far:.4} far"
    );
}

#[test]
fn penumbra_width_follows_the_light_size() {
    let gpu = common::gpu();
    let (_, far_small) = bar_edge_widths(&gpu, ShadowMethod::Ours, 4.0);
    let (_, far_large) = bar_edge_widths(&gpu, ShadowMethod::Ours, 8.0);
    let ratio = far_large / far_small;
    assert!(
        (ratio - 2.0).abs() <= 0.6,
        "doubling the light doubled the far penumbra by {ratio:.3} ({far_small:.4} -> {far_large:.4})"
    );
    // And it matches the physics: 10%-90% of a disk light's edge is about 0.69 of the full
    // width 2 d tan(theta / 2), d measured along the light; on the floor it stretches by
    // 1 / cos(incidence).
    let cos_incidence = 1.0 / (1.0 + SIDEWAYS * SIDEWAYS).sqrt();
    let d = bar_height(1.6) / cos_incidence;
    let expected = 0.69 * 2.0 * d * (8.0f32.to_radians() / 2.0).tan() / cos_incidence;
    assert!(
        (far_large / expected - 1.0).abs() < 0.5,
        "far penumbra {far_large:.4} vs the disk light's {expected:.4}"
    );
}

#[test]
fn light_size_zero_is_hard_shadows() {
    let gpu = common::gpu();
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    if let Light::Directional(l) = &mut scene.light {
        l.angular_diameter_deg = 0.0;
    }
    let camera = scene.view(0).unwrap();
    let (hard, _) = render_frame(&gpu, &scene, &camera, settings(ShadowMethod::Hard), (320, 256));
    for method in [ShadowMethod::Ours, ShadowMethod::OursFast, ShadowMethod::Pcss] {
        let (image, renderer) = render_frame(&gpu, &scene, &camera, settings(method), (320, 256));
        let plan = renderer.last_report().unwrap().plan;
        assert_eq!(plan.method(), ShadowMethod::Hard, "{}", method.name());
        assert!(
            !plan.chain.fattened_map() && !plan.chain.pcf() && !plan.chain.blur(),
            "{}: {:?}",
            method.name(),
            renderer.last_report().unwrap().passes
        );
        let differing = image.pixels().zip(hard.pixels()).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing,
            0,
            "{}: {differing} pixels differ from hard",
            method.name()
        );
    }
}

#[test]
fn mask_contains_every_hard_shadowed_pixel() {
    let gpu = common::gpu();
    let size = (320, 256);
    for name in ["teapot", "character"] {
        let scene = load_scene(&common::asset(&format!("scenes/{name}.ron"))).unwrap();
        for view in 0..3 {
            let camera = scene.view(view).unwrap();
            let (hard, without) = common::render_with_and_without_casters(
                &gpu,
                &scene,
                &camera,
                settings(ShadowMethod::Hard),
                size.0,
                size.1,
            );
            let (_, renderer) = render_frame(&gpu, &scene, &camera, settings(ShadowMethod::Ours), size);
            let (distance, channels) = read(&gpu, renderer.debug_texture(LightTexture::DistanceMap).unwrap());
            let channels = channels as usize;
            let mut shadowed = 0;
            let mut outside = 0;
            for (i, (a, b)) in hard.pixels().zip(without.pixels()).enumerate() {
                if (a[1] as f32) < 0.9 * b[1] as f32 {
                    shadowed += 1;
                    let px = &distance[i * channels..(i + 1) * channels];
                    if penumbra::debug::distance_and_mask(px).1 < 0.5 {
                        outside += 1;
                    }
                }
            }
            assert!(
                shadowed > 100,
                "{name} view {view}: only {shadowed} shadowed pixels"
            );
            assert_eq!(
                outside, 0,
                "{name} view {view}: {outside} of {shadowed} hard-shadowed pixels lie outside the mask"
            );
        }
    }
}

/// Both fattened maps, drawn and derived from the shadow map (`Fattening::Dilation`), bound
/// every penumbra: no pixel where the reference is in a penumbra lies outside the mask, under a
/// sun (the teapot's views 0 and 2, the character's 1) and under the room's lamp (a point
/// light's cube, its near casters fattened most; there the drawn map misses a few, see below).
/// The derived map without the exit map, whose absence changes only the distances.
#[test]
fn every_fattened_map_holds_the_references_penumbrae() {
    let gpu = common::gpu();
    let size = (200, 160);
    let views = [("teapot", 0), ("teapot", 2), ("character", 1), ("room", 0)];
    for (name, view) in views {
        let scene = load_scene(&common::asset(&format!("scenes/{name}.ron"))).unwrap();
        let camera = scene.view(view).unwrap();
        let mut reference = settings(ShadowMethod::Reference);
        reference.reference.samples = 64;
        let reference =
            penumbra::metrics::measure_visibility(&gpu, &scene, &camera, reference, size).unwrap();
        for (fattening, exit_map) in [(Fattening::Geometry, true), (Fattening::Dilation, false)] {
            let mut s = settings(ShadowMethod::Ours);
            s.penumbra.fattening = fattening;
            s.penumbra.exit_map = exit_map;
            let (_, renderer) = render_frame(&gpu, &scene, &camera, s, size);
            let chain = renderer.last_report().unwrap().plan.chain;
            // These scenes' few casters: the exit map has its own pass (`ExitMapDraw::Auto`);
            // the derived map leaves it out.
            assert_eq!(
                chain.light_maps(),
                if fattening == Fattening::Dilation { 1 } else { 3 },
                "{name} view {view}: {chain:?}"
            );
            let (distance, channels) = read(&gpu, renderer.debug_texture(LightTexture::DistanceMap).unwrap());
            let channels = channels as usize;
            let (mut penumbra, mut outside) = (0, 0);
            for (i, r) in reference.visibility.iter().enumerate() {
                if r.is_some_and(|r| r > 0.02 && r < 0.98) {
                    penumbra += 1;
                    // The mask: 1 inside, 0 outside, below 0 where nothing receives.
                    let px = &distance[i * channels..(i + 1) * channels];
                    if penumbra::debug::distance_and_mask(px).1 == 0.0 {
                        outside += 1;
                    }
                }
            }
            assert!(
                penumbra > 100,
                "{name} view {view}: only {penumbra} penumbra pixels"
            );
            // Known: under the room's lamp the drawn map leaves out 52 of 5823 (0.9%) at this
            // size; held there, not hidden.
            let allowed = if name == "room" && fattening == Fattening::Geometry {
                penumbra / 100
            } else {
                0
            };
            assert!(
                outside <= allowed,
                "{name} view {view}, {fattening:?}: {outside} of {penumbra} penumbra pixels of the reference lie outside the mask"
            );
        }
    }
}

#[test]
fn intermediates_stay_finite_at_extreme_settings() {
    let gpu = common::gpu();
    let base = load_scene(&common::asset("scenes/character.ron")).unwrap();
    let camera = base.view(0).unwrap();
    let mut cases: Vec<(String, ShadowSettings, f32)> = Vec::new();
    for degrees in [0.0, 0.5, 45.0] {
        for method in [
            ShadowMethod::Ours,
            ShadowMethod::OursFast,
            ShadowMethod::Traditional,
            ShadowMethod::Pcss,
        ] {
            cases.push((
                format!("{} at {degrees} degrees", method.name()),
                settings(method),
                degrees,
            ));
        }
    }
    for fatten in [0.0, 1e3] {
        for spread in [0.0, 1e3] {
            let mut s = settings(ShadowMethod::Ours);
            s.penumbra.spreads = SpreadMode::Manual {
                fatten_distance: fatten,
                pcf_spread: spread,
                blur_spread: spread,
            };
            cases.push((format!("manual fatten {fatten} spreads {spread}"), s, 3.0));
        }
    }
    for (what, s, degrees) in cases {
        let mut scene = base.clone();
        if let Light::Directional(l) = &mut scene.light {
            l.angular_diameter_deg = degrees;
        }
        let (image, renderer) = render_frame(&gpu, &scene, &camera, s, (160, 128));
        let textures = LightTexture::ALL
            .into_iter()
            .map(|which| (format!("{which:?}"), renderer.debug_texture(which)))
            .chain([("camera depth".to_string(), renderer.camera_depth_texture())]);
        for (which, texture) in textures {
            let Some(texture) = texture else {
                continue;
            };
            let (values, channels) = read(&gpu, texture);
            let bad = values.iter().filter(|v| !v.is_finite()).count();
            assert_eq!(bad, 0, "{what}: {bad} non-finite values in {which:?}");
            if which == "Visibility" || which == "BlurredVisibility" {
                // The visibility is the first channel (the compute path's raw visibility
                // carries the blur's deviations beside it).
                assert!(
                    values
                        .chunks_exact(channels as usize)
                        .all(|v| (0.0..=1.0).contains(&v[0])),
                    "{what}: visibility outside [0, 1] in {which:?}"
                );
            }
        }
        let first = *image.get_pixel(0, image.height() - 1);
        assert!(image.pixels().any(|p| *p != first), "{what}: a one-color frame");
    }
}

#[test]
fn flat_shaded_cube_fattens_into_a_closed_shape() {
    let gpu = common::gpu();
    let mut scene = Scene {
        light: sun(Vec3::new(0.4, -1.0, 0.3), 10.0),
        ..Default::default()
    };
    let material = scene.add_material(Material::colored("cube", [0.8, 0.8, 0.8]));
    let floor_material = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    assert_eq!(scene.meshes[cube].vertex_count(), 24, "split per-face normals");
    scene.add_instance(
        cube,
        material,
        Mat4::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(0.0, 1.5, 0.0)),
    );
    let floor = scene.add_mesh(primitives::plane(10.0, 1.0));
    scene.add_instance(floor, floor_material, Mat4::IDENTITY).caster = false;
    let mut s = settings(ShadowMethod::Ours);
    s.shadow_map.resolution = 512;
    // One map (no cascade atlas), read texel by texel below.
    s.shadow_map.cascades.count = 1;
    s.penumbra.spreads = SpreadMode::Manual {
        fatten_distance: 0.15,
        pcf_spread: 1.0,
        blur_spread: 1.0,
    };
    let camera = scene
        .view(0)
        .unwrap_or(Camera::look_at(Vec3::new(0.0, 5.0, 6.0), Vec3::ZERO));
    let (_, renderer) = render_frame(&gpu, &scene, &camera, s, (64, 64));
    let (real, _) = read(&gpu, renderer.debug_texture(LightTexture::ShadowMap).unwrap());
    let (fat, _) = read(&gpu, renderer.debug_texture(LightTexture::FattenedMap).unwrap());
    // The fattened map has half the shadow map's resolution: a fattened texel covers 2 x 2
    // shadow-map texels.
    let side = 256usize;
    assert_eq!(fat.len(), side * side);
    let covered = |d: &[f32], i: usize| d[i] < 1.0;
    let real_at = |i: usize| {
        let (x, y) = (i % side, i / side);
        [(0, 0), (1, 0), (0, 1), (1, 1)]
            .iter()
            .any(|(dx, dy)| covered(&real, (2 * y + dy) * 512 + 2 * x + dx))
    };
    let real_area = (0..side * side).filter(|&i| real_at(i)).count();
    let fat_area = (0..side * side).filter(|&i| covered(&fat, i)).count();
    assert!(real_area > 250, "the cube covers {real_area} fattened-map texels");
    assert!(
        (0..side * side).all(|i| !real_at(i) || covered(&fat, i)),
        "the fattened map must contain the real one"
    );
    assert!(
        fat_area as f32 > real_area as f32 * 1.1,
        "fattening grew {real_area} texels only to {fat_area}"
    );
    // Holes: uncovered texels not connected to the map's border.
    let mut outside = vec![false; side * side];
    let mut stack: Vec<usize> = (0..side)
        .flat_map(|k| [k, (side - 1) * side + k, k * side, k * side + side - 1])
        .filter(|&i| !covered(&fat, i))
        .collect();
    while let Some(i) = stack.pop() {
        if outside[i] || covered(&fat, i) {
            continue;
        }
        outside[i] = true;
        let (x, y) = (i % side, i / side);
        if x > 0 {
            stack.push(i - 1);
        }
        if x + 1 < side {
            stack.push(i + 1);
        }
        if y > 0 {
            stack.push(i - side);
        }
        if y + 1 < side {
            stack.push(i + side);
        }
    }
    let holes = (0..side * side)
        .filter(|&i| !covered(&fat, i) && !outside[i])
        .count();
    assert_eq!(holes, 0, "the fattened cube has {holes} texels of holes");
}

#[test]
fn camera_moves_reuse_the_shadow_maps() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    // One map: the camera-fitted window covers every caster from both views. (Cascades
    // follow the camera: tests/embedding/embedding.rs checks that a small move keeps them.)
    let mut one_map = settings(ShadowMethod::Ours);
    one_map.shadow_map.cascades.count = 1;
    let mut renderer = Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, one_map).unwrap();
    let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let frame = |renderer: &mut Renderer, scene: &GpuScene, camera: &Camera| {
        penumbra::render_to_image(&gpu, renderer, scene, camera, 96, 64).unwrap();
        renderer.last_report().unwrap().clone()
    };
    let first = frame(&mut renderer, &gpu_scene, &scene.view(0).unwrap());
    assert!(first.light.shadow_maps_rendered);
    assert_eq!(
        first.passes,
        [
            "depth prepass",
            "shadow map",
            "fattened shadow map",
            "exit map",
            "distance map",
            "pcf",
            "blur",
            "composite"
        ]
    );
    let second = frame(&mut renderer, &gpu_scene, &scene.view(1).unwrap());
    assert!(
        !second.light.shadow_maps_rendered,
        "a camera move must not re-render the shadow maps"
    );
    // The maps are not drawn again: only the screen-space chain and the renderer's passes.
    assert_eq!(
        second.passes,
        ["depth prepass", "distance map", "pcf", "blur", "composite"]
    );
    // Geometry is drawn twice on a camera move (prepass and composite), five times when the
    // maps are re-rendered too (the teapot's few triangles: the exit map has its own pass).
    assert_eq!(second.plan.geometry_passes(second.light.shadow_maps_rendered), 2);
    assert_eq!(second.plan.geometry_passes(true), 5);
    let mut light = scene.light;
    if let Light::Directional(l) = &mut light {
        l.direction.x += 0.1;
    }
    gpu_scene.set_light(light).unwrap();
    assert!(
        frame(&mut renderer, &gpu_scene, &scene.view(1).unwrap())
            .light
            .shadow_maps_rendered,
        "a light move must"
    );
}

#[test]
fn passes_the_method_does_not_use_are_not_allocated() {
    // Passes are made on the first frame that needs them and dropped on the first frame that
    // no longer does.
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let mut renderer = Renderer::new(
        &gpu.device,
        wgpu::TextureFormat::Rgba8UnormSrgb,
        settings(ShadowMethod::Hardware2x2),
    )
    .unwrap();
    let gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
    let camera = scene.view(0).unwrap();
    let frame = |renderer: &mut Renderer, method| {
        renderer.set_settings(&gpu.device, settings(method)).unwrap();
        penumbra::render_to_image(&gpu, renderer, &gpu_scene, &camera, 96, 64).unwrap();
    };
    frame(&mut renderer, ShadowMethod::Hardware2x2);
    assert!(renderer.debug_texture(LightTexture::ShadowMap).is_some());
    assert!(
        renderer.camera_depth_texture().is_none(),
        "hw2x2 allocated a camera depth"
    );
    // Everything but the shadow map is left unmade.
    for t in LightTexture::ALL.into_iter().skip(1) {
        assert!(renderer.debug_texture(t).is_none(), "hw2x2 allocated {t:?}");
    }
    frame(&mut renderer, ShadowMethod::Ours);
    // The tile classes exist only where the classification runs (by default on software
    // rasterizers only), so they are not asked of every device. Where the variable PCF writes
    // the light's layer (`Chain::pcf_in_layer`) there is no raw visibility to read.
    let pcf_in_layer = renderer.last_report().unwrap().plan.chain.pcf_in_layer();
    for t in LightTexture::ALL
        .into_iter()
        .filter(|t| *t != LightTexture::TileClasses)
    {
        let expected = !(pcf_in_layer && t == LightTexture::Visibility);
        assert_eq!(
            renderer.debug_texture(t).is_some(),
            expected,
            "ours: {t:?} (the PCF writing the layer: {pcf_in_layer})"
        );
    }
    assert!(
        renderer.camera_depth_texture().is_some(),
        "ours lacks the camera depth"
    );
    frame(&mut renderer, ShadowMethod::Pcss);
    assert!(renderer.debug_texture(LightTexture::FattenedMap).is_none());
    assert!(renderer.debug_texture(LightTexture::DistanceMap).is_none());
    assert!(renderer.debug_texture(LightTexture::BlurredVisibility).is_none());
    assert!(renderer.debug_texture(LightTexture::Visibility).is_some());
}

/// Which pixels lie within 8 pixels of a jump in camera depth, where a blur can smear shadow
/// (or light) in from another surface: the paper's ghosting.
fn near_depth_jumps(gpu: &HeadlessGpu, scene: &Scene, camera: &Camera, (w, h): (u32, u32)) -> Vec<bool> {
    let (_, renderer) = render_frame(gpu, scene, camera, settings(ShadowMethod::Ours), (w, h));
    let (depth, _) = read(gpu, renderer.camera_depth_texture().unwrap());
    let mut near = vec![false; (w * h) as usize];
    for y in 8..h - 8 {
        for x in 8..w - 8 {
            let i = (y * w + x) as usize;
            near[i] = depth[i] > 0.0
                && [(8i32, 0i32), (-8, 0), (0, 8), (0, -8)].iter().any(|(dx, dy)| {
                    let j = ((y as i32 + dy) * w as i32 + x as i32 + dx) as usize;
                    // Reversed depth is proportional to 1 / view distance: a 5% change.
                    (depth[j] - depth[i]).abs() > 0.05 * depth[i].max(1e-9)
                });
        }
    }
    near
}

#[test]
fn depth_aware_blur_bleeds_less_across_depth_jumps() {
    let gpu = common::gpu();
    let size = (320, 256);
    // Squared visibility error against the reference near depth jumps, with and without
    // depth-aware weights.
    let (mut plain, mut aware) = (0.0f64, 0.0f64);
    for name in ["teapot", "character"] {
        let mut scene = load_scene(&common::asset(&format!("scenes/{name}.ron"))).unwrap();
        // A large light makes wide blurs, where bleeding shows.
        if let Light::Directional(l) = &mut scene.light {
            l.angular_diameter_deg = 8.0;
        }
        for view in 0..3 {
            let camera = scene.view(view).unwrap();
            let near = near_depth_jumps(&gpu, &scene, &camera, size);
            let measure = |s: ShadowSettings| {
                penumbra::metrics::measure_visibility(&gpu, &scene, &camera, s, size).unwrap()
            };
            let reference = measure(settings(ShadowMethod::Reference));
            let error = |depth_aware: bool| {
                let mut s = settings(ShadowMethod::Ours);
                s.penumbra.depth_aware_blur = depth_aware;
                let v = measure(s);
                let mut sum = 0.0f64;
                for (i, (r, t)) in reference.visibility.iter().zip(&v.visibility).enumerate() {
                    if let (true, Some(r), Some(t)) = (near[i], r, t) {
                        sum += ((r - t) as f64).powi(2);
                    }
                }
                sum
            };
            let (p, a) = (error(false), error(true));
            eprintln!("{name} view {view}: squared error near depth jumps {p:.1} plain, {a:.1} depth-aware");
            plain += p;
            aware += a;
        }
    }
    assert!(plain > 1.0, "no error near depth jumps to measure ({plain})");
    assert!(
        aware < 0.95 * plain,
        "depth-aware weights should cut the error near depth jumps: {plain:.1} -> {aware:.1}"
    );
}

#[test]
fn indirect_light_lightens_far_shadows_more_than_contact_shadows() {
    let gpu = common::gpu();
    let (scene, camera) = tilted_bar_scene(6.0);
    let size = (600, 600);
    let render = |weight: f32| {
        let mut s = settings(ShadowMethod::Ours);
        s.penumbra.indirect_weight = weight;
        render_frame(&gpu, &scene, &camera, s, size).0
    };
    let (plain, bounced) = (render(0.0), render(0.6));
    // Shadow centers beside the bar, near the contact end and at the far end, in linear light.
    let linear = |img: &image::RgbaImage, x: f32| {
        let z = 0.3 + SIDEWAYS * bar_height(x) - 0.1;
        let (px, py) = common::project(&camera, size.0, size.1, Vec3::new(x, 0.0, z)).unwrap();
        let c = img.get_pixel(px, py)[1] as f32 / 255.0;
        ((c + 0.055) / 1.055).powf(2.4)
    };
    let near_gain = linear(&bounced, -1.2) - linear(&plain, -1.2);
    let far_gain = linear(&bounced, 1.6) - linear(&plain, 1.6);
    assert!(far_gain > 0.02, "far shadow gained only {far_gain:.3}");
    // The gain follows d / (d + h): larger where the occluder is farther.
    assert!(
        far_gain > 1.3 * near_gain.max(0.0),
        "far gain {far_gain:.3} vs contact gain {near_gain:.3}"
    );
    // Lit floor is untouched.
    let open = common::project(&camera, size.0, size.1, Vec3::new(0.0, 0.0, -1.5)).unwrap();
    assert_eq!(plain.get_pixel(open.0, open.1), bounced.get_pixel(open.0, open.1));
}

/// Reduced resolution (`PenumbraSettings::reduced_resolution`): on the teapot under a large
/// light (wide penumbrae), PCF at half resolution where the penumbra is wide changes the raw
/// PCF visibility on many pixels, keeps it bit for bit next to every depth jump and on the
/// pixels that take the taps themselves, and leaves the penumbra's error against the reference
/// where full resolution has it.
#[test]
fn reduced_resolution_keeps_the_penumbra_and_full_resolution_at_depth_edges() {
    let gpu = common::gpu();
    let (w, h) = (640u32, 512u32);
    let mut scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    if let Light::Directional(l) = &mut scene.light {
        l.angular_diameter_deg = 8.0;
    }
    let camera = scene.view(0).unwrap();
    let with = |reduced: bool| {
        let mut s = settings(ShadowMethod::Ours);
        s.penumbra.reduced_resolution = reduced;
        // Reduced resolution is drawn: full resolution too, so that the two differ only there.
        s.penumbra.fragment_passes = true;
        s
    };
    // The raw PCF visibility (before the blur) and the camera depth.
    let raw = |reduced: bool| {
        let (_, renderer) = render_frame(&gpu, &scene, &camera, with(reduced), (w, h));
        let (pcf, channels) = read(&gpu, renderer.debug_texture(LightTexture::Visibility).unwrap());
        let pcf: Vec<f32> = pcf.chunks_exact(channels as usize).map(|c| c[0]).collect();
        let (depth, _) = read(&gpu, renderer.camera_depth_texture().unwrap());
        (pcf, depth)
    };
    let ((half, depth), (full, _)) = (raw(true), raw(false));
    let differs = |i: usize| (half[i] - full[i]).abs() > 1e-6;
    let changed = (0..half.len()).filter(|&i| differs(i)).count();
    eprintln!(
        "reduced resolution: {changed} of {} raw PCF values changed",
        half.len()
    );
    assert!(changed > 2000, "half resolution served too few pixels: {changed}");
    let (mut edge_pixels, mut block_pixels) = (0, 0);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = (y * w + x) as usize;
            // The top-left pixel of each 2 x 2 block is the one the half-resolution draw
            // computes: the same taps at the same pixel.
            if x % 2 == 0 && y % 2 == 0 && depth[i] > 0.0 {
                block_pixels += 1;
                assert!(
                    !differs(i),
                    "({x}, {y}) takes the block's own taps: {} != {}",
                    half[i],
                    full[i]
                );
            }
            // Reversed depth is proportional to 1 / view distance: a 3% jump to a neighbour.
            let jump = [(1i32, 0i32), (-1, 0), (0, 1), (0, -1)].iter().any(|(dx, dy)| {
                let j = ((y as i32 + dy) * w as i32 + x as i32 + dx) as usize;
                (depth[j] - depth[i]).abs() > 0.03 * depth[i].max(depth[j])
            });
            if jump && depth[i] > 0.0 {
                edge_pixels += 1;
                assert!(
                    !differs(i),
                    "({x}, {y}) lies at a depth jump: {} != {}",
                    half[i],
                    full[i]
                );
            }
        }
    }
    assert!(
        edge_pixels > 100 && block_pixels > 10_000,
        "{edge_pixels} edge, {block_pixels} block pixels"
    );

    let measure =
        |s: ShadowSettings| penumbra::metrics::measure_visibility(&gpu, &scene, &camera, s, (w, h)).unwrap();
    let reference = measure(settings(ShadowMethod::Reference));
    let error = |reduced: bool| {
        penumbra::metrics::visibility_error(&reference, &measure(with(reduced)))
            .unwrap()
            .penumbra_rmse
    };
    let (reduced, full) = (error(true), error(false));
    eprintln!("penumbra RMSE against the reference: {reduced:.4} at reduced resolution, {full:.4} at full");
    assert!(
        reduced <= full * 1.03 + 1e-3,
        "reduced resolution costs accuracy: {full:.4} -> {reduced:.4}"
    );
}

/// The tiles whose surfaces all face away from the light
/// (`PenumbraSettings::skip_tiles_facing_away`, on by default) are listed apart and get
/// visibility 0 without the passes' taps. The teapot's own far side is such a surface: the frame
/// must be what the passes over those tiles give, and so must the visibility there, near 0.
#[test]
fn tiles_facing_away_from_the_light_get_no_light_and_the_frame_stays() {
    let gpu = common::gpu();
    let size = (640, 512);
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let mut without = settings(ShadowMethod::Ours);
    without.penumbra.skip_tiles_facing_away = false;
    let (image_with, with) = render_frame(&gpu, &scene, &camera, settings(ShadowMethod::Ours), size);
    let (image_without, without) = render_frame(&gpu, &scene, &camera, without, size);
    let classes = |r: &Renderer| read(&gpu, r.debug_texture(LightTexture::TileClasses).unwrap()).0;
    let (classes_with, classes_without) = (classes(&with), classes(&without));
    let away = |c: &[f32]| c.iter().filter(|v| (**v - 0.25).abs() < 1e-3).count();
    let listed = classes_with.iter().filter(|v| **v >= 0.5).count();
    assert_eq!(
        away(&classes_without),
        0,
        "tiles listed apart with the switch off"
    );
    assert_eq!(
        classes_without.iter().filter(|v| **v >= 0.5).count(),
        listed + away(&classes_with),
        "the tiles listed apart are kept tiles"
    );
    let layer = |r: &Renderer| read(&gpu, r.debug_texture(LightTexture::BlurredVisibility).unwrap()).0;
    let (layer_with, layer_without) = (layer(&with), layer(&without));
    let tiles_across = size.0.div_ceil(16) as usize;
    let (mut zero, mut sum, mut worst) = (0usize, 0.0f32, 0.0f32);
    for (i, (a, b)) in layer_with.iter().zip(&layer_without).enumerate() {
        let (x, y) = (i % size.0 as usize, i / size.0 as usize);
        if (classes_with[(y / 16) * tiles_across + x / 16] - 0.25).abs() >= 1e-3 {
            continue;
        }
        // Nothing drawn there reads 1, as the resolve writes.
        assert!(
            *a == 0.0 || *a == 1.0,
            "pixel {x},{y} of a tile turned away reads {a}"
        );
        if *a == 0.0 {
            zero += 1;
            sum += b;
            worst = worst.max(*b);
        }
    }
    let mean = sum / zero.max(1) as f32;
    let worst_step = image_with
        .pixels()
        .zip(image_without.pixels())
        .map(|(a, b)| (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap())
        .collect::<Vec<_>>();
    let differing = worst_step.iter().filter(|d| **d > 2).count();
    let away_tiles = away(&classes_with);
    eprintln!(
        "{away_tiles} tiles listed apart of {}, {zero} pixels at 0; the passes gave them mean {mean} max {worst}; {differing} frame pixels differ by more than 2",
        listed + away_tiles
    );
    // 40 of 460 at this size (the teapot's far side; 194 of 1243 at 1280x1024).
    assert!(
        away_tiles * 20 >= listed + away_tiles,
        "only {away_tiles} of {} kept tiles listed apart",
        listed + away_tiles
    );
    assert!(zero > 5000, "only {zero} pixels of those tiles read 0");
    // What the passes gave there is the surface's own shadow, near 0 (0.055 measured).
    assert!(
        mean < 0.1,
        "the passes gave the tiles turned away a mean visibility of {mean}"
    );
    // The lit pass's cosine is 0 there: the frame stays (none differed by more than 2/255).
    assert!(
        differing <= 50 && worst_step.iter().all(|d| *d <= 8),
        "{differing} frame pixels differ by more than 2/255"
    );
}

/// The tiles deep in the umbra (`PenumbraSettings::skip_umbra_tiles`, off by default) are listed
/// apart and get visibility 0 without the passes: there every tap finds a caster in front and
/// the blur reads only such pixels. Under a small sun the teapot's shadow on the floor holds
/// many; under the room's lamp (a point light), the floor under the desk. On the teapot's floor
/// the passes over those tiles gave 0 and every other pixel keeps its visibility, to the bit. In
/// the room the depth-aware blur carried a little light across a depth edge (the foot of a
/// chair leg, lit, beside a tile of floor in the umbra: 0.007 measured, and 0.003 in the
/// vertical blur of the pixels above that tile); the tile listed apart reads 0, as the
/// reference does there.
#[test]
fn tiles_deep_in_the_umbra_get_what_the_passes_would_give() {
    let gpu = common::gpu();
    let size = (640, 512);
    let mut teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    if let Light::Directional(l) = &mut teapot.light {
        l.angular_diameter_deg = 0.75;
    }
    let room = load_scene(&common::asset("scenes/room.ron")).unwrap();
    for (name, scene, least, tolerance) in [
        ("the teapot under a 0.75-degree sun", teapot, 20, 0.0),
        ("the room", room, 20, 0.01),
    ] {
        let camera = scene.view(0).unwrap();
        let mut on = settings(ShadowMethod::Ours);
        on.penumbra.skip_umbra_tiles = true;
        let mut without = settings(ShadowMethod::Ours);
        without.penumbra.skip_umbra_tiles = false;
        let (_, with) = render_frame(&gpu, &scene, &camera, on, size);
        let (_, without) = render_frame(&gpu, &scene, &camera, without, size);
        let classes = |r: &Renderer| read(&gpu, r.debug_texture(LightTexture::TileClasses).unwrap()).0;
        let (classes_with, classes_without) = (classes(&with), classes(&without));
        let umbra = |c: &[f32]| c.iter().filter(|v| (**v - 0.375).abs() < 1e-3).count();
        assert_eq!(
            umbra(&classes_without),
            0,
            "{name}: tiles listed apart with the switch off"
        );
        let umbra_tiles = umbra(&classes_with);
        let layer = |r: &Renderer| read(&gpu, r.debug_texture(LightTexture::BlurredVisibility).unwrap()).0;
        let (layer_with, layer_without) = (layer(&with), layer(&without));
        let tiles_across = size.0.div_ceil(16) as usize;
        let (mut inside, mut worst_inside, mut worst_outside) = (0usize, 0.0f32, 0.0f32);
        for (i, (a, b)) in layer_with.iter().zip(&layer_without).enumerate() {
            let (x, y) = (i % size.0 as usize, i / size.0 as usize);
            if (classes_with[(y / 16) * tiles_across + x / 16] - 0.375).abs() < 1e-3 {
                // Nothing drawn there (or no receiver) reads 1, as the resolve writes.
                assert!(
                    *a == 0.0 || *a == 1.0,
                    "{name}: pixel {x},{y} of a tile in the umbra reads {a}"
                );
                if *a == 0.0 {
                    inside += 1;
                    worst_inside = worst_inside.max(*b);
                } else {
                    assert_eq!(a, b, "{name}: pixel {x},{y} receives no shadow");
                }
            } else {
                worst_outside = worst_outside.max((a - b).abs());
            }
        }
        eprintln!(
            "{name}: {umbra_tiles} tiles in the umbra, {inside} pixels at 0 where the passes gave at most {worst_inside}; elsewhere the visibility moved by at most {worst_outside}"
        );
        assert!(
            umbra_tiles >= least,
            "{name}: only {umbra_tiles} tiles listed apart in the umbra"
        );
        assert!(
            worst_inside <= tolerance,
            "{name}: the passes gave a tile listed apart in the umbra {worst_inside}"
        );
        assert!(
            worst_outside <= tolerance,
            "{name}: the visibility beside the tiles in the umbra moved by {worst_outside}"
        );
    }
}
