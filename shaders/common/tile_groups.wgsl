// What `penumbra::shaders::with_light_groups` puts in place of `common/tile_list.wgsl`: a pass
// over the tile lists of a group of lights, one dispatch for all of them, or for those of one
// round (below). Each light's classification wrote its own list (count, running count, then
// x | y << 16 a tile) into a region of one buffer, and after the list the region's map: for
// each screen tile, where the list holds it (its index), or `NO_SLOT` / `AWAY_SLOT` where it is
// not listed.
//
// The buffer opens with a block of 64 words a round, then the group's header of 64 words:
// each region's length in words, the group's size, each member's light (its frame's slot and
// its layer of the visibility array) from word 2, from word 18 where each member's tiles start
// among all of them (`cs_group_args` in `group_args.wgsl` sums the lists' counts there, and the
// last entry is the whole count), then the pool's size and the rounds (`GROUP_*` below).
//
// The members' intermediates (the distance map, the deviations, the blur's horizontal result)
// are held per listed tile in a pool: slot s of a round is the tile the round's workgroup s
// works on, at tile (s % per layer) of the pool's layer s / per layer. Where every member's
// tiles do not fit the pool at once, whole members go to later rounds, each round a dispatch of
// each pass; a pass of round r binds the buffer from round r's block, which says where the
// header lies from there (word 0) and which round it is (word 1).

@group(3) @binding(0) var<storage, read> group_lists: array<u32>;

// Words before the first region (from the header); where the members' lights and their first
// tiles start in the header, the pool's size, the rounds and where each round's tiles start.
const GROUP_HEADER: u32 = 64u;
const GROUP_LIGHTS: u32 = 2u;
const GROUP_STARTS: u32 = 18u;
const GROUP_ACROSS: u32 = 36u;
const GROUP_PER_LAYER: u32 = 37u;
const GROUP_INSPECTED: u32 = 39u;
const GROUP_ROUND_STARTS: u32 = 40u;

// A map's entries for a tile not listed: nothing to blur there (the blur's horizontal result
// reads 1), or turned away from the light (0).
const NO_SLOT: u32 = 0xffffffffu;
const AWAY_SLOT: u32 = 0xfffffffeu;

// Screen pixels per tile side (`TILE` in `tile_classify.wgsl`): the compute passes'
// workgroups are this size.
const LIST_TILE: u32 = 16u;

// The member the invocation works for (its place in the group); its light is `frame_light`.
var<private> member: u32 = 0u;
// The invocation's tile's slot in the pool.
var<private> pool_slot: u32 = 0u;
// What the pool's accesses take from the header, read once in `listed_pixel`: the pool's tiles
// a layer and across, where the member's list starts, where its tiles start among all of them,
// where the round's start, and the texel and layer of the invocation's own tile's slot.
var<private> pool_per_layer: u32 = 1u;
var<private> pool_across: u32 = 1u;
var<private> member_first_word: u32 = 0u;
var<private> member_first_tile: u32 = 0u;
var<private> round_first_tile: u32 = 0u;
var<private> own_slot_texel: vec3<i32> = vec3<i32>(0);

// Word `word` of the group's header.
fn group_header(word: u32) -> u32 {
    return group_lists[group_lists[0] + word];
}

// The first word of `member`'s list.
fn member_list() -> u32 {
    return group_lists[0] + GROUP_HEADER + member * group_header(0u);
}

fn listed_tile(index: u32) -> vec2<u32> {
    let packed = group_lists[member_first_word + 2u + index];
    return vec2<u32>(packed & 0xffffu, packed >> 16u);
}

// The pixel invocation `local` of workgroup `group` works on, after setting the member, its
// light and the tile's pool slot from the workgroup's place among the round's tiles, or -1
// past the round's last tile or the screen's edge.
fn listed_pixel(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>) -> vec2<i32> {
    let round = group_lists[1];
    let first = group_header(GROUP_ROUND_STARTS + round);
    let index = first + group.x + group.y * groups.x;
    let members = group_header(1u);
    // The last member whose tiles start at or before this one (the starts rise with the
    // members; `index` is the workgroup's, so every invocation of it takes the same turns).
    var g = 0u;
    for (var k = 1u; k < members; k++) {
        if index < group_header(GROUP_STARTS + k) {
            break;
        }
        g = k;
    }
    member = g;
    frame_light = group_header(GROUP_LIGHTS + member);
    pool_slot = index - first;
    pool_per_layer = group_header(GROUP_PER_LAYER);
    pool_across = group_header(GROUP_ACROSS);
    member_first_word = member_list();
    member_first_tile = group_header(GROUP_STARTS + member);
    round_first_tile = first;
    own_slot_texel = pool_texel(pool_slot, vec2<i32>(0));
    if index >= group_header(GROUP_ROUND_STARTS + round + 1u) {
        return vec2<i32>(-1);
    }
    let pixel = listed_tile(index - member_first_tile) * LIST_TILE + local.xy;
    if any(vec2<f32>(pixel) >= frame.view.size) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(pixel);
}

// Where slot `slot` holds `pixel` (which lies in the slot's tile): the texel (xy) and the
// layer (z).
fn pool_texel(slot: u32, pixel: vec2<i32>) -> vec3<i32> {
    let t = slot % pool_per_layer;
    let corner = vec2<u32>(t % pool_across, t / pool_across) * LIST_TILE;
    return vec3<i32>(vec2<i32>(corner + vec2<u32>(pixel) % LIST_TILE), i32(slot / pool_per_layer));
}

// The invocation's own pixel `pixel` in the pool (its tile's slot).
fn pool_pixel(pixel: vec2<i32>) -> vec2<i32> {
    return own_slot_texel.xy + vec2<i32>(vec2<u32>(pixel) % LIST_TILE);
}

fn pool_layer() -> i32 {
    return own_slot_texel.z;
}

// Where the member's pixel `pixel` (any of the screen's) lies in the pool this round: its
// texel and layer, or a z of -1 where its tile is not listed (`NO_SLOT`), -2 where it is turned
// away (`AWAY_SLOT`). A member's tiles all run in one round.
fn pool_place(pixel: vec2<i32>) -> vec3<i32> {
    let tile = vec2<u32>(pixel) / LIST_TILE;
    let code = group_lists[member_first_word + 2u + pool_per_layer + tile.y * pool_across + tile.x];
    if code == NO_SLOT {
        return vec3<i32>(0, 0, -1);
    }
    if code == AWAY_SLOT {
        return vec3<i32>(0, 0, -2);
    }
    return pool_texel(member_first_tile + code - round_first_tile, pixel);
}

// Whether the invocation works for the inspected member (`Shadows::inspect`).
fn inspected() -> bool {
    return member == group_header(GROUP_INSPECTED);
}
