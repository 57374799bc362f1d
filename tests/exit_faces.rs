//! The exit map keeps the casters' faces turned away from the light. Where all of a mesh's
//! triangles turn one way seen from outside, the rasterizer culls the others; otherwise each
//! fragment tests its side (`passes::exit_map`). Both must give the same maps and frames,
//! whichever way the mesh is wound, for an instance that mirrors, and under a sun's cascades, a
//! point light's cube faces and a spot light's perspective. This test forces each way with
//! `PENUMBRA_EXIT_FACES` (read when the passes are made) and compares. One test in its own
//! binary: the environment is the process's.

mod common;

use glam::{Mat4, Vec3};
use penumbra::{LightTexture, Quality, Scene, ShadowMethod, ShadowSettings, load_scene};

/// The frame and each light's exit map, with the exit faces found `faces`' way.
fn run(gpu: &penumbra::HeadlessGpu, scene: &Scene, faces: &str) -> (image::RgbaImage, Vec<Vec<f32>>) {
    // SAFETY: this binary's only test sets it before any thread reads it.
    unsafe { std::env::set_var("PENUMBRA_EXIT_FACES", faces) };
    let settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    let camera = scene.view(0).unwrap();
    let (frame, renderer) = common::render_frame(gpu, scene, &camera, settings, (320, 256));
    let shadows = renderer.shadows();
    let maps = shadows
        .light_ids()
        .into_iter()
        .filter_map(|id| shadows.light_texture(id, LightTexture::ExitMap))
        .map(|t| common::read_f32(gpu, t).0)
        .collect();
    (frame, maps)
}

#[test]
fn culling_by_winding_gives_the_maps_each_fragment_finds() {
    let gpu = common::gpu();
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let room = load_scene(&common::asset("scenes/room.ron")).unwrap();
    // The room again with its teapot wound the other way, the lamp's shade mirrored, and one
    // triangle of the box every piece of furniture is made of turned (those draws test each
    // fragment).
    let mut turned = room.clone();
    let mesh = |name: &str| turned.meshes.iter().position(|m| m.name == name).unwrap();
    let (pot, unit, shade) = (mesh("teapot"), mesh("unit"), mesh("shade"));
    for tri in turned.meshes[pot].indices.chunks_exact_mut(3) {
        tri.swap(1, 2);
    }
    turned.meshes[unit].indices.swap(1, 2);
    for instance in turned.instances.iter_mut().filter(|i| i.mesh == shade) {
        // The shade is a sphere scaled about its centre: mirrored in x, it is the same solid.
        instance.transform *= Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    }
    for (name, scene) in [("teapot", &teapot), ("room", &room), ("room turned", &turned)] {
        let by_fragment = run(&gpu, scene, "fragment");
        let by_winding = run(&gpu, scene, "winding");
        let maps = &by_fragment.1;
        assert!(!maps.is_empty(), "{name}: no exit map");
        for (k, map) in maps.iter().enumerate() {
            let near = map.iter().filter(|d| **d < 1.0).count();
            let differing = map.iter().zip(&by_winding.1[k]).filter(|(a, b)| a != b).count();
            println!(
                "{name}, light {k}: {near} of {} exit-map texels hold a back face; {differing} differ",
                map.len()
            );
            assert!(near > 0, "{name}, light {k}: the exit map holds no back face");
            assert_eq!(differing, 0, "{name}, light {k}: culling gave another exit map");
        }
        assert!(
            by_fragment.0 == by_winding.0,
            "{name}: culling gave another frame"
        );
    }
}
