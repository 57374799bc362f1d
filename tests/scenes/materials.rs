//! glTF materials as their authors meant them: a metal has a highlight a Lambertian surface
//! lacks, a normal map changes the shading under a grazing light, vertex colours multiply the
//! base colour, and a glTF file written here with all of these (and an emissive panel) loads
//! with its factors, textures and generated tangents, and renders as it says.

use crate::common;

use std::path::{Path, PathBuf};

use base64::Engine;
use glam::{Mat4, Vec2, Vec3, Vec4};
use penumbra::{
    Camera, DirectionalLight, Light, Material, Mesh, Quality, Scene, Shading, ShadowMethod, ShadowSettings,
    TextureImage, scene::primitives,
};

const SIZE: (u32, u32) = (160, 120);

use common::{linear, linear_luminance as luminance};

fn sun(direction: Vec3, intensity: f32) -> Light {
    Light::Directional(DirectionalLight {
        direction,
        angular_diameter_deg: 1.0,
        color: Vec3::ONE,
        intensity,
    })
}

fn render(scene: &Scene, camera: &Camera, method: ShadowMethod, (w, h): (u32, u32)) -> image::RgbaImage {
    let gpu = common::gpu();
    common::render(
        &gpu,
        scene,
        camera,
        ShadowSettings::preset(method, Quality::Medium),
        w,
        h,
    )
}

/// The composite (`ours`) and the forward pass (`hard`) shade alike.
const METHODS: [ShadowMethod; 2] = [ShadowMethod::Ours, ShadowMethod::Hard];

/// A sphere of radius 1 at the origin in `material`, lit by a dim sun from the upper right
/// front, no ambient light.
fn sphere_scene(material: Material) -> Scene {
    let mut scene = Scene {
        ambient: Vec3::ZERO,
        light: sun(-Vec3::ONE, 0.1),
        ..Default::default()
    };
    let m = scene.add_material(material);
    let sphere = scene.add_mesh(primitives::sphere(1.0, 64, 32));
    scene.add_instance(sphere, m, Mat4::IDENTITY);
    scene
}

/// A smooth metal sphere shows the sun's reflection where its normal halves the way to the
/// light and to the camera, far brighter than a Lambertian sphere of the same colour anywhere.
#[test]
fn a_metal_sphere_has_a_highlight_a_lambertian_one_lacks() {
    let eye = Vec3::new(0.0, 0.0, 4.0);
    let camera = Camera::look_at(eye, Vec3::ZERO);
    let base = [0.9, 0.9, 0.9];
    let metal = Material {
        shading: Shading::MetallicRoughness {
            metallic: 1.0,
            roughness: 0.3,
        },
        ..Material::colored("metal", base)
    };
    let chalk = Material::colored("chalk", base);
    // Where the mirror reflection lies: the normal halfway between the light and the camera.
    let to_light = Vec3::ONE.normalize();
    let mut half = to_light + (eye - Vec3::ZERO).normalize();
    for _ in 0..8 {
        // Refine for the point's own direction to the camera.
        let p = half.normalize();
        half = to_light + (eye - p).normalize();
    }
    let highlight = common::project(&camera, SIZE.0, SIZE.1, half.normalize()).unwrap();
    // The sphere's disc on the screen (a little inside its outline; the rest is background).
    let centre = common::project(&camera, SIZE.0, SIZE.1, Vec3::ZERO).unwrap();
    let rim = common::project(&camera, SIZE.0, SIZE.1, Vec3::new(0.9, 0.0, 0.0)).unwrap();
    let disc = rim.0 as f32 - centre.0 as f32;
    for method in METHODS {
        let shiny = render(&sphere_scene(metal.clone()), &camera, method, SIZE);
        let matte = render(&sphere_scene(chalk.clone()), &camera, method, SIZE);
        shiny
            .save(common::output_dir().join(format!("metal-sphere-{}.png", method.name())))
            .unwrap();
        let brightest = |image: &image::RgbaImage| {
            (0..SIZE.1)
                .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
                .filter(|&(x, y)| (x as f32 - centre.0 as f32).hypot(y as f32 - centre.1 as f32) < disc)
                .max_by(|a, b| luminance(image, *a).total_cmp(&luminance(image, *b)))
                .unwrap()
        };
        let peak = brightest(&shiny);
        let matte_max = luminance(&matte, brightest(&matte));
        eprintln!(
            "{}: metal peak {:.3} at {peak:?} (half vector at {highlight:?}), Lambertian max {matte_max:.3}",
            method.name(),
            luminance(&shiny, peak)
        );
        // The Lambertian sphere: at most its colour times the irradiance, 0.9 x 0.1.
        assert!(matte_max < 0.1, "{}: Lambertian max {matte_max}", method.name());
        // The metal: a highlight several times brighter, where the half vector says.
        assert!(
            luminance(&shiny, peak) > 5.0 * matte_max,
            "{}: metal peak {}",
            method.name(),
            luminance(&shiny, peak)
        );
        let off = Vec2::new(
            peak.0 as f32 - highlight.0 as f32,
            peak.1 as f32 - highlight.1 as f32,
        );
        assert!(
            off.length() <= 6.0,
            "{}: the highlight is {off} px from the half vector",
            method.name()
        );
        // Away from the highlight a metal has no diffuse light: darker than the chalk.
        let side = common::project(&camera, SIZE.0, SIZE.1, Vec3::new(0.9, 0.1, 0.45).normalize()).unwrap();
        assert!(
            luminance(&shiny, side) < luminance(&matte, side),
            "{}: metal {} against chalk {} at {side:?}",
            method.name(),
            luminance(&shiny, side),
            luminance(&matte, side)
        );
    }
}

