//! [`Scene`]: meshes, materials and their instances, its lights and named viewpoints, and the
//! [`Model`]s loaders make.

use super::*;
use glam::{Mat4, Vec3};

use crate::error::{PenumbraError, Result};

/// One placement of a mesh with a material.
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Model-to-world transform.
    pub transform: Mat4,
    /// Drawn into the shadow map.
    pub caster: bool,
    /// Receives shadows (when false it is lit as if nothing occluded it).
    pub receiver: bool,
}

/// A named camera position.
#[derive(Debug, Clone, PartialEq)]
pub struct Viewpoint {
    /// The viewpoint's name, for menus and messages (a scene file's view `name`); names are not
    /// checked for uniqueness.
    pub name: String,
    /// The camera this viewpoint looks through ([`Scene::view`] returns it by index).
    pub camera: Camera,
}

/// Meshes, materials and textures loaded from one file, with the parts that place them.
/// Indices in `parts` refer to this model's own lists.
#[derive(Debug, Clone, Default)]
pub struct Model {
    /// The file's meshes (one per glTF primitive, or per OBJ object or group), in their own
    /// coordinates; [`Model::parts`] place them.
    pub meshes: Vec<Mesh>,
    /// The file's materials, indexed by the parts' [`Instance::material`]; their texture fields
    /// index [`Model::textures`].
    pub materials: Vec<Material>,
    /// The file's decoded images, indexed by the materials' texture fields.
    pub textures: Vec<TextureImage>,
    /// Where the meshes stand: each part names one of this model's meshes and materials, and its
    /// transform takes the mesh into the model's frame (a glTF node's global transform, or the
    /// identity for a skinned mesh, which comes already posed).
    pub parts: Vec<Instance>,
    /// The file's own lights (glTF `KHR_lights_punctual`), in the model's space, in the order
    /// of their nodes.
    pub lights: Vec<ModelLight>,
    /// Things in the file that could not be represented, in words (for the user to see).
    pub warnings: Vec<String>,
}

impl Model {
    /// Bounds of all parts in the model's frame.
    pub fn bounds(&self) -> Aabb {
        self.parts.iter().fold(Aabb::EMPTY, |acc, part| {
            acc.union(&self.meshes[part.mesh].bounds.transformed(&part.transform))
        })
    }
}

/// Errors unless `count` lights fit in one frame ([`crate::MAX_LIGHTS`]).
pub(crate) fn check_light_count(count: usize) -> Result<()> {
    if count > crate::MAX_LIGHTS {
        return Err(PenumbraError::setting(
            "lights",
            format!(
                "{count} lights, at most {} are shadowed in one frame",
                crate::MAX_LIGHTS
            ),
        ));
    }
    Ok(())
}

