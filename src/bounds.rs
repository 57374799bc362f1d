//! Axis-aligned bounding boxes.

use glam::{Mat4, Vec3};

/// An axis-aligned bounding box. An *empty* box has `min > max` on every axis
/// and absorbs nothing when united with another box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinate on every axis (`+inf` in [`Aabb::EMPTY`]).
    pub min: Vec3,
    /// The corner with the largest coordinate on every axis (`-inf` in [`Aabb::EMPTY`]).
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The box that contains nothing.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// A box from two corners (they are sorted per axis).
    pub fn new(a: Vec3, b: Vec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box around `points`; empty when there are none. Non-finite points are ignored.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> Self {
        let mut aabb = Self::EMPTY;
        for p in points {
            aabb.grow(*p);
        }
        aabb
    }

    /// True when the box contains no point.
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// Extends the box to contain `p` (ignored when `p` is not finite).
    pub fn grow(&mut self, p: Vec3) {
        if p.is_finite() {
            self.min = self.min.min(p);
            self.max = self.max.max(p);
        }
    }

    /// The part inside both boxes; empty ([`Aabb::is_empty`]) where they do not overlap.
    pub fn intersection(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.max(other.min),
            max: self.max.min(other.max),
        }
    }

    /// The smallest box containing both.
    pub fn union(&self, other: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The point halfway between `min` and `max`; meaningless for an empty box (NaN for
    /// [`Aabb::EMPTY`]).
    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The box's extent along each axis, `max - min`; zero for an empty box.
    pub fn size(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Radius of the sphere around the box's center that contains the box.
    pub fn radius(&self) -> f32 {
        self.size().length() * 0.5
    }

    /// The eight corners (meaningless for an empty box).
    pub fn corners(&self) -> [Vec3; 8] {
        let (a, b) = (self.min, self.max);
        [
            Vec3::new(a.x, a.y, a.z),
            Vec3::new(b.x, a.y, a.z),
            Vec3::new(a.x, b.y, a.z),
            Vec3::new(b.x, b.y, a.z),
            Vec3::new(a.x, a.y, b.z),
            Vec3::new(b.x, a.y, b.z),
            Vec3::new(a.x, b.y, b.z),
            Vec3::new(b.x, b.y, b.z),
        ]
    }

    /// The box around this box after `m` (exact for affine transforms of the corners).
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        if self.is_empty() {
            return Aabb::EMPTY;
        }
        let corners = self.corners().map(|c| m.transform_point3(c));
        Aabb::from_points(corners.iter())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_box_absorbs_nothing() {
        let b = Aabb::new(Vec3::ONE, Vec3::splat(2.0));
        assert_eq!(Aabb::EMPTY.union(&b), b);
        assert!(Aabb::EMPTY.is_empty());
        assert_eq!(Aabb::EMPTY.size(), Vec3::ZERO);
    }

    #[test]
    fn from_points_and_transform() {
        let pts = [Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, -2.0, 1.0), Vec3::NAN];
        let b = Aabb::from_points(pts.iter());
        assert_eq!(b.min, Vec3::new(-1.0, -2.0, 1.0));
        assert_eq!(b.max, Vec3::new(3.0, 0.0, 2.0));
        let t = b.transformed(&Mat4::from_translation(Vec3::new(1.0, 1.0, 1.0)));
        assert_eq!(t.min, Vec3::new(0.0, -1.0, 2.0));
        // A 90 degree rotation about y swaps x and z extents.
        let r = b.transformed(&Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2));
        assert!((r.size() - Vec3::new(1.0, 2.0, 4.0)).abs().max_element() < 1e-5);
    }
}
