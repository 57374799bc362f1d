// The light's layer of the visibility array (R16F) as a storage texture, for the compute
// passes that write it themselves (their `cs_layer`: the blur's vertical axis, PCSS's and the
// hard shadows' pass) instead of leaving it to a draw. The source says a 32-bit float, which
// every device can store, so that the module compiles everywhere (the web has no half-float
// storage texture; those entry points then go unused); where the device can store half floats,
// `penumbra::shaders::writing_layers` turns this line into `r16float` before the module is made.
alias LayerStorage = texture_storage_2d<r32float, write>;

// What the resolve writes into the layer for the visibility `v` at `pixel` (no distance map):
// 1 where nothing was drawn or the receiver mask leaves the pixel out, `v` clamped elsewhere.
// Needs `camera_depth` and `receiver_mask` bound by the including pass.
fn resolved(pixel: vec2<i32>, v: f32) -> f32 {
    if is_background(textureLoad(camera_depth, pixel, 0).x) {
        return 1.0;
    }
    if frame.view.has_receiver_mask != 0u && textureLoad(receiver_mask, pixel, 0).x < 0.5 {
        return 1.0;
    }
    return clamp(v, 0.0, 1.0);
}
