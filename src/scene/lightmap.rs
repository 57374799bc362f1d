//! Lightmaps: baked light in a texture atlas, sampled with a mesh's second UV set.
//!
//! A [`LightmapImage`] is linear RGB radiance decoded from a file:
//! * KTX2 (2D, every level: the smaller ones become [`LightmapImage::mips`]), uncompressed or
//!   zstd-supercompressed, in the float formats bakers
//!   write: `E5B9G9R9_UFLOAT_PACK32` (RGB9E5), `B10G11R11_UFLOAT_PACK32` (RG11B10),
//!   `R16G16B16A16_SFLOAT`, `R32G32B32A32_SFLOAT`, and 8-bit `R8G8B8A8_UNORM` / `_SRGB`;
//! * Radiance HDR (`.hdr`);
//! * PNG or JPEG (sRGB, turned linear).
//!
//! A [`Lightmaps`] entry of a [`crate::Scene`] pairs one atlas with the lighting mode it was
//! baked for and the rectangle of the atlas each mesh (by name) uses.

use glam::Vec2;
#[cfg(feature = "renderer")]
use std::path::Path;

#[cfg(feature = "renderer")]
use crate::error::{PenumbraError, Result};

/// Linear RGB radiance, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct LightmapImage {
    /// A label for messages: the file's path when it was read from one.
    pub name: String,
    /// Width of the full-size level (level 0), in texels.
    pub width: u32,
    /// Height of the full-size level (level 0), in texels.
    pub height: u32,
    /// `width * height` texels.
    pub rgb: Vec<[f32; 3]>,
    /// The smaller levels the file has (mipmaps), level 1 first: level `i` is
    /// `max(width >> i, 1)` x `max(height >> i, 1)` texels. Empty when it has one level; the
    /// lit passes then read the full-size level wherever the surface is.
    pub mips: Vec<Vec<[f32; 3]>>,
    /// What decoding changed, for the user to see: texels that were not finite (Inf or NaN,
    /// which bakers leave in atlas gutters that nothing samples) are read as 0.
    pub warnings: Vec<String>,
}

/// How a scene's light is made (engines' "lighting modes").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LightingMode {
    /// Every light and shadow computed each frame; lightmaps are not used.
    #[default]
    Dynamic,
    /// The lightmap carries the static scene's indirect light (in place of the ambient term);
    /// the lights' direct light and soft shadows are computed each frame, and the method's
    /// indirect-light attenuation is off (the lightmap holds that light).
    Mixed,
    /// Lightmapped surfaces show the lightmap alone (direct and indirect light baked); other
    /// surfaces are lit dynamically.
    Baked,
}

impl LightingMode {
    /// The three modes in the order `Dynamic`, `Mixed`, `Baked`, for listing them or looking one
    /// up by [`LightingMode::name`].
    pub const ALL: [LightingMode; 3] = [LightingMode::Dynamic, LightingMode::Mixed, LightingMode::Baked];

    /// The mode's lower-case name, `dynamic`, `mixed` or `baked` (as messages print it and the
    /// demo's `--lighting` option takes it).
    pub fn name(self) -> &'static str {
        match self {
            LightingMode::Dynamic => "dynamic",
            LightingMode::Mixed => "mixed",
            LightingMode::Baked => "baked",
        }
    }
}

/// How the lit passes read a lightmap between its texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LightmapFilter {
    /// One bilinear fetch (trilinear between the levels the file has): cheap, but its slope
    /// jumps at every texel, which shows as a grid on a low-resolution bake seen up close.
    #[default]
    Bilinear,
    /// A cubic B-spline over 4 x 4 texels (four bilinear fetches, each at the level its own
    /// derivatives pick): smooth across texels, a little blurrier; what Bevy offers as bicubic
    /// lightmap sampling.
    Bicubic,
}

