//! Lightmaps and lighting modes on a real baked scene: Bevy's mixed-lighting example
//! (`assets/scenes/mixed_lighting.ron`, which reads `assets/models/MixedLightingExample/`):
//! its KTX2 atlases (zstd, RGB9E5) decode, the baked light lands where the bake put it, the
//! three modes differ as documented, and the dynamic sphere's soft shadow moves over the
//! lightmapped floor. Misuse is an error naming what is wrong. Frames are written to
//! `target/penumbra-test-output/lightmaps-*.png`.

use crate::common;

use glam::{Mat4, Vec3};
use penumbra::{Camera, LightingMode, Scene, ShadowMethod, ShadowSettings, scene::SceneFile};

const SIZE: (u32, u32) = (320, 240);

fn scene() -> Scene {
    penumbra::load_scene(&common::asset("scenes/mixed_lighting.ron")).unwrap()
}

fn settings() -> ShadowSettings {
    ShadowSettings::preset(ShadowMethod::Ours, penumbra::Quality::Medium)
}

/// `scene` lit in `mode` with the sun at `intensity`.
fn lit(mut scene: Scene, mode: LightingMode, intensity: f32) -> Scene {
    scene.lighting = mode;
    if let penumbra::Light::Directional(l) = &mut scene.light {
        l.intensity = intensity;
    }
    scene
}

fn render(scene: &Scene, camera: &Camera, name: &str) -> image::RgbaImage {
    let gpu = common::gpu();
    let image = common::render(&gpu, scene, camera, settings(), SIZE.0, SIZE.1);
    image
        .save(common::output_dir().join(format!("lightmaps-{name}.png")))
        .unwrap();
    image
}

/// The sphere (the example's dynamic object) moved to stand 0.2 above the floor at (x, z).
fn sphere_at(mut scene: Scene, x: f32, z: f32) -> Scene {
    let sphere = scene
        .instances
        .iter()
        .position(|i| scene.meshes[i.mesh].name == "Sphere")
        .expect("the example has a sphere");
    let radius = 0.1322;
    scene.instances[sphere].transform = Mat4::from_scale_rotation_translation(
        Vec3::splat(radius),
        glam::Quat::IDENTITY,
        Vec3::new(x, 0.2 + radius, z),
    );
    scene
}

fn pixel(camera: &Camera, p: Vec3) -> (u32, u32) {
    common::project(camera, SIZE.0, SIZE.1, p).unwrap_or_else(|| panic!("{p} is off screen"))
}

#[test]
fn the_example_s_atlases_decode_and_every_mesh_finds_its_rectangle() {
    let scene = scene();
    assert_eq!(scene.lightmaps.len(), 2);
    for atlas in &scene.lightmaps {
        assert_eq!((atlas.image.width, atlas.image.height), (1024, 1024));
        assert!(
            atlas
                .image
                .rgb
                .iter()
                .flatten()
                .all(|c| c.is_finite() && *c >= 0.0)
        );
    }
    let baked = scene
        .lightmaps
        .iter()
        .find(|l| l.mode == LightingMode::Baked)
        .unwrap();
    let mixed = scene
        .lightmaps
        .iter()
        .find(|l| l.mode == LightingMode::Mixed)
        .unwrap();
    // The floor's rectangle: all light baked is bright, indirect light alone is dim.
    let floor = |atlas: &penumbra::Lightmaps| {
        let r = atlas.rects.iter().find(|r| r.mesh == "Plane").unwrap();
        atlas.image.mean(r.min, r.max)[1]
    };
    eprintln!(
        "floor mean: baked {:.4}, indirect {:.4}",
        floor(baked),
        floor(mixed)
    );
    assert!(floor(baked) > 0.5 && floor(mixed) < 0.1);
    // Every instance's mesh with a rectangle gets it; the sphere only in baked lighting.
    let sphere = scene
        .instances
        .iter()
        .position(|i| scene.meshes[i.mesh].name == "Sphere")
        .unwrap();
    assert!(scene.lightmap_of(sphere, LightingMode::Baked).is_some());
    assert!(scene.lightmap_of(sphere, LightingMode::Mixed).is_none());
    for (k, inst) in scene.instances.iter().enumerate() {
        if scene.meshes[inst.mesh].name != "Sphere" {
            assert!(
                scene.lightmap_of(k, LightingMode::Mixed).is_some(),
                "instance {k}"
            );
        }
    }
}

