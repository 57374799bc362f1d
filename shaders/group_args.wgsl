// after:
// The indirect arguments of a pass over a group of lights' tile lists (`common/tile_groups.wgsl`,
// whose header this writes): each list's length from its running count (which the group's
// classification appended to), where each member's tiles start among all of them (the sum of
// the lists before it), and one workgroup per tile of every list (at most 65535 a row, as the
// classification's `cs_finish` counts them).

@group(0) @binding(0) var<storage, read_write> group_lists: array<u32>;
@group(0) @binding(1) var<storage, read_write> group_args: array<u32, 4>;

// Words before the first list, and where the starts lie (`common/tile_groups.wgsl`).
const GROUP_HEADER: u32 = 64u;
const GROUP_STARTS: u32 = 18u;

@compute @workgroup_size(1)
fn cs_group_args() {
    let stride = group_lists[0];
    let members = group_lists[1];
    var total = 0u;
    for (var g = 0u; g < members; g++) {
        // The classification appended to the running count: it becomes the list's length,
        // and starts the next classification from an empty list.
        let list = GROUP_HEADER + g * stride;
        let listed = group_lists[list + 1u];
        group_lists[list + 1u] = 0u;
        group_lists[list] = listed;
        group_lists[GROUP_STARTS + g] = total;
        total += listed;
    }
    group_lists[GROUP_STARTS + members] = total;
    group_args[0] = min(total, 65535u);
    group_args[1] = (total + 65534u) / 65535u;
    group_args[2] = 1u;
    group_args[3] = 0u;
}
