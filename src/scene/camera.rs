//! An orbit helper for the perspective camera.

use glam::Vec3;

use crate::bounds::Aabb;
use crate::camera::Camera;

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
