//! Model loaders: OBJ (feature `obj`, through `tobj`) and glTF 2.0 (feature `gltf`).
//!
//! Both return a [`Model`](crate::Model) or an error that names the file and the reason. Anything a loader
//! cannot represent (glTF blend mode, line and point primitives, extra UV sets) is listed in
//! [`Model::warnings`](crate::Model::warnings) rather than dropped without a word.

#[cfg(feature = "gltf")]
mod gltf;
mod load;
#[cfg(feature = "obj")]
mod obj;

pub use load::*;
