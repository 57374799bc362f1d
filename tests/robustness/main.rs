//! What must hold at the edges of what penumbra takes: numbers at their extremes, lights at
//! theirs, a light grazing the floor, faults the GPU raises, and thousands of frames of lights
//! and casters coming and going. One test binary; each module's own header says what it checks.

#[path = "../common/mod.rs"]
mod common;

/// Numerical stability at the extremes (scales, sizes, settings, odd geometry, random inputs).
mod extremes;
/// Faults penumbra cannot catch by checking its inputs come back as errors, never as a panic.
mod faults;
/// Shadow-map hygiene where a light grazes the floor, and camera moves below a texel.
mod grazing;
/// A small sphere light at its extremes, against exact visibilities integrated on the CPU.
mod light_extremes;
/// 2,000 frames of lights and casters added, changed and removed: nothing kept past its use.
mod soak;