/// Everything needed to render a frame.
///
/// A scene can come from a file ([`crate::load_scene`]) or be put together in code:
///
/// ```
/// # fn main() -> penumbra::Result<()> {
/// use glam::{Mat4, Vec3};
/// use penumbra::{Camera, DirectionalLight, Light, Material, Mesh, Scene, Viewpoint};
///
/// // A unit square on y = 0 facing +Y (counter-clockwise seen from above); normals computed.
/// let square = Mesh::new(
///     "square",
///     vec![
///         Vec3::new(-0.5, 0.0, 0.5),
///         Vec3::new(0.5, 0.0, 0.5),
///         Vec3::new(0.5, 0.0, -0.5),
///         Vec3::new(-0.5, 0.0, -0.5),
///     ],
///     None,
///     None,
///     vec![0, 1, 2, 0, 2, 3],
/// )?;
///
/// let mut scene = Scene::default();
/// let mesh = scene.add_mesh(square);
/// let grey = scene.add_material(Material::colored("grey", [0.8, 0.8, 0.8]));
/// let red = scene.add_material(Material::colored("red", [0.8, 0.1, 0.1]));
/// // A 10 x 10 floor that receives shadows but casts none...
/// scene
///     .add_instance(mesh, grey, Mat4::from_scale(Vec3::new(10.0, 1.0, 10.0)))
///     .caster = false;
/// // ...and a card one unit above it that casts onto it.
/// scene.add_instance(mesh, red, Mat4::from_translation(Vec3::Y));
///
/// // A sun a little wider than the real one (softer shadows), from above and to the side.
/// scene.light = Light::Directional(DirectionalLight {
///     direction: Vec3::new(-0.3, -1.0, -0.2),
///     angular_diameter_deg: 1.0,
///     color: Vec3::ONE,
///     intensity: 1.0,
/// });
/// scene.views.push(Viewpoint {
///     name: "front".into(),
///     camera: Camera::look_at(Vec3::new(0.0, 4.0, 8.0), Vec3::ZERO),
/// });
///
/// scene.validate()?;
/// assert_eq!(scene.instances.len(), 2);
/// assert_eq!(scene.lights().count(), 1);
/// // The card is the only caster; the floor sets the scene's extent.
/// assert_eq!(scene.caster_bounds().min.y, 1.0);
/// assert_eq!(scene.bounds().size().x, 10.0);
/// assert_eq!(scene.view(0)?.eye, Vec3::new(0.0, 4.0, 8.0));
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct Scene {
    /// The meshes, each in its own model space; [`Instance::mesh`] indexes this list
    /// ([`Scene::add_mesh`] appends to it).
    pub meshes: Vec<Mesh>,
    /// The materials; [`Instance::material`] indexes this list ([`Scene::add_material`] appends
    /// to it).
    pub materials: Vec<Material>,
    /// The images that the materials' texture fields ([`Material::base_color_texture`] and the
    /// others) index.
    pub textures: Vec<TextureImage>,
    /// What the scene shows: each instance places one mesh with one material in the world and
    /// says whether it casts and receives shadows.
    pub instances: Vec<Instance>,
    /// The key light: the one the reference, the error metrics and the debug views measure.
    pub light: Light,
    /// Further shadowed lights, each drawn with the same method as the key light: at most
    /// [`crate::MAX_LIGHTS`] lights in all. The convenience renderer shades them all.
    pub more_lights: Vec<Light>,
    /// Constant light from everywhere (linear RGB), added to every surface unshadowed.
    pub ambient: Vec3,
    /// Named cameras, in order (a scene file's `views`); [`Scene::view`] takes one by index.
    /// May be empty.
    pub views: Vec<Viewpoint>,
    /// What the loaders could not represent (from [`Model::warnings`]), for the user to see.
    pub warnings: Vec<String>,
    /// Baked light: atlases, each for one lighting mode, with the meshes that use it (by name).
    pub lightmaps: Vec<Lightmaps>,
    /// How the scene is lit ([`LightingMode::Dynamic`] ignores the lightmaps).
    pub lighting: LightingMode,
    /// What a lightmap's texels are multiplied by (the lights' units against the baker's).
    pub lightmap_exposure: f32,
    /// How lightmaps are read between their texels.
    pub lightmap_filter: LightmapFilter,
    /// The camera's exposure: what the lights' lux become in the frame (the ambient term and
    /// lightmaps are not scaled). The default, a multiplier of 1, suits lights given in the
    /// project's own terms; a scene with a model file's lights gets [`Exposure::EV100_DEFAULT`].
    pub exposure: Exposure,
}

impl Default for Scene {
    fn default() -> Self {
        Self {
            meshes: Vec::new(),
            materials: Vec::new(),
            textures: Vec::new(),
            instances: Vec::new(),
            light: Light::default(),
            more_lights: Vec::new(),
            ambient: Vec3::splat(0.12),
            views: Vec::new(),
            warnings: Vec::new(),
            lightmaps: Vec::new(),
            lighting: LightingMode::Dynamic,
            lightmap_exposure: 1.0,
            lightmap_filter: LightmapFilter::Bilinear,
            exposure: Exposure::default(),
        }
    }
}

impl Scene {
    /// Adds a mesh and returns its index.
    pub fn add_mesh(&mut self, mesh: Mesh) -> usize {
        self.meshes.push(mesh);
        self.meshes.len() - 1
    }

    /// Adds a material and returns its index.
    pub fn add_material(&mut self, material: Material) -> usize {
        self.materials.push(material);
        self.materials.len() - 1
    }

    /// Adds an instance of `mesh` with `material`, casting and receiving shadows.
    pub fn add_instance(&mut self, mesh: usize, material: usize, transform: Mat4) -> &mut Instance {
        self.instances.push(Instance {
            mesh,
            material,
            transform,
            caster: true,
            receiver: true,
        });
        self.instances.last_mut().expect("just pushed")
    }

