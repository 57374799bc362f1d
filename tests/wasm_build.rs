//! The embedding core (`Casters`, `Shadows`, settings: the crate with `default-features =
//! false`) builds for the web, `wasm32-unknown-unknown` (issue 41's first step; the renderer,
//! the demo and a browser test are not there yet). A `cargo check` of the library for that
//! target, in a target directory of its own.

use std::process::Command;

#[test]
fn the_embedding_core_builds_for_wasm32() {
    let root = env!("CARGO_MANIFEST_DIR");
    let installed = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("wasm32-unknown-unknown"))
        .unwrap_or(false);
    assert!(
        installed,
        "the wasm32-unknown-unknown target is not installed: `rustup target add wasm32-unknown-unknown` \
         (the README's prerequisites)"
    );
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .current_dir(root)
        .args([
            "check",
            "--locked",
            "--lib",
            "--no-default-features",
            "--target",
            "wasm32-unknown-unknown",
            "--target-dir",
        ])
        .arg(std::path::Path::new(root).join("target").join("wasm-check"))
        .output()
        .expect("cargo runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        output.status.success(),
        "the embedding core does not build for wasm32-unknown-unknown:\n{stderr}"
    );
    assert!(
        !stderr.contains("warning:"),
        "the wasm32 build of the embedding core warns:\n{stderr}"
    );
}
