//! Clipping boxes against a light's frustum: the depth range the scene takes in it, and
//! whether a caster's box can reach a tile.

use crate::bounds::Aabb;
#[cfg(test)]
use crate::camera::Camera;
use glam::{Mat4, Vec3, Vec4};

/// The eight world-space corners of the camera's frustum from its near plane to
#[cfg(test)]
/// `max_distance` (0: its far plane).
pub(crate) fn frustum_corners(camera: &Camera, aspect: f32, max_distance: f32) -> [Vec3; 8] {
    let far = if max_distance > 0.0 {
        camera.far.min(max_distance)
    } else {
        camera.far
    }
    .max(camera.near);
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let tan_x = tan_y * aspect.max(1e-6);
    let to_world = camera.view().inverse();
    let mut corners = [Vec3::ZERO; 8];
    for (i, c) in corners.iter_mut().enumerate() {
        let d = if i & 4 == 0 { camera.near } else { far };
        let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
        let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
        *c = to_world.transform_point3(Vec3::new(sx * tan_x * d, sy * tan_y * d, -d));
    }
    corners
}

/// The faces of a box by its corners' indices (corner `i`: x side `i & 1`, y side `i & 2`, z
/// side `i & 4`).
const FACES: [[usize; 4]; 6] = [
    [0, 2, 6, 4],
    [1, 3, 7, 5],
    [0, 1, 5, 4],
    [2, 3, 7, 6],
    [0, 1, 3, 2],
    [4, 5, 7, 6],
];

/// Depth range (distance along the view's -z) of the parts of `parts` (world boxes; empty:
/// `bounds` alone) on the inner side of every plane (view space, inside where
/// `dot(plane.xyz, p) + plane.w >= 0`). When nothing is inside, the range of `bounds`' corners.
pub(super) fn clipped_depth_range(view: &Mat4, bounds: &Aabb, parts: &[Aabb], planes: &[Vec4]) -> (f32, f32) {
    let parts = if parts.is_empty() {
        std::slice::from_ref(bounds)
    } else {
        parts
    };
    let (near, far) = parts
        .iter()
        .filter_map(|part| clipped_part_range(view, part, planes))
        .fold((f32::MAX, f32::MIN), |(n, f), (a, b)| (n.min(a), f.max(b)));
    if near <= far {
        return (near, far);
    }
    let depths = bounds.corners().map(|c| -view.transform_point3(c).z);
    (
        depths.iter().cloned().fold(f32::MAX, f32::min),
        depths.iter().cloned().fold(f32::MIN, f32::max),
    )
}

/// Depth range of the part of the box `part` on the inner side of every plane, `None` where
/// none of it is. Each face is clipped one plane at a time (Sutherland-Hodgman); the extremes
/// of a clipped box lie on its clipped faces.
pub(super) fn clipped_part_range(view: &Mat4, part: &Aabb, planes: &[Vec4]) -> Option<(f32, f32)> {
    let corners = part.corners().map(|c| view.transform_point3(c));
    let (mut near, mut far) = (f32::MAX, f32::MIN);
    for face in FACES {
        let mut polygon: Vec<Vec3> = face.iter().map(|&i| corners[i]).collect();
        for plane in planes {
            polygon = clip_polygon(&polygon, *plane);
            if polygon.is_empty() {
                break;
            }
        }
        for p in &polygon {
            near = near.min(-p.z);
            far = far.max(-p.z);
        }
    }
    (near <= far).then_some((near, far))
}

/// The part of a convex polygon on the inner side of `plane`.
pub(super) fn clip_polygon(polygon: &[Vec3], plane: Vec4) -> Vec<Vec3> {
    let side = |p: Vec3| plane.truncate().dot(p) + plane.w;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        let (da, db) = (side(a), side(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// Whether the box `b`, grown by `margin` on every side, reaches into the clip volume of
/// `view_projection` (x and y in [-w, w], depth in [0, w]): false only when all its corners lie
/// beyond one plane, so a draw culled by it can miss nothing.
pub(crate) fn box_reaches_clip(view_projection: &glam::Mat4, b: &crate::bounds::Aabb, margin: f32) -> bool {
    if b.is_empty() {
        return false;
    }
    let m = glam::Vec3::splat(margin);
    let clip = crate::bounds::Aabb::new(b.min - m, b.max + m)
        .corners()
        .map(|c| *view_projection * c.extend(1.0));
    let beyond = |f: &dyn Fn(&glam::Vec4) -> bool| clip.iter().all(f);
    !(beyond(&|c| c.x < -c.w)
        || beyond(&|c| c.x > c.w)
        || beyond(&|c| c.y < -c.w)
        || beyond(&|c| c.y > c.w)
        || beyond(&|c| c.z < 0.0)
        || beyond(&|c| c.z > c.w))
}
