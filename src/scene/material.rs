//! Surface materials and their textures.

use glam::{Vec3, Vec4};

/// How a material's alpha is used.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum AlphaMode {
    /// Alpha is ignored; the surface is fully opaque.
    #[default]
    Opaque,
    /// Fragments whose alpha (texture x factor) is below `cutoff` are discarded, in the lit pass
    /// and in the shadow map (glTF's `MASK`). `cutoff` is in [0, 1]; glTF's default is 0.5.
    Mask {
        /// The alpha threshold, in [0, 1]: fragments with less alpha are discarded.
        cutoff: f32,
    },
    /// Blended over what lies behind (glTF's `BLEND`): drawn after the opaque surfaces, back to
    /// front, without writing depth. It casts shadows where its alpha is at least 0.5 (as
    /// `Mask { cutoff: 0.5 }` in the shadow map), and receives none from the screen-space
    /// methods (their visibility belongs to the opaque surface behind; the forward path of
    /// `hard` and `hw2x2` looks the shadow map up for it).
    Blend,
}

impl AlphaMode {
    /// The alpha below which the surface casts no shadow, if any.
    pub fn shadow_cutoff(self) -> Option<f32> {
        match self {
            AlphaMode::Opaque => None,
            AlphaMode::Mask { cutoff } => Some(cutoff),
            AlphaMode::Blend => Some(0.5),
        }
    }
}

/// How a texture coordinate outside [0, 1] is wrapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum WrapMode {
    /// Coordinates wrap around, so the texture tiles (glTF `REPEAT`; the default).
    #[default]
    Repeat,
    /// The texture tiles with every other copy mirrored (glTF `MIRRORED_REPEAT`).
    MirroredRepeat,
    /// Coordinates are clamped to [0, 1], so the edge texels stretch outward (glTF
    /// `CLAMP_TO_EDGE`).
    ClampToEdge,
}

/// How texels are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FilterMode {
    /// The nearest texel (or mip level): blocky when magnified.
    Nearest,
    /// Linear interpolation between neighboring texels (or mip levels); the default.
    #[default]
    Linear,
}

/// How a material's textures are sampled (glTF's sampler of its base-color texture).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TextureSampler {
    /// How u, the texture's horizontal coordinate, wraps (glTF `wrapS`).
    pub wrap_u: WrapMode,
    /// How v, the texture's vertical coordinate, wraps (glTF `wrapT`).
    pub wrap_v: WrapMode,
    /// Magnification.
    pub mag_filter: FilterMode,
    /// Minification within a mip level.
    pub min_filter: FilterMode,
    /// Between mip levels.
    pub mipmap_filter: FilterMode,
    /// False: only the full-resolution level is sampled (glTF's `NEAREST` and `LINEAR`
    /// minification).
    pub mipmaps: bool,
}

impl Default for TextureSampler {
    fn default() -> Self {
        Self {
            wrap_u: WrapMode::Repeat,
            wrap_v: WrapMode::Repeat,
            mag_filter: FilterMode::Linear,
            min_filter: FilterMode::Linear,
            mipmap_filter: FilterMode::Linear,
            mipmaps: true,
        }
    }
}

/// How a material reflects the lights' direct light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shading {
    /// A diffuse surface: the base colour times the irradiance, no highlight. The project's
    /// own scenes use it (their look and golden images were made with it).
    Lambert,
    /// glTF's metallic-roughness model (its specification's appendix B): a Lambertian diffuse
    /// of `base x (1 - metallic)` and a GGX specular lobe (Smith height-correlated visibility,
    /// Schlick Fresnel from 4% for dielectrics to the base colour for metals), with
    /// `roughness` squared as the lobe's alpha. Both factors in [0, 1], multiplied by
    /// [`Material::metallic_roughness_texture`] where there is one.
    MetallicRoughness {
        /// Metalness in [0, 1]: 0 a dielectric, 1 a metal (glTF `metallicFactor`).
        metallic: f32,
        /// Perceptual roughness in [0, 1]: 0 mirror-like, 1 fully rough (glTF
        /// `roughnessFactor`).
        roughness: f32,
    },
}

