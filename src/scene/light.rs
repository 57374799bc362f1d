//! The lights a model file names (glTF's `KHR_lights_punctual`, a scene file's own), turned
//! into shadowing [`Light`]s of a size.

use glam::Vec3;

use crate::lights::{DirectionalLight, Light, PointLight, SpotLight};

/// The kind of light a model file names.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelLightKind {
    /// glTF's `directional`: a sun, given [`ModelLightSizes::sun_diameter_deg`] as its size.
    Directional,
    /// A cone: the angles between its axis and the outer edge and where the falloff starts.
    Spot {
        /// glTF's `outerConeAngle`, in degrees: it becomes [`SpotLight::cone_angle_deg`], kept to
        /// [0.1, 89].
        outer_cone_deg: f32,
        /// glTF's `innerConeAngle`, in degrees. Not used: penumbra starts a spot's falloff at 0.85
        /// of its outer angle.
        inner_cone_deg: f32,
    },
    /// glTF's `point`: a light shining in every direction, which becomes a [`PointLight`].
    Point,
}

/// A light as a model file gives it (glTF's `KHR_lights_punctual`): in the model's space and
/// in physical units, without a size. [`lights_from_model`] makes penumbra lights of them.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelLight {
    /// The light's name in the file, empty when it has none; warnings name the light by it.
    pub name: String,
    /// Directional, spot (with its cone angles) or point.
    pub kind: ModelLightKind,
    /// Linear RGB.
    pub color: Vec3,
    /// Lux (directional) or candela (spot, point).
    pub intensity: f32,
    /// Where its node puts it, in the model's space (its node's origin; unused for a directional
    /// light).
    pub position: Vec3,
    /// The direction it shines (its node's -Z).
    pub direction: Vec3,
    /// glTF's `range` (spot and point lights), in the model's units.
    pub range: Option<f32>,
}

/// The angular diameter given to a model file's directional light, which has no size: the
/// sun's, in degrees.
pub const MODEL_SUN_DIAMETER_DEG: f32 = 0.53;
/// The radius given to a model file's spot light, which has no size: this fraction of its
/// distance to the model's centre (so its penumbrae look alike at any scale).
pub const MODEL_SPOT_RADIUS_PER_DISTANCE: f32 = 0.02;

/// The sizes given to a model file's lights, which have none (glTF's do not).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ModelLightSizes {
    /// Directional lights' angular diameter in degrees, in [0, 90). Default
    /// [`MODEL_SUN_DIAMETER_DEG`].
    #[cfg_attr(feature = "serde", serde(default = "sun_diameter"))]
    pub sun_diameter_deg: f32,
    /// Spot and point lights' radius as a fraction of their distance to the model's centre,
    /// >= 0. Default [`MODEL_SPOT_RADIUS_PER_DISTANCE`].
    #[cfg_attr(feature = "serde", serde(default = "spot_radius"))]
    pub spot_radius_per_distance: f32,
}

#[cfg(feature = "serde")]
fn sun_diameter() -> f32 {
    MODEL_SUN_DIAMETER_DEG
}
#[cfg(feature = "serde")]
fn spot_radius() -> f32 {
    MODEL_SPOT_RADIUS_PER_DISTANCE
}

impl Default for ModelLightSizes {
    fn default() -> Self {
        Self {
            sun_diameter_deg: MODEL_SUN_DIAMETER_DEG,
            spot_radius_per_distance: MODEL_SPOT_RADIUS_PER_DISTANCE,
        }
    }
}

/// Penumbra lights of a model's lights, placed by `place`, `center` the placed model's centre:
/// their intensities as the file gives them (lux for a directional light, candela for spots
/// and points, see [`DirectionalLight::intensity`]) with glTF's `range` scaled by the
/// placement, so a scene built from them wants an [`Exposure`](crate::Exposure) in physical
/// terms (such as [`Exposure::EV100_DEFAULT`](crate::Exposure::EV100_DEFAULT)). Sizes from
/// `sizes` ([`ModelLightSizes::default`]: the sun's 0.53 degrees, spots and points 2% of their
/// distance to `center`). A spot's falloff starts at 0.85 of its cone whatever the file says;
/// cones wider than 89 degrees are narrowed to 89.
/// Lights past [`crate::MAX_LIGHTS`] are left out with a warning.
pub fn lights_from_model(
    lights: &[ModelLight],
    place: glam::Mat4,
    center: Vec3,
    sizes: ModelLightSizes,
    warnings: &mut Vec<String>,
) -> Vec<Light> {
    // How much the placement scales lengths (a range is a length).
    let scale = place.transform_vector3(Vec3::X).length();
    let mut placed = Vec::new();
    for l in lights {
        let position = place.transform_point3(l.position);
        let direction = place.transform_vector3(l.direction).normalize_or(Vec3::NEG_Y);
        let name = if l.name.is_empty() { "(unnamed)" } else { &l.name };
        let intensity = if l.intensity.is_finite() {
            l.intensity.max(0.0)
        } else {
            0.0
        };
        let range = l.range.filter(|r| *r > 0.0 && r.is_finite()).map(|r| r * scale);
        let light = match l.kind {
            ModelLightKind::Point => Light::Point(PointLight {
                position,
                radius: sizes.spot_radius_per_distance * position.distance(center).max(1e-6),
                color: l.color,
                intensity,
                range,
            }),
            ModelLightKind::Directional => Light::Directional(DirectionalLight {
                direction,
                angular_diameter_deg: sizes.sun_diameter_deg,
                color: l.color,
                intensity,
            }),
            ModelLightKind::Spot { outer_cone_deg, .. } => Light::Spot(SpotLight {
                position,
                direction,
                cone_angle_deg: outer_cone_deg.clamp(0.1, 89.0),
                radius: sizes.spot_radius_per_distance * position.distance(center).max(1e-6),
                color: l.color,
                intensity,
                range,
            }),
        };
        if placed.len() == crate::MAX_LIGHTS {
            warnings.push(format!(
                "light `{name}` is left out: at most {} lights are shadowed",
                crate::MAX_LIGHTS
            ));
            continue;
        }
        placed.push(light);
    }
    placed
}
