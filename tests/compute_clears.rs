//! The compute path's shared intermediates are cleared by compute passes on a GPU and by render
//! passes' clears on a CPU adapter (`chain::TargetClears`). Both must give the same frame: this
//! test, which runs on whatever adapter the machine has, forces each way with
//! `PENUMBRA_CLEARS` (read when the intermediates are made) and compares. One test in its own
//! binary: the environment is the process's.

mod common;

use penumbra::{Quality, ShadowMethod, ShadowSettings, load_scene};

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
}