/// The part of an atlas one mesh's second UV set maps into: `atlas_uv = mix(min, max, uv1)`, in
/// texture space (v down, as wgpu samples). A negative extent mirrors.
#[derive(Debug, Clone, PartialEq)]
pub struct LightmapRect {
    /// The mesh's name ([`crate::Mesh::name`]; for a glTF file, the glTF mesh's name).
    pub mesh: String,
    /// Where the mesh's lightmap UV (0, 0) lands in the atlas, in texture space (0 to 1 across
    /// the image, v down).
    pub min: Vec2,
    /// Where the mesh's lightmap UV (1, 1) lands; below `min` on an axis, the mesh's lightmap is
    /// mirrored along it.
    pub max: Vec2,
}

impl LightmapRect {
    /// A rectangle given as engines often list it: its `min` corner and `size` in OpenGL-style
    /// UV space (v up), turned into texture space.
    pub fn from_v_up(mesh: impl Into<String>, min: Vec2, size: Vec2) -> Self {
        let min = Vec2::new(min.x, 1.0 - min.y - size.y);
        LightmapRect {
            mesh: mesh.into(),
            min,
            max: min + size,
        }
    }
}

/// One lightmap atlas of a scene: the mode it was baked for and the meshes that use it.
#[derive(Debug, Clone, PartialEq)]
pub struct Lightmaps {
    /// The lighting mode the atlas was baked for, [`LightingMode::Mixed`] or
    /// [`LightingMode::Baked`] ([`crate::Scene::validate_lightmaps`] rejects `Dynamic`): it is
    /// read while the scene is lit in that mode.
    pub mode: LightingMode,
    /// The baked light: linear RGB radiance, with the smaller levels the file had.
    pub image: LightmapImage,
    /// Which meshes (by name) sample the atlas and where; a mesh is listed at most once.
    pub rects: Vec<LightmapRect>,
}

