//! Lights: a directional light of some angular size, a spot light of some radius, a point
//! light (a sphere of some radius shining every way), or an area light: a one-sided rectangle
//! or disk shining into the half-space it faces.

use glam::Vec3;

/// The most lights the convenience renderer ([`crate::Renderer`]) shades in one frame, and so
/// the lights a scene may have: its lit pass reads them from one uniform array. 16: the spot
/// lights of Bevy's `spotlight` example (the Bevy plugin's materials hold as many). An engine's
/// own [`crate::Shadows`] holds more: as many as the device's texture arrays have layers
/// ([`crate::Shadows::max_lights`], `docs/lights.md`).
pub const MAX_LIGHTS: usize = 16;

/// A light that casts shadows. Its size sets how soft the shadows are.
///
/// `color` and `intensity` light the convenience renderer's frames; [`crate::Shadows`] (the
/// embedding path) ignores them and returns a unitless visibility per light.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Light {
    /// A light infinitely far away with a disk of some angular size, like the sun; its shadows
    /// come from orthographic maps (cascaded, see [`crate::CascadeSettings`]).
    Directional(DirectionalLight),
    /// A disk-shaped light shining into a cone; its shadows come from one perspective map.
    Spot(SpotLight),
    /// A spherical light shining every way; its shadows come from a cube of six maps.
    Point(PointLight),
    /// A one-sided rectangle shining into the half-space it faces, like a window, a ceiling
    /// panel or a softbox; its shadows come from a cube of six maps, their penumbrae as wide
    /// along each of its sides as that side is long.
    Rect(RectLight),
    /// A one-sided disk shining into the half-space it faces; its shadows come from a cube of
    /// six maps.
    Disk(DiskLight),
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
    /// Illuminance in lux on a surface facing the light (glTF's unit for a directional
    /// light), times `color`.
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
}

/// A spot light: a disk of `radius` at `position` shining along `direction` inside a cone.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpotLight {
    /// The center of the emitting disk (the cone's apex), in world coordinates.
    pub position: Vec3,
    /// The cone's axis; need not be unit length.
    pub direction: Vec3,
    /// Angle between the axis and the cone's edge in degrees, in (0, 89].
    pub cone_angle_deg: f32,
    /// Radius of the emitting disk in world units, >= 0. 0 is a point source (hard shadows).
    #[cfg_attr(feature = "serde", serde(default))]
    pub radius: f32,
    /// Linear RGB color, multiplying `intensity` (white when a scene file leaves it out).
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    /// Luminous intensity in candela along the axis (glTF's unit): a surface facing the light
    /// at distance `d` receives `intensity / d²` lux, times `color`.
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
    /// Where the light ends (glTF's `range`, world units): the inverse-square falloff is
    /// windowed by `clamp(1 - (d / range)^4, 0, 1)^2`, 0 from `range` on. `None`: no end.
    #[cfg_attr(feature = "serde", serde(default))]
    pub range: Option<f32>,
}

/// A point light: a sphere of `radius` at `position` shining in every direction. Its shadows
/// come from a cube of six maps.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PointLight {
    /// The center of the emitting sphere, in world coordinates.
    pub position: Vec3,
    /// Radius of the emitting sphere in world units, >= 0. 0 is a point source (hard shadows).
    #[cfg_attr(feature = "serde", serde(default))]
    pub radius: f32,
    /// Linear RGB color, multiplying `intensity` (white when a scene file leaves it out).
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    /// Luminous intensity in candela (glTF's unit): a surface facing the light at distance
    /// `d` receives `intensity / d²` lux, times `color`.
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
    /// Where the light ends, as [`SpotLight::range`].
    #[cfg_attr(feature = "serde", serde(default))]
    pub range: Option<f32>,
}

