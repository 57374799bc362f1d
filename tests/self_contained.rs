//! A clone of the repository with nothing beside it runs its tests, examples, benchmark and
//! scenes: no file of the repository reads from outside it. Cheap (no GPU, no build): it reads
//! every text file of the repository and checks
//!
//! * that none names the development machines' sibling folder of shared files;
//! * that every path a scene file (`.ron`) or a glTF file (`.gltf`) refers to exists inside the
//!   repository;
//! * that every `"../..."` string in a Rust file names something that exists inside the
//!   repository, from the file's own folder (`include_str!`, `#[path]`), from its crate's root
//!   (where cargo runs tests, examples and benches) or from `assets/scenes` (scene text embedded
//!   in a test);
//! * that every `path = "..."` of a `Cargo.toml` stays inside the repository.

use std::path::{Component, Path, PathBuf};

/// Folders that are build output or tool state, not the repository's files.
const SKIPPED: [&str; 4] = ["target", ".git", ".gpu", "out"];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

/// Every file of the repository whose content is UTF-8 text, with its text.
fn text_files() -> Vec<(PathBuf, String)> {
    fn walk(dir: &Path, out: &mut Vec<(PathBuf, String)>) {
        for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("directory entry").path();
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            if path.is_dir() {
                if !SKIPPED.contains(&name) {
                    walk(&path, out);
                }
            } else if let Ok(text) = std::fs::read_to_string(&path) {
                out.push((path, text));
            }
        }
    }
    let mut out = Vec::new();
    walk(&root(), &mut out);
    out
}

/// `path` with `.` and `..` folded away lexically (no file system access), or `None` when a
/// `..` climbs above the start.
fn normalize(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::CurDir => {}
            other => out.push(other.as_os_str()),
        }
    }
    Some(out)
}

/// Whether `relative`, taken from `base`, names an existing file or folder inside the
/// repository.
fn resolves_inside(base: &Path, relative: &str) -> bool {
    let root = root();
    match normalize(&base.join(relative)) {
        Some(path) => path.starts_with(&root) && path.exists(),
        None => false,
    }
}

/// The quoted strings that follow `key` on each line of `text`, with their line (1-based).
fn quoted_after<'a>(text: &'a str, key: &str) -> Vec<(&'a str, usize)> {
    let mut found = Vec::new();
    for (number, line) in text.lines().enumerate() {
        for (at, _) in line.match_indices(key) {
            let rest = line[at + key.len()..].trim_start();
            let Some(rest) = rest.strip_prefix('"') else {
                continue;
            };
            if let Some(end) = rest.find('"') {
                found.push((&rest[..end], number + 1));
            }
        }
    }
    found
}

/// The crate root a Rust file belongs to: the nearest folder above it with a `Cargo.toml`.
fn crate_root(file: &Path) -> PathBuf {
    let mut dir = file.parent().expect("a file has a folder");
    while !dir.join("Cargo.toml").is_file() {
        dir = dir.parent().expect("every Rust file lies in a crate");
    }
    dir.to_path_buf()
}

fn relative(path: &Path) -> String {
    path.strip_prefix(root()).unwrap_or(path).display().to_string()
}

#[test]
fn no_file_names_the_folder_beside_the_checkout() {
    // Spelled in two pieces so that this file does not name it either.
    let sibling = ["..", "/shared"].concat();
    let windows = ["..", "\\shared"].concat();
    let files = text_files();
    assert!(files.len() > 100, "too few files read: {}", files.len());
    let mut offending = Vec::new();
    for (path, text) in &files {
        for (number, line) in text.lines().enumerate() {
            if line.contains(&sibling) || line.contains(&windows) {
                offending.push(format!("{}:{}: {}", relative(path), number + 1, line.trim()));
            }
        }
    }
    assert!(
        offending.is_empty(),
        "files of the repository refer to the folder beside it (a clone has none):\n{}",
        offending.join("\n")
    );
}

#[test]
fn scene_and_gltf_files_refer_only_to_files_of_the_repository() {
    let mut checked = 0;
    let mut broken = Vec::new();
    for (path, text) in text_files() {
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or_default();
        let key = match extension {
            "ron" => "path:",
            "gltf" => "\"uri\":",
            _ => continue,
        };
        let folder = path.parent().expect("a file has a folder");
        for (reference, line) in quoted_after(&text, key) {
            if reference.starts_with("data:") {
                continue; // a glTF buffer embedded in the file
            }
            checked += 1;
            if !resolves_inside(folder, reference) {
                broken.push(format!("{}:{line}: {reference}", relative(&path)));
            }
        }
    }
    // The mixed-lighting scene's glTF and two lightmaps, and that glTF's buffer and textures.
    assert!(
        checked >= 12,
        "only {checked} references found: is the scanner still right?"
    );
    assert!(
        broken.is_empty(),
        "references to files that are not in the repository:\n{}",
        broken.join("\n")
    );
}

#[test]
fn rust_files_reach_no_path_outside_the_repository() {
    let mut checked = 0;
    let mut broken = Vec::new();
    for (path, text) in text_files() {
        // This file spells out bad paths on purpose, to test the checks.
        if path.extension().is_none_or(|e| e != "rs") || path.ends_with(file!()) {
            continue;
        }
        let bases = [
            path.parent().expect("a file has a folder").to_path_buf(),
            crate_root(&path),
            root().join("assets").join("scenes"),
        ];
        for (number, line) in text.lines().enumerate() {
            for (at, _) in line.match_indices("\"../") {
                let rest = &line[at + 1..];
                let end = rest.find('"').unwrap_or(rest.len());
                let reference = &rest[..end];
                checked += 1;
                if !bases.iter().any(|base| resolves_inside(base, reference)) {
                    broken.push(format!("{}:{}: {reference}", relative(&path), number + 1));
                }
            }
        }
    }
    // The shader includes, two `#[path]` modules and a scene embedded in a test at least.
    assert!(
        checked >= 4,
        "only {checked} relative paths found: is the scanner still right?"
    );
    assert!(
        broken.is_empty(),
        "Rust files name paths that do not exist inside the repository:\n{}",
        broken.join("\n")
    );
}

#[test]
fn manifests_depend_on_nothing_outside_the_repository() {
    let mut checked = 0;
    let mut broken = Vec::new();
    for (path, text) in text_files() {
        if path.file_name().is_none_or(|n| n != "Cargo.toml") {
            continue;
        }
        let folder = path.parent().expect("a file has a folder");
        for (reference, line) in quoted_after(&text, "path =") {
            checked += 1;
            if !resolves_inside(folder, reference) {
                broken.push(format!("{}:{line}: {reference}", relative(&path)));
            }
        }
    }
    assert!(checked >= 2, "only {checked} path dependencies found");
    assert!(
        broken.is_empty(),
        "path dependencies outside the repository:\n{}",
        broken.join("\n")
    );
}

#[test]
fn the_checks_catch_what_they_are_for() {
    let root = root();
    // A path that climbs out of the repository fails, even to a folder that exists.
    assert!(!resolves_inside(&root, ".."));
    assert!(!resolves_inside(&root, "../Cargo.toml"));
    assert!(resolves_inside(&root.join("src"), "../Cargo.toml"));
    assert!(!resolves_inside(&root.join("tests"), "../no-such-file"));
    assert_eq!(
        quoted_after(r#"a: (path: "x.glb"), b: (path: "../y")"#, "path:"),
        vec![("x.glb", 1), ("../y", 1)]
    );
    assert_eq!(normalize(Path::new("/a/b/../../..")), None);
}
