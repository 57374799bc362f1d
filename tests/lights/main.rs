//! Lights of every kind and what their maps need: several lights in a frame, physical units,
//! point lights' cube maps, spot lights' fit, cascades, rectangle and disk lights, grounds far
//! wider than the view, and maps sized from their penumbrae. One test binary; each module's own
//! header says what it checks.

#[path = "../common/mod.rs"]
mod common;

mod area_lights;
mod cascades;
mod large_grounds;
mod light_units;
mod lights;
mod map_resolution;
mod point_lights;
mod spot_fit;
