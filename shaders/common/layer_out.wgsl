// The light's layer of the visibility array (R16F) as a storage texture, for the compute
// passes that write it themselves (their `cs_layer`: the blur's vertical axis, PCSS's and the
// hard shadows' pass) instead of leaving it to a draw. The source says a 32-bit float, which
// every device can store, so that the module compiles everywhere (the web has no half-float
// storage texture; those entry points then go unused); where the device can store half floats,
// `penumbra::shaders::with_half_floats` turns this line into `r16float` before the module is made.
alias LayerStorage = texture_storage_2d<r32float, write>;