#[cfg(feature = "renderer")]
impl LightmapImage {
    /// Reads a lightmap file, choosing the decoder by extension (`.ktx2`, `.hdr`, `.png`,
    /// `.jpg` / `.jpeg`).
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|source| PenumbraError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let name = path.display().to_string();
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match extension.as_str() {
            "ktx2" => Self::decode_ktx2(&name, &bytes),
            "hdr" => Self::decode_image(&name, &bytes, image::ImageFormat::Hdr),
            "png" => Self::decode_image(&name, &bytes, image::ImageFormat::Png),
            "jpg" | "jpeg" => Self::decode_image(&name, &bytes, image::ImageFormat::Jpeg),
            other => Err(PenumbraError::Texture {
                name,
                reason: format!("lightmaps are read from .ktx2, .hdr, .png or .jpg files, not `.{other}`"),
            }),
        }
    }

    /// Decodes a Radiance HDR (linear) or an 8-bit PNG / JPEG (sRGB, made linear).
    fn decode_image(name: &str, bytes: &[u8], format: image::ImageFormat) -> Result<Self> {
        let bad = |reason: String| PenumbraError::Texture {
            name: name.to_string(),
            reason,
        };
        let decoded = image::load_from_memory_with_format(bytes, format).map_err(|e| bad(e.to_string()))?;
        let (width, height) = (decoded.width(), decoded.height());
        let rgb = if format == image::ImageFormat::Hdr {
            decoded.to_rgb32f().pixels().map(|p| p.0).collect()
        } else {
            decoded
                .to_rgb8()
                .pixels()
                .map(|p| p.0.map(|c| srgb_to_linear(c as f32 / 255.0)))
                .collect()
        };
        Ok(LightmapImage::with_finite_texels(name, width, height, rgb))
    }

    /// Decodes a KTX2 container's first level (see the module docs for the formats).
    pub fn decode_ktx2(name: &str, bytes: &[u8]) -> Result<Self> {
        let bad = |reason: String| PenumbraError::Texture {
            name: name.to_string(),
            reason,
        };
        let reader = ktx2::Reader::new(bytes).map_err(|e| bad(format!("not a KTX2 file: {e}")))?;
        let header = reader.header();
        if header.pixel_depth > 1 || header.layer_count > 1 || header.face_count != 1 {
            return Err(bad(
                "a lightmap must be one 2D image (no layers, faces or depth)".into()
            ));
        }
        let (width, height) = (header.pixel_width, header.pixel_height.max(1));
        let format = header.format.ok_or_else(|| {
            bad("its format is undefined (Basis Universal); lightmaps need a float or 8-bit format".into())
        })?;
        let bytes_per_texel = match format {
            ktx2::Format::E5B9G9R9_UFLOAT_PACK32
            | ktx2::Format::B10G11R11_UFLOAT_PACK32
            | ktx2::Format::R8G8B8A8_UNORM
            | ktx2::Format::R8G8B8A8_SRGB => 4,
            ktx2::Format::R16G16B16A16_SFLOAT => 8,
            ktx2::Format::R32G32B32A32_SFLOAT => 16,
            other => {
                return Err(bad(format!(
                    "format {other:?} is not supported (RGB9E5, RG11B10, RGBA16F, RGBA32F, RGBA8)"
                )));
            }
        };
        // Every level the file has, the full-size one first.
        let mut levels = Vec::new();
        for (i, level) in reader.levels().enumerate() {
            let (w, h) = ((width >> i).max(1), (height >> i).max(1));
            let data: Vec<u8> = match header.supercompression_scheme {
                None => level.data.to_vec(),
                Some(ktx2::SupercompressionScheme::Zstandard) => {
                    use std::io::Read;
                    let mut source = level.data;
                    let mut decoder = ruzstd::decoding::StreamingDecoder::new(&mut source)
                        .map_err(|e| bad(format!("level {i}: its zstd data is corrupt: {e}")))?;
                    let mut out = Vec::with_capacity(level.uncompressed_byte_length as usize);
                    decoder
                        .read_to_end(&mut out)
                        .map_err(|e| bad(format!("level {i}: its zstd data is corrupt: {e}")))?;
                    out
                }
                Some(other) => {
                    return Err(bad(format!(
                        "supercompression {other:?} is not supported (zstd or none)"
                    )));
                }
            };
            let texels = w as usize * h as usize;
            if data.len() < texels * bytes_per_texel {
                let what = if i == 0 {
                    String::new()
                } else {
                    format!("level {i}: ")
                };
                return Err(bad(format!(
                    "{what}its image data holds {} bytes, {w}x{h} texels need {}",
                    data.len(),
                    texels * bytes_per_texel
                )));
            }
            levels.push(decode_texels(format, &data, texels));
        }
        if levels.is_empty() {
            return Err(bad("it has no image data".into()));
        }
        let rgb = levels.remove(0);
        Ok(LightmapImage::with_finite_texels(name, width, height, rgb).with_mips(levels))
    }
}

/// `texels` texels of `data` in `format` (one the decoder accepts), as linear RGB.
#[cfg(feature = "renderer")]
fn decode_texels(format: ktx2::Format, data: &[u8], texels: usize) -> Vec<[f32; 3]> {
    let word = |i: usize| u32::from_le_bytes(data[i * 4..i * 4 + 4].try_into().expect("4 bytes"));
    let half = |i: usize| half::f16::from_le_bytes([data[i * 2], data[i * 2 + 1]]).to_f32();
    let float = |i: usize| f32::from_le_bytes(data[i * 4..i * 4 + 4].try_into().expect("4 bytes"));
    (0..texels)
        .map(|i| match format {
            ktx2::Format::E5B9G9R9_UFLOAT_PACK32 => rgb9e5(word(i)),
            ktx2::Format::B10G11R11_UFLOAT_PACK32 => rg11b10(word(i)),
            ktx2::Format::R16G16B16A16_SFLOAT => [half(i * 4), half(i * 4 + 1), half(i * 4 + 2)],
            ktx2::Format::R32G32B32A32_SFLOAT => [float(i * 4), float(i * 4 + 1), float(i * 4 + 2)],
            ktx2::Format::R8G8B8A8_SRGB => [0, 1, 2].map(|c| srgb_to_linear(data[i * 4 + c] as f32 / 255.0)),
            _ => [0, 1, 2].map(|c| data[i * 4 + c] as f32 / 255.0),
        })
        .collect()
}

