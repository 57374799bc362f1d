//! Perspective cameras and an orbit helper.

use glam::{Mat4, Vec3};

use super::bounds::Aabb;

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

/// A camera that orbits a target: yaw about +Y, pitch above the horizon, and a distance.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OrbitCamera {
    /// The world point the camera orbits and looks at.
    pub target: Vec3,
    /// How far the eye is from `target`, in world units, > 0 ([`OrbitCamera::zoom`] keeps it at
    /// least 1e-6).
    pub distance: f32,
    /// Degrees about +Y; 0 looks from +Z toward -Z.
    pub yaw_deg: f32,
    /// Degrees above the horizontal plane, clamped to (-89, 89).
    pub pitch_deg: f32,
    /// Vertical field of view in degrees, handed on to [`Camera::fov_y_deg`]
    /// ([`OrbitCamera::framing`] picks 40).
    pub fov_y_deg: f32,
}

impl OrbitCamera {
    /// An orbit that frames `bounds` (its bounding sphere fills the field of view).
    pub fn framing(bounds: &Aabb, yaw_deg: f32, pitch_deg: f32) -> Self {
        let fov_y_deg: f32 = 40.0;
        let radius = bounds.radius().max(1e-6);
        let distance = radius / (fov_y_deg.to_radians() * 0.5).sin() * 1.05;
        Self {
            target: bounds.center(),
            distance,
            yaw_deg,
            pitch_deg,
            fov_y_deg,
        }
    }

    /// The eye's world position: `distance` away from `target` in the direction given by the yaw
    /// and the pitch (clamped to [-89, 89] degrees).
    pub fn eye(&self) -> Vec3 {
        let (yaw, pitch) = (
            self.yaw_deg.to_radians(),
            self.pitch_deg.clamp(-89.0, 89.0).to_radians(),
        );
        self.target + self.distance * Vec3::new(yaw.sin() * pitch.cos(), pitch.sin(), yaw.cos() * pitch.cos())
    }

    /// The orbit that sees what `camera` sees (its target, distance and direction; `up` is
    /// taken to be +Y).
    pub fn from_camera(camera: &Camera) -> Self {
        let offset = camera.eye - camera.target;
        let distance = offset.length().max(1e-6);
        let dir = offset / distance;
        Self {
            target: camera.target,
            distance,
            yaw_deg: dir.x.atan2(dir.z).to_degrees().rem_euclid(360.0),
            pitch_deg: dir.y.clamp(-1.0, 1.0).asin().to_degrees().clamp(-89.0, 89.0),
            fov_y_deg: camera.fov_y_deg,
        }
    }

    /// Moves the target (and the eye with it) in the view plane by `right` and `up` times the
    /// distance, so a drag pans at the same screen speed whatever the zoom.
    pub fn pan(&mut self, right: f32, up: f32) {
        if !(right.is_finite() && up.is_finite()) {
            return;
        }
        let forward = (self.target - self.eye()).normalize_or(Vec3::NEG_Z);
        let side = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let true_up = side.cross(forward);
        self.target += (side * right + true_up * up) * self.distance;
    }

    /// Rotates by the given degrees (pitch is clamped).
    pub fn rotate(&mut self, yaw_deg: f32, pitch_deg: f32) {
        self.yaw_deg = (self.yaw_deg + yaw_deg).rem_euclid(360.0);
        self.pitch_deg = (self.pitch_deg + pitch_deg).clamp(-89.0, 89.0);
    }

    /// Multiplies the distance by `factor` (> 0).
    pub fn zoom(&mut self, factor: f32) {
        if factor.is_finite() && factor > 0.0 {
            self.distance = (self.distance * factor).max(1e-6);
        }
    }

    /// The camera, with near/far fitted around `bounds`.
    pub fn camera(&self, bounds: &Aabb) -> Camera {
        let mut camera = Camera {
            eye: self.eye(),
            target: self.target,
            up: Vec3::Y,
            fov_y_deg: self.fov_y_deg,
            near: 0.01,
            far: 100.0,
        };
        camera.fit_depth_range(bounds);
        camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_from_camera_gives_the_same_eye() {
        let c = Camera::look_at(Vec3::new(3.0, 4.0, 5.0), Vec3::new(0.5, 1.0, -1.0));
        let orbit = OrbitCamera::from_camera(&c);
        assert!(
            (orbit.eye() - c.eye).length() < 1e-4,
            "{:?} vs {:?}",
            orbit.eye(),
            c.eye
        );
        let mut panned = orbit;
        panned.pan(0.1, 0.0);
        assert!((panned.target - orbit.target).length() > 0.05);
        assert!(((panned.eye() - panned.target) - (orbit.eye() - orbit.target)).length() < 1e-4);
    }

    #[test]
    fn target_projects_to_the_center() {
        let c = Camera::look_at(Vec3::new(3.0, 4.0, 5.0), Vec3::new(0.0, 1.0, 0.0));
        let clip = c.view_projection(1.5) * Vec3::new(0.0, 1.0, 0.0).extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!(ndc.x.abs() < 1e-5 && ndc.y.abs() < 1e-5 && ndc.z > 0.0 && ndc.z < 1.0);
    }

    #[test]
    fn straight_down_view_is_finite() {
        let c = Camera::look_at(Vec3::new(0.0, 10.0, 0.0), Vec3::ZERO);
        assert!(c.view().is_finite());
    }

    #[test]
    fn orbit_frames_the_box() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let o = OrbitCamera::framing(&b, 30.0, 20.0);
        let cam = o.camera(&b);
        let vp = cam.view_projection(1.0);
        for corner in b.corners() {
            let clip = vp * corner.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            assert!(
                ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z),
                "{ndc}"
            );
        }
    }
}
