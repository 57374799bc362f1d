//! The library builds for the web, `wasm32-unknown-unknown`: the embedding core (`Casters`,
//! `Shadows`, settings: `default-features = false`) and the library with its default features
//! (the renderer and the loaders). A `cargo check` of each for that target, in a target
//! directory of its own. That it runs in a browser is `tests/web_demo.rs`'s to show.

use std::process::Command;

#[test]
fn the_library_builds_for_wasm32() {
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
    // The embedding core alone, then the whole library with its default features (the renderer,
    // glTF and OBJ loaders).
    for features in [&["--no-default-features"][..], &[][..]] {
        let output = Command::new(&cargo)
            .current_dir(root)
            .args([
                "check",
                "--locked",
                "--lib",
                "--target",
                "wasm32-unknown-unknown",
                "--target-dir",
            ])
            .arg(std::path::Path::new(root).join("target").join("wasm-check"))
            .args(features)
            .output()
            .expect("cargo runs");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success(),
            "the library ({features:?}) does not build for wasm32-unknown-unknown:\n{stderr}"
        );
        assert!(
            !stderr.contains("warning:"),
            "the wasm32 build of the library ({features:?}) warns:\n{stderr}"
        );
    }
}
