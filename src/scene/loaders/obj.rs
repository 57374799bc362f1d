//! Wavefront OBJ through `tobj`: faces triangulated, one mesh per OBJ object/group, `.mtl`
//! diffuse color (`Kd`), diffuse texture (`map_Kd`) and dissolve (`d`, as alpha). A missing or
//! unreadable `.mtl` or texture is a warning ([`Model::warnings`]): the geometry loads with the
//! default material, or the material without its texture, as other viewers do.

use std::path::Path;

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::error::{PenumbraError, Result};
use crate::scene::{Instance, Material, Mesh, Model, TextureImage};

pub(super) fn load(path: &Path) -> Result<Model> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (objects, materials) =
        tobj::load_obj(path, &options).map_err(|e| PenumbraError::model(path, e.to_string()))?;
    let mut model = Model::default();
    let obj_materials = materials.unwrap_or_else(|e| {
        model.warnings.push(format!(
            "{}: its material library (.mtl) cannot be loaded ({e}): the default material is used",
            path.display()
        ));
        Vec::new()
    });
    let base_dir = path.parent().unwrap_or(Path::new(""));

    for m in &obj_materials {
        let texture = match &m.diffuse_texture {
            Some(name) if !name.trim().is_empty() => {
                let file = base_dir.join(name.trim());
                let decoded = std::fs::read(&file).map_err(|e| e.to_string()).and_then(|bytes| {
                    TextureImage::decode(&file.display().to_string(), &bytes).map_err(|e| e.to_string())
                });
                match decoded {
                    Ok(image) => {
                        model.textures.push(image);
                        Some(model.textures.len() - 1)
                    }
                    Err(e) => {
                        model.warnings.push(format!(
                            "{}: texture {} of material `{}` cannot be loaded ({e}): the material is drawn without it",
                            path.display(),
                            file.display(),
                            m.name
                        ));
                        None
                    }
                }
            }
            _ => None,
        };
        let [r, g, b] = m.diffuse.unwrap_or([0.8, 0.8, 0.8]);
        model.materials.push(Material {
            name: m.name.clone(),
            base_color: Vec4::new(r, g, b, m.dissolve.unwrap_or(1.0)),
            base_color_texture: texture,
            ..Default::default()
        });
    }
    let default_material = model.materials.len();
    model.materials.push(Material::default());

    for object in objects {
        let mesh = object.mesh;
        if mesh.indices.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = mesh.positions.chunks_exact(3).map(Vec3::from_slice).collect();
        let normals = (!mesh.normals.is_empty()).then(|| {
            mesh.normals
                .chunks_exact(3)
                .map(Vec3::from_slice)
                .collect::<Vec<_>>()
        });
        // OBJ's v axis points up; textures here are stored top row first.
        let uvs = (!mesh.texcoords.is_empty()).then(|| {
            mesh.texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0], 1.0 - t[1]))
                .collect::<Vec<_>>()
        });
        let name = if object.name.is_empty() {
            "obj".to_string()
        } else {
            object.name
        };
        let built = Mesh::new(name, positions, normals, uvs, mesh.indices)
            .map_err(|e| PenumbraError::model(path, e.to_string()))?;
        let material = match mesh.material_id {
            Some(id) if id < obj_materials.len() => id,
            // Only when the library could not be read (warned above).
            Some(_) if obj_materials.is_empty() => default_material,
            Some(id) => {
                return Err(PenumbraError::model(
                    path,
                    format!("material id {id} does not exist"),
                ));
            }
            None => default_material,
        };
        model.meshes.push(built);
        model.parts.push(Instance {
            mesh: model.meshes.len() - 1,
            material,
            transform: Mat4::IDENTITY,
            caster: true,
            receiver: true,
        });
    }
    Ok(model)
}
