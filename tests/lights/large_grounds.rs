//! A sun (and a lamp) over a ground far wider than the view (a terrain, a game's 500,000-unit plane) that
//! casts as every mesh of an engine does: the teapot on its 18-unit floor, made a caster, then
//! on a 2,000- and a 500,000-unit one. The camera keeps the teapot in view (its near plane
//! follows what stands in front of it, not the ground's extent), and with a shadow distance
//! the sun's maps cover the view, not the ground: the penumbra error against each floor's own
//! reference stays within 1.05x the 18-unit floor's. Without one, the frame's report names the
//! caster whose shadow the maps cannot hold. The visibility images are written to
//! `target/penumbra-test-output/large-ground-*.png`.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, Light, LightFit, PointLight, Quality, Renderer, Scene, ShadowMethod, ShadowSettings,
    metrics::{measure_visibility, visibility_error},
};

const SIZE: (u32, u32) = (320, 256);
/// World units from the camera that the sun's maps cover.
const SHADOW_DISTANCE: f32 = 20.0;

/// The teapot scene with its floor scaled to `size` units a side and made a caster, and its
/// front view's camera with near and far fitted as a scene file fits them.
fn teapot_on(size: f32) -> (Scene, Camera) {
    teapot_under(size, None)
}

/// A lamp 5 units above the floor, beside the teapot: a point light of radius 0.15.
fn lamp() -> Light {
    Light::Point(PointLight {
        position: Vec3::new(1.0, 5.0, 1.0),
        radius: 0.15,
        color: Vec3::ONE,
        intensity: 100.0,
        range: None,
    })
}

/// [`teapot_on`], lit by `light` where one is given (the scene's sun otherwise).
fn teapot_under(size: f32, light: Option<Light>) -> (Scene, Camera) {
    let mut scene = penumbra::load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    if let Some(light) = light {
        scene.light = light;
    }
    let floor = scene
        .instances
        .iter_mut()
        .find(|i| !i.caster)
        .expect("the teapot scene's floor");
    floor.caster = true;
    floor.transform = Mat4::from_scale(Vec3::new(size / 18.0, 1.0, size / 18.0)) * floor.transform;
    let view = &scene.views[0].camera;
    let mut camera = Camera {
        near: 0.1,
        far: 100.0,
        ..*view
    };
    camera.fit_depth_range(&scene.bounds());
    (scene, camera)
}

fn settings(method: ShadowMethod, max_distance: f32) -> ShadowSettings {
    let mut settings = if method == ShadowMethod::Reference {
        let mut s = ShadowSettings {
            method,
            ..Default::default()
        };
        s.reference.samples = 64;
        s
    } else {
        ShadowSettings::preset(method, Quality::Medium)
    };
    settings.shadow_map.fit = LightFit::CameraFrustum { max_distance };
    settings
}

fn save(name: &str, v: &penumbra::metrics::VisibilityImage) {
    let grey = image::GrayImage::from_fn(v.width, v.height, |x, y| {
        let value = v.visibility[(y * v.width + x) as usize].unwrap_or(0.0);
        image::Luma([(value * 255.0).round() as u8])
    });
    grey.save(common::output_dir().join(format!("large-ground-{name}.png")))
        .unwrap();
}

#[test]
fn a_ground_far_wider_than_the_view_keeps_the_teapots_shadow() {
    floors_keep_the_shadow("sun", None, &[2_000.0, 500_000.0]);
}

/// A lamp over the ground (a point light 5 units above it, no shadow distance: a point light's
/// maps are not fitted to the view). Its maps' far plane lay behind the ground's farthest corner,
/// and the near plane, kept within a thousandth of it for the depths' precision, 14 units from
/// the lamp over the 20,000-unit floor (357 over a 500,000-unit one): the teapot, 1.8 units from
/// it, cast no shadow at all, with every method and in the reference (3 of 49,220 pixels
/// shadowed). Now the far plane comes in instead (`perspective_depth_range` in
/// src/light_space/fit.rs). Not held: a 500,000-unit floor of two triangles, whose depths in the
/// lamp's cube faces come out speckled behind the teapot, in the reference too (lavapipe; `ours`
/// 4.4x the 18-unit floor's error there): the rasterizer clips triangles 250,000 units across
/// at the faces' near plane in 32-bit floats. The same floor as 200 x 200 quads is clean.
#[test]
fn a_lamp_over_a_ground_far_wider_than_the_view_keeps_the_teapots_shadow() {
    floors_keep_the_shadow("lamp", Some(lamp()), &[2_000.0, 20_000.0]);
    // The report says where the maps end: over the 20,000-unit floor a thousand times the near
    // plane, before the floor's far corners; over the 18-unit floor they reach every part.
    let gpu = common::gpu();
    let reach = |size: f32, range: Option<f32>| {
        let mut light = lamp();
        if let Light::Point(p) = &mut light {
            p.range = range;
        }
        let (scene, camera) = teapot_under(size, Some(light));
        let mut renderer = Renderer::new(
            &gpu.device,
            wgpu::TextureFormat::Rgba8UnormSrgb,
            settings(ShadowMethod::Ours, 0.0),
        )
        .unwrap();
        let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
        penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 160, 128).unwrap();
        let view = renderer.last_report().unwrap().light.light_view;
        (view.shadow_reach, view.near, view.far)
    };
    let (wide, near, far) = reach(20_000.0, None);
    eprintln!("lamp over the 20000-unit floor: maps end at {wide:?} (near {near}, far {far})");
    assert!(
        wide.is_some_and(|r| r == far && (near * 999.0..=near * 1001.0).contains(&r) && r < 14_000.0),
        "{wide:?}, near {near}, far {far}"
    );
    assert_eq!(reach(18.0, None).0, None);
    // A range that ends the maps first: nothing is lost to the depths' precision.
    assert_eq!(reach(20_000.0, Some(100.0)).0, None);
}

