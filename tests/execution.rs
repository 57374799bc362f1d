//! Each choice of `ExecutionSettings` (and the light maps' `clear_by_copy` and `exit_faces`)
//! must give the same shadows: these tests, which run on whatever adapter the machine has, make
//! one frame each way and compare, texel for texel.
//! - The compute path's shared intermediates are cleared by compute passes or by render
//!   passes' clears (`ExecutionSettings::clears`, `screen::targets`).
//! - The tile classification tests a kept tile's pixels with a workgroup per tile, where the
//!   same dispatch clears those intermediates instead, or with one invocation per tile
//!   (`ExecutionSettings::tile_pixels`, `screen::tile_classify`).
//! - The variable PCF's compute pass takes the distance map itself, or a pass of its own does
//!   (`ExecutionSettings::distance_in_pcf`).
//! - The lights' 16-bit maps are set to the far plane by a copy from a buffer or by their
//!   passes' clears (`ShadowMapSettings::clear_by_copy`, `passes::light_atlas::FarPlaneFill`).
//! - The exit map culls by winding or tests each fragment's side
//!   (`ShadowMapSettings::exit_faces`, `passes::exit_map`).
//! - The exit map is kept by the shadow map's pass or drawn by its own
//!   (`ExecutionSettings::exit_map_draw`): the maps differ where a texel's four shadow-map
//!   texels see different back faces and by the depth bias, so that test holds them within
//!   that.
//! - The compute passes that finish a light's visibility write its layer themselves, or draws
//!   do (`ExecutionSettings::compute_layer_writes`).
//! - The compute path's intermediates are half floats or 32-bit floats
//!   (`ExecutionSettings::half_intermediates`): the one choice whose shadows differ, by a half
//!   float's rounding, so its test holds them within that rather than texel for texel.

mod common;

use glam::{Mat4, Vec3};
use penumbra::{
    DevicePath, ExitFaces, ExitMapDraw, Fattening, LightTexture, Quality, Scene, ShadowMethod,
    ShadowSettings, TilePixels, load_scene,
};

/// The compute pipelines `gpu`'s device holds now (wgpu's counters: made and not yet dropped).
fn compute_pipelines(gpu: &penumbra::HeadlessGpu) -> isize {
    gpu.device.get_internal_counters().hal.compute_pipelines.read()
}

