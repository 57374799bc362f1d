//! What an engine hands [`Casters`](super::Casters): where a mesh's vertices and indices lie in
//! its own buffers, its geometry for the CPU's one read, an alpha mask, an instance's transform
//! and flags, and the ids it gets back; and the checks made of them.

use crate::error::{PenumbraError, Result};
use glam::{Mat4, Vec3};

/// One vertex attribute inside an engine's buffer: where the first vertex's value starts,
/// the bytes from one vertex to the next, and its format.
#[derive(Debug, Clone, Copy)]
pub struct VertexStream<'a> {
    /// The engine's buffer holding the attribute. It needs `VERTEX` usage, and `COPY_SRC` when
    /// the mesh is read back ([`MeshGeometry::ReadBack`]); penumbra keeps a handle to it.
    pub buffer: &'a wgpu::Buffer,
    /// Byte offset of the first vertex's attribute (the attribute's offset inside an
    /// interleaved vertex included).
    pub offset: u64,
    /// Bytes between consecutive vertices (a multiple of 4).
    pub stride: u64,
    /// The attribute's format. Which formats are accepted depends on the stream: see
    /// [`CasterMeshDesc::positions`], [`CasterMeshDesc::normals`] and [`AlphaMask::uvs`].
    pub format: wgpu::VertexFormat,
}

impl<'a> VertexStream<'a> {
    /// `format` values `stride` bytes apart from byte `offset` of `buffer`.
    pub fn new(buffer: &'a wgpu::Buffer, offset: u64, stride: u64, format: wgpu::VertexFormat) -> Self {
        Self {
            buffer,
            offset,
            stride,
            format,
        }
    }
}

/// An engine's index buffer range.
#[derive(Debug, Clone, Copy)]
pub struct IndexStream<'a> {
    /// The engine's index buffer. It needs `INDEX` usage, and `COPY_SRC` when the mesh is read
    /// back ([`MeshGeometry::ReadBack`]); penumbra keeps a handle to it.
    pub buffer: &'a wgpu::Buffer,
    /// Byte offset of the first index (a multiple of the index size).
    pub offset: u64,
    /// 16- or 32-bit indices.
    pub format: wgpu::IndexFormat,
    /// Number of indices (a multiple of 3: triangle lists).
    pub count: u32,
}

impl<'a> IndexStream<'a> {
    /// The first `count` 32-bit indices of `buffer`.
    pub fn u32(buffer: &'a wgpu::Buffer, count: u32) -> Self {
        Self {
            buffer,
            offset: 0,
            format: wgpu::IndexFormat::Uint32,
            count,
        }
    }

    /// The first `count` 16-bit indices of `buffer`.
    pub fn u16(buffer: &'a wgpu::Buffer, count: u32) -> Self {
        Self {
            format: wgpu::IndexFormat::Uint16,
            ..Self::u32(buffer, count)
        }
    }
}

/// Where penumbra reads a mesh's geometry once, to compute its bounds and smoothed normals.
#[derive(Debug, Clone, Copy)]
pub enum MeshGeometry<'a> {
    /// Copies the buffers back from the GPU once (they need `COPY_SRC` usage).
    ReadBack,
    /// The same data the buffers hold, from the CPU: no read-back, no `COPY_SRC`.
    Cpu {
        /// Model-space positions, one per vertex ([`CasterMeshDesc::vertex_count`] of them),
        /// all finite.
        positions: &'a [Vec3],
        /// Shading normals, one per vertex, to orient the smoothed normals.
        normals: Option<&'a [Vec3]>,
        /// `None` when the mesh is not indexed.
        indices: Option<&'a [u32]>,
    },
}