/// The teapot on the 18-unit floor and the `wider` ones under `light` (the scene's sun where
/// `None`): the reference's shadow is in the picture, and `ours`' penumbra RMSE against it on
/// the wider floors is within 1.05x the 18-unit floor's (1.1x until the sun's depth range
/// stopped being padded by the scene's radius: the 500,000-unit floor read 1.094x).
fn floors_keep_the_shadow(name: &str, light: Option<Light>, wider: &[f32]) {
    let gpu = common::gpu();
    let mut errors = Vec::new();
    for size in std::iter::once(18.0).chain(wider.iter().copied()) {
        let (scene, camera) = teapot_under(size, light);
        assert!(
            camera.near < 5.0,
            "{name}, {size}-unit floor: the camera's near plane at {} clips the teapot",
            camera.near
        );
        let measure = |method: ShadowMethod| {
            let v =
                measure_visibility(&gpu, &scene, &camera, settings(method, SHADOW_DISTANCE), SIZE).unwrap();
            save(&format!("{name}-{size}-{}", method.name()), &v);
            v
        };
        let truth = measure(ShadowMethod::Reference);
        // The teapot's shadow is in the picture: some of the floor is in the umbra, most lit.
        let measured = truth.visibility.iter().flatten().count();
        let shadowed = truth.visibility.iter().flatten().filter(|&&v| v < 0.05).count();
        assert!(
            shadowed > measured / 100 && shadowed < measured / 3,
            "{name}, {size}-unit floor: {shadowed} of {measured} pixels shadowed in the reference"
        );
        let ours = measure(ShadowMethod::Ours);
        let error = visibility_error(&truth, &ours).unwrap();
        eprintln!(
            "{name}, {size}-unit floor: near {:.3} far {:.0}; ours penumbra RMSE {:.4} over {} pixels (RMSE {:.4})",
            camera.near, camera.far, error.penumbra_rmse, error.penumbra_pixels, error.rmse
        );
        assert!(
            error.penumbra_pixels > 200,
            "{name}, {size}-unit floor: no penumbra measured"
        );
        errors.push((size, error.penumbra_rmse));
    }
    let base = errors[0].1;
    for (size, e) in &errors[1..] {
        eprintln!(
            "{name}, {size}-unit floor: {:.3}x the 18-unit floor's penumbra RMSE",
            e / base
        );
        assert!(
            *e <= 1.05 * base,
            "{name}, {size}-unit floor: penumbra RMSE {e:.4} against the 18-unit floor's {base:.4}"
        );
    }
}

#[test]
fn a_map_spread_over_a_huge_ground_names_the_caster_it_loses() {
    let gpu = common::gpu();
    let report = |size: f32, max_distance: f32| {
        let (scene, camera) = teapot_on(size);
        let mut renderer = Renderer::new(
            &gpu.device,
            wgpu::TextureFormat::Rgba8UnormSrgb,
            settings(ShadowMethod::Ours, max_distance),
        )
        .unwrap();
        let gpu_scene = penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
        penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 160, 128).unwrap();
        renderer.last_report().unwrap().light.unheld_caster
    };
    // Up to the far plane of a 500,000-unit ground: a texel of the map is wider than the teapot.
    let lost = report(500_000.0, 0.0).expect("the teapot's shadow lost without a report");
    eprintln!("unheld: {lost:?}");
    assert!(
        lost.size < lost.texel && lost.size > 1.0 && lost.size < 10.0,
        "{lost:?}"
    );
    // With a shadow distance, and on the 18-unit floor, nothing is lost.
    assert_eq!(report(500_000.0, SHADOW_DISTANCE), None);
    assert_eq!(report(18.0, 0.0), None);
}