/// The intermediates cleared by render passes' clears and by compute passes: the same frame,
/// which shows the teapot's shadow, under `ours` and the baseline.
#[test]
fn compute_and_render_pass_clears_give_the_same_frame() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    for method in [ShadowMethod::Ours, ShadowMethod::Traditional] {
        let mut frames = Vec::new();
        let mut made = Vec::new();
        for clears in [DevicePath::RenderPass, DevicePath::Compute] {
            let mut settings = ShadowSettings::preset(method, Quality::Medium);
            settings.execution.clears = clears;
            let before = compute_pipelines(&gpu);
            let (frame, renderer) = common::render_frame(&gpu, &scene, &camera, settings, (320, 256));
            made.push(compute_pipelines(&gpu) - before);
            drop(renderer);
            frames.push(frame);
        }
        // The setting reached the intermediates: the compute clears are pipelines of their own.
        println!("{method:?}: compute pipelines made {made:?} (render-pass clears, compute clears)");
        assert!(
            made[1] > made[0],
            "{method:?}: the compute clears made no pipeline ({made:?})"
        );
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

/// The teapot's far side: tiles listed apart either way, the same frame and lists. Tested by
/// a workgroup, the classification also clears the intermediates (no clears of their own): the
/// same distance map (0 outside the listed tiles) and visibility either way, over two frames
/// (the second finds the first's values, with the light turned).
#[test]
fn the_tile_pixels_by_workgroup_or_by_loop_give_the_same_lists_and_frames() {
    let gpu = common::gpu();
    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let mut frames = Vec::new();
    for clears in [DevicePath::RenderPass, DevicePath::Compute] {
        for test in [TilePixels::Loop, TilePixels::Workgroup] {
            let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
            settings.execution.clears = clears;
            settings.execution.tile_pixels = test;
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
            // The light's layer: where the classification clears, it sets the layer the variable
            // PCF writes (`Chain::pcf_in_layer`), as the draws set it otherwise.
            let textures = [
                LightTexture::TileClasses,
                LightTexture::DistanceMap,
                LightTexture::BlurredVisibility,
            ]
            .map(read);
            frames.push((format!("{clears:?} clears, pixels by {test:?}"), frame, textures));
        }
    }
    let classes = &frames[0].2[0];
    let away = classes.iter().filter(|c| (**c - 0.25).abs() < 1e-3).count();
    let listed = classes.iter().filter(|c| **c == 1.0).count();
    // The compute path's distance map holds one value a pixel (`distance_and_mask` reads it).
    let outside = frames[0].2[1]
        .iter()
        .filter(|d| penumbra::debug::distance_and_mask(&[**d]).1 < 0.5)
        .count();
    println!(
        "{listed} tiles listed, {away} listed apart; {outside} distance-map values outside the mask of {}",
        frames[0].2[1].len()
    );
    assert!(away > 0, "no tile listed apart as turned away from the light");
    assert!(listed > 0 && outside > 0);
    for (name, frame, textures) in &frames[1..] {
        let names = ["tile classes", "distance map", "light's layer"];
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
    for test in [TilePixels::Loop, TilePixels::Workgroup] {
        let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
        settings.execution.tile_pixels = test;
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
            "{test:?}: turning the room's key light changed nothing"
        );
        room_frames.push((first, second));
    }
    assert!(
        room_frames[0] == room_frames[1],
        "the room: the two forms gave different frames"
    );
}

/// The distance map taken by the variable PCF's pass (the default) and by a pass of its own:
/// the same distance map, visibility and frame, over two frames (the light turned), under the
/// teapot's sun and the room's three lights.
#[test]
fn the_distance_in_the_pcf_or_in_its_own_pass_gives_the_same_frames() {
    let gpu = common::gpu();
    for file in ["scenes/teapot.ron", "scenes/room.ron"] {
        let scene = load_scene(&common::asset(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let mut runs = Vec::new();
        let mut made = Vec::new();
        for in_pcf in [true, false] {
            let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
            settings.execution.distance_in_pcf = in_pcf;
            let before = compute_pipelines(&gpu);
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
                    // The lights' layers (the variable PCF writes there, the blur after it).
                    read(LightTexture::BlurredVisibility).0,
                ));
            }
            made.push(compute_pipelines(&gpu) - before);
            runs.push(frames);
        }
        // The setting reached the chain: apart, the distance map is a pipeline of its own.
        println!("{file}: compute pipelines made {made:?} (the distance in the PCF, apart)");
        assert!(
            made[1] > made[0],
            "{file}: the distance map apart made no pipeline ({made:?})"
        );
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
}

/// The light maps set to the far plane by their passes' clears, then by the copy: the same maps
/// and frames, and the copy's buffer counted in the memory. A sun in two cascades, the room's
/// point light (a cube atlas) and hard shadows (the shadow map alone).
#[test]
fn the_light_maps_cleared_by_copy_or_by_their_passes_are_the_same() {
    let gpu = common::gpu();
    for (file, method) in [
        ("scenes/teapot.ron", ShadowMethod::Ours),
        ("scenes/room.ron", ShadowMethod::Ours),
        ("scenes/teapot.ron", ShadowMethod::Hard),
    ] {
        let scene = load_scene(&common::asset(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let mut runs = Vec::new();
        for by_copy in [false, true] {
            let mut settings = ShadowSettings::preset(method, Quality::Medium);
            settings.shadow_map.clear_by_copy = by_copy;
            let (frame, renderer) = common::render_frame(&gpu, &scene, &camera, settings, (320, 256));
            let map = |texture| {
                let layer = renderer.debug_texture_layer(texture).unwrap_or(0);
                renderer
                    .debug_texture(texture)
                    .map(|t| common::read_layer_f32(&gpu, t, layer).0)
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

/// The frame and each light's exit map, with the exit faces found `faces`' way, kept by the
/// shadow map's pass (`in_shadow_pass`) or drawn by a pass of its own.
fn exit_maps(
    gpu: &penumbra::HeadlessGpu,
    scene: &Scene,
    faces: ExitFaces,
    in_shadow_pass: bool,
) -> (image::RgbaImage, Vec<Vec<f32>>) {
    let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
    settings.shadow_map.exit_faces = faces;
    settings.execution.exit_map_draw = if in_shadow_pass {
        ExitMapDraw::ShadowMapPass
    } else {
        ExitMapDraw::OwnPass
    };
    let camera = scene.view(0).unwrap();
    let (frame, renderer) = common::render_frame(gpu, scene, &camera, settings, (320, 256));
    let shadows = renderer.shadows();
    let maps = shadows
        .light_ids()
        .into_iter()
        .filter_map(|id| {
            let layer = shadows.light_texture_layer(id, LightTexture::ExitMap)?;
            shadows
                .light_texture(id, LightTexture::ExitMap)
                .map(|t| (t, layer))
        })
        .map(|(t, layer)| common::read_layer_f32(gpu, t, layer).0)
        .collect();
    (frame, maps)
}

/// Where all of a mesh's triangles turn one way seen from outside, the exit map's rasterizer
/// culls the others (or, where the shadow map's pass keeps the exit map, its fragments tell the
/// sides by facing); otherwise each fragment tests its side. Both give the same maps and frames
/// whichever way the mesh is wound, for an instance that mirrors, and under a sun's cascades, a
/// point light's cube faces and a spot light's perspective, in the exit map's own pass and in
/// the shadow map's.
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
    let scenes = [("teapot", &teapot), ("room", &room), ("room turned", &turned)];
    for ((name, scene), in_shadow_pass) in scenes.into_iter().flat_map(|s| [(s, true), (s, false)]) {
        let name = format!("{name}{}", if in_shadow_pass { "" } else { ", its own pass" });
        let by_fragment = exit_maps(&gpu, scene, ExitFaces::Fragment, in_shadow_pass);
        let by_winding = exit_maps(&gpu, scene, ExitFaces::Winding, in_shadow_pass);
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

/// The shadow map's pass keeps the exit map (fragment atomics beside its depth test) that the
/// exit map's own pass would draw: the same back faces texel for texel but where a texel's four
/// shadow-map texels see different ones, depths within the shadow map's depth bias, the same
/// frames within a few pixels, and one geometry pass less.
#[test]
fn the_shadow_map_pass_keeps_the_exit_map_its_own_pass_draws() {
    let gpu = common::gpu();
    for name in ["teapot", "room"] {
        let scene = load_scene(&common::asset(&format!("scenes/{name}.ron"))).unwrap();
        let kept = exit_maps(&gpu, &scene, ExitFaces::Winding, true);
        let drawn = exit_maps(&gpu, &scene, ExitFaces::Winding, false);
        assert_eq!(kept.1.len(), drawn.1.len(), "{name}: another number of exit maps");
        for (k, (a, b)) in kept.1.iter().zip(&drawn.1).enumerate() {
            assert_eq!(a.len(), b.len(), "{name}, light {k}: another size of exit map");
            let held = |m: &[f32]| m.iter().filter(|d| **d < 1.0).count();
            let (held_a, held_b) = (held(a), held(b));
            let one_only = a
                .iter()
                .zip(b)
                .filter(|(x, y)| (**x < 1.0) != (**y < 1.0))
                .count();
            let mut gaps: Vec<f32> = a
                .iter()
                .zip(b)
                .filter(|(x, y)| **x < 1.0 && **y < 1.0)
                .map(|(x, y)| (x - y).abs())
                .collect();
            gaps.sort_by(f32::total_cmp);
            let at = |q: f64| gaps[((gaps.len() - 1) as f64 * q) as usize];
            println!(
                "{name}, light {k}: back faces in {held_a} texels kept, {held_b} drawn; in one only {one_only}; depth gap median {:.2e}, 99th percentile {:.2e}, largest {:.2e}",
                at(0.5),
                at(0.99),
                at(1.0)
            );
            assert!(
                held_b > 0,
                "{name}, light {k}: the drawn exit map holds no back face"
            );
            // Measured on lavapipe: 0.07-0.40% of the texels held in one only (the kept map
            // takes the nearest of four texels, the drawn one the texel at their centre);
            // median gaps 2.6e-6 to 9.9e-4, 99th percentiles 1.1e-4 to 9.1e-3 (the drawn map
            // is rasterized at half the side, so its slope-scaled bias is twice as deep).
            assert!(
                one_only * 100 <= held_b,
                "{name}, light {k}: {one_only} texels hold a back face in one map only, of {held_b}"
            );
            assert!(
                at(0.5) <= 2e-3 && at(0.99) <= 2e-2,
                "{name}, light {k}: the maps' depths differ by {:.2e} (median), {:.2e} (99th percentile)",
                at(0.5),
                at(0.99)
            );
        }
        let differing = kept
            .0
            .pixels()
            .zip(drawn.0.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
            .count();
        let pixels = kept.0.len() / 4;
        println!("{name}: {differing} of {pixels} pixels differ by more than 2");
        // Measured on lavapipe: 57 (teapot) and 305 (room) of 81,920.
        assert!(
            differing * 100 <= pixels,
            "{name}: {differing} of {pixels} pixels differ by more than 2 of 255"
        );
    }
}

/// `ExitMapDraw::Auto` keeps the exit map in the shadow map's pass and `Fattening::Auto`
/// derives the fattened map from the shadow map from `ExitMapDraw::AUTO_TRIANGLES` caster
/// triangles (`Fattening::AUTO_TRIANGLES`, the same count), and both draw apart below: the
/// teapot alone (9,216 triangles) draws its casters three times, the teapot drawn 55 times over
/// in one place (506,880) once, with the frame that `ExitMapDraw::ShadowMapPass` and
/// `Fattening::Dilation` give.
#[test]
fn the_light_draws_its_casters_once_for_many_triangles() {
    let gpu = common::gpu();
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let mut crowded = teapot.clone();
    let pot = crowded.meshes.iter().position(|m| m.name == "teapot").unwrap();
    let instance = crowded.instances.iter().find(|i| i.mesh == pot).unwrap().clone();
    let per_pot = crowded.meshes[pot].indices.len() / 3;
    assert_eq!(Fattening::AUTO_TRIANGLES, ExitMapDraw::AUTO_TRIANGLES);
    let copies = ExitMapDraw::AUTO_TRIANGLES.div_ceil(per_pot);
    crowded.instances.extend(std::iter::repeat_n(instance, copies));
    let camera = teapot.view(0).unwrap();
    let frame = |scene: &Scene, draw: ExitMapDraw, fattening: Fattening| {
        let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
        settings.execution.exit_map_draw = draw;
        settings.penumbra.fattening = fattening;
        let (image, renderer) = common::render_frame(&gpu, scene, &camera, settings, (96, 64));
        let chain = renderer.last_report().unwrap().plan.chain;
        (
            image,
            chain.exit_in_shadow_pass(),
            !chain.draws_fattened_map(),
            chain.light_maps(),
        )
    };
    let (_, kept, derived, maps) = frame(&teapot, ExitMapDraw::Auto, Fattening::Auto);
    assert!(
        !kept && !derived,
        "{per_pot} triangles: exit map kept {kept}, fattened map derived {derived}"
    );
    assert_eq!(maps, 3, "{per_pot} triangles");
    let (auto, kept, derived, maps) = frame(&crowded, ExitMapDraw::Auto, Fattening::Auto);
    let triangles = per_pot * (copies + 1);
    assert!(
        kept && derived,
        "{triangles} triangles: exit map kept {kept}, fattened map derived {derived}"
    );
    assert_eq!(maps, 1, "{triangles} triangles");
    let (forced, kept, derived, _) = frame(&crowded, ExitMapDraw::ShadowMapPass, Fattening::Dilation);
    assert!(kept && derived);
    assert!(
        auto == forced,
        "{triangles} triangles: Auto drew another frame than ShadowMapPass with Dilation"
    );
    let (_, kept, derived, maps) = frame(&crowded, ExitMapDraw::OwnPass, Fattening::Geometry);
    assert!(
        !kept && !derived && maps == 3,
        "OwnPass and Geometry: exit map kept {kept}, fattened map derived {derived}"
    );
}

/// The visibility array's texels (R16F), the pass names of the frame, and the frame.
fn layers(
    gpu: &penumbra::HeadlessGpu,
    scene: &penumbra::Scene,
    method: ShadowMethod,
    compute_writes: bool,
) -> (Vec<u8>, Vec<&'static str>, image::RgbaImage) {
    let mut settings = ShadowSettings::preset(method, Quality::Medium);
    settings.execution.compute_layer_writes = compute_writes;
    let camera = scene.view(0).unwrap();
    let (image, renderer) = common::render_frame(gpu, scene, &camera, settings, (320, 256));
    let visibility = renderer
        .composited_visibility()
        .unwrap_or_else(|| panic!("{method:?}: no visibility composited"));
    assert_eq!(visibility.format(), wgpu::TextureFormat::R16Float);
    let texels = penumbra::read_texture_bytes(&gpu.device, &gpu.queue, visibility).unwrap();
    (texels, renderer.last_report().unwrap().passes.clone(), image)
}

/// Where the device can store half floats, the compute passes that finish a light's visibility
/// write its layer of the visibility array themselves: the blur's vertical axis (`ours`,
/// `traditional`), PCSS's pass and the hard shadows' tap, where otherwise a draw copies or
/// resolves their result into it. Both ways give the same layers, texel for texel, and the same
/// frame.
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
        let (drawn, drawn_names, drawn_frame) = layers(&gpu, scene, method, false);
        let (stored, stored_names, stored_frame) = layers(&gpu, scene, method, true);
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
    let (_, renderer) = common::render_frame(
        &gpu,
        &teapot,
        &teapot.view(0).unwrap(),
        ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium),
        (160, 128),
    );
    assert!(renderer.debug_texture(LightTexture::BlurredVisibility).is_some());
}

/// Where the device stores half floats, the compute path keeps its intermediates (the
/// visibility before the blur and between its axes, the blur's deviations, the distance map)
/// in single or paired half floats (`ExecutionSettings::half_intermediates`): 10 bytes a pixel
/// fewer for `ours` (its visibility, the blur's axis, the deviations, the distance map), 4 for
/// the baseline (no deviations, no distance map), 2 for PCSS, and the same shadows but for a
/// half float's rounding of those values: the layers within 2e-3 of each other but at one texel in 10,000 (within 0.05
/// there), the frames within 2 of 255 at every pixel.
#[test]
fn half_float_intermediates_keep_the_shadows_in_less_memory() {
    let gpu = common::gpu();
    let features = |format| gpu.adapter.get_texture_format_features(format).allowed_usages;
    let stores_halves = [wgpu::TextureFormat::R16Float, wgpu::TextureFormat::Rg16Float]
        .into_iter()
        .all(|f| features(f).contains(wgpu::TextureUsages::STORAGE_BINDING))
        && gpu.adapter.get_info().backend != wgpu::Backend::Gl;
    println!("{}: stores half floats: {stores_halves}", gpu.describe());
    let teapot = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = teapot.view(0).unwrap();
    let size = (320u32, 256u32);
    let pixels = (size.0 * size.1) as u64;
    for (method, saved_per_pixel) in [
        (ShadowMethod::Ours, 10),
        (ShadowMethod::Traditional, 4),
        (ShadowMethod::Pcss, 2),
    ] {
        let mut runs = Vec::new();
        for half in [false, true] {
            let mut settings = ShadowSettings::preset(method, Quality::Medium);
            settings.execution.half_intermediates = half;
            // `ours`' raw visibility kept apart, so that both runs have it (its PCF writes the
            // light's layer otherwise where the device stores half floats: the next test).
            settings.execution.raw_visibility = true;
            let (frame, renderer) = common::render_frame(&gpu, &teapot, &camera, settings, size);
            let raw = renderer
                .debug_texture(LightTexture::Visibility)
                .unwrap_or_else(|| panic!("{method:?}: no raw visibility"))
                .format();
            let layer = renderer.composited_visibility().unwrap();
            let texels = penumbra::read_texture_f32(&gpu.device, &gpu.queue, layer)
                .unwrap()
                .0;
            let bytes = renderer.shadows().allocated_bytes();
            let distance = renderer
                .debug_texture(LightTexture::DistanceMap)
                .map(|t| t.format());
            assert_eq!(
                distance.is_some(),
                method == ShadowMethod::Ours,
                "{method:?}: {distance:?}"
            );
            if let Some(format) = distance {
                let expected = if half && stores_halves {
                    wgpu::TextureFormat::R16Float
                } else {
                    wgpu::TextureFormat::R32Float
                };
                assert_eq!(format, expected, "{method:?}: the distance map, half {half}");
            }
            runs.push((frame, texels, bytes, raw));
        }
        let [
            (frame32, layer32, bytes32, raw32),
            (frame16, layer16, bytes16, raw16),
        ] = &runs[..]
        else {
            unreachable!()
        };
        let worst = layer32
            .iter()
            .zip(layer16)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        let over: Vec<(usize, f32, f32)> = layer32
            .iter()
            .zip(layer16)
            .enumerate()
            .filter(|(_, (a, b))| (*a - *b).abs() > 2e-3)
            .map(|(i, (a, b))| (i, *a, *b))
            .collect();
        let frame_worst = frame32
            .pixels()
            .zip(frame16.pixels())
            .flat_map(|(a, b)| (0..3).map(move |c| (a.0[c] as i32 - b.0[c] as i32).abs()))
            .max()
            .unwrap_or(0);
        let differing = frame32
            .pixels()
            .zip(frame16.pixels())
            .filter(|(a, b)| a != b)
            .count();
        let partial = layer16.iter().filter(|v| **v > 0.02 && **v < 0.98).count();
        println!(
            "{method:?}: raw visibility {raw32:?} / {raw16:?}; {bytes32} / {bytes16} bytes; layers within \
             {worst:.2e}, {} texels over 2e-3 {:?}; {differing} pixels differ, by at most {frame_worst}; \
             {partial} layer texels in a penumbra",
            over.len(),
            &over[..over.len().min(8)]
        );
        assert!(
            partial > 100,
            "{method:?}: no penumbra in the layer ({partial} texels)"
        );
        assert_eq!(*raw32, wgpu::TextureFormat::R32Float, "{method:?}");
        if stores_halves {
            assert_eq!(
                *raw16,
                wgpu::TextureFormat::R16Float,
                "{method:?}: the setting did not reach the intermediates"
            );
            assert_eq!(
                bytes32 - bytes16,
                saved_per_pixel * pixels,
                "{method:?}: {bytes32} against {bytes16} bytes"
            );
        } else {
            assert_eq!(
                raw16, raw32,
                "{method:?}: half floats on a device that cannot store them"
            );
            assert_eq!(bytes32, bytes16, "{method:?}");
        }
        // A texel where the rounding tips a blur tap's weight moves more: a handful a frame.
        assert!(
            over.len() <= layer16.len() / 10_000 && worst <= 0.05,
            "{method:?}: {} layer texels differ by over 2e-3, the most by {worst}",
            over.len()
        );
        assert!(
            frame_worst <= 2,
            "{method:?}: the frames differ by {frame_worst} of 255"
        );
    }
}

/// Where the compute passes write the light's layer in half floats, `ours`' variable PCF
/// writes the layer itself (`Chain::pcf_in_layer`), which the blur's horizontal axis reads and
/// its vertical axis overwrites: with `ExecutionSettings::raw_visibility` off (the default) the
/// same layers and frames as with the visibility kept apart (on), 2 bytes a pixel less, and no
/// raw visibility. On the teapot (one sun, tiles turned away listed apart) and in the room (a
/// point light, a spot and a rectangle sharing the intermediates), with each form of clears.
#[test]
fn the_pcf_writing_the_layer_keeps_the_shadows_in_less_memory() {
    let gpu = common::gpu();
    // The compute passes write the layers, and keep the intermediates in half floats.
    let features = |format| gpu.adapter.get_texture_format_features(format).allowed_usages;
    let stores = penumbra::Shadows::visibility_usages(&gpu.device)
        .contains(wgpu::TextureUsages::STORAGE_BINDING)
        && [wgpu::TextureFormat::R16Float, wgpu::TextureFormat::Rg16Float]
            .into_iter()
            .all(|f| features(f).contains(wgpu::TextureUsages::STORAGE_BINDING));
    println!("{}: the PCF can write the layers: {stores}", gpu.describe());
    for file in ["scenes/teapot.ron", "scenes/room.ron"] {
        let scene = load_scene(&common::asset(file)).unwrap();
        let camera = scene.view(0).unwrap();
        let size = (320u32, 256u32);
        for clears in [DevicePath::RenderPass, DevicePath::Compute] {
            let mut runs = Vec::new();
            for raw in [true, false] {
                let mut settings = ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium);
                settings.execution.raw_visibility = raw;
                settings.execution.clears = clears;
                settings.execution.tile_pixels = match clears {
                    // The classification by workgroups clears the intermediates, the layer
                    // among them.
                    DevicePath::Compute => TilePixels::Workgroup,
                    _ => TilePixels::Loop,
                };
                let (frame, renderer) = common::render_frame(&gpu, &scene, &camera, settings, size);
                let chain = renderer.last_report().unwrap().plan.chain;
                let layers = renderer.composited_visibility().unwrap();
                let texels = penumbra::read_texture_f32(&gpu.device, &gpu.queue, layers)
                    .unwrap()
                    .0;
                let bytes = renderer.shadows().allocated_bytes();
                let raw_texture = renderer.debug_texture(LightTexture::Visibility).is_some();
                runs.push((frame, texels, bytes, chain, raw_texture));
            }
            let [
                (frame_raw, layers_raw, bytes_raw, chain_raw, kept),
                (frame, layers, bytes, chain, raw_left),
            ] = &runs[..]
            else {
                unreachable!()
            };
            let differing = layers_raw.iter().zip(layers).filter(|(a, b)| a != b).count();
            let partial = layers.iter().filter(|v| **v > 0.02 && **v < 0.98).count();
            println!(
                "{file}, {clears:?} clears: {bytes_raw} / {bytes} bytes; {differing} layer texels differ; \
                 {partial} in a penumbra; chains {chain_raw:?} / {chain:?}"
            );
            assert!(
                !chain_raw.pcf_in_layer() && *kept,
                "{file}: the raw visibility was not kept"
            );
            assert_eq!(chain.pcf_in_layer(), stores, "{file}: {chain:?}");
            assert!(
                partial > 100,
                "{file}: no penumbra in the layers ({partial} texels)"
            );
            assert_eq!(differing, 0, "{file}, {clears:?} clears: the layers differ");
            assert!(frame_raw == frame, "{file}, {clears:?} clears: the frames differ");
            if stores {
                assert!(
                    !raw_left,
                    "{file}: a raw visibility where the PCF writes the layer"
                );
                assert_eq!(
                    bytes_raw - bytes,
                    2 * u64::from(size.0 * size.1),
                    "{file}: {bytes_raw} against {bytes} bytes"
                );
            } else {
                assert_eq!(bytes_raw, bytes, "{file}");
            }
        }
    }
}
