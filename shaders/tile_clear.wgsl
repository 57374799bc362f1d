// after:
// Tile clear: one tile of a light-space atlas (the viewport the draw is given) set to what a
// cleared pass leaves, the far plane in depth and 0 in a colour target (the fattened map's
// occluder offset), so that a cascade or cube face can be redrawn while the others stay.

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    // The full-screen triangle on the far plane.
    let corner = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(corner * 2.0 - 1.0, 1.0, 1.0);
}

@fragment
fn fs_zero() -> @location(0) vec4<f32> {
    return vec4<f32>(0.0);
}
