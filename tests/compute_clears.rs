//! The compute path's shared intermediates are cleared by compute passes on a GPU and by render
//! passes' clears on a CPU adapter (`screen::targets`), and its tile classification tests
//! the pixels of a kept tile with a workgroup per tile on a GPU and one invocation per tile on a
//! CPU adapter (`screen::tile_classify`); the lights' 16-bit maps are set to the far plane by a
//! copy from a buffer rather than by their passes' clears (`passes::light_atlas::FarPlaneFill`).
//! Each pair must give the same frame: this test, which runs on whatever adapter the machine
//! has, forces each way with `PENUMBRA_CLEARS`, `PENUMBRA_TILE_PIXELS` and
//! `PENUMBRA_MAP_CLEARS` (read when the intermediates and passes are made) and compares. One
//! test in its own binary: the environment is the process's.

mod common;

use penumbra::{LightTexture, Quality, ShadowMethod, ShadowSettings, load_scene};

#[test]
fn compute_and_render_pass_clears_give_the_same_frame() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    for method in [ShadowMethod::Ours, ShadowMethod::Traditional] {
        let settings = ShadowSettings::preset(method, Quality::Medium);
        let mut frames = Vec::new();
        for clears in ["render", "compute"] {
            // SAFETY: this binary's only test sets it before any thread reads it.
            unsafe { std::env::set_var("PENUMBRA_CLEARS", clears) };
            frames.push(common::render(&gpu, &scene, &camera, settings, 320, 256));
        }
        let differing = frames[0]
            .pixels()
            .zip(frames[1].pixels())
            .filter(|(a, b)| a.0 != b.0)
            .count();
        // The frame shows a shadow: pixels under half the brightest one.
        let luminance = |p: &image::Rgba<u8>| p.0[..3].iter().map(|c| *c as u32).sum::<u32>();
        let brightest = frames[1].pixels().map(luminance).max().unwrap_or(0);
        let dark = frames[1]
            .pixels()
            .filter(|p| luminance(p) * 2 < brightest)
            .count();
        println!("{method:?}: {differing} pixels differ; {dark} pixels under half the brightest");
        assert_eq!(differing, 0, "{method:?}: the two clears gave different frames");
        assert!(
            dark > 500,
            "{method:?}: no shadow in the frame ({dark} dark pixels)"
        );
    }
    // The teapot's far side: tiles listed apart either way, the same frame and lists.
    let settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    let mut frames = Vec::new();
    for test in ["loop", "workgroup"] {
        // SAFETY: as above.
        unsafe { std::env::set_var("PENUMBRA_TILE_PIXELS", test) };
        let (frame, renderer) = common::render_frame(&gpu, &scene, &camera, settings, (320, 256));
        let classes = common::read_f32(&gpu, renderer.debug_texture(LightTexture::TileClasses).unwrap()).0;
        frames.push((frame, classes));
    }
    let away = frames[0].1.iter().filter(|c| (**c - 0.25).abs() < 1e-3).count();
    println!("pixels tested in a loop and by a workgroup: {away} tiles listed apart");
    assert!(away > 0, "no tile listed apart as turned away from the light");
    assert_eq!(frames[0].1, frames[1].1, "the two forms classified differently");
    assert!(frames[0].0 == frames[1].0, "the two forms gave different frames");

    // The light maps set to the far plane by their passes' clears, then by the copy: the same
    // maps and frames, and the copy's buffer counted in the memory. A sun in two cascades, the
    // room's point light (a cube atlas) and hard shadows (the shadow map alone).
    for (file, method) in [
        ("scenes/teapot.ron", ShadowMethod::Ours),
        ("scenes/room.ron", ShadowMethod::Ours),
        ("scenes/teapot.ron", ShadowMethod::Hard),
    ] {
        let scene = load_scene(&common::asset(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let settings = ShadowSettings::preset(method, Quality::Medium);
        let mut runs = Vec::new();
        for clears in ["pass", "copy"] {
            // SAFETY: as above.
            unsafe { std::env::set_var("PENUMBRA_MAP_CLEARS", clears) };
            let (frame, renderer) = common::render_frame(&gpu, &scene, &camera, settings, (320, 256));
            let map = |texture| {
                renderer
                    .debug_texture(texture)
                    .map(|t| common::read_f32(&gpu, t).0)
            };
            let maps = [map(LightTexture::ShadowMap), map(LightTexture::FattenedMap)];
            runs.push((frame, maps, renderer.shadows().allocated_bytes()));
        }
        let shadow_map = runs[0].1[0].as_ref().expect("a shadow map");
        let far = shadow_map.iter().filter(|d| **d == 1.0).count();
        let near = shadow_map.iter().filter(|d| **d < 1.0).count();
        println!(
            "{file} {method:?}: shadow map of {} texels, {far} at the far plane, {near} nearer; {} bytes with the passes' clears, {} with the copy",
            shadow_map.len(),
            runs[0].2,
            runs[1].2
        );
        assert!(
            far > 0 && near > 0,
            "{file}: the map holds no caster, or nothing at the far plane"
        );
        assert!(
            runs[0].1 == runs[1].1,
            "{file} {method:?}: the copy gave other maps than the clears"
        );
        assert!(
            runs[0].0 == runs[1].0,
            "{file} {method:?}: the copy gave another frame than the clears"
        );
        // The buffer the copy reads is at least as large as the 16-bit shadow map.
        let map_bytes = shadow_map.len() as u64 * 2;
        assert!(
            runs[1].2 >= runs[0].2 + map_bytes,
            "{file} {method:?}: no buffer of {map_bytes} bytes counted ({} against {})",
            runs[1].2,
            runs[0].2
        );
    }
}
