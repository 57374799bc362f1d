//! A spot light's map fitted to what the camera sees: under a wide cone, a camera close to one
//! small shadow gets a map whose texels cover only that part of the cone, and its shadow's
//! error against the reference falls well below the error with the map spread over the whole
//! cone (`LightFit::Scene`), at the same resolution. The visibility images are written to
//! `target/penumbra-test-output/spot-fit-*.png`.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{
    Camera, LightFit, Material, Scene, ShadowMethod, ShadowSettings, SpotLight,
    metrics::{measure_visibility, visibility_error},
    scene::primitives,
};

/// A 40-unit floor, a unit box floating half a unit up, a small spot light up and to the side
/// with a 70-degree cone: the cone covers tens of units of floor, the box's shadow falls
/// beside it toward -x.
fn wide_cone_scene() -> Scene {
    let mut scene = Scene {
        light: penumbra::Light::Spot(SpotLight {
            position: Vec3::new(6.0, 9.0, 0.5),
            direction: Vec3::new(-6.0, -9.0, -0.5),
            cone_angle_deg: 70.0,
            radius: 0.08,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        }),
        ..Default::default()
    };
    let grey = scene.add_material(Material::colored("floor", [0.8, 0.8, 0.8]));
    let blue = scene.add_material(Material::colored("box", [0.3, 0.5, 0.8]));
    let floor = scene.add_mesh(primitives::plane(40.0, 1.0));
    scene.add_instance(floor, grey, Mat4::IDENTITY).caster = false;
    let cube = scene.add_mesh(primitives::cuboid(Vec3::ONE));
    scene
        .add_instance(cube, blue, Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0)))
        .receiver = false;
    scene
}

/// Straight above the box's shadow, about 3 units of floor across.
fn close_camera() -> Camera {
    Camera {
        eye: Vec3::new(-1.0, 5.0, 0.0),
        target: Vec3::new(-1.0, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_deg: 35.0,
        near: 1.0,
        far: 10.0,
    }
}

#[test]
fn a_spot_map_fitted_to_the_camera_is_sharper_than_one_over_the_whole_cone() {
    let gpu = common::gpu();
    let scene = wide_cone_scene();
    let camera = close_camera();
    let size = (256, 192);
    let mut reference = ShadowSettings {
        method: ShadowMethod::Reference,
        ..Default::default()
    };
    reference.reference.samples = 64;
    let truth = measure_visibility(&gpu, &scene, &camera, reference, size).unwrap();
    // Some of the view is in shadow and most is lit: the box's shadow is in the picture.
    let shadowed = truth.visibility.iter().flatten().filter(|&&v| v < 0.05).count();
    let measured = truth.visibility.iter().flatten().count();
    assert!(
        shadowed > measured / 20 && shadowed < measured / 2,
        "{shadowed} of {measured} shadowed"
    );
    for method in [ShadowMethod::Ours, ShadowMethod::Pcss, ShadowMethod::Hard] {
        let error = |fit: LightFit| {
            let mut settings = ShadowSettings::preset(method, penumbra::Quality::Medium);
            settings.shadow_map.resolution = 512;
            settings.shadow_map.fit = fit;
            let v = measure_visibility(&gpu, &scene, &camera, settings, size).unwrap();
            // The visibility as grey levels (no receiver: black), to look at.
            let grey = image::GrayImage::from_fn(v.width, v.height, |x, y| {
                let value = v.visibility[(y * v.width + x) as usize].unwrap_or(0.0);
                image::Luma([(value * 255.0).round() as u8])
            });
            let name = match fit {
                LightFit::Scene => "whole-cone",
                LightFit::CameraFrustum { .. } => "fitted",
            };
            let path = common::output_dir().join(format!("spot-fit-{}-{name}.png", method.name()));
            grey.save(&path).unwrap();
            visibility_error(&truth, &v).unwrap()
        };
        let whole_cone = error(LightFit::Scene);
        let fitted = error(LightFit::CameraFrustum { max_distance: 0.0 });
        eprintln!(
            "{:<6} RMSE: whole cone {:.4} (penumbra {:.4}), fitted {:.4} (penumbra {:.4})",
            method.name(),
            whole_cone.rmse,
            whole_cone.penumbra_rmse,
            fitted.rmse,
            fitted.penumbra_rmse
        );
        assert!(
            fitted.rmse < 0.6 * whole_cone.rmse,
            "{}: fitted {} against whole cone {}",
            method.name(),
            fitted.rmse,
            whole_cone.rmse
        );
    }
}
