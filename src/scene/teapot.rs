//! The Utah teapot, tessellated from Newell's 32 bicubic Bezier patches.
//!
//! Evaluated in the patches' own z-up frame and turned y-up, with its bottom on y = 0, so it
//! stands on a floor at the origin. It is about 6.4 units long (spout to handle) and 3.15 tall.

use glam::{Vec2, Vec3};

use super::mesh::Mesh;
use super::teapot_data::{PATCHES, POINTS};

/// Tessellation levels accepted by [`teapot`].
pub const TESSELLATION_RANGE: std::ops::RangeInclusive<u32> = 1..=64;

/// Cubic Bernstein weights and their derivatives at `t`.
fn bernstein(t: f32) -> ([f32; 4], [f32; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
    )
}

/// z-up patch coordinates to the library's y-up frame (a rotation, so orientation is kept).
fn to_y_up(p: [f32; 3]) -> Vec3 {
    Vec3::new(p[0], p[2], -p[1])
}

/// Position and the two partial derivatives of patch control net `cp` at (u, v):
/// u runs along a row of four control points, v across the rows.
fn evaluate(cp: &[Vec3; 16], u: f32, v: f32) -> (Vec3, Vec3, Vec3) {
    let (bu, du) = bernstein(u);
    let (bv, dv) = bernstein(v);
    let (mut p, mut pu, mut pv) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for row in 0..4 {
        for col in 0..4 {
            let c = cp[row * 4 + col];
            p += c * bu[col] * bv[row];
            pu += c * du[col] * bv[row];
            pv += c * bu[col] * dv[row];
        }
    }
    (p, pu, pv)
}

/// The outward unit normal at (u, v). Where the patch is degenerate (the lid's and the
/// bottom's poles, where a whole row of control points coincides) the cross product of the
/// derivatives vanishes; the normal is then taken a small step into the patch, which is the
/// limit of the normal at the pole.
fn normal_at(cp: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    const STEP: f32 = 1e-3;
    // A derivative shorter than this (relative to the patch's size) is roundoff, not a direction.
    let size = cp
        .iter()
        .fold(Vec3::ZERO, |m, p| m.max((*p - cp[0]).abs()))
        .length();
    let min_derivative = size * 1e-4;
    let nudge = |t: f32| if t < 0.5 { t + STEP } else { t - STEP };
    for (uu, vv) in [(u, v), (u, nudge(v)), (nudge(u), v), (nudge(u), nudge(v))] {
        let (_, pu, pv) = evaluate(cp, uu, vv);
        let n = pu.cross(pv);
        if pu.length() > min_derivative && pv.length() > min_derivative && n.length() > 1e-12 {
            return n.normalize();
        }
    }
    Vec3::Y
}

/// The teapot with `level` x `level` quads per patch (clamped to [`TESSELLATION_RANGE`]):
/// 32 (level+1)^2 vertices and 64 level^2 triangles.
pub fn teapot(level: u32) -> Mesh {
    let level = level.clamp(*TESSELLATION_RANGE.start(), *TESSELLATION_RANGE.end());
    let side = level + 1;
    let mut positions = Vec::with_capacity(PATCHES.len() * (side * side) as usize);
    let mut normals = Vec::with_capacity(positions.capacity());
    let mut uvs = Vec::with_capacity(positions.capacity());
    let mut indices = Vec::with_capacity(PATCHES.len() * (level * level * 6) as usize);
    for patch in &PATCHES {
        let cp: [Vec3; 16] = patch.map(|i| to_y_up(POINTS[i as usize]));
        let base = positions.len() as u32;
        for j in 0..side {
            for i in 0..side {
                let (u, v) = (i as f32 / level as f32, j as f32 / level as f32);
                positions.push(evaluate(&cp, u, v).0);
                normals.push(normal_at(&cp, u, v));
                uvs.push(Vec2::new(u, v));
            }
        }
        for j in 0..level {
            for i in 0..level {
                let a = base + j * side + i;
                let (b, c, d) = (a + 1, a + side, a + side + 1);
                // Counter-clockwise around d(P)/du x d(P)/dv, the outward normal.
                indices.extend_from_slice(&[a, b, c, b, d, c]);
            }
        }
    }
    Mesh::new("teapot", positions, Some(normals), Some(uvs), indices)
        .expect("the teapot tessellation is consistent")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_follow_the_level() {
        let m = teapot(4);
        assert_eq!(m.vertex_count(), 32 * 25);
        assert_eq!(m.triangle_count(), 32 * 32);
        assert_eq!(teapot(0).triangle_count(), 64, "level is clamped to at least 1");
    }

    #[test]
    fn normals_are_finite_unit_and_poles_point_along_the_axis() {
        let m = teapot(8);
        for (n, s) in m.normals.iter().zip(&m.smoothed_normals) {
            assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-4, "{n}");
            assert!(s.is_finite() && (s.length() - 1.0).abs() < 1e-4, "{s}");
        }
        // Lid pole (top of the knob) points up, bottom pole points down.
        for (p, n) in m.positions.iter().zip(&m.normals) {
            if p.x.abs() < 1e-6 && p.z.abs() < 1e-6 {
                if (p.y - 3.15).abs() < 1e-4 {
                    assert!(n.y > 0.999, "knob pole normal {n}");
                } else if p.y.abs() < 1e-6 {
                    assert!(n.y < -0.999, "bottom pole normal {n}");
                }
            }
        }
    }

    #[test]
    fn normals_face_outward_and_winding_agrees() {
        let m = teapot(8);
        // Winding agrees with the normals on every non-degenerate triangle.
        for tri in m.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| m.positions[i as usize]);
            let face = (b - a).cross(c - a);
            if face.length() > 1e-7 {
                let avg: Vec3 = tri.iter().map(|&i| m.normals[i as usize]).sum();
                assert!(face.dot(avg) > 0.0, "triangle {tri:?} wound against its normals");
            }
        }
        // Outward: on each patch, the vertex farthest from the teapot's center has a
        // normal that points away from the center.
        let center = Vec3::new(0.0, 1.5, 0.0);
        let per_patch = m.vertex_count() / 32;
        for patch in 0..32 {
            let range = patch * per_patch..(patch + 1) * per_patch;
            let far = range
                .max_by(|&a, &b| {
                    let da = (m.positions[a] - center).length();
                    let db = (m.positions[b] - center).length();
                    da.total_cmp(&db)
                })
                .unwrap();
            let outward = (m.positions[far] - center).normalize();
            assert!(
                m.normals[far].dot(outward) > 0.0,
                "patch {patch}: normal {} at {} points inward",
                m.normals[far],
                m.positions[far]
            );
        }
        // The body as a whole encloses a positive volume with this winding.
        let volume: f32 = m
            .indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        assert!(volume > 20.0, "signed volume {volume}");
    }

    #[test]
    fn stands_on_the_floor() {
        let m = teapot(6);
        assert!(m.bounds.min.y.abs() < 1e-5);
        assert!((m.bounds.max.y - 3.15).abs() < 1e-3);
    }
}
