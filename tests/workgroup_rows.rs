//! The order in which the compute passes over the whole screen take their rows of workgroups
//! (`screen_row` in `shaders/common/workgroup_rows.wgsl`): for every screen height up to 80 rows
//! and every thread count up to 16 it is a permutation of the rows (no row skipped or run
//! twice), and each thread's contiguous run of it (as llvmpipe hands workgroups out) holds rows
//! from the top and the bottom of the screen. The function's own WGSL runs in a compute pass on
//! the machine's adapter and writes its answer for every case.

mod common;

const MAX_ROWS: u32 = 80;
const MAX_THREADS: u32 = 16;

/// Whether each of `threads` equal runs of `order` holds a row near the top and one near the
/// bottom of the `order.len()` rows.
fn spread(order: &[u32], threads: u32) -> bool {
    let rows = order.len() as u32;
    let run = (rows / threads) as usize;
    order.chunks(run).take(threads as usize).all(|chunk| {
        let (least, most) = (chunk.iter().min().unwrap(), chunk.iter().max().unwrap());
        *least <= 2 * threads && *most + 1 + 2 * threads >= rows
    })
}

#[test]
fn screen_rows_are_a_permutation_spread_over_each_threads_run() {
    let gpu = common::gpu();
    let piece = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/shaders/common/workgroup_rows.wgsl"
    ))
    .unwrap();
    let source = format!(
        "{piece}
@group(0) @binding(0) var<storage, read_write> rows_out: array<u32>;

// Case (rows - 1) x {MAX_THREADS} + threads - 1 holds {MAX_ROWS} entries: row i's screen row, or
// 0xffffffff past the screen's rows.
@compute @workgroup_size(64)
fn cs_test(@builtin(global_invocation_id) id: vec3<u32>) {{
    let entry = id.x % {MAX_ROWS}u;
    let which = id.x / {MAX_ROWS}u;
    if which >= {MAX_ROWS}u * {MAX_THREADS}u {{
        return;
    }}
    let rows = which / {MAX_THREADS}u + 1u;
    let threads = which % {MAX_THREADS}u + 1u;
    rows_out[id.x] = select(0xffffffffu, screen_row_among(entry, rows, threads), entry < rows);
}}
"
    );
    let device = &gpu.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("workgroup_rows test"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("workgroup_rows test"),
        layout: None,
        module: &module,
        entry_point: Some("cs_test"),
        compilation_options: Default::default(),
        cache: None,
    });
    let entries = (MAX_ROWS * MAX_THREADS * MAX_ROWS) as u64;
    let size = entries * 4;
    let out = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("rows_out"),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("rows_out staging"),
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("workgroup_rows test"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: out.as_entire_binding(),
        }],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((entries as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&out, 0, &staging, 0, size);
    gpu.queue.submit([encoder.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |r| r.expect("mapped"));
    device
        .poll(wgpu::PollType::Wait {
            submission_index: None,
            timeout: None,
        })
        .unwrap();
    let values: Vec<u32> = bytemuck::cast_slice(&staging.get_mapped_range(..).unwrap()).to_vec();

    for rows in 1..=MAX_ROWS {
        for threads in 1..=MAX_THREADS {
            let case = ((rows - 1) * MAX_THREADS + threads - 1) * MAX_ROWS;
            let order = &values[case as usize..(case + rows) as usize];
            let mut sorted = order.to_vec();
            sorted.sort_unstable();
            assert!(
                sorted.iter().copied().eq(0..rows),
                "{rows} rows, {threads} threads: {order:?} is not a permutation of the rows"
            );
            if threads >= 2 && 2 * threads <= rows {
                assert!(
                    spread(order, threads),
                    "{rows} rows, {threads} threads: a thread's run of {order:?} keeps to part of the screen"
                );
            }
            if threads == 1 {
                assert!(order.iter().copied().eq(0..rows), "one thread: the rows in order");
            }
        }
    }
    // The check can fail: the rows in order give the first thread the top of the screen alone.
    let in_order: Vec<u32> = (0..64).collect();
    assert!(!spread(&in_order, 2));
}
