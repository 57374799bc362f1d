// Shared by the passes over a tile list (`tile_list.wgsl`, or a group's, `tile_groups.wgsl`)
// whose draws cover the listed tiles: one quad per listed tile (an indirect draw).

// Corner `index` (0 to 5, two triangles) of listed tile `instance`'s quad, at depth 0.
@vertex
fn vs_listed_tile(@builtin(vertex_index) index: u32, @builtin(instance_index) instance: u32) -> @builtin(position) vec4<f32> {
    let tile = listed_tile(instance);
    let k = index % 6u;
    let corner = vec2<u32>(u32(k == 1u || k == 4u || k == 5u), u32(k == 2u || k == 3u || k == 5u));
    let pixel = min(vec2<f32>((tile + corner) * LIST_TILE), frame.view.size);
    let ndc = vec2<f32>(pixel.x * frame.view.inv_size.x * 2.0 - 1.0, 1.0 - pixel.y * frame.view.inv_size.y * 2.0);
    return vec4<f32>(ndc, 0.0, 1.0);
}
