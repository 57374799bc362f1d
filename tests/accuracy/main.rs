//! The shadows against the truth: penumbrae against the ground-truth reference on scenes an
//! independent renderer checked, a blocker near a small light, the reference against a CPU ray
//! tracer, and the reference's own checks. One test binary; each module's own header says what it
//! checks.

#[path = "../common/mod.rs"]
mod common;

mod near_blocker;
mod ray_traced_reference;
mod reference;
mod truth;
