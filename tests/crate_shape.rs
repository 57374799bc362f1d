//! What an engine gets with `default-features = false`: the embedding core alone, built on
//! wgpu, glam, bytemuck and thiserror.

use std::path::Path;
use std::process::Command;

fn cargo() -> Command {
    let mut command = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    command.current_dir(env!("CARGO_MANIFEST_DIR"));
    command
}

#[test]
fn without_default_features_the_crate_depends_on_four_crates_and_builds() {
    let output = cargo()
        .args([
            "tree",
            "--offline",
            "--locked",
            "--no-default-features",
            "--edges",
            "normal",
            "--depth",
            "1",
            "--prefix",
            "none",
        ])
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "cargo tree failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let mut direct: Vec<String> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .skip(1)
        .filter_map(|line| line.split_whitespace().next().map(str::to_string))
        .collect();
    direct.sort();
    direct.dedup();
    assert_eq!(direct, ["bytemuck", "glam", "thiserror", "wgpu"]);

    // And it compiles alone (a target directory of its own: the test's cargo holds its own).
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/crate-shape");
    let output = cargo()
        .args(["check", "--offline", "--locked", "--lib", "--no-default-features"])
        .env("CARGO_TARGET_DIR", &target)
        .env("RUSTFLAGS", "-D warnings")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the core does not build alone:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}
