//! The library's error type.
//!
//! Every error that comes from something a user controls (a file, a setting,
//! a size) names that thing and says what is wrong with it.

use std::path::PathBuf;

/// Everything that can go wrong in penumbra.
///
/// Each variant carries what a program needs to react (the setting's name, the file's path)
/// and its `Display` is a one-line message for a user:
///
/// ```
/// use penumbra::{CameraMatrices, DepthConvention, PenumbraError, ShadowMethod, ShadowSettings};
///
/// // A setting out of range: `InvalidSetting`, named by its path in `ShadowSettings`.
/// let mut settings = ShadowSettings::default();
/// settings.shadow_map.resolution = 1000; // not a power of two
/// match settings.validate(None) {
///     Err(PenumbraError::InvalidSetting { name, reason }) => {
///         assert_eq!(name, "shadow_map.resolution");
///         assert!(reason.contains("power of two"), "{reason}");
///     }
///     other => panic!("expected an invalid setting, got {other:?}"),
/// }
///
/// // An argument that cannot be used: `InvalidInput`, saying which one.
/// let camera = CameraMatrices {
///     view: glam::Mat4::IDENTITY,
///     projection: glam::Mat4::ZERO, // not invertible
///     depth: DepthConvention::Standard,
/// };
/// assert!(matches!(
///     camera.validate(),
///     Err(PenumbraError::InvalidInput { what, .. }) if what == "camera projection matrix"
/// ));
///
/// // The message names the setting and lists the valid values.
/// let error = ShadowMethod::from_name("vsm").unwrap_err();
/// assert!(matches!(error, PenumbraError::InvalidSetting { name: "method", .. }));
/// assert!(error.to_string().starts_with("invalid setting `method`: unknown method `vsm`"));
/// ```
#[derive(Debug, thiserror::Error)]
pub enum PenumbraError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file that was being read (a model, scene, texture or lightmap file).
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },

    /// A model file (OBJ or glTF) was read but is not usable.
    #[error("cannot load model {path}: {reason}")]
    Model {
        /// The model file.
        path: PathBuf,
        /// What is wrong with its content.
        reason: String,
    },

    /// A scene description file is malformed or refers to something that does not exist.
    #[error("invalid scene file {path}: {reason}")]
    SceneFile {
        /// The scene file (RON).
        path: PathBuf,
        /// The syntax error or the missing or invalid thing it refers to.
        reason: String,
    },

    /// A scene built in code is inconsistent (for example an instance names a missing mesh).
    #[error("invalid scene: {0}")]
    Scene(String),

    /// A texture image could not be decoded.
    #[error("cannot decode texture {name}: {reason}")]
    Texture {
        /// The texture's name: its file path, or the name it was given in the scene or model.
        name: String,
        /// Why it is unusable: the decoder's error, an unsupported file type or layout, or a
        /// size beyond the device's limit.
        reason: String,
    },

    /// No graphics adapter could be found.
    #[error(
        "no graphics adapter found ({detail}). On a machine without a GPU install a software \
         adapter: `apt-get install mesa-vulkan-drivers libvulkan1` (Debian/Ubuntu) for Vulkan \
         (lavapipe), or set WGPU_BACKEND=gl to use Mesa's llvmpipe through OpenGL"
    )]
    NoAdapter {
        /// wgpu's explanation of why no adapter was returned.
        detail: String,
    },

    /// The adapter refused to create a device.
    #[error("cannot create a device on adapter {adapter}: {reason}")]
    RequestDevice {
        /// The adapter's name and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
        adapter: String,
        /// wgpu's reason for refusing the device.
        reason: String,
    },

    /// A setting is out of its valid range.
    #[error("invalid setting `{name}`: {reason}")]
    InvalidSetting {
        /// The setting's path, as in `shadow_map.resolution` or `penumbra.blur_taps`, or the
        /// name of a parameter such as `method`, `quality` or `size`.
        name: &'static str,
        /// The value given and the range or values allowed.
        reason: String,
    },

    /// An argument given to the library does not fit what it must be: a texture of the wrong
    /// size or format, a buffer too short for its declared count, an unknown id.
    #[error("invalid {what}: {reason}")]
    InvalidInput {
        /// The argument at fault, e.g. `depth texture`, `camera view matrix`, `light 2`, or a
        /// caster mesh's stream named with the mesh's label.
        what: String,
        /// What it must be and how it falls short.
        reason: String,
    },

    /// The GPU reported an error (validation or out of memory) while doing `during`.
    #[error("GPU error while {during}: {reason}")]
    Gpu {
        /// The operation that failed, e.g. `reading back a texture` or `rendering the
        /// reference`.
        during: String,
        /// The error reported, in most cases wgpu's own message.
        reason: String,
    },

    /// The wgpu device was lost (its `destroy` was called, the driver failed or was reset):
    /// nothing more can be drawn on it. Reported by the calls of a [`crate::Shadows`] or
    /// [`crate::Renderer`] given a [`crate::DeviceLoss`] that saw it happen; the application
    /// makes a new device and new penumbra objects on it.
    #[error("the GPU device was lost ({reason})")]
    DeviceLost {
        /// wgpu's reason (`destroyed` when the application destroyed the device, `unknown`
        /// otherwise) and its message.
        reason: String,
    },
}

