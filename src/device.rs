//! What an application's wgpu instance and device should look like for penumbra.

/// The instance flags penumbra's tools use, and that an embedding application on Mesa's
/// lavapipe should use too: wgpu's build defaults with DEBUG removed unless `WGPU_DEBUG=1`.
/// Mesa's lavapipe crashes inside vkCmdBeginDebugUtilsLabelEXT, which wgpu calls for debug
/// groups when DEBUG is on (the default in debug builds). Other `WGPU_*` flag variables apply.
pub fn instance_flags() -> wgpu::InstanceFlags {
    (wgpu::InstanceFlags::from_build_config() - wgpu::InstanceFlags::DEBUG).with_env()
}

/// The device penumbra wants from `adapter`: the timestamp-query features where the adapter
/// has them (for per-pass GPU times; without them timing falls back to wall clock), the
/// adapter's own texture format features where it has them (a compute pass then writes the
/// visibility's half floats itself, where a draw would copy them), WebGL2-era limits with the
/// adapter's own texture size limit (shadow maps up to 8192 texels), and wgpu's
/// `MemoryHints::MemoryUsage`: the lights' maps are arrays made again as lights come and go, and
/// under `MemoryHints::Performance` (wgpu's default) the driver's memory comes in blocks of 128
/// to 256 MiB that a few small buffers keep alive after the arrays in them went. With 64 suns
/// on lavapipe the blocks held 1.2 to 1.3 GB for 1.0 GB of resources, against 2.4 to 2.8 GB
/// (`docs/limits.md`); the frames took as long.
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    let optional = wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES
        | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
    wgpu::DeviceDescriptor {
        label: Some("penumbra device"),
        required_features: adapter.features() & optional,
        required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
        memory_hints: wgpu::MemoryHints::MemoryUsage,
        ..Default::default()
    }
}

/// Whether a wgpu device has been lost, and why: what lets a [`crate::Shadows`] or
/// [`crate::Renderer`] report [`crate::PenumbraError::DeviceLost`] instead of drawing nothing
/// without a word (a lost device accepts commands and does nothing with them).
///
/// wgpu keeps one lost callback per device, so penumbra does not install one by itself:
/// [`DeviceLoss::watch`] installs it (replacing any the application set), and an application
/// with a callback of its own calls [`DeviceLoss::record`] from it instead. wgpu calls the
/// callback when it next polls the device (a submit or `Device::poll`).
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// let gpu = penumbra::HeadlessGpu::new()?;
/// let mut shadows = penumbra::Shadows::new(&gpu.device, penumbra::ShadowSettings::default())?;
/// // With no lost callback of the application's own:
/// shadows.watch_device_loss(penumbra::DeviceLoss::watch(&gpu.device));
/// // ... or from the application's own callback:
/// let loss = penumbra::DeviceLoss::default();
/// let seen = loss.clone();
/// gpu.device.set_device_lost_callback(move |reason, message| {
///     seen.record(reason, &message);
///     // the application's own handling
/// });
/// shadows.watch_device_loss(loss);
/// # Ok(()) }
/// ```
#[derive(Debug, Clone, Default)]
pub struct DeviceLoss(std::sync::Arc<std::sync::Mutex<Option<String>>>);

impl DeviceLoss {
    /// Installs a lost callback on `device` that records the loss here.
    pub fn watch(device: &wgpu::Device) -> Self {
        let loss = Self::default();
        let seen = loss.clone();
        device.set_device_lost_callback(move |reason, message| seen.record(reason, &message));
        loss
    }

    /// Records that the device was lost, with wgpu's reason and message.
    pub fn record(&self, reason: wgpu::DeviceLostReason, message: &str) {
        let reason = match reason {
            wgpu::DeviceLostReason::Destroyed => "destroyed",
            wgpu::DeviceLostReason::Unknown => "unknown",
        };
        let text = if message.is_empty() {
            reason.to_string()
        } else {
            format!("{reason}: {message}")
        };
        let mut lost = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        lost.get_or_insert(text);
    }

    /// wgpu's reason and message, once the device has been lost.
    pub fn lost(&self) -> Option<String> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// [`crate::PenumbraError::DeviceLost`] once the device has been lost.
    pub fn check(&self) -> crate::Result<()> {
        match self.lost() {
            Some(reason) => Err(crate::PenumbraError::DeviceLost { reason }),
            None => Ok(()),
        }
    }
}
