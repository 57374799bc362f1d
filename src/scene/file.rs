//! The scene file format: a RON document that lists meshes, materials, instances, the light and
//! named viewpoints. Paths inside it are relative to the file.
//!
//! ```ron
//! (
//!     meshes: [
//!         (name: "teapot", source: Teapot(tessellation: 12)),
//!         (name: "floor", source: Plane(size: 16.0)),
//!     ],
//!     materials: [(name: "porcelain", base_color: (0.9, 0.85, 0.75, 1.0))],
//!     instances: [
//!         (mesh: "teapot", material: Some("porcelain")),
//!         (mesh: "floor", material: Some("porcelain"), caster: false),
//!     ],
//!     light: Directional((direction: (-0.4, -1.0, -0.3), angular_diameter_deg: 2.0)),
//!     // or several: lights: [Directional((...)), Spot((...))], the first the key light;
//!     // also Point((...)), and the area lights Rect((...)) and Disk((...)) (docs/lights.md);
//!     // or a glTF mesh's own: lights_from: (mesh: "room", sizes: (sun_diameter_deg: 1.0)),
//!     views: [(name: "front", eye: (0.0, 4.0, 9.0), target: (0.0, 1.0, 0.0))],
//! )
//! ```

use std::path::{Path, PathBuf};

use glam::{EulerRot, Mat4, Quat, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

use super::{
    AlphaMode, Camera, Exposure, Light, LightingMode, LightmapFilter, LightmapImage, LightmapRect, Lightmaps,
    Material, Mesh, Model, ModelLightSizes, Scene, TextureImage, Viewpoint, character, primitives, teapot,
};
use crate::error::{PenumbraError, Result};

/// Where a mesh comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum MeshSource {
    /// Newell's teapot with `tessellation` x `tessellation` quads per patch (1..=64).
    Teapot {
        /// Quads along each side of a patch, in 1..=64 (outside that is an error).
        tessellation: u32,
    },
    /// The built-in humanoid figure, about 1.8 units tall.
    Character,
    /// A box with the given edge lengths, centered at the origin.
    Box {
        /// Edge lengths along x, y and z in world units, each > 0.
        size: Vec3,
    },
    /// A sphere centered at the origin.
    Sphere {
        /// Radius in world units, > 0 (the sphere has 48 segments around and 24 rings).
        radius: f32,
    },
    /// A floor on y = 0 of side `size`, with UVs repeating `uv_repeat` times.
    Plane {
        /// Side length in world units, > 0.
        size: f32,
        /// How many times a texture repeats across the floor in each direction (default 1).
        #[serde(default = "one")]
        uv_repeat: f32,
    },
    /// An OBJ or glTF (.gltf / .glb) file, relative to the scene file. Its own materials are
    /// used unless the instance names one.
    File {
        /// The file's path, relative to the scene file's directory; its extension picks the
        /// loader.
        path: String,
    },
}

/// A named mesh entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshEntry {
    /// The name that instances (`mesh`) and `lights_from` refer to; unique in the file. A
    /// built-in mesh also takes it as its [`Mesh::name`], which lightmap rectangles match; a
    /// model file's meshes keep their own names.
    pub name: String,
    /// Where the mesh comes from: a built-in shape or a model file.
    pub source: MeshSource,
}

/// Where a base-color texture comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TextureSource {
    /// A generated checkerboard of `squares` x `squares` cells of two sRGB colors.
    Checker {
        /// Cells along each side, kept to 1..=256 (the image is at most 256 texels a side).
        squares: u32,
        /// The color of the top-left cell and every other one, 8-bit sRGB RGBA.
        a: [u8; 4],
        /// The color of the remaining cells, 8-bit sRGB RGBA.
        b: [u8; 4],
    },
    /// A PNG or JPEG file, relative to the scene file.
    File {
        /// The image's path, relative to the scene file's directory.
        path: String,
    },
}

