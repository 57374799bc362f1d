// after:
// The indirect arguments of the passes over a group of lights' tile lists
// (`common/tile_groups.wgsl`, whose header this writes, bound here from the header): each
// list's length from its running count (which the group's classification appended to), where
// each member's tiles start among all of them (the sum of the lists before it), the rounds, and
// for each round one workgroup per tile of its lists (at most 65535 a row, as the
// classification's `cs_finish` counts them).
//
// A round holds whole members, as many in turn as the pool holds tiles for (next fit): a
// member's tiles never outnumber the screen's, and the pool holds a whole number of screens, so
// every round but the last holds at least that many members and the rounds recorded (the
// members over the screens the pool holds, rounded up) always suffice. Rounds left over get
// no workgroups.

@group(0) @binding(0) var<storage, read_write> group_lists: array<u32>;
@group(0) @binding(1) var<storage, read_write> group_args: array<u32>;

// Words before the first list, and where the header's entries lie (`common/tile_groups.wgsl`).
const GROUP_HEADER: u32 = 64u;
const GROUP_STARTS: u32 = 18u;
const GROUP_POOL_TILES: u32 = 35u;
const GROUP_ROUNDS: u32 = 38u;
const GROUP_ROUND_STARTS: u32 = 40u;

@compute @workgroup_size(1)
fn cs_group_args() {
    let stride = group_lists[0];
    let members = group_lists[1];
    let capacity = group_lists[GROUP_POOL_TILES];
    let rounds = group_lists[GROUP_ROUNDS];
    var total = 0u;
    var round = 0u;
    group_lists[GROUP_ROUND_STARTS] = 0u;
    for (var g = 0u; g < members; g++) {
        // The classification appended to the running count: it becomes the list's length,
        // and starts the next classification from an empty list.
        let list = GROUP_HEADER + g * stride;
        let listed = group_lists[list + 1u];
        group_lists[list + 1u] = 0u;
        group_lists[list] = listed;
        // The member opens the next round where the pool cannot hold its tiles beside the
        // round's.
        let first = group_lists[GROUP_ROUND_STARTS + round];
        if total + listed - first > capacity && total > first && round + 1u < rounds {
            round += 1u;
            group_lists[GROUP_ROUND_STARTS + round] = total;
        }
        group_lists[GROUP_STARTS + g] = total;
        total += listed;
    }
    group_lists[GROUP_STARTS + members] = total;
    for (var r = round + 1u; r <= rounds; r++) {
        group_lists[GROUP_ROUND_STARTS + r] = total;
    }
    for (var r = 0u; r < rounds; r++) {
        let count = group_lists[GROUP_ROUND_STARTS + r + 1u] - group_lists[GROUP_ROUND_STARTS + r];
        group_args[4u * r] = min(count, 65535u);
        group_args[4u * r + 1u] = (count + 65534u) / 65535u;
        group_args[4u * r + 2u] = 1u;
        group_args[4u * r + 3u] = 0u;
    }
}