/// A one-sided rectangular area light: the rectangle centred at `position`, `width` along its
/// own x axis and `height` along its own y axis, shining from the side it faces (`direction`)
/// into that half-space, as a Lambertian emitter (the same luminance every way).
///
/// Its frame is Bevy's and glTF's convention for a light: it faces its local -z, its height
/// runs along its local y (`up`, made square to `direction`), its width along its local x
/// (`direction × up`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RectLight {
    /// The rectangle's centre, world units.
    pub position: Vec3,
    /// The way its emitting side faces (the direction its light travels along its normal);
    /// need not be unit length.
    pub direction: Vec3,
    /// Which way its height runs: the part of `up` square to `direction`. Zero (the default in
    /// scene files) picks world +y, or +z where the light faces straight up or down.
    #[cfg_attr(feature = "serde", serde(default))]
    pub up: Vec3,
    /// Side along its local x, world units, >= 0.
    pub width: f32,
    /// Side along its local y (`up`), world units, >= 0.
    pub height: f32,
    /// Linear RGB color, multiplying `intensity` (white when a scene file leaves it out).
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    /// Luminance of its emitting side in nits (candela per square metre, world units taken
    /// as metres), times `color`. A rectangle of no area gives no light (its shadows still
    /// take its shape: a line's, or a point's). A light of luminous power `Φ` lumens (Bevy's `RectLight`)
    /// has `Φ / (π · width · height)` nits; seen from far along its normal it lights as a
    /// spot of `intensity · width · height` candela.
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
    /// Where the light ends, as [`SpotLight::range`], measured from its centre.
    #[cfg_attr(feature = "serde", serde(default))]
    pub range: Option<f32>,
}

/// A one-sided disk area light: the disk of `radius` centred at `position`, shining from the
/// side it faces (`direction`) into that half-space, as a Lambertian emitter. Unlike a
/// [`SpotLight`] it has no cone: it lights everything in front of it.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DiskLight {
    /// The disk's centre, world units.
    pub position: Vec3,
    /// The way its emitting side faces; need not be unit length.
    pub direction: Vec3,
    /// Radius in world units, >= 0.
    pub radius: f32,
    /// Linear RGB color, multiplying `intensity` (white when a scene file leaves it out).
    #[cfg_attr(feature = "serde", serde(default = "white"))]
    pub color: Vec3,
    /// Luminance of its emitting side in nits, times `color`: as [`RectLight::intensity`],
    /// with the area `π · radius²`.
    #[cfg_attr(feature = "serde", serde(default = "one"))]
    pub intensity: f32,
    /// Where the light ends, as [`SpotLight::range`], measured from its centre.
    #[cfg_attr(feature = "serde", serde(default))]
    pub range: Option<f32>,
}

/// The shape of an area light's emitting surface, as [`Light::area`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AreaShape {
    /// A rectangle: the surface spans `±u ± v`.
    Rect,
    /// A disk (an ellipse when `u` and `v` differ): the surface spans `u cos t + v sin t`.
    Disk,
}

/// An area light's emitting surface: its centre, its half-axes and its shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    /// The centre, world units.
    pub center: Vec3,
    /// Half the rectangle's width (or the disk's radius) along its local x.
    pub u: Vec3,
    /// Half the rectangle's height (or the disk's radius) along its local y.
    pub v: Vec3,
    /// The unit direction its emitting side faces.
    pub facing: Vec3,
    /// Rectangle or disk.
    pub shape: AreaShape,
}

impl AreaLight {
    /// The emitting area, square world units.
    pub fn area(&self) -> f32 {
        let a = 4.0 * self.u.length() * self.v.length();
        match self.shape {
            AreaShape::Rect => a,
            AreaShape::Disk => a * std::f32::consts::FRAC_PI_4,
        }
    }

    /// The point at `(s, t)` in [-1, 1]² of the rectangle, or of the square the disk is
    /// mapped from (concentric mapping, Shirley and Chiu 1997: equal areas of the square go to
    /// equal areas of the disk).
    pub fn point(&self, s: f32, t: f32) -> Vec3 {
        let (x, y) = match self.shape {
            AreaShape::Rect => (s, t),
            AreaShape::Disk => concentric(s, t),
        };
        self.center + self.u * x + self.v * y
    }
}

/// The concentric map of the square [-1, 1]² onto the unit disk.
fn concentric(s: f32, t: f32) -> (f32, f32) {
    use std::f32::consts::FRAC_PI_4;
    if s == 0.0 && t == 0.0 {
        return (0.0, 0.0);
    }
    let (r, angle) = if s.abs() > t.abs() {
        (s, FRAC_PI_4 * (t / s))
    } else {
        (t, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (s / t))
    };
    (r * angle.cos(), r * angle.sin())
}

