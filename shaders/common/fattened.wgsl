// Shared by the distance map and the tile classification: where the fattened shadow falls.
// Needs `fattened_map` bound by the including pass.

// The fattened map's texel for shadow-map position `p`.
fn fattened_texel(p: vec3<f32>) -> vec2<i32> {
    let size = vec2<i32>(textureDimensions(fattened_map));
    return clamp(vec2<i32>(p.xy * vec2<f32>(size)), vec2<i32>(0), size - 1);
}

// Whether a receiver at shadow-map position `p` (in the pixel's cascade or cube face) lies inside
// the fattened shadow, `fattened_depth` the fattened map's depth at its texel: on the map tile,
// and behind the fattened surface.
fn inside_fattened(p: vec3<f32>, fattened_depth: f32) -> bool {
    let tile = frame.cascades.tile[cascade];
    let on_map = all(p.xy >= tile.xy) && all(p.xy <= tile.zw);
    return on_map && fattened_depth < map_depth(p.z);
}
