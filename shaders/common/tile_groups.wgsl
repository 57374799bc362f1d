// What `penumbra::shaders::with_light_groups` puts in place of `common/tile_list.wgsl`: a pass
// over the tile lists of a group of lights, one dispatch for all of them. Each light's
// classification wrote its own list (count, running count, then x | y << 16 a tile) into a
// region of one buffer. The buffer opens with a header of 64 words: each region's length in
// words, the group's size, each member's light (its frame's slot and its layer of the
// visibility array) from word 2, and from word 18 where each member's tiles start in the
// dispatch (`cs_group_args` in `group_args.wgsl` sums the lists' counts there, and the last
// entry is the whole count). The dispatch runs one workgroup per tile of every list, the
// first member's tiles first.

@group(3) @binding(0) var<storage, read> group_lists: array<u32>;

// Words before the first region; where the members' lights and their first tiles start in it.
const GROUP_HEADER: u32 = 64u;
const GROUP_LIGHTS: u32 = 2u;
const GROUP_STARTS: u32 = 18u;

// Screen pixels per tile side (`TILE` in `tile_classify.wgsl`): the compute passes'
// workgroups are this size.
const LIST_TILE: u32 = 16u;

// The member the invocation works for (its place in the group: its layer of the group's
// intermediates); its light is `frame_light`.
var<private> member: u32 = 0u;

// The first word of `member`'s list.
fn member_list() -> u32 {
    return GROUP_HEADER + member * group_lists[0];
}

fn listed_tile(index: u32) -> vec2<u32> {
    let packed = group_lists[member_list() + 2u + index];
    return vec2<u32>(packed & 0xffffu, packed >> 16u);
}

// The pixel invocation `local` of workgroup `group` works on, after setting the member and its
// light from the workgroup's place among every member's tiles, or -1 past the last tile or the
// screen's edge.
fn listed_pixel(group: vec3<u32>, groups: vec3<u32>, local: vec3<u32>) -> vec2<i32> {
    let index = group.x + group.y * groups.x;
    let members = group_lists[1];
    // The members whose tiles start at or before this one, but the first: no branch (at most
    // 16 members, `MAX_MEMBERS` in `src/screen/light_group.rs`).
    var g = 0u;
    for (var k = 1u; k < 16u; k++) {
        g += select(0u, 1u, k < members && index >= group_lists[GROUP_STARTS + k]);
    }
    member = g;
    frame_light = group_lists[GROUP_LIGHTS + member];
    if index >= group_lists[GROUP_STARTS + members] {
        return vec2<i32>(-1);
    }
    let pixel = listed_tile(index - group_lists[GROUP_STARTS + member]) * LIST_TILE + local.xy;
    if any(vec2<f32>(pixel) >= frame.view.size) {
        return vec2<i32>(-1);
    }
    return vec2<i32>(pixel);
}