/// A mesh in the engine's buffers, as [`Casters::add_mesh`](crate::Casters::add_mesh) takes it.
#[derive(Debug, Clone, Copy)]
pub struct CasterMeshDesc<'a> {
    /// Named in errors.
    pub label: &'a str,
    /// `Float32x3`, `Float32x4` (w ignored) or `Float16x4` (w ignored).
    pub positions: VertexStream<'a>,
    /// Vertices in the streams. Every index must be below it; without indices it must be a
    /// multiple of 3 (a triangle list).
    pub vertex_count: u32,
    /// `None`: a non-indexed triangle list.
    pub indices: Option<IndexStream<'a>>,
    /// The shading normals (`Float32x3`, `Float32x4`, `Float16x4`, `Snorm8x4`, `Snorm16x4`),
    /// read back with [`MeshGeometry::ReadBack`] to orient the smoothed normals. Without them
    /// the faces are oriented so the mesh encloses a positive volume.
    pub normals: Option<VertexStream<'a>>,
    /// Where the CPU copy of the geometry comes from (read once, for the bounds and smoothed
    /// normals): [`MeshGeometry::ReadBack`] from [`CasterMeshDesc::new`], or the data given to
    /// [`CasterMeshDesc::cpu`].
    pub geometry: MeshGeometry<'a>,
}

impl<'a> CasterMeshDesc<'a> {
    /// A non-indexed mesh of `vertex_count` positions, read back once
    /// ([`MeshGeometry::ReadBack`]); add indices and normals with the methods below.
    pub fn new(label: &'a str, positions: VertexStream<'a>, vertex_count: u32) -> Self {
        Self {
            label,
            positions,
            vertex_count,
            indices: None,
            normals: None,
            geometry: MeshGeometry::ReadBack,
        }
    }

    /// The same mesh drawn with `indices` (a triangle list) instead of as a non-indexed one.
    pub fn indices(self, indices: IndexStream<'a>) -> Self {
        Self {
            indices: Some(indices),
            ..self
        }
    }

    /// The same mesh with shading normals, which orient its smoothed normals (see
    /// [`CasterMeshDesc::normals`]).
    pub fn normals(self, normals: VertexStream<'a>) -> Self {
        Self {
            normals: Some(normals),
            ..self
        }
    }

    /// The same data as the buffers, from the CPU (no read-back).
    pub fn cpu(self, positions: &'a [Vec3], normals: Option<&'a [Vec3]>, indices: Option<&'a [u32]>) -> Self {
        Self {
            geometry: MeshGeometry::Cpu {
                positions,
                normals,
                indices,
            },
            ..self
        }
    }
}

/// Alpha-tested casters: texels whose alpha (texture x factor) is below `cutoff` cast nothing.
#[derive(Debug, Clone, Copy)]
pub struct AlphaMask<'a> {
    /// Texture coordinates (`Float32x2`) in the engine's buffer, for the mesh's vertices.
    pub uvs: VertexStream<'a>,
    /// A filterable float 2D texture whose alpha is tested.
    pub texture: &'a wgpu::TextureView,
    /// Multiplies the texture's alpha before the test (a material's base-colour alpha); finite.
    pub alpha_factor: f32,
    /// The alpha below which a texel casts no shadow (glTF's `alphaCutoff`); finite.
    pub cutoff: f32,
}

/// A registered mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MeshId(pub(super) u32);

/// A placed mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InstanceId(pub(super) u32);

/// Where an instance is and what it does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CasterInstance {
    /// The registered mesh it places ([`Casters::add_mesh`](crate::Casters::add_mesh)).
    pub mesh: MeshId,
    /// Model to world.
    pub transform: Mat4,
    /// Drawn into the shadow maps.
    pub caster: bool,
    /// Its surfaces take shadows: counted when fitting the lights' maps (the receiver mask of
    /// a frame says which pixels take shadows). Registering receivers is optional: a surface
    /// the engine draws into the depth buffer but never registers (a floor, terrain) still
    /// gets every registered caster's shadow, whatever its distance beyond them, since a
    /// receiver beyond a map's far plane is treated as behind every caster in it.
    pub receiver: bool,
}

