//! Loaders and scene files on real files made elsewhere (`assets/models`), on the project's
//! own scenes, and on broken files made here: every failure is an `Err` naming the file and the
//! reason, never a panic.

use crate::common;

use std::path::Path;

use base64::Engine;
use glam::Vec3;
use penumbra::{Model, PenumbraError, load_model, load_scene};

fn assert_mesh_sane(model: &Model, what: &str) {
    assert!(!model.parts.is_empty(), "{what}: no parts");
    for mesh in &model.meshes {
        assert_eq!(mesh.normals.len(), mesh.vertex_count());
        assert_eq!(mesh.smoothed_normals.len(), mesh.vertex_count());
        for n in mesh.normals.iter().chain(&mesh.smoothed_normals) {
            assert!(
                n.is_finite() && (n.length() - 1.0).abs() < 1e-3,
                "{what}: bad normal {n}"
            );
        }
        assert!(mesh.positions.iter().all(|p| p.is_finite()));
        assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.vertex_count()));
    }
}

#[test]
fn teapot_obj_without_normals_gets_computed_smooth_normals() {
    let model = load_model(&common::models().join("teapot.obj")).unwrap();
    assert_mesh_sane(&model, "teapot.obj");
    let triangles: usize = model.meshes.iter().map(|m| m.triangle_count()).sum();
    assert_eq!(triangles, 6320);
    // Computed normals face outward: on the body (away from handle and spout) they point away
    // from the vertical axis, and the surface encloses a positive volume with its winding.
    let mesh = &model.meshes[0];
    let center = mesh.bounds.center();
    let body: Vec<_> = mesh
        .positions
        .iter()
        .zip(&mesh.normals)
        .filter(|(p, _)| p.x.abs() < 1.4 && (p.y - center.y).abs() < 0.5)
        .collect();
    let outward = body
        .iter()
        .filter(|(p, n)| glam::Vec2::new(p.x - center.x, p.z - center.z).dot(glam::Vec2::new(n.x, n.z)) > 0.0)
        .count();
    assert!(
        body.len() > 100 && outward as f32 > 0.97 * body.len() as f32,
        "{outward} of {}",
        body.len()
    );
    let volume: f32 = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum();
    assert!(volume > 0.0, "signed volume {volume}");
}

#[test]
fn spot_obj_keeps_its_uvs_and_gets_normals() {
    let model = load_model(&common::models().join("spot.obj")).unwrap();
    assert_mesh_sane(&model, "spot.obj");
    let mesh = &model.meshes[0];
    assert_eq!(mesh.triangle_count(), 5856);
    let distinct_uvs = mesh.uvs.iter().filter(|uv| **uv != glam::Vec2::ZERO).count();
    assert!(distinct_uvs > mesh.vertex_count() / 2, "UVs were lost");
    // The file's own UVs reach slightly past [0, 1] (u down to -0.05); flipping v keeps them in range.
    assert!(
        mesh.uvs
            .iter()
            .all(|uv| (-0.1..=1.1).contains(&uv.x) && (-0.1..=1.1).contains(&uv.y))
    );
}

#[test]
fn fox_glb_is_skinned_into_its_bind_pose_with_its_embedded_texture() {
    let model = load_model(&common::models().join("Fox.glb")).unwrap();
    assert_mesh_sane(&model, "Fox.glb");
    assert_eq!(model.textures.len(), 1, "the embedded base color texture");
    let texture = &model.textures[0];
    assert!(texture.width >= 64 && texture.height >= 64);
    let material = &model.materials[model.parts[0].material];
    assert_eq!(material.base_color_texture, Some(0));
    // In bind pose the fox stands on four legs: longer than tall, taller than wide, with
    // its feet at the bottom of its bounds.
    let b = model.bounds();
    let size = b.size();
    assert!(size.z > size.y && size.y > size.x, "fox bounds {size}");
    assert!(
        size.max_element() > 50.0 && size.max_element() < 500.0,
        "fox size {size}"
    );
}

#[test]
fn cornell_box_glb_has_several_meshes_and_materials() {
    let model = load_model(&common::models().join("CornellBox.glb")).unwrap();
    assert_mesh_sane(&model, "CornellBox.glb");
    assert!(model.parts.len() >= 3, "{} parts", model.parts.len());
    let colors: std::collections::HashSet<[u32; 3]> = model
        .parts
        .iter()
        .map(|p| {
            let c = model.materials[p.material].base_color;
            [(c.x * 100.0) as u32, (c.y * 100.0) as u32, (c.z * 100.0) as u32]
        })
        .collect();
    assert!(
        colors.len() >= 3,
        "expected red, green and white walls, got {colors:?}"
    );
}