/// A named material entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialEntry {
    /// The name that instances give as `material`; unique in the file. It becomes
    /// [`Material::name`].
    pub name: String,
    /// Linear RGBA.
    pub base_color: Vec4,
    /// A base-color texture, multiplying `base_color` (UV set 0); default none.
    #[serde(default)]
    pub texture: Option<TextureSource>,
    /// How alpha (`base_color`'s times the texture's) is used: `Opaque` (the default),
    /// `Mask(cutoff: 0.5)` with a cutoff in [0, 1], or `Blend`; see [`AlphaMode`].
    #[serde(default)]
    pub alpha_mode: AlphaMode,
    /// Metalness in [0, 1]. With `metallic` or `roughness` given the material is shaded with
    /// glTF's metallic-roughness model ([`crate::scene::Shading`]); with neither, Lambertian.
    #[serde(default)]
    pub metallic: Option<f32>,
    /// Roughness in [0, 1] (default 1 when only `metallic` is given).
    #[serde(default)]
    pub roughness: Option<f32>,
}

/// An instance entry. Rotation is in degrees about Y, then X, then Z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InstanceEntry {
    /// The `name` of the entry in `meshes` to place; a model file's entry places all its parts.
    pub mesh: String,
    /// A material name; `None` keeps a file's own materials (built-in meshes get a grey one).
    #[serde(default)]
    pub material: Option<String>,
    /// Where the mesh's origin goes, in world units (default the origin).
    #[serde(default)]
    pub translation: Vec3,
    /// Euler angles in degrees for x, y and z (default none), combined as `Ry * Rx * Rz` (glam's
    /// `EulerRot::YXZ`).
    #[serde(default)]
    pub rotation_deg: Vec3,
    /// Scale along the mesh's own x, y and z axes, applied before the rotation (default
    /// `(1.0, 1.0, 1.0)`). A zero scale is an error; a negative one mirrors.
    #[serde(default = "unit_scale")]
    pub scale: Vec3,
    /// Whether it is drawn into the shadow maps (default `true`).
    #[serde(default = "yes")]
    pub caster: bool,
    /// Whether it receives shadows (default `true`); `false` lights it as if nothing occluded it.
    #[serde(default = "yes")]
    pub receiver: bool,
}

/// A named viewpoint. Near and far planes are fitted to the scene when left out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ViewEntry {
    /// The viewpoint's name ([`Viewpoint::name`]).
    pub name: String,
    /// The camera's position in world units.
    pub eye: Vec3,
    /// The world point the camera looks at (the center of the image).
    pub target: Vec3,
    /// Vertical field of view in degrees, in (0, 180) (default 45).
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
    /// Near clip distance in world units. Default: fitted around the whole scene's bounds
    /// ([`Camera::fit_depth_range`]). The two planes must end up with 0 < near < far.
    #[serde(default)]
    pub near: Option<f32>,
    /// Far clip distance in world units; default fitted like `near`.
    #[serde(default)]
    pub far: Option<f32>,
}

/// Lights taken from a model file's own (glTF `KHR_lights_punctual`; see
/// [`crate::scene::lights_from_model`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightsFrom {
    /// A mesh entry whose source is a glTF file.
    pub mesh: String,
    /// The sizes glTF does not give: default the sun's 0.53 degrees for suns, 2% of their
    /// distance to the model's centre for spots.
    #[serde(default)]
    pub sizes: ModelLightSizes,
}

/// Where one mesh's second UV set lands in a lightmap atlas: `min` and `size` in texture space
/// (v down), or in OpenGL-style UV space (v up) when the atlas entry says `v_up`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightmapRectEntry {
    /// A mesh's name: a built-in mesh entry's, or a glTF mesh's own name inside a file.
    pub mesh: String,
    /// The rectangle's `min` corner in atlas UV units (0 to 1 across the image): in texture
    /// space (v down, so its top-left corner), or with the atlas's `v_up` in UV space with v up
    /// (its bottom-left corner).
    pub min: Vec2,
    /// The rectangle's width and height in the same units. Without `v_up` a lightmap UV `uv`
    /// lands at `min + uv * size`; a negative extent mirrors.
    pub size: Vec2,
}

