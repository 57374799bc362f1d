//! The perspective camera the shadows are seen from.

use glam::{Mat4, Vec3};

use crate::bounds::Aabb;

/// A perspective camera looking from `eye` at `target`. Right-handed, y up, reversed depth:
/// 1 at the near plane, 0 at the far plane, so a float depth buffer keeps its precision at
/// near/far ratios of 1e6 and more.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Camera {
    /// Where the camera is, in world coordinates.
    pub eye: Vec3,
    /// The world point the camera looks at, which lands at the center of the image. Where it
    /// equals `eye`, the camera looks along -Z.
    pub target: Vec3,
    /// Which world direction shows as up in the image ([`Camera::look_at`]: +Y). It need not be
    /// unit length or perpendicular to the view direction; parallel to it, some perpendicular
    /// direction is used instead.
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub fov_y_deg: f32,
    /// Near and far clip distances in world units, 0 < near < far.
    pub near: f32,
    /// The far clip distance in world units (see `near`); reversed depth puts it at depth 0.
    pub far: f32,
}

impl Default for Camera {
    fn default() -> Self {
        Self::look_at(Vec3::new(0.0, 2.0, 6.0), Vec3::ZERO)
    }
}

impl Camera {
    /// A camera at `eye` looking at `target` with a 45 degree field of view.
    pub fn look_at(eye: Vec3, target: Vec3) -> Self {
        Self {
            eye,
            target,
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.05,
            far: 200.0,
        }
    }

    /// The unit direction from `eye` toward `target` (-Z when the two coincide).
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize_or(Vec3::NEG_Z)
    }

    /// The world-to-view matrix. Copes with `up` parallel to the view direction.
    pub fn view(&self) -> Mat4 {
        let forward = self.forward();
        let up = if forward.cross(self.up).length_squared() < 1e-10 {
            forward.any_orthonormal_vector()
        } else {
            self.up
        };
        glam::camera::rh::view::look_to_mat4(self.eye, forward, up)
    }

    /// The view-to-clip matrix for a target of the given width / height, with reversed depth
    /// (near plane at depth 1, far plane at 0: depth tests use `Greater`, buffers clear to 0).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective(
            self.fov_y_deg.to_radians(),
            aspect.max(1e-6),
            self.far,
            self.near,
        )
    }

    /// The world-to-clip matrix for a target of the given width / height: [`Camera::projection`]
    /// times [`Camera::view`], with reversed depth.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// Sets near and far so that `bounds` lies inside the depth range with some margin.
    pub fn fit_depth_range(&mut self, bounds: &Aabb) {
        if bounds.is_empty() {
            return;
        }
        let distance = (bounds.center() - self.eye).length();
        let radius = bounds.radius().max(1e-6);
        self.far = (distance + radius) * 1.05;
        // The nearest point of the box (not of its bounding sphere, which may hold the eye
        // even when the box does not): a near plane as far out as possible keeps depth precise.
        let to_box = (bounds.min - self.eye)
            .max(self.eye - bounds.max)
            .max(Vec3::ZERO)
            .length();
        self.near = (to_box * 0.9).max(self.far * 1e-3).max(1e-6);
        // A far plane set by a ground far wider than the view (thousands of units) must not
        // push the near plane past what stands in front of the camera: with reversed depth a
        // float buffer keeps its precision down to a millionth of far.
        if to_box > 0.0 {
            self.near = self.near.min(to_box * 0.9).max(self.far * 1e-6).max(1e-6);
        }
        if self.near >= self.far {
            self.near = self.far * 1e-3;
        }
    }
}
