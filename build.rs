//! Writes `shaders.rs` (`src/shaders.rs` includes it): one `&str` const per file of `shaders/`,
//! that file joined after the pieces of `shaders/common/` its first line names
//! (`// after: frame cube fullscreen`), and `ALL`, every one by its file's name. So a new
//! pass's shader is its WGSL file alone, with no list to add it to.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo::rerun-if-changed=shaders");
    if let Err(message) = write(&root, &out) {
        // A build script reports by panicking; the message names the file and what is wrong.
        panic!("{message}");
    }
}

fn write(root: &Path, out: &Path) -> Result<(), String> {
    let path = out.join("shaders.rs");
    std::fs::write(&path, shader_consts(root)?).map_err(|e| format!("writing {}: {e}", path.display()))
}

/// The files of `dir` whose name ends with `.{extension}`, sorted by name (so the generated
/// lists do not follow the file system's order).
fn files(dir: &Path, extension: &str) -> Result<Vec<PathBuf>, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("reading {}: {e}", dir.display()))?;
    let mut found = Vec::new();
    for entry in entries {
        let path = entry
            .map_err(|e| format!("reading {}: {e}", dir.display()))?
            .path();
        if path.is_file() && path.extension().is_some_and(|e| e == extension) {
            found.push(path);
        }
    }
    found.sort();
    Ok(found)
}

fn stem(path: &Path) -> Result<&str, String> {
    path.file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| {
            !s.is_empty()
                && s.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
        })
        .ok_or_else(|| format!("{}: a shader's file is named in lower_snake_case", path.display()))
}

/// `include_str!` of `relative` (a path under the crate's root), written with
/// `CARGO_MANIFEST_DIR` rather than this checkout's absolute path: the generated list names
/// files, and the sources come from the checkout that compiles it.
fn include(relative: &str) -> String {
    format!(
        "include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), {:?}))",
        format!("/{relative}")
    )
}

fn shader_consts(root: &Path) -> Result<String, String> {
    let dir = root.join("shaders");
    let common = dir.join("common");
    let mut code = String::new();
    let mut all = Vec::new();
    for path in files(&dir, "wgsl")? {
        let stem = stem(&path)?;
        let text = std::fs::read_to_string(&path).map_err(|e| format!("reading {}: {e}", path.display()))?;
        let mut lines = text.lines();
        let pieces: Vec<&str> = lines
            .next()
            .and_then(|first| first.strip_prefix("// after:"))
            .ok_or_else(|| {
                format!(
                    "{}: the first line names the pieces of shaders/common/ the pass is joined \
                     after, as `// after: frame cube` (or `// after:` for none)",
                    path.display()
                )
            })?
            .split_whitespace()
            .collect();
        // The const's documentation: the file's opening comment, up to its first empty line.
        let summary: Vec<&str> = lines
            .map_while(|line| line.strip_prefix("//"))
            .map(str::trim)
            .take_while(|line| !line.is_empty())
            .collect();
        if summary.is_empty() {
            return Err(format!(
                "{}: the second line opens a comment saying what the pass does",
                path.display()
            ));
        }
        let name = stem.to_ascii_uppercase();
        let joined = if pieces.is_empty() {
            String::new()
        } else {
            format!(", joined after `shaders/common/`'s {}", pieces.join(", "))
        };
        writeln!(code, "/// `shaders/{stem}.wgsl`{joined}:").unwrap();
        writeln!(code, "///").unwrap();
        for line in summary {
            writeln!(code, "#[doc = {:?}]", line).unwrap();
        }
        write!(code, "pub const {name}: &str = concat!(").unwrap();
        for piece in pieces {
            let piece_path = common.join(format!("{piece}.wgsl"));
            if !piece_path.is_file() {
                return Err(format!(
                    "{}: its first line names `{piece}`, and there is no {}",
                    path.display(),
                    piece_path.display()
                ));
            }
            write!(
                code,
                "{}, \"\\n\", ",
                include(&format!("shaders/common/{piece}.wgsl"))
            )
            .unwrap();
        }
        writeln!(code, "{}, \"\\n\");", include(&format!("shaders/{stem}.wgsl"))).unwrap();
        all.push(format!("({stem:?}, {name})"));
    }
    writeln!(
        code,
        "/// Every pass's composed source, by the name of its file in `shaders/`."
    )
    .unwrap();
    writeln!(code, "pub const ALL: &[(&str, &str)] = &[{}];", all.join(", ")).unwrap();
    Ok(code)
}