#[test]
fn baked_light_lands_where_the_bake_put_it_and_ignores_the_dynamic_sun() {
    let base = sphere_at(scene(), 0.55, 0.35);
    let camera = base.view(0).unwrap();
    let baked_lit = render(&lit(base.clone(), LightingMode::Baked, 1.0), &camera, "baked");
    let baked_dark = render(
        &lit(base.clone(), LightingMode::Baked, 0.0),
        &camera,
        "baked-no-sun",
    );
    let dynamic_dark = render(
        &lit(base.clone(), LightingMode::Dynamic, 0.0),
        &camera,
        "dynamic-no-sun",
    );
    // Under the seat (the bake's sun shadowed it) and in the open.
    let under = pixel(&camera, Vec3::new(-0.1, 0.0, 0.05));
    let open = pixel(&camera, Vec3::new(0.2, 0.0, 0.5));
    let (u, o) = (
        common::luminance(&baked_dark, under),
        common::luminance(&baked_dark, open),
    );
    eprintln!("baked, no dynamic light: under the chair {u:.3}, in the open {o:.3}");
    assert!(
        o > 0.5 && u < 0.6 * o,
        "the baked floor must be darker under the chair: {u} vs {o}"
    );
    // Baked surfaces ignore the dynamic light: the frames with and without the sun agree on
    // every floor and chair pixel (all lightmapped in baked lighting).
    let differing = baked_lit
        .pixels()
        .zip(baked_dark.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    assert_eq!(
        differing, 0,
        "{differing} pixels of a baked frame follow the dynamic sun"
    );
    // Without the lightmap (dynamic lighting, no sun) the floor is the flat ambient light: the
    // lightmap made the difference, most of all in the open.
    let flat_open = common::luminance(&dynamic_dark, open);
    let flat_under = common::luminance(&dynamic_dark, under);
    eprintln!("dynamic, no sun: under {flat_under:.3}, open {flat_open:.3}");
    assert!((flat_open - flat_under).abs() < 0.03 && o > flat_open + 0.3);
    // The background (no geometry) is the same in every frame.
    let sky = (SIZE.0 - 3, 3);
    assert_eq!(
        baked_lit.get_pixel(sky.0, sky.1),
        dynamic_dark.get_pixel(sky.0, sky.1)
    );
}

#[test]
fn the_three_modes_differ_as_documented() {
    let base = sphere_at(scene(), 0.55, 0.35);
    let camera = base.view(0).unwrap();
    let frame = |mode, intensity| {
        render(
            &lit(base.clone(), mode, intensity),
            &camera,
            &format!("{}-{intensity}", mode.name()),
        )
    };
    let open = pixel(&camera, Vec3::new(0.2, 0.0, 0.5));
    let sphere_top = pixel(&camera, Vec3::new(0.55, 0.2 + 2.0 * 0.1322 - 0.03, 0.35));
    let l = common::luminance;
    let (mixed, mixed_dark) = (frame(LightingMode::Mixed, 1.0), frame(LightingMode::Mixed, 0.0));
    let (dynamic, dynamic_dark) = (
        frame(LightingMode::Dynamic, 1.0),
        frame(LightingMode::Dynamic, 0.0),
    );
    eprintln!(
        "open floor: mixed {:.3} / {:.3} without sun, dynamic {:.3} / {:.3}",
        l(&mixed, open),
        l(&mixed_dark, open),
        l(&dynamic, open),
        l(&dynamic_dark, open)
    );
    // Mixed: the direct light is dynamic (the sun lights the open floor), the indirect is the
    // lightmap's (dimmer than the flat ambient here: without the sun the open floor is darker
    // than dynamic lighting's ambient).
    assert!(l(&mixed, open) > l(&mixed_dark, open) + 0.3);
    assert!(l(&mixed_dark, open) < l(&dynamic_dark, open) - 0.05);
    // The sphere has no lightmap in mixed lighting: it is lit as in dynamic lighting.
    assert!((l(&mixed, sphere_top) - l(&dynamic, sphere_top)).abs() < 0.02);
}

#[test]
fn the_dynamic_sphere_moves_its_soft_shadow_over_the_lightmapped_floor() {
    let sun = Vec3::new(-0.392, -0.775, -0.495).normalize();
    let spots = [(0.55, 0.35), (0.15, 0.55)];
    let frames: Vec<(image::RgbaImage, Vec3)> = spots
        .iter()
        .map(|&(x, z)| {
            let s = lit(sphere_at(scene(), x, z), LightingMode::Mixed, 1.0);
            let camera = s.view(0).unwrap();
            let shadow = common::shadow_on_floor(Vec3::new(x, 0.2 + 0.1322, z), sun);
            (render(&s, &camera, &format!("sphere-{x}")), shadow)
        })
        .collect();
    let camera = scene().view(0).unwrap();
    for (k, (image, shadow)) in frames.iter().enumerate() {
        let other = &frames[1 - k].0;
        let at = pixel(&camera, *shadow);
        let (here, there) = (common::luminance(image, at), common::luminance(other, at));
        eprintln!("sphere {k}: its shadow's centre {here:.3}, lit when the sphere is elsewhere {there:.3}");
        assert!(here < 0.6 * there, "sphere {k}: {here} vs {there}");
    }
}

#[test]
fn lightmap_misuse_is_an_error_naming_what_is_wrong() {
    let dir = common::asset("scenes");
    let base = std::fs::read_to_string(dir.join("mixed_lighting.ron")).unwrap();
    let build = |text: &str| {
        let file = SceneFile::parse(text, &dir.join("broken.ron"))?;
        file.build(&dir, &dir.join("broken.ron"))
    };
    let expect = |text: String, needle: &str| {
        let e = build(&text).expect_err(needle).to_string();
        assert!(e.contains(needle), "`{e}` lacks `{needle}`");
    };
    expect(
        base.replacen("(mesh: \"Plane\"", "(mesh: \"Floor\"", 1),
        "no mesh is named `Floor`",
    );
    expect(
        base.replacen("Baked.zstd.ktx2", "Missing.ktx2", 1),
        "Missing.ktx2",
    );
    expect(
        base.replacen("mode: Baked", "mode: Dynamic", 1),
        "must be `Mixed` or `Baked`",
    );
    // Two atlases for one mode may not both light one mesh: the error names both files.
    let twice = build(&base.replacen("mode: Baked", "mode: Mixed", 1))
        .expect_err("a mesh in two atlases of one mode")
        .to_string();
    for needle in [
        "one atlas per mesh and mode",
        "mesh `Plane`",
        "MixedLightingExample-Baked",
        "MixedLightingExample-MixedIndirect",
    ] {
        assert!(twice.contains(needle), "`{twice}` lacks `{needle}`");
    }
    expect(
        base.replacen("lightmap_exposure: 1.0", "lightmap_exposure: -1.0", 1),
        "lightmap_exposure -1",
    );
    // A mesh with no second UV set cannot take a lightmap.
    let built_in = r#"(
        meshes: [(name: "floor", source: Plane(size: 4.0))],
        instances: [(mesh: "floor")],
        light: Directional((direction: (0.0, -1.0, 0.0))),
        views: [],
        lightmaps: [(mode: Baked, path: "../models/MixedLightingExample/lightmaps/MixedLightingExample-Baked.zstd.ktx2",
                     meshes: [(mesh: "floor", min: (0.0, 0.0), size: (1.0, 1.0))])],
    )"#;
    expect(built_in.to_string(), "no second UV set");
}