/// A material: base color factor times an optional base color texture, its shading model, and
/// its optional metallic-roughness, normal, ambient-occlusion and emissive textures.
///
/// Texture fields are indices into the scene's [`crate::Scene::textures`]:
///
/// ```
/// use glam::Vec4;
/// use penumbra::{AlphaMode, Material, Scene, Shading, TextureImage};
///
/// // Opaque, untextured and Lambertian, of a linear color.
/// let clay = Material::colored("clay", [0.7, 0.4, 0.3]);
/// assert_eq!(clay.base_color, Vec4::new(0.7, 0.4, 0.3, 1.0));
/// assert_eq!(clay.shading, Shading::Lambert);
///
/// // A checkered metal grille whose dark squares are cut out (they cast no shadow either);
/// // the fields not named keep their defaults.
/// let mut scene = Scene::default();
/// scene.textures.push(TextureImage::checker("holes", 8, [255; 4], [0, 0, 0, 0]));
/// let holes = scene.textures.len() - 1;
/// let grille = Material {
///     name: "grille".into(),
///     base_color: Vec4::new(0.9, 0.9, 0.92, 1.0),
///     base_color_texture: Some(holes),
///     alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
///     shading: Shading::MetallicRoughness { metallic: 1.0, roughness: 0.35 },
///     ..Material::default()
/// };
/// assert!(grille.is_masked());
/// assert_eq!(grille.alpha_mode.shadow_cutoff(), Some(0.5));
/// scene.add_material(grille);
/// assert_eq!(scene.textures[holes].width, 256);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// A name for messages: a scene file's material entry name, or the model file's own (a glTF
    /// material without one is called `material`).
    pub name: String,
    /// Linear RGBA multiplier.
    pub base_color: Vec4,
    /// Index into [`crate::Scene::textures`].
    pub base_color_texture: Option<usize>,
    /// How the alpha of `base_color` times the base-color texture's is used: opaque, cut out or
    /// blended. It also decides what casts a shadow ([`AlphaMode::shadow_cutoff`]).
    pub alpha_mode: AlphaMode,
    /// Ambient occlusion (glTF `occlusionTexture`: its red channel, linear), index into
    /// [`crate::Scene::textures`]. It darkens the indirect light (the ambient term, or the
    /// lightmap in mixed lighting), never the lights' direct light, and is not applied to
    /// baked lighting (a bake holds its own occlusion).
    pub occlusion_texture: Option<usize>,
    /// The UV set the occlusion texture reads: 0, or 1 (the lightmap UVs, glTF `TEXCOORD_1`).
    pub occlusion_uv_set: u32,
    /// glTF `strength` in [0, 1]: `ao = mix(1, texel, strength)`.
    pub occlusion_strength: f32,
    /// Applied to the occlusion texture's UVs (its `KHR_texture_transform`).
    pub occlusion_uv_transform: glam::Affine2,
    /// Light the surface gives off itself (linear RGB, glTF's `emissiveFactor` times its
    /// `KHR_materials_emissive_strength`), added to the frame whatever the lights, the ambient
    /// and the camera's exposure: an emissive value of 1 shows as 1.
    pub emissive: Vec3,
    /// Multiplies `emissive` (glTF `emissiveTexture`, sRGB, on UV set 0), index into
    /// [`crate::Scene::textures`].
    pub emissive_texture: Option<usize>,
    /// How the surface reflects the lights' direct light (glTF materials:
    /// [`Shading::MetallicRoughness`]).
    pub shading: Shading,
    /// glTF `metallicRoughnessTexture` (linear; blue is the metalness, green the roughness,
    /// each multiplying its factor in [`Shading::MetallicRoughness`]; on UV set 0), index
    /// into [`crate::Scene::textures`].
    pub metallic_roughness_texture: Option<usize>,
    /// A tangent-space normal map (glTF `normalTexture`, linear, on UV set 0; the mesh's
    /// tangents, or MikkTSpace ones generated when the file has none), index into
    /// [`crate::Scene::textures`].
    pub normal_texture: Option<usize>,
    /// glTF's normal `scale`: multiplies the map's x and y.
    pub normal_scale: f32,
    /// How all of the material's textures are sampled (glTF files: the base-color texture's
    /// sampler, else the occlusion texture's; by default repeating, linear and mipmapped).
    pub sampler: TextureSampler,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: Vec4::new(0.8, 0.8, 0.8, 1.0),
            base_color_texture: None,
            alpha_mode: AlphaMode::Opaque,
            occlusion_texture: None,
            occlusion_uv_set: 0,
            occlusion_strength: 1.0,
            occlusion_uv_transform: glam::Affine2::IDENTITY,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            shading: Shading::Lambert,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            sampler: TextureSampler::default(),
        }
    }
}

