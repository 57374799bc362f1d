//! `cargo bench`: every real-time method on the project's scenes, measured for speed and
//! accuracy in one run (see `report.rs`). `PENUMBRA_BENCH=quick` runs the quick mode (about 12
//! minutes on lavapipe with two cores); `PENUMBRA_BENCH=accuracy` the full run's accuracy on every
//! viewpoint with the quick run's timing. Writes target/penumbra-bench/report.md, report.json and
//! tradeoff.png, or into `PENUMBRA_BENCH_OUT` where that is set.

mod report;

fn main() -> anyhow::Result<()> {
    let out = match std::env::var_os("PENUMBRA_BENCH_OUT") {
        Some(dir) => std::path::PathBuf::from(dir),
        None => std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/penumbra-bench"),
    };
    let config = match std::env::var("PENUMBRA_BENCH").as_deref() {
        Ok("quick") => report::Config::quick(out),
        Ok("accuracy") => report::Config::accuracy(out),
        _ => report::Config::full(out),
    };
    report::run(&config)?;
    Ok(())
}