/// Engines give meshes their own lightmap images: two atlases serve baked lighting, the
/// example's for the floor and a plain green one for the chair, and each mesh shows its own.
#[test]
fn several_atlases_in_one_mode_each_light_their_own_meshes() {
    let base = lit(sphere_at(scene(), 0.55, 0.35), LightingMode::Baked, 0.0);
    let camera = base.view(0).unwrap();
    let mut split = base.clone();
    let baked = split
        .lightmaps
        .iter()
        .position(|l| l.mode == LightingMode::Baked)
        .unwrap();
    let chair: Vec<penumbra::LightmapRect> = split.lightmaps[baked]
        .rects
        .iter()
        .filter(|r| r.mesh.starts_with("SheenChair"))
        .map(|r| penumbra::LightmapRect {
            mesh: r.mesh.clone(),
            min: glam::Vec2::ZERO,
            max: glam::Vec2::ONE,
        })
        .collect();
    assert!(chair.len() >= 3, "the chair's meshes: {chair:?}");
    split.lightmaps[baked]
        .rects
        .retain(|r| !r.mesh.starts_with("SheenChair"));
    split.lightmaps.push(penumbra::Lightmaps {
        mode: LightingMode::Baked,
        image: penumbra::LightmapImage::with_finite_texels("green.hdr", 4, 4, vec![[0.0, 0.8, 0.0]; 16]),
        rects: chair,
    });
    split.validate_lightmaps().unwrap();
    let one = render(&base, &camera, "one-baked-atlas");
    let two = render(&split, &camera, "two-baked-atlases");
    let green = |image: &image::RgbaImage| {
        image
            .pixels()
            .filter(|p| {
                let [r, g, b, _] = p.0.map(u32::from);
                g >= 16 && g > 2 * r && g > 2 * b
            })
            .count()
    };
    let (before, after) = (green(&one), green(&two));
    eprintln!("green pixels: one atlas {before}, two atlases {after}");
    // The chair covers about a fifth of the frame.
    assert!(
        before < 50 && after > 3000,
        "the chair must show its own green atlas"
    );
    // The floor keeps the example's atlas.
    let open = pixel(&camera, Vec3::new(0.2, 0.0, 0.5));
    let (a, b) = (one.get_pixel(open.0, open.1).0, two.get_pixel(open.0, open.1).0);
    assert!(
        a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 2),
        "the floor changed: {a:?} vs {b:?}"
    );
}