    /// Appends a model's meshes, materials and textures, placing its parts under `transform`.
    /// `material_override`, when given, replaces the model's own materials.
    /// Returns the range of the new instances.
    pub fn add_model(
        &mut self,
        model: &Model,
        transform: Mat4,
        material_override: Option<usize>,
        caster: bool,
        receiver: bool,
    ) -> std::ops::Range<usize> {
        let (mesh_base, material_base, texture_base) =
            (self.meshes.len(), self.materials.len(), self.textures.len());
        self.meshes.extend(model.meshes.iter().cloned());
        self.warnings.extend(model.warnings.iter().cloned());
        self.textures.extend(model.textures.iter().cloned());
        self.materials.extend(model.materials.iter().map(|m| Material {
            base_color_texture: m.base_color_texture.map(|t| t + texture_base),
            occlusion_texture: m.occlusion_texture.map(|t| t + texture_base),
            emissive_texture: m.emissive_texture.map(|t| t + texture_base),
            metallic_roughness_texture: m.metallic_roughness_texture.map(|t| t + texture_base),
            normal_texture: m.normal_texture.map(|t| t + texture_base),
            ..m.clone()
        }));
        let first = self.instances.len();
        for part in &model.parts {
            self.instances.push(Instance {
                mesh: part.mesh + mesh_base,
                material: material_override.unwrap_or(part.material + material_base),
                transform: transform * part.transform,
                caster,
                receiver,
            });
        }
        first..self.instances.len()
    }

    /// World bounds of the instances that pass `filter`.
    pub fn bounds_where(&self, filter: impl Fn(&Instance) -> bool) -> Aabb {
        self.instances
            .iter()
            .filter(|i| filter(i))
            .filter_map(|i| {
                self.meshes
                    .get(i.mesh)
                    .map(|m| m.bounds.transformed(&i.transform))
            })
            .fold(Aabb::EMPTY, |acc, b| acc.union(&b))
    }

    /// World bounds of every instance.
    pub fn bounds(&self) -> Aabb {
        self.bounds_where(|_| true)
    }

    /// World bounds of the shadow casters.
    pub fn caster_bounds(&self) -> Aabb {
        self.bounds_where(|i| i.caster)
    }

    /// World bounds of the shadow receivers.
    pub fn receiver_bounds(&self) -> Aabb {
        self.bounds_where(|i| i.receiver)
    }

    /// The atlas and rectangle instance `k` samples in `mode`, if any.
    pub fn lightmap_of(&self, k: usize, mode: LightingMode) -> Option<(usize, &LightmapRect)> {
        let mesh = &self.meshes.get(self.instances.get(k)?.mesh)?.name;
        self.lightmaps.iter().enumerate().find_map(|(atlas, l)| {
            (l.mode == mode)
                .then(|| l.rects.iter().find(|r| &r.mesh == mesh))
                .flatten()
                .map(|r| (atlas, r))
        })
    }

