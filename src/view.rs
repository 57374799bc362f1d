//! The engine's camera as penumbra takes it: its own view and projection matrices, whatever
//! they are (perspective or orthographic, off-centre, jittered, infinite far), and the depth
//! convention its depth buffer uses. The screen-space passes reconstruct world positions from
//! the engine's depth with exactly these matrices, so the visibility lines up with its pixels.

use glam::{Mat4, Vec3, Vec4};

use crate::camera::Camera;
use crate::error::{PenumbraError, Result};

/// How a depth buffer maps distance to depth.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DepthConvention {
    /// Near plane at depth 0, far plane at 1; the buffer clears to 1 (`Less` tests).
    Standard,
    /// Near plane at depth 1, far plane at 0; the buffer clears to 0 (`Greater` tests). More
    /// precise with a float depth buffer; what [`crate::Renderer`] uses.
    #[default]
    Reversed,
}

impl DepthConvention {
    /// The depth buffer's clear value: where nothing was drawn.
    pub fn clear_depth(self) -> f32 {
        match self {
            DepthConvention::Standard => 1.0,
            DepthConvention::Reversed => 0.0,
        }
    }
}

/// The camera an engine renders with: world-to-view and view-to-clip matrices (right-handed
/// view space looking down -z; clip depth in [0, 1] as wgpu's), and its depth convention.
///
/// ```
/// # fn main() -> penumbra::Result<()> {
/// use glam::Vec3;
/// use penumbra::{CameraMatrices, DepthConvention};
///
/// let eye = Vec3::new(0.0, 2.0, 5.0);
/// let camera = CameraMatrices {
///     view: glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
///     // Depth 0 at the near plane (0.1), 1 at the far plane (100): standard depth.
///     projection: glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 0.1, 100.0),
///     depth: DepthConvention::Standard,
/// };
/// camera.validate()?;
/// assert!(camera.is_perspective());
/// assert!(camera.eye().distance(eye) < 1e-3);
/// let (near, far) = camera.distance_range(0.0, 1000.0);
/// assert!((near - 0.1).abs() < 1e-3 && (far - 100.0).abs() < 0.1);
///
/// // Reversed depth (near plane at 1) is the same camera with its planes swapped.
/// let reversed = CameraMatrices {
///     projection: glam::camera::rh::proj::directx::perspective(60f32.to_radians(), 16.0 / 9.0, 100.0, 0.1),
///     depth: DepthConvention::Reversed,
///     ..camera
/// };
/// assert_eq!(reversed.depth.clear_depth(), 0.0);
/// let (near, far) = reversed.distance_range(0.0, 1000.0);
/// assert!((near - 0.1).abs() < 1e-3 && (far - 100.0).abs() < 0.1);
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraMatrices {
    /// World to view: the inverse of the camera's placement in the world. Finite and
    /// invertible.
    pub view: Mat4,
    /// View to clip, with clip depth in [0, 1]: any projection (perspective or orthographic,
    /// off-centre, jittered, infinite far plane). Finite and invertible.
    pub projection: Mat4,
    /// How `projection` maps distance to depth: what the engine's depth buffer holds.
    pub depth: DepthConvention,
}

impl CameraMatrices {
    /// The matrices of a [`Camera`] for a target of `aspect` (width / height): reversed depth.
    pub fn from_camera(camera: &Camera, aspect: f32) -> Self {
        Self {
            view: camera.view(),
            projection: camera.projection(aspect),
            depth: DepthConvention::Reversed,
        }
    }

    /// Errors unless both matrices are finite and invertible.
    pub fn validate(&self) -> Result<()> {
        for (name, m) in [("view", self.view), ("projection", self.projection)] {
            let det = m.determinant();
            if !m.is_finite() || !det.is_finite() || det == 0.0 {
                return Err(PenumbraError::input(
                    format!("camera {name} matrix"),
                    "it must be finite and invertible",
                ));
            }
        }
        Ok(())
    }

