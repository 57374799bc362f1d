// The compute path's screen-sized intermediates as storage textures: the visibility before and
// between the blur's axes (`VisibilityStorage`), the blur's deviations along each axis
// (`SigmaStorage`) and the distance map (`DistanceStorage`, one value a pixel, below). The
// source says 32-bit floats, which every device can store, so that the module compiles
// everywhere (the web has no single or paired half-float storage texture); where the device
// can store half floats, `penumbra::shaders::with_half_floats` turns these lines into
// `r16float` and `rg16float` before the module is made, and the textures take half the memory.
alias VisibilityStorage = texture_storage_2d<r32float, write>;
alias SigmaStorage = texture_storage_2d<rg32float, write>;
alias DistanceStorage = texture_storage_2d<r32float, write>;

// The compute path's distance map holds one value a pixel, where the draws' holds two (R the
// distance, G the mask) and a depth (the classification):
// - at least 0: inside the fattened shadow, the distance to the occluder;
// - `OUTSIDE_CAN_FALL`: outside it, but a shadow can fall (the mask's early out off), at
//   distance 0;
// - `NO_SHADOW_HERE` (what the map is cleared to): outside it, no pass runs;
// - `NOT_RECEIVER`, `BACKGROUND`: a surface the receiver mask leaves out; nothing drawn.
// `distance_value` in `common/distance.wgsl` writes it, `penumbra::debug` decodes it.
const OUTSIDE_CAN_FALL: f32 = -0.25;
const NO_SHADOW_HERE: f32 = -1.0;
const NOT_RECEIVER: f32 = -2.0;
const BACKGROUND: f32 = -3.0;

// Whether a shadow can fall at a pixel whose distance map holds `v`: the later passes run there.
fn shadow_can_fall(v: f32) -> bool {
    return v > 0.5 * (OUTSIDE_CAN_FALL + NO_SHADOW_HERE);
}

// The distance to the occluder at a pixel whose distance map holds `v` (0 where none is).
fn distance_of(v: f32) -> f32 {
    return max(v, 0.0);
}