/// Bicubic lightmap filtering (`LightmapFilter::Bicubic`) spreads a step in a coarse bake
/// over more of the floor than bilinear filtering, and leaves flat light as it is.
#[test]
fn bicubic_lightmap_filtering_smooths_a_coarse_bake() {
    let base = lit(sphere_at(scene(), 0.55, 0.35), LightingMode::Baked, 0.0);
    let camera = base.view(0).unwrap();
    // The floor alone takes an 8 x 8 lightmap over its whole second UV set.
    let with = |texel: &dyn Fn(usize) -> f32, filter: penumbra::LightmapFilter| {
        let mut scene = base.clone();
        let rgb = (0..64).map(|i| [texel(i % 8); 3]).collect();
        scene.lightmaps = vec![penumbra::Lightmaps {
            mode: LightingMode::Baked,
            image: penumbra::LightmapImage::with_finite_texels("step", 8, 8, rgb),
            rects: vec![penumbra::LightmapRect {
                mesh: "Plane".into(),
                min: glam::Vec2::ZERO,
                max: glam::Vec2::ONE,
            }],
        }];
        scene.lightmap_filter = filter;
        scene
    };
    use penumbra::LightmapFilter::{Bicubic, Bilinear};
    let step = |x: usize| if x < 4 { 0.1 } else { 0.9 };
    let dark = render(&with(&|_| 0.1, Bilinear), &camera, "filter-dark");
    let bright = render(&with(&|_| 0.9, Bilinear), &camera, "filter-bright");
    let bilinear = render(&with(&step, Bilinear), &camera, "filter-bilinear");
    let bicubic = render(&with(&step, Bicubic), &camera, "filter-bicubic");
    // Flat light comes out the same either way.
    let flat = render(&with(&|_| 0.9, Bicubic), &camera, "filter-bright-bicubic");
    let differing = flat
        .pixels()
        .zip(bright.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    assert!(
        differing < 20,
        "{differing} pixels of flat light changed with the filter"
    );
    // Where the step lies between the floor lit all dark and all bright (0 to 1): pixels part
    // way across it.
    let luminance = |image: &image::RgbaImage, x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        (0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32) / 255.0
    };
    let across = |image: &image::RgbaImage| {
        let (mut partway, mut ends) = (0, 0);
        for y in 0..SIZE.1 {
            for x in 0..SIZE.0 {
                let (lo, hi) = (luminance(&dark, x, y), luminance(&bright, x, y));
                if hi - lo < 0.1 {
                    continue;
                }
                let t = (luminance(image, x, y) - lo) / (hi - lo);
                if (0.1..=0.9).contains(&t) {
                    partway += 1;
                } else {
                    ends += 1;
                }
            }
        }
        (partway, ends)
    };
    let (linear_partway, linear_ends) = across(&bilinear);
    let (cubic_partway, cubic_ends) = across(&bicubic);
    eprintln!(
        "floor pixels part way across the step: bilinear {linear_partway} (of {}), bicubic {cubic_partway} (of {})",
        linear_partway + linear_ends,
        cubic_partway + cubic_ends
    );
    assert!(
        linear_partway > 100 && linear_ends > 1000,
        "the step must show on the floor"
    );
    assert!(
        cubic_partway as f32 > 1.5 * linear_partway as f32,
        "bicubic filtering must spread the step wider"
    );
    // The one-pass forward path (hard shadows) filters the same way.
    let gpu = common::gpu();
    let hard = ShadowSettings::preset(ShadowMethod::Hard, penumbra::Quality::Medium);
    let forward = common::render(&gpu, &with(&step, Bicubic), &camera, hard, SIZE.0, SIZE.1);
    let (forward_partway, _) = across(&forward);
    eprintln!("forward path, bicubic: {forward_partway} part way");
    assert!(forward_partway as f32 > 1.5 * linear_partway as f32);
}

