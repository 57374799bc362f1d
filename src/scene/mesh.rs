//! Triangle meshes with the per-position *smoothed normal* the fattening pass needs.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};

use crate::bounds::Aabb;
use crate::casters::normals::smoothed_normals;
use crate::error::{PenumbraError, Result};

/// An indexed triangle mesh, ready for upload.
///
/// Invariants established by [`Mesh::new`]: all four attribute arrays have one entry per
/// vertex, every index is in range, the index count is a multiple of three, positions are
/// finite, and `normals` / `smoothed_normals` are unit length.
///
/// ```
/// # fn main() -> penumbra::Result<()> {
/// use glam::{Vec2, Vec3};
/// use penumbra::Mesh;
///
/// // A unit square on y = 0, counter-clockwise seen from above, with a UV per corner.
/// let positions = vec![
///     Vec3::ZERO,
///     Vec3::X,
///     Vec3::new(1.0, 0.0, -1.0),
///     Vec3::NEG_Z,
/// ];
/// let uvs = vec![Vec2::new(0.0, 1.0), Vec2::ONE, Vec2::X, Vec2::ZERO];
/// // No normals given: they are computed from the triangles.
/// let tile = Mesh::new("tile", positions, None, Some(uvs.clone()), vec![0, 1, 2, 0, 2, 3])?
///     // The same UVs serve as its lightmap UVs (the second set).
///     .with_lightmap_uvs(uvs)?;
///
/// assert_eq!((tile.vertex_count(), tile.triangle_count()), (4, 2));
/// assert!(tile.normals.iter().all(|n| (*n - Vec3::Y).length() < 1e-6));
/// assert_eq!(tile.bounds.min, Vec3::new(0.0, 0.0, -1.0));
/// assert_eq!(tile.bounds.max, Vec3::X);
///
/// // Bad input is an error, not a panic: index 3 does not exist in a 3-vertex mesh.
/// assert!(Mesh::new("broken", vec![Vec3::ZERO; 3], None, None, vec![0, 1, 3]).is_err());
/// # Ok(()) }
/// ```
#[derive(Debug, Clone)]
pub struct Mesh {
    /// A name for messages, and what lightmap rectangles ([`crate::LightmapRect::mesh`]) match:
    /// a glTF mesh's or OBJ object's name, or a scene file's mesh entry name for a built-in.
    pub name: String,
    /// Vertex positions in the mesh's own model space, finite.
    pub positions: Vec<Vec3>,
    /// Shading normals, one per vertex (may differ between vertices at one position: hard edges).
    pub normals: Vec<Vec3>,
    /// The first UV set (glTF `TEXCOORD_0`), which material textures are read with: one per
    /// vertex, in texture space (v down, as glTF; the OBJ loader flips its v). Zero where the
    /// input had none.
    pub uvs: Vec<Vec2>,
    /// The second UV set (glTF `TEXCOORD_1`), which lightmaps are sampled with: one per vertex,
    /// or empty when the mesh has none (see [`Mesh::with_lightmap_uvs`]).
    pub lightmap_uvs: Vec<Vec2>,
    /// Vertex colours (glTF `COLOR_0`, linear RGBA), multiplying the material's base colour:
    /// one per vertex, or empty when the mesh has none (white).
    pub colors: Vec<Vec4>,
    /// Tangents for normal maps (glTF `TANGENT`: xyz the tangent, w the bitangent's sign, +-1):
    /// one per vertex, or empty when the mesh has none (see [`Mesh::with_tangents`] and
    /// [`Mesh::with_generated_tangents`]).
    pub tangents: Vec<Vec4>,
    /// One averaged normal per *position*: all vertices that share a position (within
    /// [`Mesh::WELD_TOLERANCE`]) have the same smoothed normal, so displacing along it never
    /// tears the mesh open at hard edges.
    pub smoothed_normals: Vec<Vec3>,
    /// A triangle list: three indices into the vertex arrays per triangle. Counter-clockwise is
    /// the front (wgpu's default), which matters where the shadow pass culls faces
    /// ([`crate::ShadowMapSettings::cull_mode`]).
    pub indices: Vec<u32>,
    /// The box around `positions` in model space, computed by [`Mesh::new`] (editing
    /// `positions` afterwards does not update it).
    pub bounds: Aabb,
}