/// A tangent-space normal map of bumps `period` texels apart in both directions, `size`
/// texels a side, tilting the normal by up to about 30 degrees.
fn bumps(size: u32, period: f32) -> TextureImage {
    let mut rgba8 = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            let t = std::f32::consts::TAU / period;
            let n = Vec3::new(0.5 * (x as f32 * t).sin(), 0.5 * (y as f32 * t).sin(), 1.0).normalize();
            let e = (n * 0.5 + 0.5) * 255.0;
            rgba8.extend_from_slice(&[e.x.round() as u8, e.y.round() as u8, e.z.round() as u8, 255]);
        }
    }
    TextureImage::from_rgba8("bumps", size, size, rgba8)
}

/// A floor under a grazing sun: flat, it is evenly lit; with a normal map (MikkTSpace tangents
/// generated from its UVs), its bumps face toward and away from the light in stripes.
#[test]
fn a_normal_map_changes_the_shading_under_a_grazing_light() {
    let camera = Camera::look_at(Vec3::new(0.0, 6.0, 4.0), Vec3::ZERO);
    let floor_scene = |normal_mapped: bool| {
        let mut scene = Scene {
            ambient: Vec3::ZERO,
            // 80 degrees from the vertical, from the side.
            light: sun(Vec3::new(-1.0, -0.18, -0.3), 1.0),
            ..Default::default()
        };
        scene.textures.push(bumps(64, 16.0));
        let material = Material {
            normal_texture: normal_mapped.then_some(0),
            ..Material::colored("floor", [0.8, 0.8, 0.8])
        };
        let m = scene.add_material(material);
        let floor = scene.add_mesh(primitives::plane(8.0, 4.0).with_generated_tangents());
        scene.add_instance(floor, m, Mat4::IDENTITY).caster = false;
        scene
    };
    for method in METHODS {
        let spread = |scene: &Scene, name: &str| {
            let image = render(scene, &camera, method, SIZE);
            image
                .save(common::output_dir().join(format!("normal-map-{name}-{}.png", method.name())))
                .unwrap();
            // The floor's middle: 40 x 30 pixels around the centre.
            let values: Vec<f32> = (45..75)
                .flat_map(|y| (60..100).map(move |x| (x, y)))
                .map(|p| luminance(&image, p))
                .collect();
            let mean = values.iter().sum::<f32>() / values.len() as f32;
            let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32).sqrt();
            (mean, sd)
        };
        let (flat_mean, flat_sd) = spread(&floor_scene(false), "flat");
        let (bumpy_mean, bumpy_sd) = spread(&floor_scene(true), "bumpy");
        eprintln!(
            "{}: flat mean {flat_mean:.4} sd {flat_sd:.4}; normal-mapped mean {bumpy_mean:.4} sd {bumpy_sd:.4}",
            method.name()
        );
        assert!(
            flat_mean > 0.05,
            "{}: the flat floor is lit ({flat_mean})",
            method.name()
        );
        assert!(
            flat_sd < 0.01,
            "{}: the flat floor is even ({flat_sd})",
            method.name()
        );
        assert!(
            bumpy_sd > 0.05 && bumpy_sd > 10.0 * flat_sd,
            "{}: the normal map shows ({bumpy_sd} against {flat_sd})",
            method.name()
        );
    }
}