impl CasterInstance {
    /// `mesh` at `transform`, casting and receiving shadows.
    pub fn new(mesh: MeshId, transform: Mat4) -> Self {
        Self {
            mesh,
            transform,
            caster: true,
            receiver: true,
        }
    }
}

pub(super) const POSITION_FORMATS: &[wgpu::VertexFormat] = &[
    wgpu::VertexFormat::Float32x3,
    wgpu::VertexFormat::Float32x4,
    wgpu::VertexFormat::Float16x4,
];

pub(super) const NORMAL_FORMATS: &[wgpu::VertexFormat] = &[
    wgpu::VertexFormat::Float32x3,
    wgpu::VertexFormat::Float32x4,
    wgpu::VertexFormat::Float16x4,
    wgpu::VertexFormat::Snorm8x4,
    wgpu::VertexFormat::Snorm16x4,
];

/// Errors unless the stream's format is one of `formats`, it is a vertex buffer, its layout is
/// one wgpu accepts, and `count` vertices fit in the buffer.
pub(super) fn check_stream(
    what: &str,
    name: &str,
    s: &VertexStream,
    count: u32,
    formats: &[wgpu::VertexFormat],
) -> Result<()> {
    let fail = |reason: String| Err(PenumbraError::input(format!("{what} {name}"), reason));
    if !formats.contains(&s.format) {
        return fail(format!(
            "format {:?} is not supported; use one of {formats:?}",
            s.format
        ));
    }
    if !s.buffer.usage().contains(wgpu::BufferUsages::VERTEX) {
        return fail("the buffer lacks VERTEX usage".into());
    }
    if s.stride < s.format.size() || !s.stride.is_multiple_of(4) || s.stride > 2048 {
        return fail(format!(
            "stride {} must be a multiple of 4, at least the format's {} bytes and at most 2048",
            s.stride,
            s.format.size()
        ));
    }
    if !s.offset.is_multiple_of(4) {
        return fail(format!("offset {} is not a multiple of 4", s.offset));
    }
    let needed = if count == 0 {
        s.offset
    } else {
        s.offset + s.stride * (count as u64 - 1) + s.format.size()
    };
    let (offset, stride, size) = (s.offset, s.stride, s.buffer.size());
    if needed > size {
        return fail(format!(
            "{count} vertices from offset {offset} with stride {stride} need {needed} bytes; the buffer has {size}"
        ));
    }
    Ok(())
}

pub(super) fn index_size(format: wgpu::IndexFormat) -> u64 {
    match format {
        wgpu::IndexFormat::Uint16 => 2,
        wgpu::IndexFormat::Uint32 => 4,
    }
}

pub(super) fn check_indices(what: &str, ix: &IndexStream) -> Result<()> {
    let fail = |reason: String| Err(PenumbraError::input(format!("{what} indices"), reason));
    if !ix.buffer.usage().contains(wgpu::BufferUsages::INDEX) {
        return fail("the buffer lacks INDEX usage".into());
    }
    if !ix.count.is_multiple_of(3) {
        return fail(format!("count {} is not a multiple of 3", ix.count));
    }
    let size = index_size(ix.format);
    if !ix.offset.is_multiple_of(size) {
        return fail(format!(
            "offset {} is not a multiple of the index size {size}",
            ix.offset
        ));
    }
    let needed = ix.offset + ix.count as u64 * size;
    let (count, offset, size) = (ix.count, ix.offset, ix.buffer.size());
    if needed > size {
        return fail(format!(
            "{count} indices from offset {offset} need {needed} bytes; the buffer has {size}"
        ));
    }
    Ok(())
}

pub(super) fn check_transform(m: &Mat4, what: &str) -> Result<()> {
    if m.is_finite() {
        Ok(())
    } else {
        Err(PenumbraError::input(
            what.to_string(),
            "the transform is not finite",
        ))
    }
}