/// What [`Mesh::new`] had to fix in its input, for callers who want to report it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeshRepairs {
    /// Normals that were NaN, infinite or zero length and were replaced.
    pub repaired_normals: usize,
    /// True when the input had no normals and all were computed.
    pub computed_normals: bool,
}

impl Mesh {
    /// Relative tolerance (times the bounding box diagonal) within which two vertices count as
    /// one position for the smoothed normal.
    pub const WELD_TOLERANCE: f32 = crate::casters::normals::WELD_TOLERANCE;

    /// Builds a mesh, validating indices and computing what is missing.
    ///
    /// * `normals`: `None` computes them (angle-weighted, smooth across shared positions);
    ///   NaN or zero-length entries are repaired the same way.
    /// * `uvs`: `None` fills zeros.
    ///
    /// Errors when an index is out of range, the index count is not a multiple of 3, an
    /// attribute array has the wrong length, or a position is not finite.
    pub fn new(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        indices: Vec<u32>,
    ) -> Result<Mesh> {
        Self::new_with_report(name, positions, normals, uvs, indices).map(|(mesh, _)| mesh)
    }

    /// As [`Mesh::new`], also saying what was repaired.
    pub fn new_with_report(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        indices: Vec<u32>,
    ) -> Result<(Mesh, MeshRepairs)> {
        let name = name.into();
        let n = positions.len();
        let bad = |reason: String| PenumbraError::Scene(format!("mesh `{name}`: {reason}"));
        if !indices.len().is_multiple_of(3) {
            return Err(bad(format!(
                "index count {} is not a multiple of 3",
                indices.len()
            )));
        }
        if let Some(i) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(bad(format!(
                "index {i} is out of range (the mesh has {n} vertices)"
            )));
        }
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(bad(format!("position {i} is not finite")));
        }
        if let Some(ns) = &normals
            && ns.len() != n
        {
            return Err(bad(format!("{} normals for {n} positions", ns.len())));
        }
        if let Some(uv) = &uvs
            && uv.len() != n
        {
            return Err(bad(format!("{} uvs for {n} positions", uv.len())));
        }

        let bounds = Aabb::from_points(positions.iter());
        let smoothed_normals = smoothed_normals(&positions, &indices, bounds, normals.as_deref());
        let mut repairs = MeshRepairs::default();
        let normals = match normals {
            Some(mut ns) => {
                for (normal, smooth) in ns.iter_mut().zip(&smoothed_normals) {
                    let len = normal.length();
                    if len.is_finite() && len > 1e-12 {
                        *normal /= len;
                    } else {
                        *normal = *smooth;
                        repairs.repaired_normals += 1;
                    }
                }
                ns
            }
            None => {
                repairs.computed_normals = true;
                smoothed_normals.clone()
            }
        };
        let uvs = uvs
            .map(|uv| {
                uv.into_iter()
                    .map(|t| if t.is_finite() { t } else { Vec2::ZERO })
                    .collect()
            })
            .unwrap_or_else(|| vec![Vec2::ZERO; n]);
        Ok((
            Mesh {
                name,
                positions,
                normals,
                uvs,
                lightmap_uvs: Vec::new(),
                colors: Vec::new(),
                tangents: Vec::new(),
                smoothed_normals,
                indices,
                bounds,
            },
            repairs,
        ))
    }

    /// The mesh with a second UV set for lightmaps, one per vertex (non-finite entries become
    /// zero). Errors when the count differs from the vertex count.
    pub fn with_lightmap_uvs(mut self, uvs: Vec<Vec2>) -> Result<Mesh> {
        if uvs.len() != self.positions.len() {
            return Err(PenumbraError::Scene(format!(
                "mesh `{}`: {} lightmap uvs for {} positions",
                self.name,
                uvs.len(),
                self.positions.len()
            )));
        }
        self.lightmap_uvs = uvs
            .into_iter()
            .map(|t| if t.is_finite() { t } else { Vec2::ZERO })
            .collect();
        Ok(self)
    }

    /// The number of vertices: entries in each per-vertex array.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// The mesh with vertex colours (linear RGBA), one per vertex; non-finite entries become
    /// white. Errors when the count differs from the vertex count.
    pub fn with_colors(mut self, colors: Vec<Vec4>) -> Result<Mesh> {
        self.check_count("vertex colours", colors.len())?;
        self.colors = colors
            .into_iter()
            .map(|c| if c.is_finite() { c } else { Vec4::ONE })
            .collect();
        Ok(self)
    }

    /// The mesh with tangents (xyz the tangent, w the bitangent's sign), one per vertex.
    /// Tangents that are not finite, have no length or lie along the normal are replaced by
    /// generated ones. Errors when the count differs from the vertex count.
    pub fn with_tangents(mut self, tangents: Vec<Vec4>) -> Result<Mesh> {
        self.check_count("tangents", tangents.len())?;
        let usable = |(t, n): (&Vec4, &Vec3)| {
            let xyz = t.truncate();
            t.is_finite() && xyz.length() > 1e-6 && xyz.normalize().dot(*n).abs() < 0.999
        };
        if !tangents.iter().zip(&self.normals).all(usable) {
            let generated = generated_tangents(&self);
            self.tangents = tangents
                .iter()
                .zip(&self.normals)
                .zip(&generated)
                .map(|((t, n), g)| if usable((t, n)) { *t } else { *g })
                .collect();
            return Ok(self);
        }
        self.tangents = tangents
            .into_iter()
            .map(|t| {
                t.truncate()
                    .normalize()
                    .extend(if t.w < 0.0 { -1.0 } else { 1.0 })
            })
            .collect();
        Ok(self)
    }

    /// The mesh with MikkTSpace tangents from its positions, normals and first UV set (what
    /// normal maps are baked against). A vertex the algorithm leaves without one (a degenerate
    /// triangle alone) gets a tangent perpendicular to its normal.
    pub fn with_generated_tangents(mut self) -> Mesh {
        self.tangents = generated_tangents(&self);
        self
    }

    fn check_count(&self, what: &str, count: usize) -> Result<()> {
        if count != self.positions.len() {
            return Err(PenumbraError::Scene(format!(
                "mesh `{}`: {count} {what} for {} positions",
                self.name,
                self.positions.len()
            )));
        }
        Ok(())
    }

    /// The number of triangles, `indices.len() / 3`.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// This mesh with `m` applied to positions and normals (normals by the inverse transpose).
    /// Smoothed normals and bounds are recomputed.
    pub fn transformed(&self, m: &Mat4) -> Result<Mesh> {
        let normal_matrix = Mat3::from_mat4(*m).inverse().transpose();
        let flip = m.determinant() < 0.0;
        let positions = self.positions.iter().map(|p| m.transform_point3(*p)).collect();
        let normals = self
            .normals
            .iter()
            .map(|n| (normal_matrix * *n).normalize_or_zero())
            .collect();
        let mut indices = self.indices.clone();
        if flip {
            for tri in indices.chunks_exact_mut(3) {
                tri.swap(1, 2);
            }
        }
        let mut mesh = Mesh::new(
            self.name.clone(),
            positions,
            Some(normals),
            Some(self.uvs.clone()),
            indices,
        )?;
        if !self.lightmap_uvs.is_empty() {
            mesh = mesh.with_lightmap_uvs(self.lightmap_uvs.clone())?;
        }
        if !self.colors.is_empty() {
            mesh = mesh.with_colors(self.colors.clone())?;
        }
        if !self.tangents.is_empty() {
            // Tangents turn with the surface; a mirroring transform flips the bitangent's side.
            let linear = Mat3::from_mat4(*m);
            let sign = if flip { -1.0 } else { 1.0 };
            let tangents = self
                .tangents
                .iter()
                .map(|t| (linear * t.truncate()).normalize_or_zero().extend(t.w * sign))
                .collect();
            mesh = mesh.with_tangents(tangents)?;
        }
        Ok(mesh)
    }

    /// Concatenates several meshes into one (their vertices stay separate). Lightmap UVs,
    /// vertex colours and tangents are kept where every part has them; colours where only some
    /// parts have them (the others white). Lightmap UVs or tangents on only some parts are an
    /// error naming a part without them: there is nothing to give the others.
    pub fn merge(name: impl Into<String>, parts: &[Mesh]) -> Result<Mesh> {
        let name = name.into();
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        let mut indices = Vec::new();
        for part in parts {
            let base = positions.len() as u32;
            positions.extend_from_slice(&part.positions);
            normals.extend_from_slice(&part.normals);
            uvs.extend_from_slice(&part.uvs);
            indices.extend(part.indices.iter().map(|i| i + base));
        }
        let mut mesh = Mesh::new(name.clone(), positions, Some(normals), Some(uvs), indices)?;
        // Every part's values of one attribute, `None` when no part has it.
        let all_or_none = |what: &str, has: fn(&Mesh) -> bool| -> Result<bool> {
            match parts.iter().find(|p| !has(p)) {
                Some(_) if !parts.iter().any(has) => Ok(false),
                Some(without) => Err(PenumbraError::Scene(format!(
                    "merging into mesh `{name}`: some parts have {what} and `{}` has none",
                    without.name
                ))),
                None => Ok(!parts.is_empty()),
            }
        };
        if all_or_none("lightmap uvs", |p| !p.lightmap_uvs.is_empty())? {
            mesh = mesh.with_lightmap_uvs(
                parts
                    .iter()
                    .flat_map(|p| p.lightmap_uvs.iter().copied())
                    .collect(),
            )?;
        }
        if all_or_none("tangents", |p| !p.tangents.is_empty())? {
            mesh = mesh.with_tangents(parts.iter().flat_map(|p| p.tangents.iter().copied()).collect())?;
        }
        if parts.iter().any(|p| !p.colors.is_empty()) {
            let colors = parts.iter().flat_map(|p| {
                let white = std::iter::repeat_n(Vec4::ONE, p.positions.len());
                if p.colors.is_empty() {
                    white.collect::<Vec<_>>()
                } else {
                    p.colors.clone()
                }
            });
            mesh = mesh.with_colors(colors.collect())?;
        }
        Ok(mesh)
    }
}

