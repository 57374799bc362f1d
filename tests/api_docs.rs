//! The API reference builds clean: `cargo doc` of the library (its default features) with
//! every rustdoc warning denied: broken or private intra-doc links, bad code blocks, invalid
//! HTML. The doc examples themselves run with the other tests (`cargo test` runs doc-tests).

use std::path::Path;
use std::process::Command;

#[test]
fn cargo_doc_builds_without_warnings() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    // The tests' own build directory: the dependencies already checked there serve it.
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("target");
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or(target, Into::into);
    let out = Command::new(cargo)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["doc", "--no-deps", "--offline", "--locked", "-p", "penumbra"])
        .arg("--target-dir")
        .arg(&target)
        .env("RUSTDOCFLAGS", "-D warnings")
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo doc failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(target.join("doc/penumbra/index.html").is_file());
}