/// A lightmap's smaller levels (mipmaps), when it has them, are what a surface that shrinks it
/// reads: a 2048-texel atlas dark at full size and bright in its smaller levels lights the floor
/// (a few hundred pixels across) bright; without them the floor reads the full size, dark.
#[test]
fn a_shrunk_lightmap_reads_its_smaller_levels() {
    let base = lit(sphere_at(scene(), 0.55, 0.35), LightingMode::Baked, 0.0);
    let camera = base.view(0).unwrap();
    let side = 2048u32;
    let with = |levels: u32| {
        let mut scene = base.clone();
        let full = vec![[0.1f32; 3]; (side * side) as usize];
        let mips = (1..levels)
            .map(|i| vec![[0.9f32; 3]; ((side >> i) * (side >> i)) as usize])
            .collect();
        scene.lightmaps = vec![penumbra::Lightmaps {
            mode: LightingMode::Baked,
            image: penumbra::LightmapImage::with_finite_texels("levels", side, side, full).with_mips(mips),
            rects: vec![penumbra::LightmapRect {
                mesh: "Plane".into(),
                min: glam::Vec2::ZERO,
                max: glam::Vec2::ONE,
            }],
        }];
        scene.validate_lightmaps().unwrap();
        scene
    };
    let one = render(&with(1), &camera, "levels-one");
    let all = render(&with(12), &camera, "levels-all");
    // The floor in the open, near the camera and far from it.
    for p in [Vec3::new(0.2, 0.0, 0.5), Vec3::new(-0.5, 0.0, -0.5)] {
        let at = pixel(&camera, p);
        let (dark, bright) = (common::luminance(&one, at), common::luminance(&all, at));
        eprintln!("floor at {p}: full size only {dark:.3}, with its levels {bright:.3}");
        assert!(
            bright > dark + 0.3,
            "the shrunk floor must read the bright smaller levels"
        );
    }
    // A level of the wrong size is an error naming the lightmap and the level.
    let mut wrong = with(1);
    wrong.lightmaps[0].image.mips = vec![vec![[0.5; 3]; 3]];
    let e = wrong.validate_lightmaps().unwrap_err().to_string();
    assert!(e.contains("levels") && e.contains("level 1"), "{e}");
}

