// Shared by the compute passes dispatched over the whole screen: the order their rows of
// workgroups take.
//
// A software rasterizer's threads take a dispatch's workgroups in contiguous runs (llvmpipe
// gives each of its threads an equal count, in order): in screen order, the thread whose run
// held the shadows did most of the work while the others waited. With ROW_THREADS threads,
// workgroup row `row` of `rows` runs the screen's rows in the order 0, t, 2t, ..., then 1,
// 1 + t, ...: each thread's run covers the screen from top to bottom, in rows near each other.
// 1 (a GPU, which hands workgroups out as they finish): the rows in order.
override ROW_THREADS: u32 = 1u;

fn screen_row(row: u32, rows: u32) -> u32 {
    return screen_row_among(row, rows, ROW_THREADS);
}

// `screen_row` for `threads` threads (`tests/workgroup_rows.rs` checks it for many).
fn screen_row_among(row: u32, rows: u32, threads: u32) -> u32 {
    let t = max(threads, 1u);
    var start = 0u;
    for (var residue = 0u; residue < t; residue++) {
        // the rows whose index leaves `residue` divided by t
        let count = (rows + t - 1u - residue) / t;
        if row < start + count {
            return residue + t * (row - start);
        }
        start += count;
    }
    return row;
}