/// The unit axes of a light facing `direction` with its height along `up`: its local x (the
/// width) and y (the height). A zero or parallel `up` picks world +y, or +z where the light
/// faces straight up or down.
pub fn light_axes(direction: Vec3, up: Vec3) -> (Vec3, Vec3) {
    let facing = direction.normalize_or(Vec3::NEG_Y);
    let mut y = up - facing * up.dot(facing);
    if y.length_squared() < 1e-12 {
        let fallback = if facing.cross(Vec3::Y).length_squared() < 1e-6 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        y = fallback - facing * fallback.dot(facing);
    }
    let y = y.normalize();
    (facing.cross(y).normalize(), y)
}

/// How bright a frame shows the light it receives: the camera's exposure. A Lambertian surface
/// of albedo `a` receiving `E` lux from a light shows `a · E · scale()` in linear values
/// (`scale()` folds in the BRDF's `1/π`); the ambient term and lightmaps are not scaled
/// (lightmaps have [`crate::Scene::lightmap_exposure`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Exposure {
    /// The scale itself. `Multiplier(1.0)`, the default, shows 1 lux on a white surface as
    /// 1: the project's own scenes give their lights in those terms.
    Multiplier(f32),
    /// Exposure value at ISO 100, as Bevy and Filament define it: the scale is
    /// `1 / (π · 1.2 · 2^ev100)`, so a surface looks as it does there. Bevy's default camera
    /// has 9.7 ([`Exposure::EV100_DEFAULT`]); a bright sunny day is about 15.
    Ev100(f32),
}

impl Exposure {
    /// Bevy's default camera exposure (its "Blender" exposure), for files in physical units.
    pub const EV100_DEFAULT: f32 = 9.7;

    /// What a lux on a white surface becomes in the frame's linear values.
    pub fn scale(self) -> f32 {
        match self {
            Exposure::Multiplier(m) => m,
            Exposure::Ev100(ev) => 1.0 / (std::f32::consts::PI * 1.2 * 2f32.powf(ev)),
        }
    }

    /// Errors unless the scale is finite and >= 0 (an EV100 finite).
    pub fn validate(self) -> crate::error::Result<()> {
        let ok = match self {
            Exposure::Multiplier(m) => m.is_finite() && m >= 0.0,
            Exposure::Ev100(ev) => ev.is_finite() && self.scale().is_finite(),
        };
        if ok {
            Ok(())
        } else {
            Err(crate::error::PenumbraError::setting(
                "exposure",
                format!("{self:?} must be finite (a multiplier >= 0)"),
            ))
        }
    }
}

impl Default for Exposure {
    fn default() -> Self {
        Exposure::Multiplier(1.0)
    }
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
    /// Where a spot or point light ends ([`SpotLight::range`]); `None` for a sun or no end.
    pub fn range(&self) -> Option<f32> {
        match self {
            Light::Directional(_) => None,
            Light::Spot(l) => l.range,
            Light::Point(l) => l.range,
            Light::Rect(l) => l.range,
            Light::Disk(l) => l.range,
        }
    }

    /// An area light's emitting surface (rectangle or disk); `None` for other lights.
    pub fn area(&self) -> Option<AreaLight> {
        match *self {
            Light::Rect(l) => {
                let (x, y) = light_axes(l.direction, l.up);
                Some(AreaLight {
                    center: l.position,
                    u: x * (0.5 * l.width),
                    v: y * (0.5 * l.height),
                    facing: self.direction(),
                    shape: AreaShape::Rect,
                })
            }
            Light::Disk(l) => {
                let (x, y) = light_axes(l.direction, Vec3::ZERO);
                Some(AreaLight {
                    center: l.position,
                    u: x * l.radius,
                    v: y * l.radius,
                    facing: self.direction(),
                    shape: AreaShape::Disk,
                })
            }
            _ => None,
        }
    }

    /// The radius of the sphere about [`Light::position`] that holds the emitting surface: a
    /// spot's or point light's radius, half a rectangle's diagonal, a disk's radius; 0 for a
    /// sun.
    pub fn enclosing_radius(&self) -> f32 {
        match self {
            Light::Directional(_) => 0.0,
            Light::Spot(l) => l.radius,
            Light::Point(l) => l.radius,
            Light::Rect(l) => 0.5 * (l.width * l.width + l.height * l.height).sqrt(),
            Light::Disk(l) => l.radius,
        }
    }