impl LightmapImage {
    /// An image of `rgb` whose texels that are not finite (Inf or NaN) are replaced by 0, with
    /// one warning naming the image and how many were.
    pub fn with_finite_texels(name: &str, width: u32, height: u32, mut rgb: Vec<[f32; 3]>) -> Self {
        let mut replaced = 0usize;
        for texel in &mut rgb {
            if texel.iter().any(|c| !c.is_finite()) {
                *texel = [0.0; 3];
                replaced += 1;
            }
        }
        let warnings = (replaced > 0)
            .then(|| {
                format!(
                    "lightmap `{name}`: {replaced} of {} texels are not finite (Inf or NaN) and are read as 0",
                    rgb.len()
                )
            })
            .into_iter()
            .collect();
        LightmapImage {
            name: name.to_string(),
            width,
            height,
            rgb,
            mips: Vec::new(),
            warnings,
        }
    }

    /// This image with `mips` as its smaller levels (level 1 first), their texels that are
    /// not finite replaced by 0 and counted in its warning. Level `i` must hold
    /// [`Self::level_size`]`(i)` texels ([`crate::Scene::validate_lightmaps`] checks).
    pub fn with_mips(mut self, mut mips: Vec<Vec<[f32; 3]>>) -> Self {
        let mut replaced = 0usize;
        for texel in mips.iter_mut().flatten() {
            if texel.iter().any(|c| !c.is_finite()) {
                *texel = [0.0; 3];
                replaced += 1;
            }
        }
        if replaced > 0 {
            self.warnings.push(format!(
                "lightmap `{}`: {replaced} texels of its smaller levels are not finite (Inf or NaN) and are read as 0",
                self.name
            ));
        }
        self.mips = mips;
        self
    }

    /// Texels across and down level `level` (0: the full size).
    pub fn level_size(&self, level: usize) -> (u32, u32) {
        ((self.width >> level).max(1), (self.height >> level).max(1))
    }

    /// The texel at (x, y), clamped to the image.
    pub fn texel(&self, x: i64, y: i64) -> [f32; 3] {
        let x = x.clamp(0, self.width as i64 - 1) as usize;
        let y = y.clamp(0, self.height as i64 - 1) as usize;
        self.rgb[y * self.width as usize + x]
    }

    /// The mean radiance over a rectangle of texture space (`uv` in [0, 1], v down).
    pub fn mean(&self, min: Vec2, max: Vec2) -> [f32; 3] {
        let (w, h) = (self.width as f32, self.height as f32);
        let (x0, x1) = (
            (min.x.min(max.x) * w) as i64,
            (min.x.max(max.x) * w).ceil() as i64,
        );
        let (y0, y1) = (
            (min.y.min(max.y) * h) as i64,
            (min.y.max(max.y) * h).ceil() as i64,
        );
        let mut sum = [0.0f64; 3];
        let mut n = 0.0;
        for y in y0..y1.max(y0 + 1) {
            for x in x0..x1.max(x0 + 1) {
                let t = self.texel(x, y);
                for c in 0..3 {
                    sum[c] += t[c] as f64;
                }
                n += 1.0;
            }
        }
        sum.map(|s| (s / n) as f32)
    }
}

