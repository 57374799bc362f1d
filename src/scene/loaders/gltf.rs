//! glTF 2.0 through the `gltf` crate: `.gltf` with external or embedded (data URI) buffers,
//! `.glb`, the node hierarchy's transforms, base-color factor and texture, alpha mode MASK,
//! skinned meshes posed in their bind pose (the joints' rest transforms), the lights of
//! `KHR_lights_punctual` (see [`crate::scene::lights_from_model`]) and the base-color texture's
//! `KHR_texture_transform` (applied to the primitive's UVs).

use std::collections::HashMap;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::error::{PenumbraError, Result};
use crate::scene::{
    AlphaMode, Instance, Material, Mesh, Model, ModelLight, ModelLightKind, Shading, TextureImage,
};

/// A `KHR_lights_punctual` light at its node, in the model's space: it shines along the
/// node's -Z.
fn convert_light(light: &gltf::khr_lights_punctual::Light, global: &Mat4) -> ModelLight {
    use gltf::khr_lights_punctual::Kind;
    let kind = match light.kind() {
        Kind::Directional => ModelLightKind::Directional,
        Kind::Point => ModelLightKind::Point,
        Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => ModelLightKind::Spot {
            outer_cone_deg: outer_cone_angle.to_degrees(),
            inner_cone_deg: inner_cone_angle.to_degrees(),
        },
    };
    ModelLight {
        name: light.name().unwrap_or("").to_string(),
        kind,
        color: Vec3::from(light.color()),
        intensity: light.intensity(),
        position: global.transform_point3(Vec3::ZERO),
        direction: global.transform_vector3(Vec3::NEG_Z),
        range: light.range(),
    }
}