/// A scene file with lightmaps may give no light: it is lit by its lightmaps and its ambient
/// alone, as the example is with its sun turned off. Without lightmaps, no light is an error.
#[test]
fn a_scene_lit_by_its_lightmaps_alone_is_valid() {
    let dir = common::asset("scenes");
    let text = std::fs::read_to_string(dir.join("mixed_lighting.ron")).unwrap();
    let start = text.find("    lights: [").expect("the example's lights");
    let end = start + text[start..].find("    ],\n").expect("the end of its lights") + "    ],\n".len();
    let unlit = format!("{}{}", &text[..start], &text[end..]);
    let file = SceneFile::parse(&unlit, &dir.join("unlit.ron")).unwrap();
    let mut alone = file.build(&dir, &dir.join("unlit.ron")).unwrap();
    assert_eq!(alone.light, penumbra::Light::none());
    assert!(alone.more_lights.is_empty());
    alone.lighting = LightingMode::Baked;
    let camera = alone.view(0).unwrap();
    let by_lightmaps = render(&alone, &camera, "lightmaps-alone");
    let sun_off = render(&lit(scene(), LightingMode::Baked, 0.0), &camera, "sun-off");
    let differing = by_lightmaps
        .pixels()
        .zip(sun_off.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ from the example with its sun off"
    );
    // The bake shows: the floor under the seat darker than in the open.
    let under = pixel(&camera, Vec3::new(-0.1, 0.0, 0.05));
    let open = pixel(&camera, Vec3::new(0.2, 0.0, 0.5));
    assert!(common::luminance(&by_lightmaps, under) < 0.6 * common::luminance(&by_lightmaps, open));
    // No light and no lightmap: an error saying what to give.
    let bare = r#"(
        meshes: [(name: "floor", source: Plane(size: 4.0))],
        instances: [(mesh: "floor")],
        views: [],
    )"#;
    let e = SceneFile::parse(bare, &dir.join("bare.ron"))
        .and_then(|f| f.build(&dir, &dir.join("bare.ron")))
        .unwrap_err()
        .to_string();
    assert!(e.contains("bare.ron") && e.contains("no light"), "{e}");
}

/// The chair's occlusion textures (glTF `occlusionTexture` on `TEXCOORD_1`) darken the
/// indirect light and leave the direct light alone.
#[test]
fn occlusion_darkens_the_indirect_light_only() {
    let scene = scene();
    let fabric = scene
        .materials
        .iter()
        .find(|m| m.name.starts_with("fabric"))
        .expect("the chair's fabric");
    assert!(fabric.occlusion_texture.is_some() && fabric.occlusion_uv_set == 1);
    let camera = scene.view(0).unwrap();
    let without_occlusion = |mut s: Scene| {
        for m in &mut s.materials {
            m.occlusion_strength = 0.0;
        }
        s
    };
    // Indirect light alone: a strong ambient, no sun.
    let mut ambient_only = lit(scene.clone(), LightingMode::Dynamic, 0.0);
    ambient_only.ambient = Vec3::splat(0.8);
    // Direct light alone: the sun, no ambient.
    let mut sun_only = lit(scene.clone(), LightingMode::Dynamic, 1.0);
    sun_only.ambient = Vec3::ZERO;
    // The frame's mean brightness (the chair and the floor; the background is the same).
    let chair = |image: &image::RgbaImage| -> f64 {
        let sum: f64 = image
            .pixels()
            .map(|p| p.0[..3].iter().map(|c| *c as f64).sum::<f64>())
            .sum();
        sum / (3.0 * image.pixels().len() as f64)
    };
    let ao = render(&ambient_only, &camera, "ambient-occluded");
    let plain = render(&without_occlusion(ambient_only.clone()), &camera, "ambient-plain");
    let darkened = ao
        .pixels()
        .zip(plain.pixels())
        .filter(|(a, b)| a.0[..3].iter().zip(&b.0[..3]).any(|(x, y)| x + 8 < *y))
        .count();
    eprintln!(
        "ambient light: mean {:.2} occluded, {:.2} not; {darkened} pixels darker by more than 8 levels",
        chair(&ao),
        chair(&plain)
    );
    assert!(chair(&ao) < chair(&plain) && darkened > 500);
    let sun_ao = render(&sun_only, &camera, "sun-occluded");
    let sun_plain = render(&without_occlusion(sun_only), &camera, "sun-plain");
    let differing = sun_ao
        .pixels()
        .zip(sun_plain.pixels())
        .filter(|(a, b)| a.0 != b.0)
        .count();
    assert_eq!(
        differing, 0,
        "occlusion changed {differing} pixels of direct light"
    );
}
