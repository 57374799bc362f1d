//! The plugin in a headless Bevy app: a box above a plane under each kind of light, penumbra's
//! shadow against Bevy's own, and the changes a scene goes through.

#[path = "../examples/common/mod.rs"]
mod common;

use bevy::light::NotShadowCaster;
use bevy::light::ShadowFilteringMethod;
use bevy::prelude::*;
use common::Headless;
use penumbra_bevy::{PenumbraCamera, PenumbraLightSize, PenumbraPlugin};

const SIZE: UVec2 = UVec2::new(256, 256);
/// The camera looks straight down from this height at a plane of this half-size: world x
/// maps to image columns, world z to rows.
const EYE_HEIGHT: f32 = 12.0;

/// One Bevy app at a time: each holds a device on the software adapter.
static ONE_APP: std::sync::Mutex<()> = std::sync::Mutex::new(());

struct Scene {
    headless: Headless,
    camera: Entity,
    box_entity: Entity,
}

/// A grey plane, a red box whose bottom is 1.5 above it, `light`, and a camera looking down.
fn box_above_plane(light: impl Bundle) -> Scene {
    let mut headless = Headless::new(SIZE, |app| {
        app.add_plugins(PenumbraPlugin);
    });
    let world = headless.app.world_mut();
    world.insert_resource(GlobalAmbientLight {
        brightness: 80.0,
        ..default()
    });
    let plane = world.resource_mut::<Assets<Mesh>>().add(Plane3d::default().mesh().size(16.0, 16.0));
    let cube = world.resource_mut::<Assets<Mesh>>().add(Cuboid::new(1.0, 1.0, 1.0));
    let grey = world.resource_mut::<Assets<StandardMaterial>>().add(StandardMaterial {
        base_color: Color::srgb(0.7, 0.7, 0.7),
        perceptual_roughness: 1.0,
        ..default()
    });
    let red = world.resource_mut::<Assets<StandardMaterial>>().add(StandardMaterial {
        base_color: Color::srgb(0.8, 0.05, 0.05),
        perceptual_roughness: 1.0,
        ..default()
    });
    world.spawn((Mesh3d(plane), MeshMaterial3d(grey)));
    let box_entity = world
        .spawn((Mesh3d(cube), MeshMaterial3d(red), Transform::from_xyz(0.0, 2.0, 0.0)))
        .id();
    world.spawn(light);
    let camera_bundle = headless.camera(Vec3::new(0.0, EYE_HEIGHT, 0.0), Vec3::ZERO);
    let camera = headless
        .app
        .world_mut()
        .spawn((camera_bundle, PenumbraCamera::default(), ShadowFilteringMethod::Hardware2x2))
        .id();
    Scene {
        headless,
        camera,
        box_entity,
    }
}

/// A sun shining down and toward +x: the box's shadow falls at x from 0.7 to 2.5.
fn sun(angular_diameter_deg: f32) -> impl Bundle {
    (
        DirectionalLight {
            illuminance: 1500.0,
            shadow_maps_enabled: true,
            ..default()
        },
        PenumbraLightSize(angular_diameter_deg.to_radians()),
        Transform::default().looking_to(Vec3::new(0.8, -1.0, 0.0), Vec3::Y),
    )
}

/// How shadowed each plane pixel is, 0 lit to 1 as dark as the darkest plane pixel, `None` on
/// the box (red).
fn darkness(image: &image::RgbaImage) -> Vec<Option<f32>> {
    let plane = |p: &image::Rgba<u8>| {
        let [r, g, b, _] = p.0;
        (r as i32 - g as i32).abs() < 24 && (g as i32 - b as i32).abs() < 24
    };
    let values: Vec<Option<f32>> = image
        .pixels()
        .map(|p| plane(p).then(|| p.0[1] as f32))
        .collect();
    let lit = values.iter().flatten().copied().fold(0.0, f32::max);
    let dark = values.iter().flatten().copied().fold(255.0, f32::min);
    assert!(lit - dark > 40.0, "no shadow on the plane: lit {lit}, darkest {dark}");
    values
        .into_iter()
        .map(|v| v.map(|v| ((lit - v) / (lit - dark)).clamp(0.0, 1.0)))
        .collect()
}

/// The darkness-weighted centroid of the plane's shadow, in pixels, and its weight.
fn centroid(darkness: &[Option<f32>]) -> (Vec2, f32) {
    let mut sum = Vec2::ZERO;
    let mut weight = 0.0;
    for (i, d) in darkness.iter().enumerate() {
        if let Some(d) = d {
            let p = Vec2::new((i as u32 % SIZE.x) as f32 + 0.5, (i as u32 / SIZE.x) as f32 + 0.5);
            sum += p * *d;
            weight += *d;
        }
    }
    (sum / weight.max(1e-6), weight)
}

/// Pixels inside the penumbra (darkness between 0.1 and 0.9).
fn penumbra_pixels(darkness: &[Option<f32>]) -> usize {
    darkness.iter().flatten().filter(|d| **d > 0.1 && **d < 0.9).count()
}

fn save(name: &str, image: &image::RgbaImage) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("penumbra-bevy");
    std::fs::create_dir_all(&dir).unwrap();
    image.save(dir.join(name)).unwrap();
}

#[test]
fn a_suns_shadow_lies_where_bevys_does_and_is_soft() {
    let _one = ONE_APP.lock().unwrap_or_else(|e| e.into_inner());
    let mut scene = box_above_plane(sun(10.0));
    let ours = scene.headless.render(12);
    save("sun_penumbra.png", &ours);
    scene
        .headless
        .app
        .world_mut()
        .get_mut::<PenumbraCamera>(scene.camera)
        .unwrap()
        .enabled = false;
    let bevy = scene.headless.render(6);
    save("sun_bevy.png", &bevy);

    let (ours_dark, bevy_dark) = (darkness(&ours), darkness(&bevy));
    let (ours_at, ours_weight) = centroid(&ours_dark);
    let (bevy_at, bevy_weight) = centroid(&bevy_dark);
    println!("centroids: penumbra {ours_at} ({ours_weight:.0}), bevy {bevy_at} ({bevy_weight:.0})");
    assert!(ours_at.distance(bevy_at) < 2.0, "penumbra's shadow at {ours_at}, Bevy's at {bevy_at}");
    // The shadow is right of the box (+x is right in the image) where the geometry puts it.
    let px_per_unit = SIZE.x as f32 / (2.0 * EYE_HEIGHT * (std::f32::consts::FRAC_PI_4 / 2.0).tan());
    let expected_x = SIZE.x as f32 / 2.0 + 1.6 * px_per_unit;
    assert!((ours_at.x - expected_x).abs() < 0.5 * px_per_unit, "shadow centre at x {} px, expected about {expected_x}", ours_at.x);
    let (ours_soft, bevy_soft) = (penumbra_pixels(&ours_dark), penumbra_pixels(&bevy_dark));
    println!("penumbra pixels: penumbra {ours_soft}, bevy {bevy_soft}");
    assert!(ours_soft > 2 * bevy_soft.max(20), "penumbra {ours_soft} penumbra pixels, Bevy's hard shadow {bevy_soft}");
}
