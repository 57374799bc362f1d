//! The smoothed normals a caster is fattened along and the way its triangles turn, from its
//! positions and indices alone (computed once a mesh, on the CPU).

use std::collections::HashMap;

use glam::Vec3;

use crate::bounds::Aabb;

/// Positions closer than this share of the bounding box's diagonal are welded into one for the
/// smoothed normals ([`crate::Mesh::WELD_TOLERANCE`]).
pub(crate) const WELD_TOLERANCE: f32 = 1e-5;

/// The geometric normal of a triangle scaled by nothing (unit length, or zero when degenerate).
pub(crate) fn face_normal(a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    (b - a).cross(c - a).normalize_or_zero()
}

/// Six times the volume the triangles enclose, signed by their winding (positive when
/// counter-clockwise seen from outside).
fn signed_volume(positions: &[Vec3], indices: &[u32]) -> f32 {
    indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
            a.dot(b.cross(c))
        })
        .sum()
}

/// Angle at `a` between edges to `b` and `c` (0 for degenerate edges).
fn corner_angle(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let (u, v) = ((b - a).normalize_or_zero(), (c - a).normalize_or_zero());
    if u == Vec3::ZERO || v == Vec3::ZERO {
        0.0
    } else {
        u.dot(v).clamp(-1.0, 1.0).acos()
    }
}

/// Groups vertices whose positions lie within the weld tolerance; returns each vertex's group.
fn weld_groups(positions: &[Vec3], bounds: Aabb) -> (Vec<u32>, usize) {
    let tolerance = (bounds.size().length() * WELD_TOLERANCE).max(f32::MIN_POSITIVE);
    let cell_of = |p: Vec3| {
        let c = ((p - bounds.min) / tolerance).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    };
    let mut cells: HashMap<(i64, i64, i64), Vec<(u32, Vec3)>> = HashMap::new();
    let mut group_of = Vec::with_capacity(positions.len());
    let mut groups = 0u32;
    for &p in positions {
        let (cx, cy, cz) = cell_of(p);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = cells.get(&(cx + dx, cy + dy, cz + dz)) {
                        for &(g, q) in list {
                            if (p - q).length() <= tolerance {
                                found = Some(g);
                                break 'search;
                            }
                        }
                    }
                }
            }
        }
        let g = found.unwrap_or_else(|| {
            let g = groups;
            groups += 1;
            cells.entry((cx, cy, cz)).or_default().push((g, p));
            g
        });
        group_of.push(g);
    }
    (group_of, groups as usize)
}

/// Angle-weighted average of the face normals around each welded position, given to every
/// vertex at that position. Independent of how faces are triangulated; a position with no
/// usable triangle (or whose normals cancel out) gets +Y.
///
/// Independent of the triangles' winding too: each face normal is turned to the side its
/// vertices' shading `normals` point to; without normals, all faces are turned so the mesh
/// encloses a positive volume (outward for a closed mesh, whichever way it is wound).
pub(crate) fn smoothed_normals(
    positions: &[Vec3],
    indices: &[u32],
    bounds: Aabb,
    normals: Option<&[Vec3]>,
) -> Vec<Vec3> {
    let (group_of, group_count) = weld_groups(positions, bounds);
    let mut sums = vec![Vec3::ZERO; group_count];
    let global_flip = normals.is_none() && signed_volume(positions, indices) < 0.0;
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| positions[i as usize]);
        let mut n = face_normal(a, b, c);
        if n == Vec3::ZERO {
            continue;
        }
        let flip = match normals {
            Some(ns) => {
                let shading: Vec3 = tri
                    .iter()
                    .map(|&i| ns[i as usize])
                    .filter(|v| v.is_finite())
                    .sum();
                n.dot(shading) < 0.0
            }
            None => global_flip,
        };
        if flip {
            n = -n;
        }
        let weights = [
            corner_angle(a, b, c),
            corner_angle(b, c, a),
            corner_angle(c, a, b),
        ];
        for (k, &i) in tri.iter().enumerate() {
            sums[group_of[i as usize] as usize] += n * weights[k];
        }
    }
    group_of
        .iter()
        .map(|&g| {
            let n = sums[g as usize].normalize_or_zero();
            if n == Vec3::ZERO { Vec3::Y } else { n }
        })
        .collect()
}

/// Which way a caster's triangles turn, seen from outside it (the side its smoothed normals
/// point to), or, for one draw, seen in a light-space pass's target
/// ([`crate::casters::Casters::draw`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum OutwardWinding {
    /// Counter-clockwise, every triangle.
    Ccw,
    /// Clockwise, every triangle.
    Cw,
    /// Some one way, some the other, or a triangle whose smoothed normals do not agree on its
    /// outside (a thin sheet's two sides welded together).
    Mixed,
}

/// The height of the thinnest triangle [`outward_winding`] counts, over its longest edge.
pub(crate) const SLIVER: f32 = 1e-4;

/// Which way `indices`' triangles turn seen from outside: a triangle is counter-clockwise when
/// its face normal (`(b - a) x (c - a)`) and the smoothed normals of its three vertices all
/// point to one side, clockwise when they all point to opposite sides. Triangles without an
/// area are passed over, as are slivers, thinner than [`SLIVER`] times their longest edge. The exit map keeps the faces turned away from the light by culling
/// when every triangle agrees, and tests each fragment otherwise (`passes::exit_map`).
pub(crate) fn outward_winding(positions: &[Vec3], indices: &[u32], smoothed: &[Vec3]) -> OutwardWinding {
    let (mut ccw, mut cw) = (false, false);
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        let longest = (b - a)
            .length_squared()
            .max((c - a).length_squared())
            .max((c - b).length_squared());
        // Slivers (a sphere's or a teapot's pole: two corners a rounding error apart) turn
        // whichever way rounding says, cover next to no texel, and lie where their neighbours
        // draw.
        if !n.is_finite() || n.length() <= SLIVER * longest {
            continue;
        }
        let dots = [tri[0], tri[1], tri[2]].map(|i| n.dot(smoothed[i as usize]));
        if dots.iter().all(|d| *d > 0.0) {
            ccw = true;
        } else if dots.iter().all(|d| *d < 0.0) {
            cw = true;
        } else {
            return OutwardWinding::Mixed;
        }
        if ccw && cw {
            return OutwardWinding::Mixed;
        }
    }
    if cw {
        OutwardWinding::Cw
    } else {
        OutwardWinding::Ccw
    }
}