pub(super) fn load(path: &Path) -> Result<Model> {
    let fail = |reason: String| PenumbraError::model(path, reason);
    let bytes = std::fs::read(path).map_err(|source| PenumbraError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let gltf = gltf::Gltf::from_slice(&bytes).map_err(|e| fail(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new(""));
    for buffer in gltf.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source()
            && !uri.starts_with("data:")
        {
            let file = base.join(uri);
            if !file.is_file() {
                return Err(fail(format!(
                    "buffer {} refers to `{uri}`, which does not exist ({})",
                    buffer.index(),
                    file.display()
                )));
            }
        }
    }
    let buffers = gltf::import_buffers(&gltf.document, Some(base), gltf.blob.clone())
        .map_err(|e| fail(format!("cannot read its buffers: {e}")))?;
    for buffer in gltf.buffers() {
        let have = buffers[buffer.index()].len();
        if have < buffer.length() {
            return Err(fail(format!(
                "buffer {} declares {} bytes but has {have}",
                buffer.index(),
                buffer.length()
            )));
        }
    }
    check_accessors(&gltf.document, &buffers).map_err(fail)?;
    let images = gltf::import_images(&gltf.document, Some(base), &buffers)
        .map_err(|e| fail(format!("cannot read its images: {e}")))?;

    let mut model = Model::default();
    for extension in gltf.extensions_used() {
        if !matches!(
            extension,
            "KHR_lights_punctual" | "KHR_texture_transform" | "KHR_materials_emissive_strength"
        ) {
            model
                .warnings
                .push(format!("extension {extension} is not supported: ignored"));
        }
    }
    for (i, image) in images.into_iter().enumerate() {
        model
            .textures
            .push(to_rgba8(format!("{} image {i}", path.display()), image).map_err(fail)?);
    }
    for material in gltf.materials() {
        model
            .materials
            .push(convert_material(&material, &mut model.warnings));
    }
    let default_material = model.materials.len();
    model.materials.push(Material::default());

    let document = &gltf.document;
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or_else(|| fail("it has no scene".into()))?;
    let globals = global_transforms(document);
    let mut mesh_cache: HashMap<(usize, usize, Option<usize>), usize> = HashMap::new();
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    let mut visited = vec![false; document.nodes().len()];
    // The lights with their nodes' indices: they are listed in node order.
    let mut lights = Vec::new();
    while let Some(node) = stack.pop() {
        if std::mem::replace(&mut visited[node.index()], true) {
            return Err(fail(format!(
                "node {} is reachable twice (a cycle or shared child)",
                node.index()
            )));
        }
        stack.extend(node.children());
        if let Some(light) = node.light() {
            lights.push((node.index(), convert_light(&light, &globals[node.index()])));
        }
        let Some(mesh) = node.mesh() else { continue };
        let skin = node.skin();
        for primitive in mesh.primitives() {
            let label = format!(
                "mesh {} `{}` primitive {}",
                mesh.index(),
                mesh.name().unwrap_or(""),
                primitive.index()
            );
            let Some(mut built) = read_primitive(&primitive, &buffers, &label, &mut model.warnings)
                .map_err(|e| fail(format!("{label}: {e}")))?
            else {
                continue;
            };
            // The glTF mesh's own name: what scene files assign lightmaps by.
            built.name = mesh
                .name()
                .map_or_else(|| format!("mesh {}", mesh.index()), str::to_string);
            // A skinned mesh is placed by its joints, not by its node (glTF spec 3.7.3).
            let transform = match &skin {
                Some(skin) => {
                    built = pose_skinned(built, &primitive, skin, &buffers, &globals)
                        .map_err(|e| fail(format!("{label}: {e}")))?;
                    Mat4::IDENTITY
                }
                None => globals[node.index()],
            };
            let key = (mesh.index(), primitive.index(), skin.as_ref().map(|s| s.index()));
            let mesh_index = *mesh_cache.entry(key).or_insert_with(|| {
                model.meshes.push(built);
                model.meshes.len() - 1
            });
            let material = primitive.material().index().unwrap_or(default_material);
            model.parts.push(Instance {
                mesh: mesh_index,
                material,
                transform,
                caster: true,
                receiver: true,
            });
        }
    }
    lights.sort_by_key(|(node, _)| *node);
    model.lights = lights.into_iter().map(|(_, light)| light).collect();
    Ok(model)
}

/// Checks that every accessor's data lies inside its buffer, so reading can never go out of bounds.
fn check_accessors(document: &gltf::Document, buffers: &[gltf::buffer::Data]) -> Result<(), String> {
    for accessor in document.accessors() {
        let Some(view) = accessor.view() else {
            continue;
        };
        let element = accessor.size();
        let stride = view.stride().unwrap_or(element);
        let count = accessor.count();
        let needed = if count == 0 {
            0
        } else {
            (count - 1)
                .checked_mul(stride)
                .and_then(|n| n.checked_add(element))
                .and_then(|n| n.checked_add(accessor.offset()))
                .ok_or_else(|| format!("accessor {} is too large", accessor.index()))?
        };
        if needed > view.length() {
            return Err(format!(
                "accessor {} needs {needed} bytes but its buffer view {} has {}",
                accessor.index(),
                view.index(),
                view.length()
            ));
        }
        let buffer_len = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
        if view.offset() + view.length() > buffer_len {
            return Err(format!(
                "buffer view {} ends at byte {} but buffer {} has {buffer_len} bytes",
                view.index(),
                view.offset() + view.length(),
                view.buffer().index()
            ));
        }
    }
    Ok(())
}

fn convert_material(material: &gltf::Material, warnings: &mut Vec<String>) -> Material {
    let pbr = material.pbr_metallic_roughness();
    let name = material.name().unwrap_or("material").to_string();
    let alpha_mode = match material.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask {
            cutoff: material.alpha_cutoff().unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let texture = pbr.base_color_texture().map(|info| {
        let set = info
            .texture_transform()
            .and_then(|t| t.tex_coord())
            .unwrap_or(info.tex_coord());
        if set != 0 {
            warnings.push(format!(
                "material `{name}`: base color texture uses UV set {set}, read from set 0"
            ));
        }
        info.texture().source().index()
    });
    // The metallic-roughness and normal textures read UV set 0, as the base colour's does.
    let on_set_zero = |what: &str, set: u32, index: usize, warnings: &mut Vec<String>| {
        if set != 0 {
            warnings.push(format!(
                "material `{name}`: {what} texture uses UV set {set}, read from set 0"
            ));
        }
        index
    };
    let metallic_roughness_texture = pbr.metallic_roughness_texture().map(|info| {
        on_set_zero(
            "metallic-roughness",
            info.tex_coord(),
            info.texture().source().index(),
            warnings,
        )
    });
    let normal = material.normal_texture();
    let normal_texture = normal
        .as_ref()
        .map(|n| on_set_zero("normal", n.tex_coord(), n.texture().source().index(), warnings));
    // Occlusion: its own UV set (0 or 1); glTF's strength.
    let occlusion = material.occlusion_texture();
    // Its KHR_texture_transform (the crate reads it for plain texture infos only).
    let transform = occlusion
        .as_ref()
        .and_then(|o| o.extension_value("KHR_texture_transform"))
        .cloned();
    let number = |key: &str, i: usize, default: f32| {
        transform
            .as_ref()
            .and_then(|t| t.get(key))
            .and_then(|v| {
                if i == usize::MAX {
                    v.as_f64()
                } else {
                    v.get(i)?.as_f64()
                }
            })
            .map_or(default, |v| v as f32)
    };
    let occlusion_uv_transform = uv_transform(
        [number("offset", 0, 0.0), number("offset", 1, 0.0)],
        number("rotation", usize::MAX, 0.0),
        [number("scale", 0, 1.0), number("scale", 1, 1.0)],
    );
    let occlusion_uv_set = transform
        .as_ref()
        .and_then(|t| t.get("texCoord")?.as_u64())
        .map(|t| t as u32)
        .or(occlusion.as_ref().map(|o| o.tex_coord()))
        .unwrap_or(0);
    if occlusion_uv_set > 1 {
        warnings.push(format!(
            "material `{name}`: occlusion texture uses UV set {occlusion_uv_set}, read from set 1"
        ));
    }
    // The base-color texture's sampler serves the material's textures.
    let sampler = pbr
        .base_color_texture()
        .map(|info| convert_sampler(&info.texture().sampler()))
        .or_else(|| {
            material
                .occlusion_texture()
                .map(|o| convert_sampler(&o.texture().sampler()))
        })
        .unwrap_or_default();
    let emissive_texture = material.emissive_texture().map(|info| {
        on_set_zero(
            "emissive",
            info.tex_coord(),
            info.texture().source().index(),
            warnings,
        )
    });
    Material {
        name,
        base_color: Vec4::from_array(pbr.base_color_factor()),
        base_color_texture: texture,
        alpha_mode,
        occlusion_texture: occlusion.as_ref().map(|o| o.texture().source().index()),
        occlusion_uv_set: occlusion_uv_set.min(1),
        occlusion_strength: occlusion.as_ref().map_or(1.0, |o| o.strength().clamp(0.0, 1.0)),
        occlusion_uv_transform,
        emissive: Vec3::from(material.emissive_factor()) * material.emissive_strength().unwrap_or(1.0),
        emissive_texture,
        shading: Shading::MetallicRoughness {
            metallic: pbr.metallic_factor().clamp(0.0, 1.0),
            roughness: pbr.roughness_factor().clamp(0.0, 1.0),
        },
        metallic_roughness_texture,
        normal_texture,
        normal_scale: normal.as_ref().map_or(1.0, |n| n.scale()),
        sampler,
    }
}

/// glTF's sampler as this crate's (its default: repeat, linear filtering).
fn convert_sampler(sampler: &gltf::texture::Sampler) -> crate::scene::TextureSampler {
    use crate::scene::{FilterMode, TextureSampler, WrapMode};
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |w: WrappingMode| match w {
        WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
        WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        WrappingMode::Repeat => WrapMode::Repeat,
    };
    let (min_filter, mipmap_filter, mipmaps) = match sampler.min_filter() {
        Some(MinFilter::Nearest) => (FilterMode::Nearest, FilterMode::Nearest, false),
        Some(MinFilter::Linear) => (FilterMode::Linear, FilterMode::Nearest, false),
        Some(MinFilter::NearestMipmapNearest) => (FilterMode::Nearest, FilterMode::Nearest, true),
        Some(MinFilter::NearestMipmapLinear) => (FilterMode::Nearest, FilterMode::Linear, true),
        Some(MinFilter::LinearMipmapNearest) => (FilterMode::Linear, FilterMode::Nearest, true),
        Some(MinFilter::LinearMipmapLinear) | None => (FilterMode::Linear, FilterMode::Linear, true),
    };
    TextureSampler {
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
        mag_filter: match sampler.mag_filter() {
            Some(MagFilter::Nearest) => FilterMode::Nearest,
            _ => FilterMode::Linear,
        },
        min_filter,
        mipmap_filter,
        mipmaps,
    }
}

/// The mesh of one primitive, or `None` (with a warning) for points and lines.
fn read_primitive(
    primitive: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    label: &str,
    warnings: &mut Vec<String>,
) -> Result<Option<Mesh>, String> {
    use gltf::mesh::Mode;
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or("it has no POSITION attribute")?
        .map(Vec3::from_array)
        .collect();
    let normals = reader
        .read_normals()
        .map(|it| it.map(Vec3::from_array).collect::<Vec<_>>());
    let uvs = reader
        .read_tex_coords(0)
        .map(|it| it.into_f32().map(Vec2::from_array).collect::<Vec<_>>());
    let vertex_order: Vec<u32> = match reader.read_indices() {
        Some(it) => it.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = match primitive.mode() {
        Mode::Triangles => vertex_order,
        Mode::TriangleStrip => (2..vertex_order.len())
            .flat_map(|i| {
                let (a, b, c) = (vertex_order[i - 2], vertex_order[i - 1], vertex_order[i]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => (2..vertex_order.len())
            .flat_map(|i| [vertex_order[0], vertex_order[i - 1], vertex_order[i]])
            .collect(),
        other => {
            warnings.push(format!(
                "{label}: {other:?} primitives are not drawn (triangles only)"
            ));
            return Ok(None);
        }
    };
    if indices.len() % 3 != 0 {
        return Err(format!(
            "{} indices is not a whole number of triangles",
            indices.len()
        ));
    }
    let normals = normals.filter(|n| n.len() == positions.len());
    let mut uvs = uvs.filter(|t| t.len() == positions.len());
    // KHR_texture_transform on the base-color texture: a primitive has one material, so its
    // UVs take the transform (glTF: translation x rotation x scale).
    let transform = primitive
        .material()
        .pbr_metallic_roughness()
        .base_color_texture()
        .and_then(|info| info.texture_transform());
    if let (Some(t), Some(uvs)) = (transform, uvs.as_mut()) {
        let matrix = uv_transform(t.offset(), t.rotation(), t.scale());
        for uv in uvs.iter_mut() {
            *uv = matrix.transform_point2(*uv);
        }
    }
    let lightmap_uvs = reader
        .read_tex_coords(1)
        .map(|it| it.into_f32().map(Vec2::from_array).collect::<Vec<_>>())
        .filter(|t| t.len() == positions.len());
    let colors = reader
        .read_colors(0)
        .map(|it| it.into_rgba_f32().map(Vec4::from_array).collect::<Vec<_>>())
        .filter(|c| c.len() == positions.len());
    let tangents = reader
        .read_tangents()
        .map(|it| it.map(Vec4::from_array).collect::<Vec<_>>())
        .filter(|t| t.len() == positions.len());
    let normal_mapped = primitive.material().normal_texture().is_some();
    let mut mesh = Mesh::new(label, positions, normals, uvs, indices).map_err(|e| e.to_string())?;
    if let Some(uv1) = lightmap_uvs {
        mesh = mesh.with_lightmap_uvs(uv1).map_err(|e| e.to_string())?;
    }
    if let Some(colors) = colors {
        mesh = mesh.with_colors(colors).map_err(|e| e.to_string())?;
    }
    // Tangents where a normal map needs them: the file's, or MikkTSpace's (as glTF asks).
    if normal_mapped {
        mesh = match tangents {
            Some(tangents) => mesh.with_tangents(tangents).map_err(|e| e.to_string())?,
            None => mesh.with_generated_tangents(),
        };
    }
    Ok(Some(mesh))
}

/// `KHR_texture_transform`'s matrix: translation by `offset` times a rotation by `rotation`
/// radians (counter-clockwise in UV space) times a scale.
fn uv_transform(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> glam::Affine2 {
    let (sin, cos) = rotation.sin_cos();
    glam::Affine2::from_translation(Vec2::from_array(offset))
        * glam::Affine2::from_mat2(glam::Mat2::from_cols(Vec2::new(cos, -sin), Vec2::new(sin, cos)))
        * glam::Affine2::from_scale(Vec2::from_array(scale))
}

/// World transforms of every node from its local transform and its parents'.
fn global_transforms(document: &gltf::Document) -> Vec<Mat4> {
    let count = document.nodes().len();
    let mut parent = vec![None; count];
    for node in document.nodes() {
        for child in node.children() {
            parent[child.index()] = Some(node.index());
        }
    }
    let local: Vec<Mat4> = document
        .nodes()
        .map(|n| Mat4::from_cols_array_2d(&n.transform().matrix()))
        .collect();
    (0..count)
        .map(|mut i| {
            let mut m = local[i];
            let mut steps = 0;
            while let Some(p) = parent[i] {
                m = local[p] * m;
                i = p;
                steps += 1;
                if steps > count {
                    break; // a cycle: stop rather than loop forever
                }
            }
            m
        })
        .collect()
}

/// Applies linear-blend skinning with every joint at its rest transform (the bind pose).
fn pose_skinned(
    mesh: Mesh,
    primitive: &gltf::Primitive,
    skin: &gltf::Skin,
    buffers: &[gltf::buffer::Data],
    globals: &[Mat4],
) -> Result<Mesh, String> {
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let skin_reader = skin.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    let inverse_bind: Vec<Mat4> = match skin_reader.read_inverse_bind_matrices() {
        Some(it) => it.map(|m| Mat4::from_cols_array_2d(&m)).collect(),
        None => vec![Mat4::IDENTITY; joints.len()],
    };
    if inverse_bind.len() < joints.len() {
        return Err("the skin has fewer inverse bind matrices than joints".into());
    }
    let joint_matrices: Vec<Mat4> = joints
        .iter()
        .zip(&inverse_bind)
        .map(|(&j, ibm)| globals[j] * *ibm)
        .collect();
    let (Some(joint_ids), Some(weights)) = (reader.read_joints(0), reader.read_weights(0)) else {
        return Ok(mesh); // a skin without weights: leave the mesh as authored
    };
    let joint_ids: Vec<[u16; 4]> = joint_ids.into_u16().collect();
    let weights: Vec<[f32; 4]> = weights.into_f32().collect();
    if joint_ids.len() != mesh.vertex_count() || weights.len() != mesh.vertex_count() {
        return Err("JOINTS_0/WEIGHTS_0 counts differ from the vertex count".into());
    }
    let mut positions = Vec::with_capacity(mesh.vertex_count());
    let mut normals = Vec::with_capacity(mesh.vertex_count());
    for (v, (ids, w)) in joint_ids.iter().zip(&weights).enumerate() {
        let mut m = Mat4::ZERO;
        let mut total = 0.0;
        for k in 0..4 {
            if w[k] != 0.0 {
                let joint = joint_matrices
                    .get(ids[k] as usize)
                    .ok_or_else(|| format!("vertex {v} uses joint {} of {}", ids[k], joints.len()))?;
                m += *joint * w[k];
                total += w[k];
            }
        }
        let m = if total > 1e-6 {
            m * (1.0 / total)
        } else {
            Mat4::IDENTITY
        };
        positions.push(m.transform_point3(mesh.positions[v]));
        normals.push(m.transform_vector3(mesh.normals[v]));
    }
    let (lightmap_uvs, colors, normal_mapped) = (mesh.lightmap_uvs, mesh.colors, !mesh.tangents.is_empty());
    let posed = Mesh::new(mesh.name, positions, Some(normals), Some(mesh.uvs), mesh.indices)
        .map(|posed| Mesh {
            lightmap_uvs,
            colors,
            ..posed
        })
        .map_err(|e| e.to_string())?;
    // Tangents for the posed normals (MikkTSpace again: the file's were for the bind pose).
    Ok(if normal_mapped {
        posed.with_generated_tangents()
    } else {
        posed
    })
}

fn to_rgba8(name: String, image: gltf::image::Data) -> Result<TextureImage, String> {
    use gltf::image::Format;
    let (w, h) = (image.width, image.height);
    let px = &image.pixels;
    let n = (w as usize) * (h as usize);
    let rgba: Vec<u8> = match image.format {
        Format::R8G8B8A8 => px.clone(),
        Format::R8G8B8 => px.chunks_exact(3).flat_map(|c| [c[0], c[1], c[2], 255]).collect(),
        Format::R8G8 => px
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[0], c[0], c[1]])
            .collect(),
        Format::R8 => px.iter().flat_map(|&c| [c, c, c, 255]).collect(),
        Format::R16G16B16A16 => px
            .chunks_exact(8)
            .flat_map(|c| [c[1], c[3], c[5], c[7]])
            .collect(),
        Format::R16G16B16 => px.chunks_exact(6).flat_map(|c| [c[1], c[3], c[5], 255]).collect(),
        other => return Err(format!("{name}: pixel format {other:?} is not supported")),
    };
    if rgba.len() != n * 4 {
        return Err(format!("{name}: {w}x{h} image has {} bytes of pixels", px.len()));
    }
    Ok(TextureImage::from_rgba8(name, w, h, rgba))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_transform_follows_the_extensions_example() {
        // The extension's own example: the lower left quadrant of the image (v down), turned
        // clockwise by 90 degrees.
        let m = uv_transform([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
        for (uv, expected) in [
            ((0.0, 0.0), (0.0, 1.0)),
            ((1.0, 0.0), (0.0, 0.5)),
            ((0.0, 1.0), (0.5, 1.0)),
            ((1.0, 1.0), (0.5, 0.5)),
        ] {
            let got = m.transform_point2(Vec2::new(uv.0, uv.1));
            assert!(
                (got - Vec2::new(expected.0, expected.1)).length() < 1e-6,
                "{uv:?} -> {got}"
            );
        }
        // Flipping v: offset (0, 1), scale (1, -1).
        let flip = uv_transform([0.0, 1.0], 0.0, [1.0, -1.0]);
        assert!((flip.transform_point2(Vec2::new(0.25, 0.0)) - Vec2::new(0.25, 1.0)).length() < 1e-6);
    }
}
