//! The embedding API on its own, and the engine example built on it. One test binary; each
//! module's own header says what it checks.

#[path = "../common/mod.rs"]
mod common;

mod embedding;
mod engine;