    /// What its light gives at a distance `d` along its axis, far away, times `d²`: its
    /// intensity in candela for a spot or point light, luminance times area for an area light
    /// (lux for a sun, where distance does not matter).
    pub fn far_intensity(&self) -> f32 {
        match self.area() {
            Some(area) => self.intensity() * area.area(),
            None => self.intensity(),
        }
    }

    /// Whether its shadows come from a cube of six maps: point and area lights.
    pub fn uses_cube(&self) -> bool {
        matches!(self, Light::Point(_) | Light::Rect(_) | Light::Disk(_))
    }

    /// The key light of a scene lit by its lightmaps alone (a scene file with lightmaps and no
    /// light): a black, point-like sun straight down, which adds no light.
    pub fn none() -> Self {
        Light::Directional(DirectionalLight {
            direction: Vec3::NEG_Y,
            angular_diameter_deg: 0.0,
            color: Vec3::ZERO,
            intensity: 0.0,
        })
    }

    /// The unit direction the light travels at the scene.
    pub fn direction(&self) -> Vec3 {
        let d = match self {
            Light::Directional(l) => l.direction,
            Light::Spot(l) => l.direction,
            Light::Rect(l) => l.direction,
            Light::Disk(l) => l.direction,
            // Every way: down stands for it where one direction is asked for.
            Light::Point(_) => Vec3::NEG_Y,
        };
        d.normalize_or(Vec3::NEG_Y)
    }

    /// The light turned by `rotation` about the world's origin: its direction (sun, spot) and
    /// its position (spot, point); size, colour and intensity kept.
    pub fn turned(&self, rotation: glam::Quat) -> Light {
        match *self {
            Light::Directional(l) => Light::Directional(DirectionalLight {
                direction: rotation * l.direction,
                ..l
            }),
            Light::Spot(l) => Light::Spot(SpotLight {
                position: rotation * l.position,
                direction: rotation * l.direction,
                ..l
            }),
            Light::Point(l) => Light::Point(PointLight {
                position: rotation * l.position,
                ..l
            }),
            Light::Rect(l) => {
                // Its height's axis turns with it (the default one too).
                let (_, up) = light_axes(l.direction, l.up);
                Light::Rect(RectLight {
                    position: rotation * l.position,
                    direction: rotation * l.direction,
                    up: rotation * up,
                    ..l
                })
            }
            Light::Disk(l) => Light::Disk(DiskLight {
                position: rotation * l.position,
                direction: rotation * l.direction,
                ..l
            }),
        }
    }

    /// Where the light is: `None` for a directional light.
    pub fn position(&self) -> Option<Vec3> {
        match self {
            Light::Directional(_) => None,
            Light::Spot(l) => Some(l.position),
            Light::Point(l) => Some(l.position),
            Light::Rect(l) => Some(l.position),
            Light::Disk(l) => Some(l.position),
        }
    }

    /// Color times intensity.
    pub fn radiance(&self) -> Vec3 {
        self.color() * self.intensity()
    }

    /// Linear RGB color.
    pub fn color(&self) -> Vec3 {
        match self {
            Light::Directional(l) => l.color,
            Light::Spot(l) => l.color,
            Light::Point(l) => l.color,
            Light::Rect(l) => l.color,
            Light::Disk(l) => l.color,
        }
    }

    /// Intensity in the light's own unit (lux, candela or nits: see each light's
    /// `intensity`).
    pub fn intensity(&self) -> f32 {
        match self {
            Light::Directional(l) => l.intensity,
            Light::Spot(l) => l.intensity,
            Light::Point(l) => l.intensity,
            Light::Rect(l) => l.intensity,
            Light::Disk(l) => l.intensity,
        }
    }

    /// The same light with `intensity` in its own unit.
    pub fn with_intensity(mut self, intensity: f32) -> Light {
        match &mut self {
            Light::Directional(l) => l.intensity = intensity,
            Light::Spot(l) => l.intensity = intensity,
            Light::Point(l) => l.intensity = intensity,
            Light::Rect(l) => l.intensity = intensity,
            Light::Disk(l) => l.intensity = intensity,
        }
        self
    }