/// A lightmap atlas baked for one lighting mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LightmapEntry {
    /// `Mixed` (indirect light only) or `Baked` (direct and indirect).
    pub mode: LightingMode,
    /// A .ktx2, .hdr, .png or .jpg file, relative to the scene file.
    pub path: String,
    /// The rectangles are given with v up (as Bevy and OpenGL tools list them).
    #[serde(default)]
    pub v_up: bool,
    /// The meshes this atlas lights and the rectangle each samples; a mesh may appear once per
    /// atlas, and in one atlas per mode.
    pub meshes: Vec<LightmapRectEntry>,
}

/// A scene description as stored on disk.
///
/// [`load_scene`] reads and builds one from a path; [`SceneFile::parse`] and
/// [`SceneFile::build`] do the same from text. Built-in meshes need no other file:
///
/// ```
/// # fn main() -> penumbra::Result<()> {
/// use std::path::Path;
/// use penumbra::SceneFile;
///
/// let text = r#"(
///     meshes: [
///         (name: "ball", source: Sphere(radius: 1.0)),
///         (name: "floor", source: Plane(size: 10.0)),
///     ],
///     materials: [(name: "red", base_color: (0.8, 0.1, 0.1, 1.0))],
///     instances: [
///         (mesh: "ball", material: Some("red"), translation: (0.0, 1.5, 0.0)),
///         (mesh: "floor", caster: false),
///     ],
///     light: Directional((direction: (-0.3, -1.0, -0.2), angular_diameter_deg: 0.53)),
///     views: [(name: "front", eye: (0.0, 3.0, 8.0), target: (0.0, 1.0, 0.0))],
/// )"#;
/// let file = SceneFile::parse(text, Path::new("inline.ron"))?;
/// // Paths in the file would be relative to the first argument; this one has none.
/// let scene = file.build(Path::new("."), Path::new("inline.ron"))?;
///
/// assert_eq!(scene.instances.len(), 2);
/// assert_eq!(scene.views[0].name, "front");
/// // The ball (radius 1, centered 1.5 up) is the only caster: it stops 0.5 above the floor.
/// assert!((scene.caster_bounds().min.y - 0.5).abs() < 1e-4);
/// // Fields left out take their defaults.
/// assert_eq!(file.ambient, glam::Vec3::splat(0.12));
/// assert_eq!(file.views[0].fov_y_deg, 45.0);
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneFile {
    /// The meshes instances can place, by name (required).
    pub meshes: Vec<MeshEntry>,
    /// The materials instances can name (default none: built-in meshes then get a grey one,
    /// model files keep their own).
    #[serde(default)]
    pub materials: Vec<MaterialEntry>,
    /// What the scene shows: each entry places one mesh entry (required).
    pub instances: Vec<InstanceEntry>,
    /// The one light, or the key light when `lights` lists more.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub light: Option<Light>,
    /// The lights (at most 16, [`crate::MAX_LIGHTS`]), the first the key light; use one of `light`, `lights` and
    /// `lights_from`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<Light>,
    /// The lights of a glTF mesh entry's file, placed like that mesh's first instance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lights_from: Option<LightsFrom>,
    /// Constant light from everywhere, linear RGB, added to every surface unshadowed and not
    /// scaled by the exposure (default `(0.12, 0.12, 0.12)`).
    #[serde(default = "default_ambient")]
    pub ambient: Vec3,
    /// The named viewpoints, in order ([`Scene::view`] takes them by index). Required, but may be
    /// `[]`.
    pub views: Vec<ViewEntry>,
    /// Lightmap atlases, each for one lighting mode.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lightmaps: Vec<LightmapEntry>,
    /// How the scene is lit at first (default `Dynamic`).
    #[serde(default)]
    pub lighting: LightingMode,
    /// What lightmap texels are multiplied by (default 1).
    #[serde(default = "one")]
    pub lightmap_exposure: f32,
    /// How lightmaps are read between their texels (default `Bilinear`).
    #[serde(default)]
    pub lightmap_filter: LightmapFilter,
    /// The camera's exposure (see [`Exposure`]): `Multiplier(m)` or `Ev100(ev)`. Default:
    /// `Multiplier(1.0)`, or `Ev100(9.7)` when the lights come from a model file
    /// (`lights_from`), whose intensities are lux and candela.
    #[serde(default)]
    pub exposure: Option<Exposure>,
}

