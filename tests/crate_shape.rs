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

    // And it compiles alone, without a warning. In the tests' own build directory: the
    // dependencies `cargo doc` checked for tests/api_docs.rs (the same wgpu) serve it too.
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("target");
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or(target, Into::into);
    let output = cargo()
        .args([
            "check",
            "--offline",
            "--locked",
            "--lib",
            "--no-default-features",
            "--message-format",
            "json",
        ])
        .arg("--target-dir")
        .arg(&target)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the core does not build alone:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // rustc's warnings on the crate (cargo replays them for a crate already checked).
    let warnings: Vec<String> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|line| serde_json::from_str::<serde_json::Value>(line).ok())
        .filter(|m| {
            m["reason"] == "compiler-message"
                && m["message"]["level"] == "warning"
                && m["package_id"].as_str().is_some_and(|id| id.contains("penumbra"))
        })
        .map(|m| m["message"]["rendered"].as_str().unwrap_or("?").to_string())
        .collect();
    assert!(
        warnings.is_empty(),
        "the core alone builds with warnings:\n{}",
        warnings.join("\n")
    );
}