/// MikkTSpace tangents of `mesh`, one per vertex (see [`Mesh::with_generated_tangents`]).
#[cfg(feature = "renderer")]
fn generated_tangents(mesh: &Mesh) -> Vec<Vec4> {
    struct Faces<'a> {
        mesh: &'a Mesh,
        tangents: Vec<Option<Vec4>>,
    }
    impl Faces<'_> {
        fn vertex(&self, face: usize, vert: usize) -> usize {
            self.mesh.indices[face * 3 + vert] as usize
        }
    }
    impl bevy_mikktspace::Geometry for Faces<'_> {
        fn num_faces(&self) -> usize {
            self.mesh.indices.len() / 3
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.mesh.positions[self.vertex(face, vert)].to_array()
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.mesh.normals[self.vertex(face, vert)].to_array()
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            self.mesh.uvs[self.vertex(face, vert)].to_array()
        }
        fn set_tangent(&mut self, space: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
            let v = self.vertex(face, vert);
            self.tangents[v] = space.map(|s| Vec4::from_array(s.tangent_encoded()));
        }
    }
    let mut faces = Faces {
        mesh,
        tangents: vec![None; mesh.positions.len()],
    };
    // It fails only on meshes it cannot index (none here: `Mesh::new` checked them); then
    // every vertex takes the fallback below.
    let _ = bevy_mikktspace::generate_tangents(&mut faces);
    faces
        .tangents
        .iter()
        .zip(&mesh.normals)
        .map(|(t, n)| match t {
            Some(t) if t.is_finite() && t.truncate().length() > 1e-6 => *t,
            _ => n.any_orthonormal_vector().extend(1.0),
        })
        .collect()
}