/// Shorthand for `Result<T, PenumbraError>`.
pub type Result<T, E = PenumbraError> = std::result::Result<T, E>;

/// What slot `index` of `slots` holds: [`PenumbraError::no_such`] `kind` where it is empty or
/// beyond the end (an id removed or never handed out).
/// Waits until the GPU has done all the work submitted to `device`; a wait that fails is a
/// [`PenumbraError::Gpu`] while `during`.
pub(crate) fn wait_for_gpu(device: &wgpu::Device, during: &str) -> Result<()> {
    let wait = wgpu::PollType::Wait {
        submission_index: None,
        timeout: None,
    };
    match device.poll(wait) {
        Ok(_) => Ok(()),
        Err(e) => Err(PenumbraError::Gpu {
            during: during.into(),
            reason: e.to_string(),
        }),
    }
}

/// Maps `slice` for reading and waits until it is mapped (or `during` fails).
pub(crate) fn map_for_reading(device: &wgpu::Device, slice: wgpu::BufferSlice, during: &str) -> Result<()> {
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = sender.send(r);
    });
    wait_for_gpu(device, during)?;
    let failed = |reason: String| PenumbraError::Gpu {
        during: during.into(),
        reason,
    };
    receiver
        .recv()
        .map_err(|e| failed(e.to_string()))?
        .map_err(|e| failed(e.to_string()))
}

pub(crate) fn slot<'a, T>(slots: &'a [Option<T>], kind: &str, index: u32) -> Result<&'a T> {
    slots
        .get(index as usize)
        .and_then(Option::as_ref)
        .ok_or_else(|| PenumbraError::no_such(kind, index))
}

/// [`slot`], to change.
pub(crate) fn slot_mut<'a, T>(slots: &'a mut [Option<T>], kind: &str, index: u32) -> Result<&'a mut T> {
    slots
        .get_mut(index as usize)
        .and_then(Option::as_mut)
        .ok_or_else(|| PenumbraError::no_such(kind, index))
}

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

    /// Runs `f` inside wgpu's validation and out-of-memory error scopes
    /// ([`crate::gpu_helpers::scoped`]): a wgpu error it raised is returned as
    /// [`PenumbraError::Gpu`] naming `during`, otherwise what `f` returned.
    pub(crate) fn scoped<T>(
        device: &wgpu::Device,
        during: impl FnOnce() -> String,
        f: impl FnOnce() -> Result<T>,
    ) -> Result<T> {
        match crate::gpu_helpers::scoped(device, f) {
            (_, Some(error)) => Err(Self::gpu(during(), error)),
            (result, None) => result,
        }
    }

    /// A wgpu error raised while penumbra did `during` ([`PenumbraError::Gpu`]).
    pub(crate) fn gpu(during: impl Into<String>, error: wgpu::Error) -> Self {
        let reason = match &error {
            wgpu::Error::OutOfMemory { .. } => format!("out of GPU memory: {error}"),
            wgpu::Error::Validation { description, .. } => format!("wgpu validation failed: {description}"),
            wgpu::Error::Internal { description, .. } => format!("internal GPU error: {description}"),
        };
        Self::Gpu {
            during: during.into(),
            reason,
        }
    }

    /// [`PenumbraError::InvalidInput`] for an id with nothing behind it: `kind` `index` was
    /// removed or never added.
    pub(crate) fn no_such(kind: &str, index: u32) -> Self {
        Self::input(
            format!("{kind} {index}"),
            format!("no such {kind} (removed or never added)"),
        )
    }

    pub(crate) fn setting(name: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidSetting {
            name,
            reason: reason.into(),
        }
    }
}
