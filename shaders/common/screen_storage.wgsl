// The compute path's screen-sized intermediates as storage textures: the visibility before and
// between the blur's axes (`VisibilityStorage`) and the blur's deviations along each axis
// (`SigmaStorage`). The source says 32-bit floats, which every device can store, so that the
// module compiles everywhere (the web has no half-float storage texture); where the device can
// store half floats, `penumbra::shaders::with_half_floats` turns these lines into `r16float`
// and `rg16float` before the module is made, and the textures take half the memory.
alias VisibilityStorage = texture_storage_2d<r32float, write>;
alias SigmaStorage = texture_storage_2d<rg32float, write>;
