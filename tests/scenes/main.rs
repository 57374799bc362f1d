//! Scenes made elsewhere: the loaders and scene files on real files, glTF materials as their
//! authors meant them, and baked lightmaps with their lighting modes. One test binary; each
//! module's own header says what it checks.

#[path = "../common/mod.rs"]
mod common;

mod lightmaps;
mod loaders;
mod materials;