#[test]
fn project_scenes_load_with_three_viewpoints() {
    for name in ["teapot", "character"] {
        let scene = load_scene(&common::asset(&format!("scenes/{name}.ron"))).unwrap();
        assert_eq!(scene.views.len(), 3, "{name}");
        assert!(scene.instances.iter().any(|i| i.caster) && scene.instances.iter().any(|i| i.receiver));
        // The caster stands on the floor: contact shadows are possible.
        assert!(
            scene.caster_bounds().min.y.abs() < 1e-3,
            "{name}: caster floats at {}",
            scene.caster_bounds().min.y
        );
        for k in 0..3 {
            let cam = scene.view(k).unwrap();
            assert!(cam.near > 0.0 && cam.far > cam.near);
        }
        assert!(scene.view(3).is_err());
    }
}

#[test]
fn models_given_as_scenes_are_shown_on_a_floor() {
    let scene = load_scene(&common::models().join("spot.obj")).unwrap();
    assert_eq!(scene.views.len(), 3);
    let casters = scene.caster_bounds();
    assert!(casters.min.y.abs() < 1e-4, "model is set on the floor");
    let floor = scene.bounds_where(|i| !i.caster);
    assert!(floor.size().x > casters.size().x * 2.0);
}

// ---------------------------------------------------------------------------------------------
// Broken input

fn expect_error(path: &Path, needle: &str) -> PenumbraError {
    let err = match load_model(path) {
        Ok(_) => panic!("{} loaded but is broken", path.display()),
        Err(e) => e,
    };
    let text = err.to_string();
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(text.contains(&*name), "error does not name the file: {text}");
    assert!(
        text.to_lowercase().contains(&needle.to_lowercase()),
        "error does not say `{needle}`: {text}"
    );
    err
}

#[test]
fn missing_and_unsupported_files_are_named() {
    let dir = common::scratch_dir("missing");
    expect_error(&dir.join("nowhere.obj"), "not found");
    let stl = dir.join("model.stl");
    std::fs::write(&stl, b"solid x").unwrap();
    expect_error(&stl, "unsupported file type");
}

#[test]
fn truncated_and_garbage_files_give_errors() {
    let dir = common::scratch_dir("garbage");
    let fox = std::fs::read(common::models().join("Fox.glb")).unwrap();
    for (name, len) in [
        ("fox_header.glb", 12),
        ("fox_half.glb", fox.len() / 2),
        ("fox_minus_one.glb", fox.len() - 1),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, &fox[..len]).unwrap();
        expect_error(&path, "");
    }
    let noise: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    for name in ["noise.glb", "noise.gltf", "noise.obj"] {
        let path = dir.join(name);
        std::fs::write(&path, &noise).unwrap();
        expect_error(&path, "");
    }
    let teapot = std::fs::read(common::models().join("teapot.obj")).unwrap();
    let cut = dir.join("teapot_cut.obj");
    std::fs::write(&cut, &teapot[..teapot.len() / 3]).unwrap();
    // A cut OBJ may still be a valid prefix; it must load or fail cleanly, never panic.
    let _ = load_model(&cut);
    let empty = dir.join("empty.obj");
    std::fs::write(&empty, b"# nothing here\n").unwrap();
    expect_error(&empty, "no triangles");
}

#[test]
fn obj_with_out_of_range_face_index_is_rejected() {
    let dir = common::scratch_dir("obj_range");
    let path = dir.join("bad_face.obj");
    std::fs::write(&path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n").unwrap();
    expect_error(&path, "");
}

#[test]
fn obj_with_a_missing_mtl_loads_with_a_warning_and_the_default_material() {
    let dir = common::scratch_dir("obj_missing_mtl");
    let path = dir.join("missing_mtl.obj");
    std::fs::write(
        &path,
        "mtllib nothere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n",
    )
    .unwrap();
    let model = penumbra::loaders::load_model(&path).unwrap();
    assert_eq!(model.meshes.len(), 1);
    assert_eq!(model.meshes[0].triangle_count(), 1);
    assert_eq!(
        model.materials[model.parts[0].material],
        penumbra::Material::default()
    );
    assert!(
        model
            .warnings
            .iter()
            .any(|w| w.contains("missing_mtl.obj") && w.contains(".mtl")),
        "{:?}",
        model.warnings
    );
}

/// A minimal glTF with one triangle, its buffer given by `uri`.
fn gltf_json(uri: &str, byte_length: usize, index_count: usize) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],
        "buffers":[{{"uri":"{uri}","byteLength":{byte_length}}}],
        "bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":{}}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
                     {{"bufferView":1,"componentType":5125,"count":{index_count},"type":"SCALAR"}}]}}"#,
        index_count * 4
    )
}

