//! [`load_model`]: a model file loaded by the loader its extension names.

use std::path::Path;

#[cfg(feature = "gltf")]
use super::gltf;
#[cfg(feature = "obj")]
use super::obj;
use crate::error::{PenumbraError, Result};
use crate::scene::Model;

/// Loads an OBJ (`.obj`) or glTF (`.gltf`, `.glb`) file, chosen by extension.
pub fn load_model(path: &Path) -> Result<Model> {
    if !path.exists() {
        return Err(PenumbraError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "file not found"),
        });
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let model: Model = match ext.as_str() {
        #[cfg(feature = "obj")]
        "obj" => guarded(path, || obj::load(path)),
        #[cfg(feature = "gltf")]
        "gltf" | "glb" => guarded(path, || gltf::load(path)),
        _ => Err(PenumbraError::model(
            path,
            format!(
                "unsupported file type `.{ext}`; supported: {}",
                supported_extensions().join(", ")
            ),
        )),
    }?;
    if model.parts.is_empty() {
        return Err(PenumbraError::model(path, "the file contains no triangles"));
    }
    Ok(model)
}

/// The extensions [`load_model`] accepts with the enabled features.
pub fn supported_extensions() -> Vec<&'static str> {
    let mut v = Vec::new();
    if !cfg!(any(feature = "obj", feature = "gltf")) {
        v.push("none (enable the `obj` or `gltf` cargo feature)");
    }
    if cfg!(feature = "obj") {
        v.push(".obj");
    }
    if cfg!(feature = "gltf") {
        v.extend([".gltf", ".glb"]);
    }
    v
}

/// Runs a parser and turns a panic inside a third-party parser into an error naming the file:
/// a last line of defence, since malformed files must never take the caller down.
#[cfg_attr(not(any(feature = "obj", feature = "gltf")), allow(dead_code))]
fn guarded(path: &Path, load: impl FnOnce() -> Result<Model>) -> Result<Model> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(load)) {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown failure".into());
            Err(PenumbraError::model(
                path,
                format!("malformed file (parser failed: {what})"),
            ))
        }
    }
}