    /// Checks the lightmaps: a mixed or baked mode per atlas, one atlas per mesh and mode
    /// (several atlases may serve one mode), every rectangle naming a mesh that exists and has
    /// lightmap UVs, a finite exposure >= 0.
    pub fn validate_lightmaps(&self) -> Result<()> {
        let bad = |s: String| Err(PenumbraError::Scene(s));
        if !(self.lightmap_exposure >= 0.0 && self.lightmap_exposure.is_finite()) {
            return bad(format!(
                "lightmap_exposure {} must be finite and >= 0",
                self.lightmap_exposure
            ));
        }
        for (k, atlas) in self.lightmaps.iter().enumerate() {
            let name = &atlas.image.name;
            if atlas.mode == LightingMode::Dynamic {
                return bad(format!("lightmap `{name}`: dynamic lighting uses no lightmap"));
            }
            // Several atlases may serve one mode (engines give each mesh its own image), but a
            // mesh takes one atlas per mode.
            for (r, rect) in atlas.rects.iter().enumerate() {
                if atlas.rects[..r].iter().any(|other| other.mesh == rect.mesh) {
                    return bad(format!("lightmap `{name}`: mesh `{}` is listed twice", rect.mesh));
                }
                let earlier = self.lightmaps[..k].iter().find(|other| {
                    other.mode == atlas.mode && other.rects.iter().any(|o| o.mesh == rect.mesh)
                });
                if let Some(other) = earlier {
                    return bad(format!(
                        "lightmaps `{}` and `{name}` both give mesh `{}` its {} lighting (one atlas per mesh and mode)",
                        other.image.name,
                        rect.mesh,
                        atlas.mode.name()
                    ));
                }
            }
            if atlas.image.rgb.len() != atlas.image.width as usize * atlas.image.height as usize
                || atlas.image.width == 0
            {
                return bad(format!("lightmap `{name}`: its size does not match its texels"));
            }
            let full_chain = 32 - atlas.image.width.max(atlas.image.height).leading_zeros() as usize;
            if atlas.image.mips.len() >= full_chain {
                return bad(format!(
                    "lightmap `{name}`: {} smaller levels, a {}x{} image has at most {}",
                    atlas.image.mips.len(),
                    atlas.image.width,
                    atlas.image.height,
                    full_chain - 1
                ));
            }
            for (i, mip) in atlas.image.mips.iter().enumerate() {
                let (w, h) = atlas.image.level_size(i + 1);
                if mip.len() != w as usize * h as usize {
                    return bad(format!(
                        "lightmap `{name}`: level {} holds {} texels, {w}x{h} need {}",
                        i + 1,
                        mip.len(),
                        w * h
                    ));
                }
            }
            for rect in &atlas.rects {
                let meshes: Vec<&Mesh> = self.meshes.iter().filter(|m| m.name == rect.mesh).collect();
                if meshes.is_empty() {
                    return bad(format!(
                        "lightmap `{name}`: no mesh is named `{}` (mesh names: {})",
                        rect.mesh,
                        self.meshes
                            .iter()
                            .map(|m| m.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ));
                }
                if let Some(m) = meshes.iter().find(|m| m.lightmap_uvs.len() != m.positions.len()) {
                    return bad(format!(
                        "lightmap `{name}`: mesh `{}` has no second UV set (TEXCOORD_1) to sample it with",
                        m.name
                    ));
                }
            }
        }
        Ok(())
    }

    /// Checks that every index is in range and every transform and setting is valid: the
    /// instances' mesh and material indices and transforms, the materials' texture indices and
    /// factors, the textures' sizes, the meshes' colour and tangent counts, the ambient term,
    /// the lights (at most [`crate::MAX_LIGHTS`], each [`Light::validate`]), the exposure and
    /// the lightmaps ([`Scene::validate_lightmaps`]). The error names what is wrong.
    pub fn validate(&self) -> Result<()> {
        self.validate_lightmaps()?;
        self.exposure.validate()?;
        let bad = |s: String| Err(PenumbraError::Scene(s));
        for m in &self.meshes {
            for (what, count) in [("vertex colours", m.colors.len()), ("tangents", m.tangents.len())] {
                if count != 0 && count != m.positions.len() {
                    return bad(format!(
                        "mesh `{}` has {count} {what} for {} positions (one each, or none)",
                        m.name,
                        m.positions.len()
                    ));
                }
            }
        }
        for (k, inst) in self.instances.iter().enumerate() {
            if inst.mesh >= self.meshes.len() {
                return bad(format!(
                    "instance {k} uses mesh {} of {}",
                    inst.mesh,
                    self.meshes.len()
                ));
            }
            if inst.material >= self.materials.len() {
                return bad(format!(
                    "instance {k} uses material {} of {}",
                    inst.material,
                    self.materials.len()
                ));
            }
            if !inst.transform.is_finite() {
                return bad(format!("instance {k} has a non-finite transform"));
            }
        }
        for m in &self.materials {
            let textures = [
                ("texture", m.base_color_texture),
                ("occlusion texture", m.occlusion_texture),
                ("emissive texture", m.emissive_texture),
                ("metallic-roughness texture", m.metallic_roughness_texture),
                ("normal texture", m.normal_texture),
            ];
            for (what, texture) in textures {
                if let Some(t) = texture
                    && t >= self.textures.len()
                {
                    return bad(format!(
                        "material `{}` uses {what} {t} of {}",
                        m.name,
                        self.textures.len()
                    ));
                }
            }
            if !(0.0..=1.0).contains(&m.occlusion_strength) || m.occlusion_uv_set > 1 {
                return bad(format!(
                    "material `{}`: occlusion strength {} must be in [0, 1] and its UV set 0 or 1",
                    m.name, m.occlusion_strength
                ));
            }
            if !m.base_color.is_finite() {
                return bad(format!("material `{}` has a non-finite base color", m.name));
            }
            if let Shading::MetallicRoughness { metallic, roughness } = m.shading
                && !((0.0..=1.0).contains(&metallic) && (0.0..=1.0).contains(&roughness))
            {
                return bad(format!(
                    "material `{}`: metallic {metallic} and roughness {roughness} must be in [0, 1]",
                    m.name
                ));
            }
            if !m.normal_scale.is_finite() {
                return bad(format!("material `{}` has a non-finite normal scale", m.name));
            }
            if !m.emissive.is_finite() || m.emissive.min_element() < 0.0 {
                return bad(format!(
                    "material `{}`: emissive {} must be finite and >= 0",
                    m.name, m.emissive
                ));
            }
        }
        for t in &self.textures {
            if t.width == 0 || t.height == 0 || t.rgba8.len() != (t.width * t.height * 4) as usize {
                return bad(format!(
                    "texture `{}` is {}x{} with {} bytes",
                    t.name,
                    t.width,
                    t.height,
                    t.rgba8.len()
                ));
            }
        }
        if !self.ambient.is_finite() || self.ambient.min_element() < 0.0 {
            return bad("ambient must be finite and non-negative".into());
        }
        check_light_count(1 + self.more_lights.len())?;
        self.lights().try_for_each(Light::validate)
    }

    /// The key light, then the others.
    pub fn lights(&self) -> impl Iterator<Item = &Light> {
        std::iter::once(&self.light).chain(&self.more_lights)
    }

    /// The camera of viewpoint `index`, or an error listing how many there are.
    pub fn view(&self, index: usize) -> Result<Camera> {
        self.views.get(index).map(|v| v.camera).ok_or_else(|| {
            PenumbraError::setting(
                "view",
                format!(
                    "viewpoint {index} does not exist; the scene has {}",
                    self.views.len()
                ),
            )
        })
    }

    /// A scene that shows `model` standing on a floor: the model is moved so its bounds rest on
    /// y = 0 centered at the origin, a floor four times its footprint is added, three
    /// viewpoints orbit it, and the model's own lights shine on it (see [`lights_from_model`]),
    /// or, where it has none, a default directional light from above at an angle.
    pub fn showcase(model: &Model) -> Result<Scene> {
        let bounds = model.bounds();
        if bounds.is_empty() {
            return Err(PenumbraError::Scene("the model has no geometry".into()));
        }
        let mut scene = Scene::default();
        let center = bounds.center();
        let place = Mat4::from_translation(Vec3::new(-center.x, -bounds.min.y, -center.z));
        scene.add_model(model, place, None, true, true);
        // The file's own lights where it has any (the first the key light), else the default.
        let lights = lights_from_model(
            &model.lights,
            place,
            place.transform_point3(center),
            ModelLightSizes::default(),
            &mut scene.warnings,
        );
        if let Some((key, more)) = lights.split_first() {
            scene.light = *key;
            scene.more_lights = more.to_vec();
            // The file's lights are in lux and candela.
            scene.exposure = Exposure::Ev100(Exposure::EV100_DEFAULT);
        }
        let size = bounds.size();
        let footprint = size.x.max(size.z).max(size.y * 0.5).max(1e-6);
        let floor_material = scene.add_material(Material::colored("floor", [0.75, 0.75, 0.72]));
        let floor = scene.add_mesh(primitives::plane(footprint * 4.0, 1.0));
        // A hair below the model, so a flat-bottomed model's base and the floor do not fight
        // for the same depth (stripes in the screen-space methods' composite).
        let below = Mat4::from_translation(Vec3::new(0.0, -footprint * 1e-3, 0.0));
        scene.add_instance(floor, floor_material, below).caster = false;
        let framed = Aabb::new(
            Vec3::new(-size.x * 0.5, 0.0, -size.z * 0.5),
            Vec3::new(size.x * 0.5, size.y, size.z * 0.5),
        );
        let all = scene.bounds();
        for (k, yaw) in [35.0f32, 155.0, 275.0].into_iter().enumerate() {
            let orbit = OrbitCamera::framing(&framed, yaw, 28.0);
            scene.views.push(Viewpoint {
                name: format!("orbit {k}"),
                camera: orbit.camera(&all),
            });
        }
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn showcase_floor_lies_just_below_a_flat_bottomed_model() {
        let mut model = Model::default();
        model.meshes.push(primitives::cuboid(Vec3::new(2.0, 1.0, 2.0)));
        model.materials.push(Material::colored("box", [0.5, 0.5, 0.5]));
        model.parts.push(Instance {
            mesh: 0,
            material: 0,
            transform: Mat4::from_translation(Vec3::new(5.0, 3.0, 0.0)),
            caster: true,
            receiver: true,
        });
        let scene = Scene::showcase(&model).unwrap();
        let model_bottom = scene.bounds_where(|i| i.caster).min.y;
        let floor_top = scene.bounds_where(|i| !i.caster).max.y;
        assert!(model_bottom.abs() < 1e-6, "model placed at {model_bottom}");
        // Below, so the two do not fight for depth, but by a hair: no visible gap.
        assert!(
            floor_top < model_bottom && floor_top > -0.01,
            "floor at {floor_top}"
        );
    }
}