fn triangle_bytes(indices: &[u32]) -> Vec<u8> {
    let positions: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let mut bytes: Vec<u8> = bytemuck::cast_slice(&positions).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(indices));
    bytes
}

#[test]
fn gltf_with_embedded_buffer_loads() {
    let dir = common::scratch_dir("gltf_ok");
    let bytes = triangle_bytes(&[0, 1, 2]);
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bytes)
    );
    let path = dir.join("triangle.gltf");
    std::fs::write(&path, gltf_json(&uri, bytes.len(), 3)).unwrap();
    let model = load_model(&path).unwrap();
    assert_eq!(model.meshes[0].triangle_count(), 1);
    // Missing normals were computed: the triangle faces +Z.
    assert!((model.meshes[0].normals[0] - Vec3::Z).length() < 1e-5);
}

#[test]
fn gltf_with_external_buffer_loads_and_a_missing_bin_is_named() {
    let dir = common::scratch_dir("gltf_bin");
    let bytes = triangle_bytes(&[0, 1, 2]);
    std::fs::write(dir.join("triangle.bin"), &bytes).unwrap();
    let path = dir.join("triangle.gltf");
    std::fs::write(&path, gltf_json("triangle.bin", bytes.len(), 3)).unwrap();
    assert_eq!(load_model(&path).unwrap().meshes.len(), 1);

    let path = dir.join("orphan.gltf");
    std::fs::write(&path, gltf_json("gone.bin", bytes.len(), 3)).unwrap();
    expect_error(&path, "gone.bin");

    let path = dir.join("short.gltf");
    std::fs::write(dir.join("short.bin"), &bytes[..20]).unwrap();
    std::fs::write(&path, gltf_json("short.bin", bytes.len(), 3)).unwrap();
    expect_error(&path, "");
}

#[test]
fn gltf_with_out_of_range_indices_is_rejected() {
    let dir = common::scratch_dir("gltf_range");
    let bytes = triangle_bytes(&[0, 1, 7]);
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    let path = dir.join("bad_index.gltf");
    std::fs::write(&path, gltf_json("tri.bin", bytes.len(), 3)).unwrap();
    expect_error(&path, "out of range");
    // An accessor that claims more indices than its buffer view holds.
    let path = dir.join("bad_count.gltf");
    std::fs::write(
        &path,
        gltf_json("tri.bin", bytes.len(), 3).replace(
            "\"count\":3,\"type\":\"SCALAR\"",
            "\"count\":3000,\"type\":\"SCALAR\"",
        ),
    )
    .unwrap();
    expect_error(&path, "");
}

#[test]
fn broken_scene_files_name_the_file() {
    let dir = common::scratch_dir("scene_files");
    let path = dir.join("bad.ron");
    std::fs::write(
        &path,
        "(meshes: [(name: \"a\", source: Teapot(tessellation: 8))], instances: [",
    )
    .unwrap();
    let err = load_scene(&path).unwrap_err().to_string();
    assert!(err.contains("bad.ron"), "{err}");
    let path = dir.join("missing_model.ron");
    std::fs::write(
        &path,
        r#"(meshes: [(name: "m", source: File(path: "nothere.glb"))], instances: [(mesh: "m")],
            light: Directional((direction: (0.0, -1.0, 0.0))), views: [])"#,
    )
    .unwrap();
    let err = load_scene(&path).unwrap_err().to_string();
    assert!(err.contains("nothere.glb"), "{err}");
    let path = dir.join("bad_tess.ron");
    std::fs::write(
        &path,
        r#"(meshes: [(name: "t", source: Teapot(tessellation: 0))], instances: [(mesh: "t")],
            light: Directional((direction: (0.0, -1.0, 0.0))), views: [])"#,
    )
    .unwrap();
    let err = load_scene(&path).unwrap_err().to_string();
    assert!(
        err.contains("bad_tess.ron") && err.contains("tessellation"),
        "{err}"
    );
}

