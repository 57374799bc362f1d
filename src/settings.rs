//! Public shadow settings: plain structs with defaults, units and ranges.

use serde::{Deserialize, Serialize};

use crate::error::{PenumbraError, Result};

/// How shadows are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum ShadowMethod {
    /// One depth comparison per pixel, nearest texel: hard, aliased edges.
    Hard,
    /// The hardware's bilinear 2x2 percentage-closer filter (one comparison sample with
    /// linear filtering; Reeves, Salesin and Cook, "Rendering antialiased shadows with depth
    /// maps", SIGGRAPH 1987): edges one shadow-map texel wide.
    #[default]
    Hardware2x2,
}

impl ShadowMethod {
    /// Every method, in the order tools list them.
    pub const ALL: [ShadowMethod; 2] = [ShadowMethod::Hard, ShadowMethod::Hardware2x2];

    /// The name used on command lines (`hard`, `hw2x2`).
    pub fn name(self) -> &'static str {
        match self {
            ShadowMethod::Hard => "hard",
            ShadowMethod::Hardware2x2 => "hw2x2",
        }
    }

    /// Parses a command-line name; the error lists the valid ones.
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|m| m.name()).collect();
                PenumbraError::setting(
                    "method",
                    format!(
                        "unknown method `{name}`; choose one of {}",
                        names.join(", ")
                    ),
                )
            })
    }
}

/// Depth format of the shadow map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum DepthFormat {
    /// 16-bit normalized: half the memory, needs a tight near/far fit.
    Depth16,
    /// At least 24 bits (the device picks 24-bit unorm or 32-bit float).
    Depth24,
    /// 32-bit float.
    #[default]
    Depth32,
}

impl DepthFormat {
    pub fn texture_format(self) -> wgpu::TextureFormat {
        match self {
            DepthFormat::Depth16 => wgpu::TextureFormat::Depth16Unorm,
            DepthFormat::Depth24 => wgpu::TextureFormat::Depth24Plus,
            DepthFormat::Depth32 => wgpu::TextureFormat::Depth32Float,
        }
    }
}

/// Which triangles the shadow pass skips.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub enum CullMode {
    /// Draw both sides: works for open meshes and single-sided planes (the default).
    #[default]
    None,
    /// Skip triangles facing away from the light: the usual choice for a camera.
    Back,
    /// Skip triangles facing the light, so depth comes from the back sides of closed meshes:
    /// less acne on lit surfaces, but open meshes and planes cast no shadow.
    Front,
}

impl CullMode {
    pub fn face(self) -> Option<wgpu::Face> {
        match self {
            CullMode::None => None,
            CullMode::Back => Some(wgpu::Face::Back),
            CullMode::Front => Some(wgpu::Face::Front),
        }
    }
}

/// The shadow map: its size, format, bias and culling.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShadowMapSettings {
    /// Width and height in texels, a power of two in [64, 8192] and within the device's limit.
    /// Default 2048.
    pub resolution: u32,
    /// Default [`DepthFormat::Depth32`].
    pub depth_format: DepthFormat,
    /// Constant depth bias, in units of the depth format's smallest resolvable difference
    /// (for 32-bit float, about 2^-23 times the largest depth in the triangle). Default 4.
    pub constant_bias: i32,
    /// Slope-scaled depth bias: times the triangle's largest depth slope in light space.
    /// In [0, 16]. Default 2.0.
    pub slope_bias: f32,
    /// Which faces the shadow pass culls. Default [`CullMode::None`].
    pub cull_mode: CullMode,
}

impl Default for ShadowMapSettings {
    fn default() -> Self {
        Self {
            resolution: 2048,
            depth_format: DepthFormat::default(),
            constant_bias: 4,
            slope_bias: 2.0,
            cull_mode: CullMode::default(),
        }
    }
}

/// All shadow settings. `Default` gives hardware 2x2 PCF on a 2048^2 32-bit shadow map.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct ShadowSettings {
    pub method: ShadowMethod,
    pub shadow_map: ShadowMapSettings,
}

impl ShadowSettings {
    /// Checks every field against its documented range (and the device's texture limit when
    /// `max_texture_side` is given); the error names the field.
    pub fn validate(&self, max_texture_side: Option<u32>) -> Result<()> {
        let sm = &self.shadow_map;
        if !(64..=8192).contains(&sm.resolution) || !sm.resolution.is_power_of_two() {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!("{} is not a power of two in [64, 8192]", sm.resolution),
            ));
        }
        if let Some(limit) = max_texture_side
            && sm.resolution > limit
        {
            return Err(PenumbraError::setting(
                "shadow_map.resolution",
                format!("{} exceeds this device's limit of {limit}", sm.resolution),
            ));
        }
        if !(0.0..=16.0).contains(&sm.slope_bias) {
            return Err(PenumbraError::setting(
                "shadow_map.slope_bias",
                format!("{} is outside [0, 16]", sm.slope_bias),
            ));
        }
        if !(0..=1 << 20).contains(&sm.constant_bias) {
            return Err(PenumbraError::setting(
                "shadow_map.constant_bias",
                format!("{} is outside [0, 1048576]", sm.constant_bias),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        ShadowSettings::default().validate(Some(8192)).unwrap();
        let mut s = ShadowSettings::default();
        s.shadow_map.resolution = 1000;
        assert!(
            s.validate(None)
                .unwrap_err()
                .to_string()
                .contains("shadow_map.resolution")
        );
        s.shadow_map.resolution = 4096;
        assert!(
            s.validate(Some(2048))
                .unwrap_err()
                .to_string()
                .contains("limit")
        );
        s.shadow_map.resolution = 1024;
        s.shadow_map.slope_bias = f32::NAN;
        assert!(
            s.validate(None)
                .unwrap_err()
                .to_string()
                .contains("slope_bias")
        );
    }

    #[test]
    fn method_names_round_trip() {
        for m in ShadowMethod::ALL {
            assert_eq!(ShadowMethod::from_name(m.name()).unwrap(), m);
        }
        let err = ShadowMethod::from_name("vsm").unwrap_err().to_string();
        assert!(err.contains("vsm") && err.contains("hw2x2"), "{err}");
    }
}