    /// World to clip: `projection * view`.
    pub fn view_projection(&self) -> Mat4 {
        self.projection * self.view
    }

    /// True for a perspective projection (clip w depends on view depth), false for an
    /// orthographic one.
    pub fn is_perspective(&self) -> bool {
        self.projection.z_axis.w.abs() > self.projection.w_axis.w.abs()
    }

    /// The camera's position in the world (perspective).
    pub fn eye(&self) -> Vec3 {
        self.view.inverse().transform_point3(Vec3::ZERO)
    }

    /// The direction from the scene toward the camera (the view's +z in the world).
    pub fn backward(&self) -> Vec3 {
        self.view
            .inverse()
            .transform_vector3(Vec3::Z)
            .normalize_or(Vec3::Z)
    }

    /// What the shaders need to turn a surface toward the camera: the eye with w = 1
    /// (perspective), or the direction toward the camera with w = 0 (orthographic).
    pub(crate) fn toward_camera(&self) -> [f32; 4] {
        if self.is_perspective() {
            self.eye().extend(1.0).to_array()
        } else {
            self.backward().extend(0.0).to_array()
        }
    }

    /// `(a, b, c, e)` such that a depth-buffer value `d` lies at view distance
    /// `|(a d + b) / (c d + e)|`: rows z and w of the inverse projection. Off-centre and
    /// jittered projections keep x and y out of those rows.
    pub(crate) fn depth_to_view(&self) -> [f32; 4] {
        let inv = self.projection.inverse();
        let (row_z, row_w) = (inv.row(2), inv.row(3));
        [row_z.z, row_z.w, row_w.z, row_w.w]
    }

    /// Screen pixels per world unit at clip w = 1 for a target `height` pixels tall: divided by
    /// clip w (the view distance in perspective, 1 in orthographic), a world size in pixels.
    pub(crate) fn pixels_per_unit(&self, height: u32) -> f32 {
        self.projection.y_axis.y.abs() * height as f32 * 0.5
    }

    /// View distance of a clip depth (infinite for the far plane of an infinite projection).
    fn distance_at_depth(&self, depth: f32) -> f32 {
        let p = self.projection.inverse() * Vec4::new(0.0, 0.0, depth, 1.0);
        (p.z / p.w).abs()
    }

    /// The eight world-space corners of the view frustum from the near plane to `max_distance`
    /// (0: the far plane). An infinite far plane with no `max_distance` ends at `fallback_far`.
    pub fn frustum_corners(&self, max_distance: f32, fallback_far: f32) -> [Vec3; 8] {
        let (near, far) = self.distance_range(max_distance, fallback_far);
        self.frustum_slice(near, far)
    }

    /// The view distances of the near plane and of the far plane, or `max_distance` when that
    /// is nearer (0: no limit); an infinite far plane with no limit ends at `fallback_far`.
    pub fn distance_range(&self, max_distance: f32, fallback_far: f32) -> (f32, f32) {
        let (near_depth, far_depth) = self.depth_bounds();
        let near = self.distance_at_depth(near_depth);
        let mut far = self.distance_at_depth(far_depth);
        if max_distance > 0.0 {
            far = far.min(max_distance);
        }
        if !far.is_finite() {
            far = fallback_far;
        }
        (near, far.max(near))
    }

    fn depth_bounds(&self) -> (f32, f32) {
        match self.depth {
            DepthConvention::Standard => (0.0, 1.0),
            DepthConvention::Reversed => (1.0, 0.0),
        }
    }