#[test]
fn gltf_node_hierarchy_and_alpha_mask_are_applied() {
    let dir = common::scratch_dir("gltf_hierarchy");
    let bytes = triangle_bytes(&[0, 1, 2]);
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    // A parent translated up by 5 holds a child scaled by 2 that draws the unit triangle,
    // with a masked material.
    let json = gltf_json("tri.bin", bytes.len(), 3)
        .replace(
            r#""scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}]"#,
            r#""scenes":[{"nodes":[0]}],"nodes":[{"children":[1],"translation":[0,5,0]},{"mesh":0,"scale":[2,2,2]}],
               "materials":[{"alphaMode":"MASK","alphaCutoff":0.3,"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}}]"#,
        )
        .replace(r#""indices":1}"#, r#""indices":1,"material":0}"#);
    let path = dir.join("nested.gltf");
    std::fs::write(&path, json).unwrap();
    let model = load_model(&path).unwrap();
    let b = model.bounds();
    assert!((b.min - Vec3::new(0.0, 5.0, 0.0)).length() < 1e-5, "{b:?}");
    assert!((b.max - Vec3::new(2.0, 7.0, 0.0)).length() < 1e-5, "{b:?}");
    let material = &model.materials[model.parts[0].material];
    assert_eq!(material.alpha_mode, penumbra::AlphaMode::Mask { cutoff: 0.3 });
    assert_eq!(material.base_color, glam::Vec4::new(1.0, 0.0, 0.0, 1.0));
}

#[test]
fn gltf_emissive_factor_and_strength_are_read() {
    let dir = common::scratch_dir("gltf_emissive");
    let bytes = triangle_bytes(&[0, 1, 2]);
    std::fs::write(dir.join("tri.bin"), &bytes).unwrap();
    let json = gltf_json("tri.bin", bytes.len(), 3)
        .replace(
            r#""scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}]"#,
            r#""scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
               "extensionsUsed":["KHR_materials_emissive_strength"],
               "materials":[{"emissiveFactor":[1,0.5,0.25],
                             "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}]"#,
        )
        .replace(r#""indices":1}"#, r#""indices":1,"material":0}"#);
    let path = dir.join("glowing.gltf");
    std::fs::write(&path, json).unwrap();
    let model = load_model(&path).unwrap();
    let material = &model.materials[model.parts[0].material];
    assert_eq!(material.emissive, Vec3::new(4.0, 2.0, 1.0));
    assert_eq!(material.emissive_texture, None);
    assert!(
        !model.warnings.iter().any(|w| w.contains("emissive")),
        "{:?}",
        model.warnings
    );
}

#[test]
fn obj_material_library_gives_color_and_texture() {
    let dir = common::scratch_dir("obj_mtl");
    image::RgbaImage::from_pixel(4, 4, image::Rgba([10, 200, 30, 255]))
        .save(dir.join("green.png"))
        .unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        "newmtl painted\nKd 0.5 0.25 1.0\nmap_Kd green.png\n\nnewmtl plain\nKd 0.2 0.3 0.4\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("quad.obj"),
        "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         o painted_quad\nusemtl painted\nf 1/1 2/2 3/3 4/4\no plain_tri\nusemtl plain\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    let model = load_model(&dir.join("quad.obj")).unwrap();
    assert_eq!(model.parts.len(), 2);
    let painted = &model.materials[model.parts[0].material];
    assert_eq!(painted.base_color, glam::Vec4::new(0.5, 0.25, 1.0, 1.0));
    let texture = &model.textures[painted.base_color_texture.expect("map_Kd loaded")];
    assert_eq!((texture.width, texture.height), (4, 4));
    assert_eq!(&texture.rgba8[..4], &[10, 200, 30, 255]);
    assert_eq!(model.meshes[0].triangle_count(), 2, "the quad is triangulated");
    let plain = &model.materials[model.parts[1].material];
    assert_eq!(plain.base_color, glam::Vec4::new(0.2, 0.3, 0.4, 1.0));
    assert_eq!(plain.base_color_texture, None);
    // A texture the .mtl names but that does not exist: a warning naming it, and the material
    // without its texture (its colour kept).
    std::fs::remove_file(dir.join("green.png")).unwrap();
    let model = penumbra::loaders::load_model(&dir.join("quad.obj")).unwrap();
    assert!(model.materials.iter().all(|m| m.base_color_texture.is_none()));
    assert!(
        model.warnings.iter().any(|w| w.contains("green.png")),
        "{:?}",
        model.warnings
    );
}

/// The unit triangle (standing in the XY plane) lit by a glTF sun and spot, both turned -60
/// degrees about X (shining down and toward -z), and a point light.
fn gltf_with_lights(spot: &str) -> String {
    let turned = r#""rotation":[-0.5,0,0,0.8660254]"#;
    gltf_json("tri.bin", 36 + 12, 3).replace(
        r#""scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}]"#,
        &format!(
            r#""scenes":[{{"nodes":[0,1,2,3]}}],
                "nodes":[{{"mesh":0}},
                  {{"extensions":{{"KHR_lights_punctual":{{"light":0}}}},{turned}}},
                  {{"extensions":{{"KHR_lights_punctual":{{"light":1}}}},{turned},"translation":[0,3,3]}},
                  {{"extensions":{{"KHR_lights_punctual":{{"light":2}}}},"translation":[2,2,2]}}],
                "extensionsUsed":["KHR_lights_punctual"],"extensionsRequired":["KHR_lights_punctual"],
                "extensions":{{"KHR_lights_punctual":{{"lights":[
                  {{"type":"directional","name":"sun","color":[1,0.9,0.8],"intensity":3}},
                  {{"type":"spot","name":"lamp","intensity":300{spot}}},
                  {{"type":"point","name":"bulb","intensity":100,"range":20}}]}}}}"#
        ),
    )
}

#[test]
fn gltf_lights_are_read_and_light_the_showcase() {
    let dir = common::scratch_dir("gltf_lights");
    std::fs::write(dir.join("tri.bin"), triangle_bytes(&[0, 1, 2])).unwrap();
    let path = dir.join("lit.gltf");
    std::fs::write(&path, gltf_with_lights(r#","spot":{"outerConeAngle":0.6}"#)).unwrap();
    let model = load_model(&path).unwrap();
    assert_eq!(model.lights.len(), 3);
    let down = Vec3::new(0.0, -0.8660254, -0.5);
    let sun = &model.lights[0];
    assert_eq!(sun.kind, penumbra::scene::ModelLightKind::Directional);
    assert!((sun.direction - down).length() < 1e-4, "{}", sun.direction);
    assert_eq!((sun.color, sun.intensity), (Vec3::new(1.0, 0.9, 0.8), 3.0));
    let lamp = &model.lights[1];
    let penumbra::scene::ModelLightKind::Spot { outer_cone_deg, .. } = lamp.kind else {
        panic!("{:?}", lamp.kind)
    };
    assert!((outer_cone_deg - 0.6f32.to_degrees()).abs() < 1e-3);
    assert!((lamp.position - Vec3::new(0.0, 3.0, 3.0)).length() < 1e-5);
    assert!((lamp.direction - down).length() < 1e-4);

    // The showcase takes the file's lights as they are: the sun (3 lux) is the key light, the
    // spot (300 cd) the second, the point light (100 cd, range 20) the third; the camera's
    // exposure is in physical terms (Bevy's default EV100).
    let scene = penumbra::Scene::showcase(&model).unwrap();
    assert_eq!(
        scene.exposure,
        penumbra::Exposure::Ev100(penumbra::Exposure::EV100_DEFAULT)
    );
    let penumbra::Light::Directional(key) = scene.light else {
        panic!("{:?}", scene.light)
    };
    assert!((key.direction.normalize() - down).length() < 1e-4);
    assert_eq!(key.angular_diameter_deg, penumbra::scene::MODEL_SUN_DIAMETER_DEG);
    assert_eq!(key.intensity, 3.0);
    assert_eq!(scene.more_lights.len(), 2);
    let penumbra::Light::Spot(spot) = scene.more_lights[0] else {
        panic!("{:?}", scene.more_lights[0])
    };
    assert_eq!((spot.intensity, spot.range), (300.0, None));
    assert!(
        (spot.radius - 0.02 * 15.5f32.sqrt()).abs() < 1e-4,
        "{}",
        spot.radius
    );
    // The bulb: 100 cd within 20 units, its size 2% of its distance to the model's centre.
    let penumbra::Light::Point(bulb) = scene.more_lights[1] else {
        panic!("{:?}", scene.more_lights[1])
    };
    assert_eq!((bulb.intensity, bulb.range), (100.0, Some(20.0)));
    assert!(
        !scene.warnings.iter().any(|w| w.contains("bulb")),
        "{:?}",
        scene.warnings
    );

    // Both lights reach the picture: it differs from the key light alone (an exposure that
    // shows 3 lux and the spot's 19 lux at the model).
    let gpu = common::gpu();
    let camera = scene.view(0).unwrap();
    let settings = penumbra::ShadowSettings::default();
    let scene = penumbra::Scene {
        exposure: penumbra::Exposure::Multiplier(0.04),
        ..scene
    };
    let both = common::render(&gpu, &scene, &camera, settings, 160, 120);
    let alone = penumbra::Scene {
        more_lights: vec![],
        ..scene.clone()
    };
    assert_ne!(both, common::render(&gpu, &alone, &camera, settings, 160, 120));

    // A spot without its cone is refused with the file's name, not a panic.
    let broken = dir.join("broken.gltf");
    std::fs::write(&broken, gltf_with_lights("")).unwrap();
    expect_error(&broken, "");
}

#[test]
fn bevys_mixed_lighting_scene_loads_with_its_sun() {
    // It requires KHR_lights_punctual and KHR_texture_transform, which were refused before.
    let path = common::models().join("MixedLightingExample/MixedLightingExample.gltf");
    let model = load_model(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_mesh_sane(&model, "MixedLightingExample");
    let suns: Vec<_> = model
        .lights
        .iter()
        .filter(|l| l.kind == penumbra::scene::ModelLightKind::Directional)
        .collect();
    assert_eq!(suns.len(), 1, "{:?}", model.lights);
    // The sun shines downward.
    assert!(suns[0].direction.normalize().y < -0.3, "{}", suns[0].direction);
    let scene = penumbra::Scene::showcase(&model).unwrap();
    assert!(matches!(scene.light, penumbra::Light::Directional(_)));
    // The picture has a shadow: some floor is darker than the brightest floor by the sun's share.
    let gpu = common::gpu();
    let camera = scene.view(0).unwrap();
    let image = common::render(
        &gpu,
        &scene,
        &camera,
        penumbra::ShadowSettings::default(),
        200,
        150,
    );
    let lums: Vec<f32> = image
        .pixels()
        .map(|p| p.0[0] as f32 + p.0[1] as f32 + p.0[2] as f32)
        .collect();
    let max = lums.iter().cloned().fold(0.0, f32::max);
    assert!(lums.iter().filter(|&&l| l < 0.5 * max).count() > 200);
    image
        .save(common::output_dir().join("mixed-lighting-showcase.png"))
        .unwrap();
}

#[test]
fn a_scene_file_takes_a_gltf_files_lights_with_lights_from() {
    let dir = common::scratch_dir("gltf_lights_from");
    std::fs::write(dir.join("tri.bin"), triangle_bytes(&[0, 1, 2])).unwrap();
    std::fs::write(
        dir.join("lit.gltf"),
        gltf_with_lights(r#","spot":{"outerConeAngle":0.6}"#),
    )
    .unwrap();
    let scene_text = |lights: &str, translation: &str| {
        format!(
            r#"(
            meshes: [(name: "lit", source: File(path: "lit.gltf")), (name: "floor", source: Plane(size: 20.0))],
            instances: [(mesh: "lit", translation: {translation}), (mesh: "floor", caster: false)],
            {lights}
            views: [(name: "a", eye: (10.0, 4.0, 8.0), target: (10.0, 0.0, 0.0))],
        )"#
        )
    };
    let path = dir.join("room.ron");
    std::fs::write(
        &path,
        scene_text(
            r#"lights_from: (mesh: "lit", sizes: (sun_diameter_deg: 1.5)),"#,
            "(10.0, 0.0, 0.0)",
        ),
    )
    .unwrap();
    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let penumbra::Light::Directional(sun) = scene.light else {
        panic!("{:?}", scene.light)
    };
    assert_eq!(sun.angular_diameter_deg, 1.5);
    let penumbra::Light::Spot(spot) = scene.more_lights[0] else {
        panic!("{:?}", scene.more_lights)
    };
    // Placed with the instance; the default spot size.
    assert!(
        (spot.position - Vec3::new(10.0, 3.0, 3.0)).length() < 1e-4,
        "{}",
        spot.position
    );
    let distance = spot.position.distance(Vec3::new(10.5, 0.5, 0.0));
    assert!((spot.radius - 0.02 * distance).abs() < 1e-4);
    // The bulb, a point light, placed with the instance too.
    let penumbra::Light::Point(bulb) = scene.more_lights[1] else {
        panic!("{:?}", scene.more_lights)
    };
    assert!(
        (bulb.position - Vec3::new(12.0, 2.0, 2.0)).length() < 1e-4,
        "{}",
        bulb.position
    );
    assert!(
        !scene.warnings.iter().any(|w| w.contains("not used")),
        "{:?}",
        scene.warnings
    );

    // Without lights_from the file's lights are reported as unused.
    std::fs::write(
        &path,
        scene_text(
            "light: Directional((direction: (0.0, -1.0, 0.0))),",
            "(0.0, 0.0, 0.0)",
        ),
    )
    .unwrap();
    let scene = load_scene(&path).unwrap();
    assert!(
        scene.warnings.iter().any(|w| w.contains("not used")),
        "{:?}",
        scene.warnings
    );

    for (lights, expected) in [
        (r#"lights_from: (mesh: "floor"),"#, "no directional or spot light"),
        (
            r#"lights_from: (mesh: "lamp"),"#,
            "`lamp`, which no instance places",
        ),
        (
            r#"lights_from: (mesh: "lit"), light: Directional((direction: (0.0, -1.0, 0.0))),"#,
            "more than one",
        ),
        (
            r#"lights_from: (mesh: "lit", sizes: (sun_diameter_deg: 95.0)),"#,
            "angular_diameter_deg",
        ),
    ] {
        std::fs::write(&path, scene_text(lights, "(0.0, 0.0, 0.0)")).unwrap();
        let err = load_scene(&path).unwrap_err().to_string();
        assert!(err.contains("room.ron") && err.contains(expected), "{err}");
    }
}

/// glTF samplers (wrap and filter modes) and occlusion textures (UV set, strength, their
/// KHR_texture_transform) are read.
#[test]
fn gltf_samplers_and_occlusion_textures_are_read() {
    use penumbra::scene::{FilterMode, WrapMode};
    let dir = common::scratch_dir("gltf_sampler");
    std::fs::write(dir.join("tri.bin"), triangle_bytes(&[0, 1, 2])).unwrap();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 100, 50, 255]))
        .save(dir.join("tex.png"))
        .unwrap();
    let json = gltf_json("tri.bin", 36 + 12, 3)
        .replace(r#""indices":1}"#, r#""indices":1,"material":0}"#)
        .replace(
            r#""buffers":"#,
            r#""samplers":[{"wrapS":33071,"wrapT":33648,"magFilter":9728,"minFilter":9729}],
               "images":[{"uri":"tex.png"}],
               "textures":[{"sampler":0,"source":0}],
               "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}},
                             "occlusionTexture":{"index":0,"texCoord":0,"strength":0.5,
                               "extensions":{"KHR_texture_transform":{"offset":[0.5,0],"scale":[2,3],"texCoord":1}}}}],
               "buffers":"#,
        );
    let path = dir.join("sampled.gltf");
    std::fs::write(&path, json).unwrap();
    let model = penumbra::loaders::load_model(&path).unwrap();
    let m = &model.materials[model.parts[0].material];
    assert_eq!(m.sampler.wrap_u, WrapMode::ClampToEdge);
    assert_eq!(m.sampler.wrap_v, WrapMode::MirroredRepeat);
    assert_eq!(m.sampler.mag_filter, FilterMode::Nearest);
    assert_eq!(m.sampler.min_filter, FilterMode::Linear);
    assert!(
        !m.sampler.mipmaps,
        "LINEAR minification samples the full level only"
    );
    assert_eq!(m.occlusion_texture, m.base_color_texture);
    assert!(m.occlusion_texture.is_some());
    // The occlusion texture's own KHR_texture_transform: its texCoord (1) and its matrix.
    assert_eq!((m.occlusion_uv_set, m.occlusion_strength), (1, 0.5));
    let t = m.occlusion_uv_transform;
    assert_eq!(t.transform_point2(glam::Vec2::ZERO), glam::Vec2::new(0.5, 0.0));
    assert_eq!(t.transform_point2(glam::Vec2::ONE), glam::Vec2::new(2.5, 3.0));
}