impl Material {
    /// An opaque, untextured material of the given linear color.
    pub fn colored(name: impl Into<String>, rgb: [f32; 3]) -> Self {
        Self {
            name: name.into(),
            base_color: Vec4::new(rgb[0], rgb[1], rgb[2], 1.0),
            ..Default::default()
        }
    }

    /// True when the material needs the alpha-testing variant of the passes.
    pub fn is_masked(&self) -> bool {
        matches!(self.alpha_mode, AlphaMode::Mask { .. })
    }
}

/// An 8-bit sRGB RGBA image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureImage {
    /// A label for messages and the GPU texture (for an image read from a file, its path).
    pub name: String,
    /// Width in texels, > 0.
    pub width: u32,
    /// Height in texels, > 0.
    pub height: u32,
    /// The texels, `width * height * 4` bytes (R, G, B, A per texel), rows top to bottom. Read as
    /// sRGB where the image colors a surface (base color, emissive), as linear data where it is
    /// an occlusion, metallic-roughness or normal map.
    pub rgba8: Vec<u8>,
}

impl TextureImage {
    /// Decodes a PNG or JPEG image from memory. `name` is used in error messages.
    #[cfg(feature = "renderer")]
    pub fn decode(name: &str, bytes: &[u8]) -> crate::Result<Self> {
        let img = image::load_from_memory(bytes).map_err(|e| crate::PenumbraError::Texture {
            name: name.to_string(),
            reason: e.to_string(),
        })?;
        let rgba = img.to_rgba8();
        Ok(Self::from_rgba8(
            name,
            rgba.width(),
            rgba.height(),
            rgba.into_raw(),
        ))
    }

    /// An image from raw bytes laid out as [`TextureImage::rgba8`]. Nothing is checked here:
    /// [`crate::Scene::validate`] rejects a size that does not match the bytes.
    pub fn from_rgba8(name: impl Into<String>, width: u32, height: u32, rgba8: Vec<u8>) -> Self {
        Self {
            name: name.into(),
            width,
            height,
            rgba8,
        }
    }

    /// A checkerboard of `squares` x `squares` cells alternating two sRGB colors.
    pub fn checker(name: impl Into<String>, squares: u32, a: [u8; 4], b: [u8; 4]) -> Self {
        let squares = squares.clamp(1, 256);
        let cell = (256 / squares).max(1);
        let size = cell * squares;
        let mut rgba8 = Vec::with_capacity((size * size * 4) as usize);
        for y in 0..size {
            for x in 0..size {
                let c = if (x / cell + y / cell).is_multiple_of(2) {
                    a
                } else {
                    b
                };
                rgba8.extend_from_slice(&c);
            }
        }
        Self::from_rgba8(name, size, size, rgba8)
    }
}
