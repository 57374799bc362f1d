//! The compute path's shared intermediates are cleared by compute passes on a GPU and by render
//! passes' clears on a CPU adapter (`screen::targets`), and its tile classification tests
//! the pixels of a kept tile with a workgroup per tile on a GPU, where the same dispatch clears
//! those intermediates instead, and one invocation per tile on a CPU adapter
//! (`screen::tile_classify`); the lights' 16-bit maps are set to the far plane by a
//! copy from a buffer rather than by their passes' clears (`passes::light_atlas::FarPlaneFill`).
//! Each pair must give the same frame: this test, which runs on whatever adapter the machine
//! has, forces each way with `PENUMBRA_CLEARS`, `PENUMBRA_TILE_PIXELS` and
//! `PENUMBRA_MAP_CLEARS` (read when the intermediates and passes are made) and compares. The
//! distance map is taken by the variable PCF's compute pass itself, or by a pass of its own
//! (`PENUMBRA_DISTANCE_PCF=apart`): the same again. One test in its own binary: the
//! environment is the process's.

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
    // The teapot's far side: tiles listed apart either way, the same frame and lists. Tested by
    // a workgroup, the classification also clears the intermediates (no clears of their own):
    // the same distance map (0 outside the listed tiles) and visibility either way, over two
    // frames (the second finds the first's values, with the light turned).
    let settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    let mut frames = Vec::new();
    for clears in ["render", "compute"] {
        for test in ["loop", "workgroup"] {
            // SAFETY: as above.
            unsafe {
                std::env::set_var("PENUMBRA_CLEARS", clears);
                std::env::set_var("PENUMBRA_TILE_PIXELS", test);
            }
            let mut renderer =
                penumbra::Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
            let mut gpu_scene =
                penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
            let image = |renderer: &mut penumbra::Renderer, gpu_scene: &penumbra::GpuScene| {
                penumbra::render_to_image(&gpu, renderer, gpu_scene, &camera, 320, 256).unwrap()
            };
            image(&mut renderer, &gpu_scene);
            gpu_scene
                .set_light(scene.light.turned(glam::Quat::from_rotation_y(0.3)))
                .unwrap();
            let frame = image(&mut renderer, &gpu_scene);
            let read = |texture| common::read_f32(&gpu, renderer.debug_texture(texture).unwrap()).0;
            let textures = [
                LightTexture::TileClasses,
                LightTexture::DistanceMap,
                LightTexture::Visibility,
            ]
            .map(read);
            frames.push((format!("{clears} clears, pixels by {test}"), frame, textures));
        }
    }
    let classes = &frames[0].2[0];
    let away = classes.iter().filter(|c| (**c - 0.25).abs() < 1e-3).count();
    let listed = classes.iter().filter(|c| **c == 1.0).count();
    let zero_distance = frames[0].2[1].iter().filter(|d| **d == 0.0).count();
    println!(
        "{listed} tiles listed, {away} listed apart; {zero_distance} distance-map values 0 of {}",
        frames[0].2[1].len()
    );
    assert!(away > 0, "no tile listed apart as turned away from the light");
    assert!(listed > 0 && zero_distance > 0);
    for (name, frame, textures) in &frames[1..] {
        let names = ["tile classes", "distance map", "visibility"];
        for (k, texture) in textures.iter().enumerate() {
            assert!(
                *texture == frames[0].2[k],
                "{name}: another {} than {}'s",
                names[k],
                frames[0].0
            );
        }
        assert!(
            *frame == frames[0].1,
            "{name}: another frame than {}'s",
            frames[0].0
        );
    }
    // The room's three lights (a point light's cube faces, a spot, a rectangle) share the
    // intermediates and the lists, one chain after the other: both forms give the same frames,
    // the second with the key light turned.
    let room = load_scene(&common::asset("scenes/room.ron")).unwrap();
    let room_camera = room.view(0).unwrap();
    let mut room_frames = Vec::new();
    for test in ["loop", "workgroup"] {
        // SAFETY: as above.
        unsafe { std::env::set_var("PENUMBRA_TILE_PIXELS", test) };
        let mut renderer =
            penumbra::Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
        let mut gpu_scene =
            penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &room).unwrap();
        let first =
            penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &room_camera, 320, 256).unwrap();
        gpu_scene
            .set_light(room.light.turned(glam::Quat::from_rotation_y(0.3)))
            .unwrap();
        let second =
            penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &room_camera, 320, 256).unwrap();
        assert!(
            first != second,
            "{test}: turning the room's key light changed nothing"
        );
        room_frames.push((first, second));
    }
    assert!(
        room_frames[0] == room_frames[1],
        "the room: the two forms gave different frames"
    );

    // The distance map taken by the variable PCF's pass (the default) and by a pass of its own
    // (`PENUMBRA_DISTANCE_PCF=apart`): the same distance map, visibility and frame, over two
    // frames (the light turned), under the teapot's sun and the room's three lights.
    for file in ["scenes/teapot.ron", "scenes/room.ron"] {
        let scene = load_scene(&common::asset(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let mut runs = Vec::new();
        for distance in ["in pcf", "apart"] {
            // SAFETY: as above.
            unsafe {
                std::env::remove_var("PENUMBRA_CLEARS");
                std::env::remove_var("PENUMBRA_TILE_PIXELS");
                std::env::set_var("PENUMBRA_DISTANCE_PCF", distance);
            }
            let mut renderer =
                penumbra::Renderer::new(&gpu.device, wgpu::TextureFormat::Rgba8UnormSrgb, settings).unwrap();
            let mut gpu_scene =
                penumbra::GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene).unwrap();
            let mut frames = Vec::new();
            for turn in [0.0, 0.3] {
                gpu_scene
                    .set_light(scene.light.turned(glam::Quat::from_rotation_y(turn)))
                    .unwrap();
                let frame =
                    penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 320, 256).unwrap();
                let read = |texture| common::read_f32(&gpu, renderer.debug_texture(texture).unwrap());
                frames.push((
                    frame,
                    read(LightTexture::DistanceMap),
                    read(LightTexture::Visibility).0,
                ));
            }
            runs.push(frames);
        }
        // Both frames show a penumbra: visibility strictly between 0 and 1, and distances above 0.
        for (frame, distance, visibility) in &runs[0] {
            let penumbra = visibility.iter().filter(|v| **v > 0.05 && **v < 0.95).count();
            let (distance, channels) = distance;
            let distances = distance
                .chunks_exact(*channels as usize)
                .filter(|px| px[0] > 0.0)
                .count();
            println!(
                "{file}, the distance in PCF: {penumbra} visibility values in a penumbra, {distances} distances above 0"
            );
            assert!(penumbra > 100 && distances > 100, "{file}: no penumbra");
            assert!(frame.pixels().any(|p| p.0[0] < 128));
        }
        for (k, (a, b)) in runs[0].iter().zip(&runs[1]).enumerate() {
            assert!(a.1 == b.1, "{file}, frame {k}: the distance maps differ");
            assert!(a.2 == b.2, "{file}, frame {k}: the visibilities differ");
            assert!(a.0 == b.0, "{file}, frame {k}: the frames differ");
        }
    }
    // SAFETY: as above.
    unsafe { std::env::remove_var("PENUMBRA_DISTANCE_PCF") };

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
