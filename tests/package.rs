//! The crate as it would be published: `cargo package` lists the library's sources, every
//! shader, the build script that composes the shaders, the licences, the front page and the
//! changelog, and nothing else (no pictures, benchmark reports, tests or examples); the packed
//! `.crate` stays small.

mod common;

use std::path::Path;
use std::process::Command;

/// Runs `cargo package` with `args` at the crate's root, offline, with the working tree as it
/// is; returns its standard output.
fn cargo_package(args: &[&str], target_dir: &Path) -> String {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["package", "--offline", "--allow-dirty", "--locked"])
        .args(args)
        .arg("--target-dir")
        .arg(target_dir)
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo package {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Every file under `dir` (relative to the crate root) whose name ends with `extension`.
fn files(dir: &str, extension: &str) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut found = Vec::new();
    let mut stack = vec![root.join(dir)];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.to_string_lossy().ends_with(extension) {
                let rel = path
                    .strip_prefix(root)
                    .unwrap()
                    .to_string_lossy()
                    .replace('\\', "/");
                found.push(rel);
            }
        }
    }
    found
}

#[test]
fn the_package_holds_the_library_its_shaders_and_licences_and_nothing_else() {
    let scratch = common::scratch_dir("package");
    let listed = cargo_package(&["--list"], &scratch);
    let listed: Vec<&str> = listed.lines().collect();
    for required in [
        "README.md",
        "CHANGELOG.md",
        "LICENSE-MIT",
        "LICENSE-APACHE",
        "Cargo.toml",
        "build.rs",
        "src/lib.rs",
    ] {
        assert!(
            listed.contains(&required),
            "{required} is not packaged: {listed:?}"
        );
    }
    // The library's every source and shader: `include_str!` needs the shaders (in the
    // sources `build.rs` writes).
    for file in files("src", ".rs").iter().chain(&files("shaders", ".wgsl")) {
        assert!(listed.contains(&file.as_str()), "{file} is not packaged");
    }
    // Nothing else: no pictures, reports, tests, examples, benchmark or assets.
    let allowed = |f: &&str| {
        f.starts_with("src/")
            || f.starts_with("shaders/")
            || [
                "README.md",
                "CHANGELOG.md",
                "LICENSE-MIT",
                "LICENSE-APACHE",
                "Cargo.toml",
                "Cargo.toml.orig",
                "build.rs",
                "Cargo.lock",
                ".cargo_vcs_info.json",
            ]
            .contains(f)
    };
    let extra: Vec<&&str> = listed.iter().filter(|f| !allowed(f)).collect();
    assert!(extra.is_empty(), "packaged besides the library: {extra:?}");

    // The packed crate, without cargo's verification build: that build compiles wgpu and the
    // other dependencies once more, with other features than the tests' (2.5 minutes of CI on
    // two cores). What a build from the archive needs besides the manifest is what the lists
    // above check: every source and every shader the sources include.
    let target = common::scratch_dir("package-target");
    cargo_package(&["--no-verify"], &target);
    let crate_file = std::fs::read_dir(target.join("package"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "crate"))
        .expect("a .crate file");
    let bytes = std::fs::metadata(&crate_file).unwrap().len();
    eprintln!(
        "{}: {} bytes ({} files)",
        crate_file.display(),
        bytes,
        listed.len()
    );
    // crates.io takes at most 10 MB; the library with its teapot data and shaders is far less.
    assert!(bytes < 1_000_000, "{} is {bytes} bytes", crate_file.display());
}
