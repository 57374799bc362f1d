// Shared by the screen-space passes that draw only the screen tiles the tile classification
// kept (`tile_classify.wgsl`): one instanced quad per tile (instance `instance`, row by row),
// two triangles; a dropped tile's vertices all lie outside clip space and nothing of it is
// drawn. Its pixels keep what the pass's targets were cleared to, which is what the
// classification test would have left there.

// One texel per screen tile: 1 where the fattened shadow can fall.
@group(2) @binding(0) var tile_classes: texture_2d<f32>;

// Screen pixels per tile side (`TILE` in `tile_classify.wgsl`).
const CLASS_TILE: f32 = 16.0;

fn tile_kept(tile: vec2<u32>) -> bool {
    return textureLoad(tile_classes, vec2<i32>(tile), 0).x >= 0.5;
}

// Corner `index` (0 to 5) of tile `instance`'s quad, at clip depth `z`. A run of kept tiles
// along a row is drawn as one quad, by the run's first tile (a rasterizer covers one wide quad
// faster than many small ones); the others collapse.
fn tile_vertex(index: u32, instance: u32, z: f32) -> vec4<f32> {
    let across = textureDimensions(tile_classes).x;
    let tile = vec2<u32>(instance % across, instance / across);
    if !tile_kept(tile) || (tile.x > 0u && tile_kept(tile - vec2<u32>(1u, 0u))) {
        return vec4<f32>(2.0, 2.0, 0.0, 1.0);
    }
    var end = tile.x + 1u;
    while end < across && tile_kept(vec2<u32>(end, tile.y)) {
        end += 1u;
    }
    var corners = array<vec2<u32>, 6>(
        vec2<u32>(0u, 0u),
        vec2<u32>(1u, 0u),
        vec2<u32>(0u, 1u),
        vec2<u32>(0u, 1u),
        vec2<u32>(1u, 0u),
        vec2<u32>(1u, 1u),
    );
    let corner = corners[index % 6u];
    let cell = vec2<f32>(f32(select(tile.x, end, corner.x == 1u)), f32(tile.y + corner.y));
    let pixel = min(cell * CLASS_TILE, frame.view.size);
    let ndc = vec2<f32>(pixel.x * frame.view.inv_size.x * 2.0 - 1.0, 1.0 - pixel.y * frame.view.inv_size.y * 2.0);
    return vec4<f32>(ndc, z, 1.0);
}

// The kept tiles at depth 0, like `vs_fullscreen`'s triangle.
@vertex
fn vs_tile(@builtin(vertex_index) index: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    return tile_vertex(index, instance, 0.0);
}
