//! Where the device can store half floats, the compute passes that finish a light's visibility
//! write its layer of the visibility array themselves: the blur's vertical axis (`ours`,
//! `traditional`), PCSS's pass and the hard shadows' tap, where otherwise a draw copies or
//! resolves their result into it (`Shadows`, `layer_storage`). Both ways must give the same
//! layers, texel for texel, and the same frame: this test forces the draws with
//! `PENUMBRA_LAYER_WRITES=draw` (read when a `Shadows` is made) and compares. One test in its
//! own binary: the environment is the process's.

mod common;

use penumbra::{LightTexture, Quality, ShadowMethod, ShadowSettings, load_scene};

/// The visibility array's texels (R16F), the pass names of the frame, and the frame.
fn frame(
    gpu: &penumbra::HeadlessGpu,
    scene: &penumbra::Scene,
    method: ShadowMethod,
    writes: &str,
) -> (Vec<u8>, Vec<&'static str>, image::RgbaImage) {
    // SAFETY: this binary's only test sets it before any thread reads it.
    unsafe { std::env::set_var("PENUMBRA_LAYER_WRITES", writes) };
    let settings = ShadowSettings::preset(method, Quality::Medium);
    let camera = scene.view(0).unwrap();
    let (image, renderer) = common::render_frame(gpu, scene, &camera, settings, (320, 256));
    let visibility = renderer
        .composited_visibility()
        .unwrap_or_else(|| panic!("{method:?}: no visibility composited"));
    assert_eq!(visibility.format(), wgpu::TextureFormat::R16Float);
    let texels = penumbra::read_texture_bytes(&gpu.device, &gpu.queue, visibility).unwrap();
    (texels, renderer.last_report().unwrap().plan.names(), image)
}

#[test]
fn compute_passes_write_the_layers_as_the_draws_did() {
    let gpu = common::gpu();
    let features = gpu
        .adapter
        .get_texture_format_features(wgpu::TextureFormat::R16Float);
    let stores_halves = features
        .allowed_usages
        .contains(wgpu::TextureUsages::STORAGE_BINDING)
        && gpu.adapter.get_info().backend != wgpu::Backend::Gl;
    println!("{}: stores half floats: {stores_halves}", gpu.describe());
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    // The room's three lights: under hard shadows each runs its screen-space chain (one tap)
    // and the composite shades them, where one light is shaded in the forward pass.
    let room = load_scene(&common::asset("scenes/room.ron")).unwrap();
    let cases = [
        (&teapot, ShadowMethod::Ours),
        (&teapot, ShadowMethod::Traditional),
        (&teapot, ShadowMethod::Pcss),
        (&room, ShadowMethod::Ours),
        (&room, ShadowMethod::Hard),
    ];
    for (scene, method) in cases {
        let (drawn, drawn_names, drawn_frame) = frame(&gpu, scene, method, "draw");
        let (stored, stored_names, stored_frame) = frame(&gpu, scene, method, "storage");
        let halves = |bytes: &[u8]| -> Vec<f32> {
            bytes
                .chunks_exact(2)
                .map(|b| half::f16::from_le_bytes([b[0], b[1]]).to_f32())
                .collect()
        };
        let (a, b) = (halves(&drawn), halves(&stored));
        let differing = a
            .iter()
            .zip(&b)
            .filter(|(x, y)| x.to_bits() != y.to_bits())
            .count();
        let shadowed = b.iter().filter(|v| **v < 0.5).count();
        let partial = b.iter().filter(|v| **v > 0.02 && **v < 0.98).count();
        println!(
            "{method:?}: {differing} of {} texels differ; {shadowed} under 0.5, {partial} in a penumbra; passes {stored_names:?}",
            b.len()
        );
        assert_eq!(differing, 0, "{method:?}: the layers differ");
        assert_eq!(drawn_frame, stored_frame, "{method:?}: the frames differ");
        assert!(
            shadowed > 500 && partial > 100,
            "{method:?}: the layers show no soft shadow ({shadowed} under 0.5, {partial} in a penumbra)"
        );
        // The draws resolve or copy; the compute pass writes the layer where the device can.
        assert_eq!(
            drawn_names.contains(&"resolve"),
            method == ShadowMethod::Pcss || method == ShadowMethod::Hard,
            "{method:?}: {drawn_names:?}"
        );
        assert_eq!(
            stored_names.contains(&"resolve"),
            !stores_halves && (method == ShadowMethod::Pcss || method == ShadowMethod::Hard),
            "{method:?}: {stored_names:?}"
        );
    }
    // A debug view of the blurred visibility reads the layer either way.
    unsafe { std::env::set_var("PENUMBRA_LAYER_WRITES", "storage") };
    let (_, renderer) = common::render_frame(
        &gpu,
        &teapot,
        &teapot.view(0).unwrap(),
        ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium),
        (160, 128),
    );
    assert!(renderer.debug_texture(LightTexture::BlurredVisibility).is_some());
}