/// Without the convenience layer (no MikkTSpace crate): a tangent perpendicular to each normal.
#[cfg(not(feature = "renderer"))]
fn generated_tangents(mesh: &Mesh) -> Vec<Vec4> {
    mesh.normals
        .iter()
        .map(|n| n.any_orthonormal_vector().extend(1.0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    use crate::casters::normals::{OutwardWinding, face_normal, outward_winding};
    use crate::scene::primitives;

    /// A unit quad in the xz plane with every optional attribute: lightmap uvs, red colours,
    /// tangents along +x with the bitangent on the +1 side.
    fn dressed_quad() -> Mesh {
        let quad = primitives::plane(1.0, 1.0);
        let n = quad.vertex_count();
        quad.with_lightmap_uvs(vec![Vec2::new(0.25, 0.75); n])
            .unwrap()
            .with_colors(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n])
            .unwrap()
            .with_tangents(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n])
            .unwrap()
    }

    #[test]
    fn outward_winding_follows_the_triangles_and_their_smoothed_normals() {
        let sphere = primitives::sphere(1.0, 16, 8);
        let winding = |indices: &[u32]| outward_winding(&sphere.positions, indices, &sphere.smoothed_normals);
        assert_eq!(winding(&sphere.indices), OutwardWinding::Ccw);
        // Its poles' slivers are passed over, and the teapot's.
        let teapot = crate::scene::teapot::teapot(12);
        assert_eq!(
            outward_winding(&teapot.positions, &teapot.indices, &teapot.smoothed_normals),
            OutwardWinding::Ccw
        );
        let reversed: Vec<u32> = sphere
            .indices
            .chunks_exact(3)
            .flat_map(|t| [t[0], t[2], t[1]])
            .collect();
        assert_eq!(winding(&reversed), OutwardWinding::Cw);
        // One triangle at the equator turned the other way.
        let mut one = sphere.indices.clone();
        let k = sphere.indices.len() / 6 * 3;
        one[k..k + 3].copy_from_slice(&reversed[k..k + 3]);
        assert_eq!(winding(&one), OutwardWinding::Mixed);
        // A sheet whose two sides share positions: its smoothed normals cancel to +Y, which
        // one side's triangles agree with and the other's not.
        let plane = primitives::plane(1.0, 1.0);
        let both: Vec<u32> = plane
            .indices
            .iter()
            .copied()
            .chain(plane.indices.chunks_exact(3).flat_map(|t| [t[0], t[2], t[1]]))
            .collect();
        let smoothed = smoothed_normals(&plane.positions, &both, plane.bounds, None);
        assert_eq!(
            outward_winding(&plane.positions, &both, &smoothed),
            OutwardWinding::Mixed
        );
    }

    #[test]
    fn transforming_a_mesh_keeps_its_lightmap_uvs_colours_and_tangents() {
        let quad = dressed_quad();
        let turned = quad
            .transformed(&Mat4::from_rotation_y(std::f32::consts::FRAC_PI_2))
            .unwrap();
        assert_eq!(turned.lightmap_uvs, quad.lightmap_uvs);
        assert_eq!(turned.colors, quad.colors);
        // +x turned a quarter about y is -z.
        for t in &turned.tangents {
            assert!((t.truncate() - Vec3::NEG_Z).length() < 1e-5 && t.w == 1.0, "{t}");
        }
        // A mirror keeps the tangent's direction where it is not mirrored and flips the
        // bitangent's side.
        let mirrored = quad
            .transformed(&Mat4::from_scale(Vec3::new(1.0, 1.0, -1.0)))
            .unwrap();
        assert!(mirrored.tangents.iter().all(|t| t.x == 1.0 && t.w == -1.0));
    }

    #[test]
    fn merging_keeps_what_every_part_has_fills_colours_and_refuses_half_given_uvs() {
        let dressed = dressed_quad();
        let plain = primitives::plane(1.0, 1.0);
        let both = Mesh::merge("both", &[dressed.clone(), dressed.clone()]).unwrap();
        assert_eq!(both.lightmap_uvs.len(), 2 * dressed.vertex_count());
        assert_eq!(both.tangents.len(), 2 * dressed.vertex_count());
        assert_eq!(both.colors.len(), 2 * dressed.vertex_count());
        // Colours on one part only: the other is white.
        let coloured = plain
            .clone()
            .with_colors(vec![Vec4::new(0.0, 0.0, 1.0, 1.0); plain.vertex_count()])
            .unwrap();
        let mixed = Mesh::merge("mixed", &[coloured, plain.clone()]).unwrap();
        let n = plain.vertex_count();
        assert!(
            mixed.colors[..n]
                .iter()
                .all(|c| *c == Vec4::new(0.0, 0.0, 1.0, 1.0))
        );
        assert!(mixed.colors[n..].iter().all(|c| *c == Vec4::ONE));
        assert!(mixed.lightmap_uvs.is_empty() && mixed.tangents.is_empty());
        // Lightmap uvs on one part only: an error naming the part without.
        let mut bare = plain.clone();
        bare.name = "bare".into();
        let error = Mesh::merge("half", &[dressed, bare]).unwrap_err().to_string();
        assert!(
            error.contains("lightmap uvs") && error.contains("`bare`"),
            "{error}"
        );
    }

    #[test]
    fn split_normal_cube_gets_one_smoothed_normal_per_corner() {
        let cube = primitives::cuboid(Vec3::splat(2.0));
        assert_eq!(cube.vertex_count(), 24, "the cube has split per-face vertices");
        let mut per_corner: HashMap<[i32; 3], Vec<Vec3>> = HashMap::new();
        for (p, s) in cube.positions.iter().zip(&cube.smoothed_normals) {
            per_corner
                .entry([p.x as i32, p.y as i32, p.z as i32])
                .or_default()
                .push(*s);
        }
        assert_eq!(per_corner.len(), 8);
        for (corner, normals) in per_corner {
            assert_eq!(normals.len(), 3);
            let expected = Vec3::new(corner[0] as f32, corner[1] as f32, corner[2] as f32).normalize();
            for n in normals {
                assert!(
                    (n - expected).length() < 1e-5,
                    "corner {corner:?}: {n} vs {expected}"
                );
            }
        }
        // The shading normals stay split (one per face).
        assert!(cube.normals.iter().all(|n| n.abs().max_element() > 0.999));
    }

    #[test]
    fn missing_and_broken_normals_are_computed_and_repaired() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
        let indices = vec![0, 2, 1];
        let (m, r) = Mesh::new_with_report("t", positions.clone(), None, None, indices.clone()).unwrap();
        assert!(r.computed_normals);
        for n in &m.normals {
            assert!((*n - Vec3::Y).length() < 1e-6, "{n}");
        }
        let normals = vec![Vec3::NAN, Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0)];
        let (m, r) = Mesh::new_with_report("t", positions, Some(normals), None, indices).unwrap();
        assert_eq!(r.repaired_normals, 2);
        for n in &m.normals {
            assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn degenerate_triangles_give_finite_normals() {
        let positions = vec![Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, Vec3::X];
        let m = Mesh::new("d", positions, None, None, vec![0, 1, 2, 0, 1, 3]).unwrap();
        assert!(
            m.normals
                .iter()
                .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5)
        );
    }

    #[test]
    fn bad_indices_are_rejected_with_the_mesh_name() {
        let err = Mesh::new("wing", vec![Vec3::ZERO; 3], None, None, vec![0, 1, 7]).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("wing") && text.contains("out of range"), "{text}");
        let err = Mesh::new("wing", vec![Vec3::ZERO; 3], None, None, vec![0, 1]).unwrap_err();
        assert!(err.to_string().contains("multiple of 3"));
        let err = Mesh::new("wing", vec![Vec3::NAN; 3], None, None, vec![0, 1, 2]).unwrap_err();
        assert!(err.to_string().contains("not finite"));
    }

    #[test]
    fn mirrored_transform_keeps_winding_outward() {
        let cube = primitives::cuboid(Vec3::ONE);
        let mirrored = cube
            .transformed(&Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)))
            .unwrap();
        for tri in mirrored.indices.chunks_exact(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| mirrored.positions[i as usize]);
            let n = face_normal(a, b, c);
            assert!(n.dot(mirrored.normals[tri[0] as usize]) > 0.99);
        }
    }
}
