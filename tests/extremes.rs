//! Numerical stability at the extremes: the same scene at very different scales, extreme sizes
//! and settings, odd geometry, and random settings and light directions (proptest).

mod common;

use glam::{Mat4, Vec3};
use penumbra::{Camera, Light, Scene, ShadowMethod, ShadowSettings, SpreadMode, load_scene};

/// `scene` and `camera` scaled by `s` about the origin: geometry, camera distances and a spot
/// light's position and radius. (A directional light's angle does not scale.)
fn scaled(scene: &Scene, camera: &Camera, s: f32) -> (Scene, Camera) {
    let mut scene = scene.clone();
    for instance in &mut scene.instances {
        instance.transform = Mat4::from_scale(Vec3::splat(s)) * instance.transform;
    }
    if let Light::Spot(spot) = &mut scene.light {
        spot.position *= s;
        spot.radius *= s;
    }
    let camera = Camera {
        eye: camera.eye * s,
        target: camera.target * s,
        near: camera.near * s,
        far: camera.far * s,
        ..*camera
    };
    (scene, camera)
}

/// The teapot scene at 1e-3, 1 and 1e4 world units per unit gives the same picture: every
/// setting in world units is derived from the light (physical spreads) or is in texels, pixels
/// or depth steps.
#[test]
fn scaled_scenes_render_the_same_image() {
    let gpu = common::gpu();
    let base = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = base.view(0).unwrap();
    let (w, h) = (320, 240);
    for method in [ShadowMethod::Ours, ShadowMethod::Traditional, ShadowMethod::Pcss] {
        let settings = ShadowSettings {
            method,
            ..Default::default()
        };
        let reference = common::render(&gpu, &base, &camera, settings, w, h);
        for s in [1e-3f32, 1e4] {
            let (scene, cam) = scaled(&base, &camera, s);
            let image = common::render(&gpu, &scene, &cam, settings, w, h);
            let (mean, map) = penumbra::metrics::flip(&reference, &image).unwrap();
            let file = format!("scale_{}_{s:e}", method.name());
            image.save(common::output_dir().join(format!("{file}.png"))).unwrap();
            eprintln!("{} at scale {s:e}: mean FLIP {mean:.4}", method.name());
            if mean >= 0.01 {
                map.save(common::output_dir().join(format!("{file}_flip.png"))).unwrap();
            }
            assert!(mean < 0.01, "{} at scale {s:e}: mean FLIP {mean:.4}", method.name());
        }
    }
    // Spreads set by hand in world units do not scale, so the same check sees a difference.
    let manual = ShadowSettings {
        penumbra: penumbra::PenumbraSettings {
            spreads: SpreadMode::Manual {
                fatten_distance: 0.3,
                pcf_spread: 4.0,
                blur_spread: 12.0,
            },
            ..Default::default()
        },
        ..Default::default()
    };
    let reference = common::render(&gpu, &base, &camera, manual, w, h);
    let (scene, cam) = scaled(&base, &camera, 1e-3);
    let image = common::render(&gpu, &scene, &cam, manual, w, h);
    let (mean, _) = penumbra::metrics::flip(&reference, &image).unwrap();
    eprintln!("manual spreads at scale 1e-3: mean FLIP {mean:.4}");
    assert!(mean > 0.01, "unscaled manual spreads changed nothing ({mean:.4}): the check is blind");
}