    /// The eight world-space corners of the part of the view frustum between view distances
    /// `near` and `far` (corner `i`: x side `i & 1`, y side `i & 2`, far end `i & 4`).
    pub fn frustum_slice(&self, near: f32, far: f32) -> [Vec3; 8] {
        let (near_depth, far_depth) = self.depth_bounds();
        let mid_depth = (near_depth + far_depth) * 0.5;
        let plane_near = self.distance_at_depth(near_depth);
        let mid = self.distance_at_depth(mid_depth);
        let inv_proj = self.projection.inverse();
        let to_world = self.view.inverse();
        let unproject = |x: f32, y: f32, depth: f32| {
            let p = inv_proj * Vec4::new(x, y, depth, 1.0);
            p.truncate() / p.w
        };
        let mut corners = [Vec3::ZERO; 8];
        for (i, c) in corners.iter_mut().enumerate() {
            let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
            let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
            // The corner's ray, through its near and middle points, at the wanted distance.
            let a = unproject(sx, sy, near_depth);
            let b = unproject(sx, sy, mid_depth);
            let d = if i & 4 == 0 { near } else { far };
            let t = if (mid - plane_near).abs() > 1e-30 {
                (d - plane_near) / (mid - plane_near)
            } else {
                0.0
            };
            *c = to_world.transform_point3(a + (b - a) * t);
        }
        corners
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn depth_to_view_inverts_perspective_and_orthographic_projections() {
        let view = Mat4::IDENTITY;
        let cases = [
            (
                glam::camera::rh::proj::directx::perspective(1.0, 1.5, 100.0, 0.1),
                DepthConvention::Reversed,
            ),
            (
                glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0),
                DepthConvention::Standard,
            ),
            (
                glam::camera::rh::proj::directx::orthographic(-4.0, 4.0, -3.0, 3.0, 0.5, 50.0),
                DepthConvention::Standard,
            ),
            (
                glam::camera::rh::proj::directx::perspective_infinite_reverse(1.0, 1.5, 0.1),
                DepthConvention::Reversed,
            ),
        ];
        for (projection, depth) in cases {
            let m = CameraMatrices {
                view,
                projection,
                depth,
            };
            let [a, b, c, e] = m.depth_to_view();
            for distance in [0.5f32, 3.0, 40.0] {
                let clip = projection * Vec4::new(0.3, -0.2, -distance, 1.0);
                let d = clip.z / clip.w;
                let back = ((a * d + b) / (c * d + e)).abs();
                assert!((back - distance).abs() < 1e-3 * distance, "{back} vs {distance}");
            }
        }
    }

    #[test]
    fn frustum_corners_match_a_cameras_and_stop_an_infinite_far_plane() {
        let camera = Camera::look_at(Vec3::new(1.0, 2.0, 5.0), Vec3::ZERO);
        let m = CameraMatrices::from_camera(&camera, 1.5);
        let corners = m.frustum_corners(20.0, 1e3);
        let expected = crate::light_space::frustum_corners(&camera, 1.5, 20.0);
        for (a, b) in corners.iter().zip(&expected) {
            assert!(a.distance(*b) < 1e-3 * (1.0 + b.length()), "{a} vs {b}");
        }
        let infinite = CameraMatrices {
            projection: glam::camera::rh::proj::directx::perspective_infinite_reverse(1.0, 1.5, 0.1),
            ..m
        };
        let corners = infinite.frustum_corners(0.0, 50.0);
        assert!(corners.iter().all(|c| c.is_finite()));
        let eye = camera.eye;
        let farthest = corners
            .iter()
            .map(|c| (*c - eye).dot(camera.forward()))
            .fold(0.0, f32::max);
        assert!((farthest - 50.0).abs() < 0.05, "{farthest}");
    }

    #[test]
    fn orthographic_is_told_from_perspective() {
        let camera = Camera::look_at(Vec3::new(0.0, 2.0, 5.0), Vec3::ZERO);
        assert!(CameraMatrices::from_camera(&camera, 1.0).is_perspective());
        let ortho = CameraMatrices {
            view: camera.view(),
            projection: glam::camera::rh::proj::directx::orthographic(-1.0, 1.0, -1.0, 1.0, 0.1, 10.0),
            depth: DepthConvention::Standard,
        };
        assert!(!ortho.is_perspective());
        assert!(ortho.backward().distance(-camera.forward()) < 1e-5);
    }
}