#[cfg(feature = "renderer")]
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// `E5B9G9R9_UFLOAT_PACK32`: three 9-bit mantissas (R in the low bits) sharing a 5-bit exponent
/// (bias 15), no implicit leading one.
pub fn rgb9e5(packed: u32) -> [f32; 3] {
    let exponent = (packed >> 27) as i32 - 15 - 9;
    let scale = 2f32.powi(exponent);
    [0, 9, 18].map(|shift| ((packed >> shift) & 0x1ff) as f32 * scale)
}

/// `B10G11R11_UFLOAT_PACK32`: R and G are 11-bit (6-bit mantissa, 5-bit exponent), B 10-bit
/// (5-bit mantissa), unsigned small floats with exponent bias 15, R in the low bits.
pub fn rg11b10(packed: u32) -> [f32; 3] {
    let small = |bits: u32, mantissa_bits: u32| -> f32 {
        let mantissa = bits & ((1 << mantissa_bits) - 1);
        let exponent = bits >> mantissa_bits;
        let m = mantissa as f32 / (1u32 << mantissa_bits) as f32;
        match exponent {
            0 => m * 2f32.powi(-14),
            31 => {
                if mantissa == 0 {
                    f32::INFINITY
                } else {
                    f32::NAN
                }
            }
            e => (1.0 + m) * 2f32.powi(e as i32 - 15),
        }
    };
    [
        small(packed & 0x7ff, 6),
        small((packed >> 11) & 0x7ff, 6),
        small(packed >> 22, 5),
    ]
}

