//! Shadow casters drawn from the engine's own vertex and index buffers.
//!
//! An engine registers each mesh once, pointing at where its positions already are (buffer,
//! offset, stride, format; interleaved layouts are fine) and at its index buffer. penumbra
//! keeps one extra stream per mesh: the *smoothed normals* the fattened shadow map pushes the
//! casters out along, computed once on the CPU and oriented by the mesh's shading normals (or
//! by the volume it encloses), so the triangles' winding never matters.
//!
//! Instances place a mesh in the world with a transform and two flags (casts, receives).
//! Moving one uploads only its 144 bytes of instance data. Every change is logged with the
//! world boxes it touched, so each light re-renders its maps exactly when a change falls inside
//! its frustum ([`Casters::changed_inside`]).

mod desc;
pub(crate) mod normals;
mod read_back;
mod registry;
pub use desc::{
    AlphaMask, CasterInstance, CasterMeshDesc, IndexStream, InstanceId, MeshGeometry, MeshId, VertexStream,
};

pub use registry::*;
