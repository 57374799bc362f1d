//! What an application's wgpu instance and device should look like for penumbra.

/// The instance flags penumbra's tools use, and that an embedding application on Mesa's
/// lavapipe should use too: wgpu's build defaults with DEBUG removed unless `WGPU_DEBUG=1`.
/// Mesa's lavapipe crashes inside vkCmdBeginDebugUtilsLabelEXT, which wgpu calls for debug
/// groups when DEBUG is on (the default in debug builds). Other `WGPU_*` flag variables apply.
pub fn instance_flags() -> wgpu::InstanceFlags {
    (wgpu::InstanceFlags::from_build_config() - wgpu::InstanceFlags::DEBUG).with_env()
}

/// The device penumbra wants from `adapter`: the timestamp-query features where the adapter
/// has them (for per-pass GPU times; without them timing falls back to wall clock), WebGL2-era
/// limits with the adapter's own texture size limit (shadow maps up to 8192 texels).
pub fn device_descriptor(adapter: &wgpu::Adapter) -> wgpu::DeviceDescriptor<'static> {
    let optional = wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES;
    wgpu::DeviceDescriptor {
        label: Some("penumbra device"),
        required_features: adapter.features() & optional,
        required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
        ..Default::default()
    }
}