fn one() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}
fn unit_scale() -> Vec3 {
    Vec3::ONE
}
fn default_fov() -> f32 {
    45.0
}
fn default_ambient() -> Vec3 {
    Vec3::splat(0.12)
}

impl SceneFile {
    /// Parses RON text. `path` is only used in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
        // `light: Directional(...)` reads as `Some(...)` without the wrapper.
        let options =
            ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        options.from_str(text).map_err(|e| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
    }

    /// Reads and parses a scene file.
    pub fn read(path: &Path) -> Result<SceneFile> {
        let text = std::fs::read_to_string(path).map_err(|source| PenumbraError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    /// Serializes to pretty RON.
    pub fn to_ron(&self) -> String {
        ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .expect("scene files always serialize")
    }

    /// Builds the scene, loading referenced files relative to `base_dir`. `path` names the
    /// scene file in errors.
    pub fn build(&self, base_dir: &Path, path: &Path) -> Result<Scene> {
        let bad = |reason: String| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason,
        };
        let (light, more_lights) = match (self.light, self.lights.split_first(), &self.lights_from) {
            (Some(light), None, None) => (light, Vec::new()),
            (None, Some((key, more)), None) => (*key, more.to_vec()),
            // Placed once the meshes are.
            (None, None, Some(_)) => (Light::default(), Vec::new()),
            // Lit by its lightmaps alone: a key light that adds nothing.
            (None, None, None) if !self.lightmaps.is_empty() => (Light::none(), Vec::new()),
            (None, None, None) => {
                return Err(bad(
                    "it has no light: give `light`, `lights` or `lights_from` (only a scene with lightmaps may have none)"
                        .into(),
                ));
            }
            _ => {
                return Err(bad(
                    "it has more than one of `light`, `lights` and `lights_from`: give one of them".into(),
                ));
            }
        };
        let mut scene = Scene {
            light,
            more_lights,
            ambient: self.ambient,
            ..Scene::default()
        };
        super::check_light_count(1 + scene.more_lights.len()).map_err(|e| bad(e.to_string()))?;
        for (k, light) in scene.lights().enumerate() {
            light.validate().map_err(|e| bad(format!("light {k}: {e}")))?;
        }

        let material_index = self.add_materials(&mut scene, base_dir, path)?;

        let models = self.models(&mut scene, base_dir, path)?;

        // The model, transform and sizes `lights_from` takes its lights from.
        let mut lights_placed = None;
        for (k, inst) in self.instances.iter().enumerate() {
            let model = models.get(&inst.mesh).ok_or_else(|| {
                bad(format!(
                    "instance {k} uses mesh `{}`, which is not in `meshes`",
                    inst.mesh
                ))
            })?;
            let material = match &inst.material {
                None => None,
                Some(name) => Some(*material_index.get(name).ok_or_else(|| {
                    bad(format!(
                        "instance {k} uses material `{name}`, which is not in `materials`"
                    ))
                })?),
            };
            let r = inst.rotation_deg;
            let transform = Mat4::from_scale_rotation_translation(
                inst.scale,
                Quat::from_euler(
                    EulerRot::YXZ,
                    r.y.to_radians(),
                    r.x.to_radians(),
                    r.z.to_radians(),
                ),
                inst.translation,
            );
            if !transform.is_finite() || transform.determinant().abs() < 1e-20 {
                return Err(bad(format!(
                    "instance {k}: transform is not finite or has a zero scale"
                )));
            }
            scene.add_model(model, transform, material, inst.caster, inst.receiver);
            if let Some(from) = self.lights_from.as_ref().filter(|f| f.mesh == inst.mesh) {
                lights_placed.get_or_insert((model, transform, from.sizes));
            }
        }
        if let Some(from) = &self.lights_from {
            let Some((model, place, sizes)) = lights_placed else {
                return Err(bad(format!(
                    "`lights_from` names mesh `{}`, which no instance places",
                    from.mesh
                )));
            };
            let center = place.transform_point3(model.bounds().center());
            let lights = super::lights_from_model(&model.lights, place, center, sizes, &mut scene.warnings);
            let Some((key, more)) = lights.split_first() else {
                return Err(bad(format!(
                    "`lights_from`: mesh `{}`'s file has no directional or spot light",
                    from.mesh
                )));
            };
            scene.light = *key;
            scene.more_lights = more.to_vec();
            for (k, light) in scene.lights().enumerate() {
                light
                    .validate()
                    .map_err(|e| bad(format!("`lights_from` light {k}: {e}")))?;
            }
        }

        self.add_lightmaps(&mut scene, base_dir, path)?;
        scene.lighting = self.lighting;
        scene.lightmap_exposure = self.lightmap_exposure;
        scene.lightmap_filter = self.lightmap_filter;
        scene.exposure = self.exposure.unwrap_or(if self.lights_from.is_some() {
            Exposure::Ev100(Exposure::EV100_DEFAULT)
        } else {
            Exposure::default()
        });
        scene.exposure.validate().map_err(|e| bad(e.to_string()))?;
        scene.validate_lightmaps().map_err(|e| bad(e.to_string()))?;

        self.add_views(&mut scene, path)?;
        scene.validate().map_err(|e| bad(e.to_string()))?;
        Ok(scene)
    }

    /// The file's materials added to `scene`, by name.
    fn add_materials(
        &self,
        scene: &mut Scene,
        base_dir: &Path,
        path: &Path,
    ) -> Result<std::collections::HashMap<String, usize>> {
        let bad = |reason: String| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason,
        };
        let mut material_index = std::collections::HashMap::new();
        for entry in &self.materials {
            if !entry.base_color.is_finite() {
                return Err(bad(format!(
                    "material `{}` has a non-finite base_color",
                    entry.name
                )));
            }
            if let AlphaMode::Mask { cutoff } = entry.alpha_mode
                && !(0.0..=1.0).contains(&cutoff)
            {
                return Err(bad(format!(
                    "material `{}`: alpha cutoff {cutoff} is outside [0, 1]",
                    entry.name
                )));
            }
            let texture = match &entry.texture {
                None => None,
                Some(TextureSource::Checker { squares, a, b }) => {
                    scene
                        .textures
                        .push(TextureImage::checker(&entry.name, *squares, *a, *b));
                    Some(scene.textures.len() - 1)
                }
                Some(TextureSource::File { path: rel }) => {
                    let file = base_dir.join(rel);
                    let bytes = std::fs::read(&file).map_err(|source| PenumbraError::Io {
                        path: file.clone(),
                        source,
                    })?;
                    scene
                        .textures
                        .push(TextureImage::decode(&file.display().to_string(), &bytes)?);
                    Some(scene.textures.len() - 1)
                }
            };
            let index = scene.add_material(Material {
                name: entry.name.clone(),
                base_color: entry.base_color,
                base_color_texture: texture,
                alpha_mode: entry.alpha_mode,
                shading: match (entry.metallic, entry.roughness) {
                    (None, None) => crate::scene::Shading::Lambert,
                    (metallic, roughness) => crate::scene::Shading::MetallicRoughness {
                        metallic: metallic.unwrap_or(0.0),
                        roughness: roughness.unwrap_or(1.0),
                    },
                },
                ..Default::default()
            });
            if material_index.insert(entry.name.clone(), index).is_some() {
                return Err(bad(format!("material `{}` is defined twice", entry.name)));
            }
        }
        Ok(material_index)
    }

