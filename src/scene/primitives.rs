//! Built-in shapes: boxes, spheres, capsules, cylinders and floors.
//!
//! All are centered at the origin, wound counter-clockwise seen from outside, with
//! analytic normals and UVs.

use std::f32::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::mesh::Mesh;

/// Builds a mesh from generated data that is valid by construction.
fn build(name: &str, positions: Vec<Vec3>, normals: Vec<Vec3>, uvs: Vec<Vec2>, indices: Vec<u32>) -> Mesh {
    Mesh::new(name, positions, Some(normals), Some(uvs), indices)
        .expect("built-in primitive data is consistent")
}

/// A box with the given edge lengths and split (per-face) normals: 24 vertices.
pub fn cuboid(size: Vec3) -> Mesh {
    let h = size.abs() * 0.5;
    let mut positions = Vec::with_capacity(24);
    let mut normals = Vec::with_capacity(24);
    let mut uvs = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(36);
    // (normal, u axis, v axis) with u x v = normal.
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    for (n, u, v) in faces {
        let base = positions.len() as u32;
        for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            positions.push((n + u * su + v * sv) * h);
            normals.push(n);
            uvs.push(Vec2::new((su + 1.0) * 0.5, (1.0 - sv) * 0.5));
        }
        indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    build("box", positions, normals, uvs, indices)
}

/// A floor: a square of side `size` on the plane y = 0 facing +Y, UVs repeating `uv_repeat` times.
pub fn plane(size: f32, uv_repeat: f32) -> Mesh {
    let h = size * 0.5;
    let positions = vec![
        Vec3::new(-h, 0.0, h),
        Vec3::new(h, 0.0, h),
        Vec3::new(h, 0.0, -h),
        Vec3::new(-h, 0.0, -h),
    ];
    let uvs = vec![
        Vec2::new(0.0, uv_repeat),
        Vec2::new(uv_repeat, uv_repeat),
        Vec2::new(uv_repeat, 0.0),
        Vec2::new(0.0, 0.0),
    ];
    build("plane", positions, vec![Vec3::Y; 4], uvs, vec![0, 1, 2, 0, 2, 3])
}

/// A surface of revolution about +Y from a profile of (radius, height) points with their
/// profile normals (radial, vertical), listed bottom to top.
fn lathe(name: &str, profile: &[(Vec2, Vec2)], segments: u32) -> Mesh {
    let segments = segments.max(3);
    let rings = profile.len() as u32;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for (i, &(p, n)) in profile.iter().enumerate() {
        for j in 0..=segments {
            let theta = TAU * j as f32 / segments as f32;
            let (s, c) = theta.sin_cos();
            positions.push(Vec3::new(p.x * c, p.y, p.x * s));
            normals.push(Vec3::new(n.x * c, n.y, n.x * s).normalize_or_zero());
            uvs.push(Vec2::new(
                j as f32 / segments as f32,
                1.0 - i as f32 / (rings - 1).max(1) as f32,
            ));
        }
    }
    let row = segments + 1;
    let mut indices = Vec::new();
    for i in 0..rings.saturating_sub(1) {
        for j in 0..segments {
            let a = i * row + j;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    build(name, positions, normals, uvs, indices)
}

/// A UV sphere.
pub fn sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
    let rings = rings.max(2);
    let profile: Vec<(Vec2, Vec2)> = (0..=rings)
        .map(|i| {
            let phi = -PI / 2.0 + PI * i as f32 / rings as f32;
            let n = Vec2::new(phi.cos(), phi.sin());
            (n * radius, n)
        })
        .collect();
    lathe("sphere", &profile, segments)
}

/// A capsule along +Y: a cylinder of `length` between two hemispheres of `radius`
/// (total height `length + 2 radius`), centered at the origin.
pub fn capsule(radius: f32, length: f32, segments: u32) -> Mesh {
    let cap_rings = (segments / 4).max(2);
    let mut profile = Vec::new();
    for i in 0..=cap_rings {
        let phi = -PI / 2.0 + PI / 2.0 * i as f32 / cap_rings as f32;
        let n = Vec2::new(phi.cos(), phi.sin());
        profile.push((n * radius - Vec2::new(0.0, length * 0.5), n));
    }
    for i in 0..=cap_rings {
        let phi = PI / 2.0 * i as f32 / cap_rings as f32;
        let n = Vec2::new(phi.cos(), phi.sin());
        profile.push((n * radius + Vec2::new(0.0, length * 0.5), n));
    }
    lathe("capsule", &profile, segments)
}

/// A closed cylinder along +Y of the given radius and height, centered at the origin,
/// with flat caps (split normals at the rims).
pub fn cylinder(radius: f32, height: f32, segments: u32) -> Mesh {
    let h = height * 0.5;
    let profile = [
        (Vec2::new(0.0, -h), Vec2::NEG_Y),
        (Vec2::new(radius, -h), Vec2::NEG_Y),
        (Vec2::new(radius, -h), Vec2::X),
        (Vec2::new(radius, h), Vec2::X),
        (Vec2::new(radius, h), Vec2::Y),
        (Vec2::new(0.0, h), Vec2::Y),
    ];
    lathe("cylinder", &profile, segments)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle's winding agrees with its vertices' normals, and the signed volume is
    /// positive (closed, outward-facing shapes).
    fn assert_outward(mesh: &Mesh, expected_volume: f32) {
        let mut volume = 0.0;
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| mesh.positions[i as usize]);
            let face = (b - a).cross(c - a);
            volume += a.dot(b.cross(c)) / 6.0;
            if face.length() > 1e-9 {
                let avg: Vec3 = tri.iter().map(|&i| mesh.normals[i as usize]).sum();
                assert!(
                    face.dot(avg) > 0.0,
                    "{}: triangle wound against its normals",
                    mesh.name
                );
            }
        }
        assert!(
            (volume - expected_volume).abs() < expected_volume * 0.05,
            "{}: volume {volume} expected {expected_volume}",
            mesh.name
        );
    }

    #[test]
    fn primitives_are_closed_and_outward() {
        assert_outward(&cuboid(Vec3::new(1.0, 2.0, 3.0)), 6.0);
        assert_outward(&sphere(1.0, 48, 24), 4.0 / 3.0 * PI);
        assert_outward(&capsule(0.5, 1.0, 48), PI * 0.25 * 1.0 + 4.0 / 3.0 * PI * 0.125);
        assert_outward(&cylinder(1.0, 2.0, 64), 2.0 * PI);
    }

    #[test]
    fn plane_faces_up() {
        let p = plane(4.0, 1.0);
        let [a, b, c] = [0, 1, 2].map(|i| p.positions[p.indices[i] as usize]);
        assert!((b - a).cross(c - a).normalize().dot(Vec3::Y) > 0.999);
        assert_eq!(p.bounds.size(), Vec3::new(4.0, 0.0, 4.0));
    }
}