/// Vertex colours (glTF `COLOR_0`) multiply the base colour: a white floor with red vertices
/// shows red.
#[test]
fn vertex_colours_multiply_the_base_colour() {
    let camera = Camera::look_at(Vec3::new(0.0, 5.0, 3.0), Vec3::ZERO);
    let mut scene = Scene {
        light: sun(Vec3::new(0.2, -1.0, 0.1), 1.0),
        ..Default::default()
    };
    let white = scene.add_material(Material::colored("white", [1.0, 1.0, 1.0]));
    let plane = primitives::plane(8.0, 1.0);
    let red = vec![Vec4::new(1.0, 0.0, 0.0, 1.0); plane.positions.len()];
    let floor = scene.add_mesh(plane.with_colors(red).unwrap());
    scene.add_instance(floor, white, Mat4::IDENTITY).caster = false;
    let centre = common::project(&camera, SIZE.0, SIZE.1, Vec3::ZERO).unwrap();
    for method in METHODS {
        let image = render(&scene, &camera, method, SIZE);
        let p = image.get_pixel(centre.0, centre.1).0;
        eprintln!("{}: the floor's centre {p:?}", method.name());
        assert!(p[0] > 150 && p[1] <= 2 && p[2] <= 2, "{}: {p:?}", method.name());
    }
    // A count that does not match the vertices is an error naming the mesh.
    let err = primitives::plane(1.0, 1.0)
        .with_colors(vec![Vec4::ONE; 3])
        .unwrap_err()
        .to_string();
    assert!(err.contains("plane") && err.contains("3 vertex colours"), "{err}");
}

/// One buffer, its views and accessors, built up as a glTF file is written.
#[derive(Default)]
struct Buffer {
    bytes: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Buffer {
    /// Appends `data` as an accessor of `count` elements of `kind` (`VEC3`, ...) and component
    /// type `component` (5126 float, 5125 unsigned int); returns its index.
    fn accessor(
        &mut self,
        data: &[u8],
        count: usize,
        kind: &str,
        component: u32,
        bounds: Option<(Vec3, Vec3)>,
    ) -> usize {
        while !self.bytes.len().is_multiple_of(4) {
            self.bytes.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bytes.len(),
            data.len()
        ));
        self.bytes.extend_from_slice(data);
        let bounds = bounds.map_or(String::new(), |(min, max)| {
            format!(
                r#","min":[{},{},{}],"max":[{},{},{}]"#,
                min.x, min.y, min.z, max.x, max.y, max.z
            )
        });
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{component},"count":{count},"type":"{kind}"{bounds}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    /// A primitive's JSON for `mesh` (positions, normals, UVs and indices; no tangents) in
    /// material `material`.
    fn primitive(&mut self, mesh: &Mesh, material: usize) -> String {
        let n = mesh.positions.len();
        let position = self.accessor(
            bytemuck::cast_slice(&mesh.positions),
            n,
            "VEC3",
            5126,
            Some((mesh.bounds.min, mesh.bounds.max)),
        );
        let normal = self.accessor(bytemuck::cast_slice(&mesh.normals), n, "VEC3", 5126, None);
        let uv = self.accessor(bytemuck::cast_slice(&mesh.uvs), n, "VEC2", 5126, None);
        let indices = self.accessor(
            bytemuck::cast_slice(&mesh.indices),
            mesh.indices.len(),
            "SCALAR",
            5125,
            None,
        );
        format!(
            r#"{{"primitives":[{{"attributes":{{"POSITION":{position},"NORMAL":{normal},"TEXCOORD_0":{uv}}},"indices":{indices},"material":{material}}}]}}"#
        )
    }
}

fn png_data_uri(image: &TextureImage) -> String {
    let mut png = Vec::new();
    image::RgbaImage::from_raw(image.width, image.height, image.rgba8.clone())
        .unwrap()
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    )
}