#[cfg(all(test, feature = "renderer"))]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn rgb9e5_decodes_known_values() {
        // Exponent 15 (scale 2^-9): mantissa 256 is 0.5; exponent 16 makes mantissa 256 one.
        let pack = |r: u32, g: u32, b: u32, e: u32| r | (g << 9) | (b << 18) | (e << 27);
        assert_eq!(rgb9e5(pack(256, 0, 511, 15)), [0.5, 0.0, 511.0 / 512.0]);
        assert_eq!(rgb9e5(pack(256, 128, 64, 16)), [1.0, 0.5, 0.25]);
        assert_eq!(rgb9e5(0), [0.0; 3]);
    }

    #[test]
    fn rg11b10_decodes_known_values() {
        // 1.0: exponent 15, mantissa 0; 2.0: exponent 16; 0.5 in the 10-bit blue: exponent 14.
        let r = 15 << 6;
        let g = 16 << 6;
        let b = 14 << 5;
        assert_eq!(rg11b10(r | (g << 11) | (b << 22)), [1.0, 2.0, 0.5]);
        // 1.5: mantissa half full.
        assert_eq!(rg11b10((15 << 6) | 32)[0], 1.5);
    }

    #[test]
    fn rects_given_v_up_become_texture_space() {
        let r = LightmapRect::from_v_up("Plane", Vec2::new(0.026, 0.026), Vec2::new(0.71, 0.71));
        assert!((r.min - Vec2::new(0.026, 0.264)).length() < 1e-6);
        assert!((r.max - Vec2::new(0.736, 0.974)).length() < 1e-6);
    }

    /// A KTX2 container of one `width` x `height` level in Vulkan format `format`, its data
    /// zstd-supercompressed when `zstd`.
    fn ktx2(format: u32, width: u32, height: u32, texels: &[u8], zstd: bool) -> Vec<u8> {
        ktx2_levels(format, width, height, &[texels], zstd)
    }

    /// As [`ktx2`] with several levels, the full-size one first.
    fn ktx2_levels(format: u32, width: u32, height: u32, levels: &[&[u8]], zstd: bool) -> Vec<u8> {
        let data: Vec<Vec<u8>> = levels
            .iter()
            .map(|texels| {
                if zstd {
                    ruzstd::encoding::compress_to_vec(*texels, ruzstd::encoding::CompressionLevel::Fastest)
                } else {
                    texels.to_vec()
                }
            })
            .collect();
        let mut out = b"\xABKTX 20\xBB\r\n\x1A\n".to_vec();
        let type_size = if format == 97 { 2 } else { 4 };
        for v in [
            format,
            type_size,
            width,
            height,
            0,
            0,
            1,
            levels.len() as u32,
            if zstd { 2 } else { 0 },
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        // Index: an empty data format descriptor (its length word alone) after the level
        // index, no key/value or global data.
        let dfd_offset = 80 + 24 * levels.len();
        for v in [dfd_offset, 4, 0, 0] {
            out.extend_from_slice(&(v as u32).to_le_bytes());
        }
        out.extend_from_slice(&0u64.to_le_bytes());
        out.extend_from_slice(&0u64.to_le_bytes());
        let mut offset = (dfd_offset as u64 + 4).next_multiple_of(16);
        for (texels, level) in levels.iter().zip(&data) {
            for v in [offset, level.len() as u64, texels.len() as u64] {
                out.extend_from_slice(&v.to_le_bytes());
            }
            offset = (offset + level.len() as u64).next_multiple_of(16);
        }
        out.extend_from_slice(&4u32.to_le_bytes());
        for level in &data {
            out.resize(out.len().next_multiple_of(16), 0);
            out.extend_from_slice(level);
        }
        out
    }

    #[test]
    fn ktx2_levels_become_mips() {
        let halfs = |v: f32, n: usize| -> Vec<u8> {
            (0..n)
                .flat_map(|_| [v, v, v, 1.0])
                .flat_map(|c| half::f16::from_f32(c).to_le_bytes())
                .collect()
        };
        for zstd in [false, true] {
            let file = ktx2_levels(97, 4, 2, &[&halfs(0.25, 8), &halfs(0.5, 2), &halfs(1.0, 1)], zstd);
            let image = LightmapImage::decode_ktx2("mips.ktx2", &file).unwrap();
            assert_eq!((image.width, image.height), (4, 2));
            assert_eq!(image.rgb, vec![[0.25; 3]; 8]);
            assert_eq!(image.mips, vec![vec![[0.5; 3]; 2], vec![[1.0; 3]]]);
            assert_eq!((image.level_size(1), image.level_size(2)), ((2, 1), (1, 1)));
        }
        // A level with too little data: an error naming the file and the level.
        let short = ktx2_levels(97, 4, 2, &[&halfs(0.25, 8), &halfs(0.5, 1)], false);
        let e = LightmapImage::decode_ktx2("short-mip.ktx2", &short)
            .unwrap_err()
            .to_string();
        assert!(e.contains("short-mip.ktx2") && e.contains("level 1"), "{e}");
    }

    #[test]
    fn ktx2_float_formats_decode_plain_and_zstd() {
        // Two texels: RGBA16F (1, 0.5, 0.25) and (2, 4, 8).
        let halfs: Vec<u8> = [1.0f32, 0.5, 0.25, 1.0, 2.0, 4.0, 8.0, 1.0]
            .iter()
            .flat_map(|v| half::f16::from_f32(*v).to_le_bytes())
            .collect();
        // RG11B10: (1, 2, 0.5) twice.
        let packed = ((15u32 << 6) | ((16 << 6) << 11) | ((14 << 5) << 22)).to_le_bytes();
        let rg11b10: Vec<u8> = [packed, packed].concat();
        // RGB9E5: (1, 0.5, 0.25) and zero.
        let e5 = (256u32 | (128 << 9) | (64 << 18) | (16 << 27)).to_le_bytes();
        let rgb9e5: Vec<u8> = [e5, [0; 4]].concat();
        for zstd in [false, true] {
            let image = |format, texels: &[u8]| {
                LightmapImage::decode_ktx2("test.ktx2", &ktx2(format, 2, 1, texels, zstd)).unwrap()
            };
            let a = image(97, &halfs);
            assert_eq!((a.width, a.height), (2, 1));
            assert_eq!(a.rgb, vec![[1.0, 0.5, 0.25], [2.0, 4.0, 8.0]]);
            assert_eq!(image(122, &rg11b10).rgb, vec![[1.0, 2.0, 0.5]; 2]);
            assert_eq!(image(123, &rgb9e5).rgb, vec![[1.0, 0.5, 0.25], [0.0; 3]]);
        }
        // Texels a baker left Inf or NaN (atlas gutters): read as 0, the image kept, one
        // warning naming the file and the count.
        let floats: Vec<u8> = [
            1.0f32,
            2.0,
            3.0,
            1.0,
            f32::NAN,
            0.5,
            0.5,
            1.0,
            0.25,
            f32::INFINITY,
            0.0,
            1.0,
        ]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
        let gutters = LightmapImage::decode_ktx2("gutters.ktx2", &ktx2(109, 3, 1, &floats, false)).unwrap();
        assert_eq!(gutters.rgb, vec![[1.0, 2.0, 3.0], [0.0; 3], [0.0; 3]]);
        assert_eq!(gutters.warnings.len(), 1);
        assert!(
            gutters.warnings[0].contains("gutters.ktx2") && gutters.warnings[0].contains("2 of 3"),
            "{:?}",
            gutters.warnings
        );
        let clean = LightmapImage::decode_ktx2("clean.ktx2", &ktx2(97, 2, 1, &halfs, false)).unwrap();
        assert!(clean.warnings.is_empty(), "{:?}", clean.warnings);
        // Too little data, an unsupported format: errors naming the file and the reason.
        let short = LightmapImage::decode_ktx2("short.ktx2", &ktx2(97, 4, 4, &halfs, false)).unwrap_err();
        assert!(short.to_string().contains("short.ktx2"), "{short}");
        let bc7 = LightmapImage::decode_ktx2("bc7.ktx2", &ktx2(145, 2, 1, &halfs, false)).unwrap_err();
        assert!(bc7.to_string().contains("not supported"), "{bc7}");
    }

    #[test]
    fn hdr_and_png_lightmaps_decode_linear() {
        let dir = std::env::temp_dir().join(format!("penumbra-lightmap-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let hdr = dir.join("light.hdr");
        let pixels = vec![image::Rgb([2.5f32, 0.5, 0.125]); 4];
        image::Rgb32FImage::from_raw(2, 2, pixels.into_iter().flat_map(|p| p.0).collect())
            .unwrap()
            .save(&hdr)
            .unwrap();
        let h = LightmapImage::load(&hdr).unwrap();
        assert_eq!((h.width, h.height), (2, 2));
        // Radiance's shared exponent keeps about 8 bits of mantissa.
        for (got, want) in h.rgb[0].iter().zip([2.5, 0.5, 0.125]) {
            assert!((got - want).abs() < want * 0.01, "{got} vs {want}");
        }
        let png = dir.join("light.png");
        image::RgbImage::from_pixel(1, 1, image::Rgb([255, 188, 0]))
            .save(&png)
            .unwrap();
        let p = LightmapImage::load(&png).unwrap();
        // sRGB 188 is about 0.5 linear.
        assert!((p.rgb[0][0] - 1.0).abs() < 1e-6 && (p.rgb[0][1] - 0.5).abs() < 0.01 && p.rgb[0][2] == 0.0);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_files_are_errors_naming_them() {
        let e = LightmapImage::decode_ktx2("broken.ktx2", b"not a ktx2 file").unwrap_err();
        assert!(e.to_string().contains("broken.ktx2"), "{e}");
        let e = LightmapImage::load(Path::new("missing/lightmap.ktx2")).unwrap_err();
        assert!(e.to_string().contains("missing/lightmap.ktx2"), "{e}");
        let e = LightmapImage::load(Path::new("Cargo.toml")).unwrap_err();
        assert!(e.to_string().contains(".toml"), "{e}");
    }
}
