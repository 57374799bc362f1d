// Shared by the passes that run over the list of screen tiles a tile classification wrote
// (`cs_classify` in `tile_classify.wgsl`): the compute passes, one 16 x 16 workgroup per listed
// tile in a dispatch sized by the list itself (indirect), and a draw that must stay a draw (it
// writes the engine's render target) as one quad per listed tile (an indirect draw,
// `vs_listed_tile` in `tile_quads.wgsl`).

// The listed tiles: how many, the classification's running count (which its last step copies
// into `count` and sets back to 0 for the next list), then each tile as x | y << 16 (in no
// particular order).
struct TileList {
    count: u32,
    appended: u32,
    tiles: array<u32>,
}

@group(3) @binding(0) var<storage, read> tile_list: TileList;

// Screen pixels per tile side (`TILE` in `tile_classify.wgsl`): the compute passes'
// workgroups are this size.
const LIST_TILE: u32 = 16u;

fn listed_tile(index: u32) -> vec2<u32> {
    let packed = tile_list.tiles[index];
    return vec2<u32>(packed & 0xffffu, packed >> 16u);
}

// The pixel invocation `local` of workgroup `group` works on (`groups` the dispatch's size: a
// list longer than a dispatch's rows allow runs on over rows of workgroups), or -1 past the
// list's end or the screen's edge.
fn listed_pixel(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>) -> vec2<i32> {
    let index = group.x + group.y * groups.x;
    if index >= tile_list.count {
        return vec2<i32>(-1);
    }
    let pixel = listed_tile(index) * LIST_TILE + local.xy;
    if any(vec2<f32>(pixel) >= frame.view.size) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(pixel);
}

// Whether the invocation works for the inspected light (`Shadows::inspect`): always, over one
// light's list (over a group's, the header says which member is: `common/tile_groups.wgsl`).
fn inspected() -> bool {
    return true;
}