/// Writes `materials.gltf` into `dir`: a normal-mapped floor, three spheres (polished gold,
/// brushed steel, and a red plastic whose vertices carry colours), and an emissive panel,
/// materials in glTF's metallic-roughness model. No tangents: the loader generates them.
fn write_material_gltf(dir: &Path) -> PathBuf {
    let mut buffer = Buffer::default();
    let floor = buffer.primitive(&primitives::plane(10.0, 8.0), 0);
    let sphere = primitives::sphere(0.6, 48, 24);
    let gold = buffer.primitive(&sphere, 1);
    let steel = buffer.primitive(&sphere, 2);
    // The plastic sphere: COLOR_0 red at the top to white at the bottom, times a white base.
    let colors: Vec<Vec4> = sphere
        .positions
        .iter()
        .map(|p| {
            let t = (p.y / 0.6) * 0.5 + 0.5;
            Vec4::new(1.0, 1.0 - 0.9 * t, 1.0 - 0.9 * t, 1.0)
        })
        .collect();
    let mut plastic = buffer.primitive(&sphere, 3);
    let color = buffer.accessor(bytemuck::cast_slice(&colors), colors.len(), "VEC4", 5126, None);
    plastic = plastic.replace(r#""TEXCOORD_0""#, &format!(r#""COLOR_0":{color},"TEXCOORD_0""#));
    let panel = buffer.primitive(&primitives::cuboid(Vec3::new(3.2, 1.2, 0.1)), 4);
    let meshes = [floor, gold, steel, plastic, panel].join(",");
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&buffer.bytes)
    );
    let json = format!(
        r#"{{"asset":{{"version":"2.0","generator":"penumbra tests/scenes/materials.rs"}},
        "extensionsUsed":["KHR_materials_emissive_strength"],
        "scene":0,"scenes":[{{"nodes":[0,1,2,3,4]}}],
        "nodes":[{{"mesh":0,"name":"floor"}},
                 {{"mesh":1,"name":"gold","translation":[-1.5,0.6,0]}},
                 {{"mesh":2,"name":"steel","translation":[0,0.6,0]}},
                 {{"mesh":3,"name":"plastic","translation":[1.5,0.6,0]}},
                 {{"mesh":4,"name":"panel","translation":[0,0.6,-1.8]}}],
        "meshes":[{meshes}],
        "materials":[
          {{"name":"bumpy floor","pbrMetallicRoughness":{{"baseColorFactor":[0.5,0.5,0.5,1],"metallicFactor":0,"roughnessFactor":0.9}},
            "normalTexture":{{"index":0,"scale":1.0}}}},
          {{"name":"polished gold","pbrMetallicRoughness":{{"baseColorFactor":[1.0,0.77,0.34,1],"metallicFactor":1,"roughnessFactor":0.2}}}},
          {{"name":"brushed steel","pbrMetallicRoughness":{{"baseColorFactor":[0.56,0.57,0.58,1],"metallicFactor":1,"roughnessFactor":1,
            "metallicRoughnessTexture":{{"index":1}}}}}},
          {{"name":"plastic","pbrMetallicRoughness":{{"baseColorFactor":[1,1,1,1],"metallicFactor":0,"roughnessFactor":0.35}}}},
          {{"name":"lamp panel","pbrMetallicRoughness":{{"baseColorFactor":[0.1,0.1,0.1,1],"metallicFactor":0,"roughnessFactor":1}},
            "emissiveFactor":[0.8,0.4,0.12],"extensions":{{"KHR_materials_emissive_strength":{{"emissiveStrength":1.25}}}}}}],
        "textures":[{{"source":0}},{{"source":1}}],
        "images":[{{"uri":"{normal}"}},{{"uri":"{roughness}"}}],
        "buffers":[{{"uri":"{uri}","byteLength":{length}}}],
        "bufferViews":[{views}],
        "accessors":[{accessors}]}}"#,
        normal = png_data_uri(&bumps(64, 16.0)),
        // Steel's texture: roughness (green) 0.45, metalness (blue) 1.
        roughness = png_data_uri(&TextureImage::from_rgba8("rough", 1, 1, vec![0, 115, 255, 255])),
        length = buffer.bytes.len(),
        views = buffer.views.join(","),
        accessors = buffer.accessors.join(","),
    );
    let path = dir.join("materials.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// The glTF file loads with its factors and textures, no "not used" warning, MikkTSpace
/// tangents on the normal-mapped floor (unit, across the normal, along the UVs' u), and the
/// plastic's vertex colours.
#[test]
fn a_gltf_with_metal_normal_maps_and_vertex_colours_loads_as_written() {
    let path = write_material_gltf(&common::scratch_dir("materials_gltf"));
    let model = penumbra::loaders::load_model(&path).unwrap();
    assert!(
        !model.warnings.iter().any(|w| w.contains("not used")),
        "{:?}",
        model.warnings
    );
    let material = |name: &str| model.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(
        material("polished gold").shading,
        Shading::MetallicRoughness {
            metallic: 1.0,
            roughness: 0.2
        }
    );
    assert!(material("brushed steel").metallic_roughness_texture.is_some());
    let floor_material = material("bumpy floor");
    assert!(floor_material.normal_texture.is_some());
    assert_eq!(floor_material.normal_scale, 1.0);
    assert_eq!(material("lamp panel").emissive, Vec3::new(0.8, 0.4, 0.12) * 1.25);
    // The floor, normal-mapped, has tangents; the spheres, not normal-mapped, need none.
    let mesh_in = |name: &str| {
        let part = model
            .parts
            .iter()
            .find(|p| model.materials[p.material].name == name)
            .unwrap();
        &model.meshes[part.mesh]
    };
    let floor = mesh_in("bumpy floor");
    assert_eq!(floor.tangents.len(), floor.positions.len());
    for (t, n) in floor.tangents.iter().zip(&floor.normals) {
        assert!((t.truncate().length() - 1.0).abs() < 1e-3, "{t}");
        assert!(t.truncate().dot(*n).abs() < 1e-3, "{t} against {n}");
        assert!(t.w == 1.0 || t.w == -1.0, "{t}");
    }
    // Along u: between two vertices of one row, u grows along the tangent.
    let (a, b) = (0, 1);
    let du = floor.uvs[b].x - floor.uvs[a].x;
    let dp = floor.positions[b] - floor.positions[a];
    if du.abs() > 1e-6 {
        assert!(dp.dot(floor.tangents[a].truncate()) * du > 0.0, "{dp} {du}");
    }
    let plastic = mesh_in("plastic");
    assert_eq!(plastic.colors.len(), plastic.positions.len());
    assert!(mesh_in("polished gold").tangents.is_empty());
}

/// The glTF file rendered: each sphere shows its material, the floor its bumps, the panel its
/// own light with the sun off. Writes `materials.png` (the picture in `docs/materials.md`).
#[test]
fn a_gltf_with_metal_normal_maps_and_an_emissive_panel_renders_as_written() {
    let path = write_material_gltf(&common::scratch_dir("materials_render"));
    let model = penumbra::loaders::load_model(&path).unwrap();
    let scene_with = |intensity: f32| {
        let mut scene = Scene {
            light: sun(Vec3::new(-0.6, -0.55, -0.6), intensity),
            ambient: Vec3::splat(0.1),
            ..Default::default()
        };
        scene.add_model(&model, Mat4::IDENTITY, None, true, true);
        scene
    };
    let camera = Camera::look_at(Vec3::new(0.0, 2.6, 5.2), Vec3::new(0.0, 0.4, 0.0));
    let size = (640, 400);
    let image = render(&scene_with(1.6), &camera, ShadowMethod::Ours, size);
    image.save(common::output_dir().join("materials.png")).unwrap();
    let at = |image: &image::RgbaImage, p: Vec3| {
        luminance(image, common::project(&camera, size.0, size.1, p).unwrap())
    };
    // The panel glows with the sun off; the floor then shows only the ambient.
    let dark = render(&scene_with(0.0), &camera, ShadowMethod::Ours, size);
    // A point of its front face that no sphere hides.
    let panel_front = Vec3::new(0.9, 1.0, -1.74);
    eprintln!(
        "panel {:.3} lit, {:.3} with the sun off; floor {:.3} with the sun off",
        at(&image, panel_front),
        at(&dark, panel_front),
        at(&dark, Vec3::new(2.5, 0.0, 1.5))
    );
    // Its own light (1, 0.5, 0.15) and the ambient light on its dark base colour.
    let (x, y) = common::project(&camera, size.0, size.1, panel_front).unwrap();
    let glow = dark.get_pixel(x, y).0;
    let glow = [linear(glow[0]), linear(glow[1]), linear(glow[2])];
    for (got, want) in glow.iter().zip([1.0, 0.5, 0.15]) {
        assert!((got - (want + 0.01)).abs() < 0.03, "the emissive panel: {glow:?}");
    }
    assert!(at(&dark, Vec3::new(2.5, 0.0, 1.5)) < 0.1);
    // The plastic sphere: its vertex colours redden its top against its bottom.
    let green_over_red = |direction: Vec3| {
        let p = Vec3::new(1.5, 0.6, 0.0) + 0.6 * direction.normalize();
        let (x, y) = common::project(&camera, size.0, size.1, p).unwrap();
        let c = image.get_pixel(x, y).0;
        linear(c[1]) / linear(c[0]).max(1e-3)
    };
    let (top, bottom) = (
        green_over_red(Vec3::new(0.0, 0.8, 0.6)),
        green_over_red(Vec3::new(0.0, -0.5, 0.87)),
    );
    assert!(
        top < 0.5 * bottom,
        "plastic green/red: top {top}, bottom {bottom}"
    );
    // The gold sphere is gold (red over blue), and brightest at its highlight.
    let gold: Vec<[u8; 4]> = (0..size.1)
        .flat_map(|y| (0..size.0).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (cx, cy) = common::project(&camera, size.0, size.1, Vec3::new(-1.5, 0.6, 0.0)).unwrap();
            (x as f32 - cx as f32).hypot(y as f32 - cy as f32) < 30.0
        })
        .map(|(x, y)| image.get_pixel(x, y).0)
        .collect();
    let brightest = gold
        .iter()
        .max_by_key(|p| p[0] as u32 + p[1] as u32 + p[2] as u32)
        .unwrap();
    assert!(brightest[0] > 240, "gold's highlight {brightest:?}");
    let mean_blue = gold.iter().map(|p| p[2] as f32).sum::<f32>() / gold.len() as f32;
    let mean_red = gold.iter().map(|p| p[0] as f32).sum::<f32>() / gold.len() as f32;
    assert!(mean_red > 1.3 * mean_blue, "gold red {mean_red} blue {mean_blue}");
}
