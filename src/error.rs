//! The library's error type.
//!
//! Every error that comes from something a user controls (a file, a setting,
//! a size) names that thing and says what is wrong with it.

use std::path::PathBuf;

/// Everything that can go wrong in penumbra.
#[derive(Debug, thiserror::Error)]
pub enum PenumbraError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A model file (OBJ or glTF) was read but is not usable.
    #[error("cannot load model {path}: {reason}")]
    Model { path: PathBuf, reason: String },

    /// A scene description file is malformed or refers to something that does not exist.
    #[error("invalid scene file {path}: {reason}")]
    SceneFile { path: PathBuf, reason: String },

    /// A scene built in code is inconsistent (for example an instance names a missing mesh).
    #[error("invalid scene: {0}")]
    Scene(String),

    /// A texture image could not be decoded.
    #[error("cannot decode texture {name}: {reason}")]
    Texture { name: String, reason: String },

    /// No graphics adapter could be found.
    #[error(
        "no graphics adapter found ({detail}). On a machine without a GPU install a software \
         adapter: `apt-get install mesa-vulkan-drivers libvulkan1` (Debian/Ubuntu) for Vulkan \
         (lavapipe), or set WGPU_BACKEND=gl to use Mesa's llvmpipe through OpenGL"
    )]
    NoAdapter { detail: String },

    /// The adapter refused to create a device.
    #[error("cannot create a device on adapter {adapter}: {reason}")]
    RequestDevice { adapter: String, reason: String },

    /// A setting is out of its valid range.
    #[error("invalid setting `{name}`: {reason}")]
    InvalidSetting { name: &'static str, reason: String },

    /// An argument given to the library does not fit what it must be: a texture of the wrong
    /// size or format, a buffer too short for its declared count, an unknown id.
    #[error("invalid {what}: {reason}")]
    InvalidInput { what: String, reason: String },

    /// The GPU reported an error (validation or out of memory) while doing `during`.
    #[error("GPU error while {during}: {reason}")]
    Gpu { during: String, reason: String },
}

/// Shorthand for `Result<T, PenumbraError>`.
pub type Result<T, E = PenumbraError> = std::result::Result<T, E>;

impl PenumbraError {
    pub(crate) fn model(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        Self::Model {
            path: path.into(),
            reason: reason.into(),
        }
    }

    pub(crate) fn input(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Self::InvalidInput {
            what: what.into(),
            reason: reason.into(),
        }
    }

    pub(crate) fn setting(name: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidSetting {
            name,
            reason: reason.into(),
        }
    }
}
