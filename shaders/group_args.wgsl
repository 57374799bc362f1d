// after:
// The indirect arguments of a pass over a group of lights' tile lists (`common/tile_groups.wgsl`,
// whose header this reads: each list's length in words, the group's size, then the lists): one
// workgroup per tile of the longest list along x and y (at most 65535 a row, as the
// classification's `cs_finish` counts them), one layer of workgroups per member along z.

@group(0) @binding(0) var<storage, read> group_lists: array<u32>;
@group(0) @binding(1) var<storage, read_write> group_args: array<u32, 4>;

// Words before the first list (`GROUP_HEADER` in `common/tile_groups.wgsl`).
const GROUP_HEADER: u32 = 64u;

@compute @workgroup_size(1)
fn cs_group_args() {
    let stride = group_lists[0];
    let members = group_lists[1];
    var longest = 0u;
    for (var g = 0u; g < members; g++) {
        longest = max(longest, group_lists[GROUP_HEADER + g * stride]);
    }
    group_args[0] = min(longest, 65535u);
    group_args[1] = (longest + 65534u) / 65535u;
    group_args[2] = members;
    group_args[3] = 0u;
}
