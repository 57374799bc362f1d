//! Lights: a directional light of some angular size, or a spot light of some radius.

use glam::Vec3;

/// A light that casts shadows. Its size sets how soft the shadows are.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Light {
    Directional(DirectionalLight),
    Spot(SpotLight),
}

/// A light infinitely far away, like the sun.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DirectionalLight {
    /// The direction the light travels (from the light toward the scene); need not be unit length.
    pub direction: Vec3,
    /// Angular diameter of the light's disk in degrees, in [0, 90). 0 is a point-like light
    /// (hard shadows); the sun is about 0.53.
    #[cfg_attr(feature = "serde", serde(default))]
    pub angular_diameter_deg: f32,
    /// Linear RGB color.
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    /// Multiplier on `color` (irradiance on a surface facing the light).
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
}

/// A spot light: a disk of `radius` at `position` shining along `direction` inside a cone.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpotLight {
    pub position: Vec3,
    /// The cone's axis; need not be unit length.
    pub direction: Vec3,
    /// Angle between the axis and the cone's edge in degrees, in (0, 89].
    pub cone_angle_deg: f32,
    /// Radius of the emitting disk in world units, >= 0. 0 is a point source (hard shadows).
    #[cfg_attr(feature = "serde", serde(default))]
    pub radius: f32,
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
}

fn white() -> Vec3 {
    Vec3::ONE
}
fn one() -> f32 {
    1.0
}

impl Default for Light {
    fn default() -> Self {
        Light::Directional(DirectionalLight {
            direction: Vec3::new(-0.5, -1.0, -0.35),
            angular_diameter_deg: 2.0,
            color: Vec3::ONE,
            intensity: 1.0,
        })
    }
}

impl Light {
    /// The unit direction the light travels at the scene.
    pub fn direction(&self) -> Vec3 {
        let d = match self {
            Light::Directional(l) => l.direction,
            Light::Spot(l) => l.direction,
        };
        d.normalize_or(Vec3::NEG_Y)
    }

    /// Color times intensity.
    pub fn radiance(&self) -> Vec3 {
        match self {
            Light::Directional(l) => l.color * l.intensity,
            Light::Spot(l) => l.color * l.intensity,
        }
    }

    /// Checks the documented ranges; the error names the field.
    pub fn validate(&self) -> crate::Result<()> {
        use crate::PenumbraError as E;
        let finite = |v: Vec3| v.is_finite();
        match self {
            Light::Directional(l) => {
                if !finite(l.direction) || l.direction.length() < 1e-12 {
                    return Err(E::setting("light.direction", "must be a finite, non-zero vector"));
                }
                if !(0.0..90.0).contains(&l.angular_diameter_deg) {
                    return Err(E::setting(
                        "light.angular_diameter_deg",
                        format!("{} is outside [0, 90)", l.angular_diameter_deg),
                    ));
                }
            }
            Light::Spot(l) => {
                if !finite(l.position) {
                    return Err(E::setting("light.position", "must be finite"));
                }
                if !finite(l.direction) || l.direction.length() < 1e-12 {
                    return Err(E::setting("light.direction", "must be a finite, non-zero vector"));
                }
                if !(l.cone_angle_deg > 0.0 && l.cone_angle_deg <= 89.0) {
                    return Err(E::setting(
                        "light.cone_angle_deg",
                        format!("{} is outside (0, 89]", l.cone_angle_deg),
                    ));
                }
                if !(l.radius >= 0.0 && l.radius.is_finite()) {
                    return Err(E::setting("light.radius", format!("{} must be >= 0", l.radius)));
                }
            }
        }
        let (color, intensity) = match self {
            Light::Directional(l) => (l.color, l.intensity),
            Light::Spot(l) => (l.color, l.intensity),
        };
        if !finite(color) || color.min_element() < 0.0 {
            return Err(E::setting("light.color", "must be finite and non-negative"));
        }
        if !(intensity >= 0.0 && intensity.is_finite()) {
            return Err(E::setting("light.intensity", "must be finite and non-negative"));
        }
        Ok(())
    }
}