    /// How a spot light's cone shades: the position (the origin for a directional light) and
    /// the cosines of the outer edge and of where the falloff starts (0.85 of the cone
    /// angle); a directional light gives -1 and -1 (no falloff), a point light its position
    /// and -1 and -1.
    pub fn cone(&self) -> (Vec3, f32, f32) {
        match self {
            Light::Directional(_) => (Vec3::ZERO, -1.0, -1.0),
            Light::Point(point) => (point.position, -1.0, -1.0),
            Light::Rect(rect) => (rect.position, -1.0, -1.0),
            Light::Disk(disk) => (disk.position, -1.0, -1.0),
            Light::Spot(spot) => {
                let outer = spot.cone_angle_deg.to_radians();
                (spot.position, outer.cos(), (outer * 0.85).cos())
            }
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
            Light::Point(l) => {
                if !finite(l.position) {
                    return Err(E::setting("light.position", "must be finite"));
                }
                if !(l.radius >= 0.0 && l.radius.is_finite()) {
                    return Err(E::setting("light.radius", format!("{} must be >= 0", l.radius)));
                }
            }
            Light::Rect(l) => {
                if !finite(l.position) {
                    return Err(E::setting("light.position", "must be finite"));
                }
                if !finite(l.direction) || l.direction.length() < 1e-12 {
                    return Err(E::setting("light.direction", "must be a finite, non-zero vector"));
                }
                if !finite(l.up) {
                    return Err(E::setting("light.up", "must be finite"));
                }
                for (name, side) in [("light.width", l.width), ("light.height", l.height)] {
                    if !(side >= 0.0 && side.is_finite()) {
                        return Err(E::setting(name, format!("{side} must be finite and >= 0")));
                    }
                }
            }
            Light::Disk(l) => {
                if !finite(l.position) {
                    return Err(E::setting("light.position", "must be finite"));
                }
                if !finite(l.direction) || l.direction.length() < 1e-12 {
                    return Err(E::setting("light.direction", "must be a finite, non-zero vector"));
                }
                if !(l.radius >= 0.0 && l.radius.is_finite()) {
                    return Err(E::setting("light.radius", format!("{} must be >= 0", l.radius)));
                }
            }
        }
        let (color, intensity) = (self.color(), self.intensity());
        if let Some(range) = self.range()
            && !(range > 0.0 && range.is_finite())
        {
            return Err(E::setting(
                "light.range",
                format!("{range} must be finite and > 0"),
            ));
        }
        if !finite(color) || color.min_element() < 0.0 {
            return Err(E::setting("light.color", "must be finite and non-negative"));
        }
        if !(intensity >= 0.0 && intensity.is_finite()) {
            return Err(E::setting("light.intensity", "must be finite and non-negative"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turned_light_keeps_its_size_and_turns_its_direction_and_position() {
        let quarter = glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let spot = Light::Spot(SpotLight {
            position: Vec3::new(1.0, 4.0, 0.0),
            direction: Vec3::new(0.0, -1.0, 1.0).normalize(),
            cone_angle_deg: 30.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 2.0,
            range: None,
        });
        let Light::Spot(turned) = spot.turned(quarter) else {
            panic!("a spot stays a spot");
        };
        // A quarter turn about +y takes +x to -z and +z to +x.
        assert!(turned.position.abs_diff_eq(Vec3::new(0.0, 4.0, -1.0), 1e-5));
        assert!(
            turned
                .direction
                .abs_diff_eq(Vec3::new(1.0, -1.0, 0.0).normalize(), 1e-5)
        );
        assert_eq!(
            (turned.radius, turned.cone_angle_deg, turned.intensity),
            (0.2, 30.0, 2.0)
        );
        let sun = Light::Directional(DirectionalLight {
            direction: Vec3::X,
            angular_diameter_deg: 0.53,
            color: Vec3::ONE,
            intensity: 1.0,
        });
        assert!(sun.turned(quarter).direction().abs_diff_eq(Vec3::NEG_Z, 1e-5));
        let point = Light::Point(PointLight {
            position: Vec3::Z,
            radius: 0.1,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        assert!(
            point
                .turned(quarter)
                .position()
                .unwrap()
                .abs_diff_eq(Vec3::X, 1e-5)
        );
    }
}