    /// The file's meshes as models, by name (built-ins become one-part models).
    fn models(
        &self,
        scene: &mut Scene,
        base_dir: &Path,
        path: &Path,
    ) -> Result<std::collections::HashMap<String, Model>> {
        let bad = |reason: String| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason,
        };
        let mut models = std::collections::HashMap::new();
        for entry in &self.meshes {
            // A built-in mesh takes its entry's name (what lightmaps are assigned by).
            let builtin = |mesh: Mesh| Model {
                meshes: vec![Mesh {
                    name: entry.name.clone(),
                    ..mesh
                }],
                materials: vec![Material::default()],
                textures: vec![],
                warnings: vec![],
                lights: vec![],
                parts: vec![super::Instance {
                    mesh: 0,
                    material: 0,
                    transform: Mat4::IDENTITY,
                    caster: true,
                    receiver: true,
                }],
            };
            let positive = |what: &str, v: f32| {
                if v > 0.0 && v.is_finite() {
                    Ok(v)
                } else {
                    Err(bad(format!("mesh `{}`: {what} {v} must be positive", entry.name)))
                }
            };
            let model = match &entry.source {
                MeshSource::Teapot { tessellation } => {
                    if !teapot::TESSELLATION_RANGE.contains(tessellation) {
                        return Err(bad(format!(
                            "mesh `{}`: teapot tessellation {tessellation} is outside {:?}",
                            entry.name,
                            teapot::TESSELLATION_RANGE
                        )));
                    }
                    builtin(teapot::teapot(*tessellation))
                }
                MeshSource::Character => builtin(character::character()),
                MeshSource::Box { size } => {
                    for v in size.to_array() {
                        positive("box size", v)?;
                    }
                    builtin(primitives::cuboid(*size))
                }
                MeshSource::Sphere { radius } => {
                    builtin(primitives::sphere(positive("radius", *radius)?, 48, 24))
                }
                MeshSource::Plane { size, uv_repeat } => {
                    builtin(primitives::plane(positive("plane size", *size)?, *uv_repeat))
                }
                MeshSource::File { path: rel } => {
                    let model = super::loaders::load_model(&base_dir.join(rel))?;
                    let lights_used = self.lights_from.as_ref().is_some_and(|f| f.mesh == entry.name);
                    if !model.lights.is_empty() && !lights_used {
                        scene.warnings.push(format!(
                            "{}: its {} light(s) are not used (a scene file takes a file's lights with `lights_from`)",
                            rel,
                            model.lights.len()
                        ));
                    }
                    model
                }
            };
            if models.insert(entry.name.clone(), model).is_some() {
                return Err(bad(format!("mesh `{}` is defined twice", entry.name)));
            }
        }
        Ok(models)
    }

    /// The file's lightmaps, loaded and added to `scene`.
    fn add_lightmaps(&self, scene: &mut Scene, base_dir: &Path, path: &Path) -> Result<()> {
        let bad = |reason: String| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason,
        };
        for atlas in &self.lightmaps {
            if atlas.mode == LightingMode::Dynamic {
                return Err(bad(format!(
                    "lightmap `{}`: its mode must be `Mixed` or `Baked` (dynamic lighting uses no lightmap)",
                    atlas.path
                )));
            }
            let image = LightmapImage::load(&base_dir.join(&atlas.path))?;
            scene.warnings.extend(image.warnings.iter().cloned());
            let rects = atlas
                .meshes
                .iter()
                .map(|r| {
                    if !(r.min.is_finite() && r.size.is_finite()) {
                        return Err(bad(format!(
                            "lightmap `{}`: mesh `{}`'s rectangle is not finite",
                            atlas.path, r.mesh
                        )));
                    }
                    Ok(if atlas.v_up {
                        LightmapRect::from_v_up(&r.mesh, r.min, r.size)
                    } else {
                        LightmapRect {
                            mesh: r.mesh.clone(),
                            min: r.min,
                            max: r.min + r.size,
                        }
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            scene.lightmaps.push(Lightmaps {
                mode: atlas.mode,
                image,
                rects,
            });
        }
        Ok(())
    }

    /// The file's viewpoints added to `scene`, their depth ranges fitted to it.
    fn add_views(&self, scene: &mut Scene, path: &Path) -> Result<()> {
        let bad = |reason: String| PenumbraError::SceneFile {
            path: path.to_path_buf(),
            reason,
        };
        let bounds = scene.bounds();
        for v in &self.views {
            let mut camera = Camera {
                eye: v.eye,
                target: v.target,
                up: Vec3::Y,
                fov_y_deg: v.fov_y_deg,
                near: 0.1,
                far: 100.0,
            };
            if !(v.fov_y_deg > 0.0 && v.fov_y_deg < 180.0 && v.eye.is_finite() && v.target.is_finite()) {
                return Err(bad(format!(
                    "view `{}`: fov must be in (0, 180) and eye/target finite",
                    v.name
                )));
            }
            camera.fit_depth_range(&bounds);
            if let Some(near) = v.near {
                camera.near = near;
            }
            if let Some(far) = v.far {
                camera.far = far;
            }
            if !(camera.near > 0.0 && camera.far > camera.near) {
                return Err(bad(format!("view `{}`: need 0 < near < far", v.name)));
            }
            scene.views.push(Viewpoint {
                name: v.name.clone(),
                camera,
            });
        }
        Ok(())
    }
}

/// Loads a scene: a `.ron` scene file, or an OBJ / glTF model shown by [`Scene::showcase`].
///
/// The extension decides which (`.ron`, else the model loaders'). A scene file's own paths
/// are relative to its directory. What the loaders could not represent is listed in
/// [`Scene::warnings`].
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use std::path::Path;
///
/// let scene = penumbra::load_scene(Path::new("assets/scenes/teapot.ron"))?;
/// for warning in &scene.warnings {
///     eprintln!("warning: {warning}");
/// }
/// let camera = scene.view(0)?;
/// println!("{} instances, first view from {}", scene.instances.len(), camera.eye);
///
/// // A model file gets a floor, three orbiting views and a light (its own, if it has any).
/// let showcase = penumbra::load_scene(Path::new("model.glb"))?;
/// assert_eq!(showcase.views.len(), 3);
/// # Ok(()) }
/// ```
pub fn load_scene(path: &Path) -> Result<Scene> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "ron" => {
            let file = SceneFile::read(path)?;
            let base: PathBuf = path.parent().map(Path::to_path_buf).unwrap_or_default();
            file.build(&base, path)
        }
        _ => {
            let model = super::loaders::load_model(path)?;
            Scene::showcase(&model).map_err(|e| PenumbraError::model(path, e.to_string()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINI: &str = r#"(
        meshes: [(name: "ball", source: Sphere(radius: 1.0)), (name: "floor", source: Plane(size: 10.0))],
        materials: [(name: "red", base_color: (1.0, 0.0, 0.0, 1.0))],
        instances: [(mesh: "ball", material: Some("red"), translation: (0.0, 1.5, 0.0)),
                    (mesh: "floor", caster: false)],
        light: Directional((direction: (0.0, -1.0, 0.0))),
        views: [(name: "a", eye: (0.0, 3.0, 8.0), target: (0.0, 1.0, 0.0))],
    )"#;

    #[test]
    fn parses_and_builds_and_round_trips() {
        let file = SceneFile::parse(MINI, Path::new("mini.ron")).unwrap();
        let scene = file.build(Path::new("."), Path::new("mini.ron")).unwrap();
        assert_eq!(scene.instances.len(), 2);
        assert!(!scene.instances[1].caster && scene.instances[1].receiver);
        assert!((scene.caster_bounds().min.y - 0.5).abs() < 1e-4);
        let again = SceneFile::parse(&file.to_ron(), Path::new("x.ron")).unwrap();
        assert_eq!(again, file);
    }

    #[test]
    fn rectangle_and_disk_lights_read_with_their_defaults_and_errors() {
        let sun = "Directional((direction: (0.0, -1.0, 0.0)))";
        let rect = "Rect((position: (0.0, 3.0, 0.0), direction: (0.0, -1.0, 0.0), width: 1.2, height: 0.3))";
        let disk =
            "Disk((position: (1.0, 3.0, 0.0), direction: (0.0, -1.0, 0.0), radius: 0.2, intensity: 5.0))";
        let text = MINI.replace(&format!("light: {sun}"), &format!("lights: [{rect}, {disk}]"));
        let scene = SceneFile::parse(&text, Path::new("area.ron"))
            .unwrap()
            .build(Path::new("."), Path::new("area.ron"))
            .unwrap();
        let Light::Rect(r) = scene.light else {
            panic!("the key light is the rectangle: {:?}", scene.light)
        };
        // Defaults: no `up` (picked: the light faces straight down, so its height runs along z),
        // white, 1 nit, no range.
        assert_eq!(
            (r.up, r.color, r.intensity, r.range),
            (Vec3::ZERO, Vec3::ONE, 1.0, None)
        );
        let area = scene.light.area().unwrap();
        assert!(area.v.normalize().abs_diff_eq(Vec3::Z, 1e-6) && (area.u.length() - 0.6).abs() < 1e-6);
        assert!(matches!(scene.more_lights.as_slice(), [Light::Disk(d)] if d.intensity == 5.0));
        // A negative side is refused, naming the field and the file.
        let bad = MINI.replace(
            &format!("light: {sun}"),
            &format!("light: {}", rect.replace("width: 1.2", "width: -1.0")),
        );
        let err = SceneFile::parse(&bad, Path::new("area.ron"))
            .and_then(|f| f.build(Path::new("."), Path::new("area.ron")))
            .unwrap_err()
            .to_string();
        assert!(err.contains("area.ron") && err.contains("light.width"), "{err}");
    }

    #[test]
    fn a_list_of_lights_gives_the_key_light_and_the_rest() {
        let sun = "Directional((direction: (0.0, -1.0, 0.0)))";
        let spot = "Spot((position: (0.0, 5.0, 0.0), direction: (0.0, -1.0, 0.0), cone_angle_deg: 30.0, radius: 0.1))";
        let text = MINI.replace(
            &format!("light: {sun}"),
            &format!("lights: [{spot}, {sun}, {sun}]"),
        );
        let file = SceneFile::parse(&text, Path::new("lights.ron")).unwrap();
        let scene = file.build(Path::new("."), Path::new("lights.ron")).unwrap();
        assert!(matches!(scene.light, Light::Spot(_)));
        assert_eq!(scene.more_lights.len(), 2);
        assert_eq!(scene.lights().count(), 3);
        let again = SceneFile::parse(&file.to_ron(), Path::new("x.ron")).unwrap();
        assert_eq!(again, file);
        // Both, neither, too many and a bad one: errors that name the file and the field.
        let both = MINI.replace(
            &format!("light: {sun},"),
            &format!("light: {sun}, lights: [{sun}],"),
        );
        let neither = MINI.replace(&format!("light: {sun},"), "");
        let seventeen = MINI.replace(
            &format!("light: {sun}"),
            &format!("lights: [{}]", [sun; 17].join(", ")),
        );
        let bad = MINI.replace(
            &format!("light: {sun}"),
            &format!("lights: [{sun}, {}]", spot.replace("30.0", "95.0")),
        );
        for (text, expected) in [
            (both, "more than one of `light`, `lights`"),
            (neither, "no light"),
            (seventeen, "at most 16"),
            (bad, "light 1"),
        ] {
            let file = SceneFile::parse(&text, Path::new("l.ron")).unwrap();
            let err = file
                .build(Path::new("."), Path::new("l.ron"))
                .unwrap_err()
                .to_string();
            assert!(err.contains("l.ron") && err.contains(expected), "{err}");
        }
    }

    #[test]
    fn errors_name_the_file_and_the_problem() {
        let err = SceneFile::parse("(meshes: [", Path::new("broken.ron")).unwrap_err();
        assert!(err.to_string().contains("broken.ron"), "{err}");
        let text = MINI.replace("mesh: \"ball\"", "mesh: \"cube\"");
        let file = SceneFile::parse(&text, Path::new("s.ron")).unwrap();
        let err = file
            .build(Path::new("."), Path::new("s.ron"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("s.ron") && err.contains("`cube`"), "{err}");
        let text = MINI.replace("radius: 1.0", "radius: -1.0");
        let file = SceneFile::parse(&text, Path::new("s.ron")).unwrap();
        assert!(file.build(Path::new("."), Path::new("s.ron")).is_err());
        let err = load_scene(Path::new("does/not/exist.ron"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("does/not/exist.ron"), "{err}");
    }
}
