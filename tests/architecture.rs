//! The crate's modules depend on each other one way: no module of `src` reaches another through
//! `crate::` paths that reaches it back, and the generic GPU helpers (`src/gpu_helpers.rs`) are
//! a leaf that reaches no other module. A module is a top-level file or folder of `src`; the
//! unit tests at the end of a file (`#[cfg(test)] mod tests`) and comments are left out, since
//! they may reach anywhere.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a file of `src` belongs to (`None` for the crate root).
fn module_of(file: &Path, src: &Path) -> Option<String> {
    let first = file.strip_prefix(src).ok()?.components().next()?;
    let name = first.as_os_str().to_str()?.trim_end_matches(".rs").to_string();
    (name != "lib").then_some(name)
}

/// The modules `text` names after `crate::`, each with the line it does so on (1-based).
fn references(text: &str) -> Vec<(String, usize)> {
    let code = match text.find("#[cfg(test)]\nmod tests") {
        Some(end) => &text[..end],
        None => text,
    };
    let mut found = Vec::new();
    for (number, line) in code.lines().enumerate() {
        let line = match line.find("//") {
            Some(comment) => &line[..comment],
            None => line,
        };
        for (at, _) in line.match_indices("crate::") {
            let name: String = line[at + "crate::".len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                found.push((name, number + 1));
            }
        }
    }
    found
}

/// The names the crate root re-exports (`pub use module::{A, B};` in `lib.rs`), each with the
/// name it comes from first (`crate::MAX_LIGHTS` reaches the module that defines it).
fn root_exports(lib: &str) -> BTreeMap<String, String> {
    let mut exports = BTreeMap::new();
    for statement in lib.split(';') {
        let Some(at) = statement.find("pub use ") else {
            continue;
        };
        let path = &statement[at + "pub use ".len()..];
        let Some((from, items)) = path.split_once("::") else {
            continue;
        };
        for item in items.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')) {
            if !item.is_empty() && item != "self" {
                exports.insert(item.to_string(), from.trim().to_string());
            }
        }
    }
    exports
}

/// Module -> the modules it reaches, each with one place that does so.
fn module_graph() -> BTreeMap<String, BTreeMap<String, String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let modules: BTreeSet<String> = files.iter().filter_map(|f| module_of(f, &src)).collect();
    let lib = std::fs::read_to_string(src.join("lib.rs")).expect("src/lib.rs");
    let exports = root_exports(&lib);
    // A name at the crate root: the module it is, or the module it is re-exported from.
    let resolve = |name: &str| {
        let mut name = name.to_string();
        for _ in 0..4 {
            if modules.contains(&name) {
                return Some(name);
            }
            name = exports.get(&name)?.clone();
        }
        None
    };
    let mut graph: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for file in files {
        let Some(module) = module_of(&file, &src) else {
            continue;
        };
        let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let edges = graph.entry(module.clone()).or_default();
        for (name, line) in references(&text) {
            let Some(target) = resolve(&name) else {
                continue;
            };
            if target != module {
                edges
                    .entry(target)
                    .or_insert_with(|| format!("{}:{line}", file.strip_prefix(&src).unwrap().display()));
            }
        }
    }
    graph
}

/// A circle through `graph`, as the modules on it, if there is one.
fn find_circle(graph: &BTreeMap<String, BTreeMap<String, String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeMap<String, String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            return Some(path[at..].to_vec());
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flat_map(|edges| edges.keys()) {
            if let Some(circle) = visit(next, graph, path, done) {
                return Some(circle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|start| visit(start, graph, &mut Vec::new(), &mut done))
}

#[test]
fn no_module_reaches_back_a_module_that_reaches_it() {
    let graph = module_graph();
    assert!(
        graph.len() > 10,
        "too few modules found in src: {:?}",
        graph.keys()
    );
    if let Some(circle) = find_circle(&graph) {
        let steps: Vec<String> = circle
            .iter()
            .zip(circle.iter().cycle().skip(1))
            .map(|(from, to)| format!("{from} -> {to} ({})", graph[from][to]))
            .collect();
        panic!("an import circle in src: {}", steps.join(", "));
    }
}

/// The convenience layer's modules: the scene model with its loaders and files, and the renderer.
const CONVENIENCE: [&str; 2] = ["scene", "renderer"];

#[test]
fn the_embedding_core_reaches_neither_the_scene_model_nor_the_renderer() {
    let graph = module_graph();
    assert!(
        graph.contains_key("scene") && graph.contains_key("lights"),
        "modules: {:?}",
        graph.keys()
    );
    let reaching: Vec<String> = graph
        .iter()
        .filter(|(module, _)| !CONVENIENCE.contains(&module.as_str()))
        .flat_map(|(module, edges)| {
            edges
                .iter()
                .filter(|(target, _)| CONVENIENCE.contains(&target.as_str()))
                .map(move |(target, at)| format!("{module} -> {target} ({at})"))
        })
        .collect();
    assert!(
        reaching.is_empty(),
        "the core reaches the convenience layer: {reaching:?}"
    );
}

#[test]
fn the_gpu_helpers_reach_no_other_module() {
    let graph = module_graph();
    let helpers = graph.get("gpu_helpers").expect("src/gpu_helpers.rs");
    assert!(helpers.is_empty(), "src/gpu_helpers.rs reaches {helpers:?}");
}

#[test]
fn the_circle_finder_finds_a_circle() {
    // The check itself can fail: a graph with a circle is reported.
    let mut graph: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    graph
        .entry("a".into())
        .or_default()
        .insert("b".into(), "a.rs:1".into());
    graph
        .entry("b".into())
        .or_default()
        .insert("c".into(), "b.rs:1".into());
    graph
        .entry("c".into())
        .or_default()
        .insert("a".into(), "c.rs:1".into());
    assert_eq!(
        find_circle(&graph),
        Some(vec!["a".to_string(), "b".to_string(), "c".to_string()])
    );
    graph.get_mut("c").unwrap().clear();
    assert_eq!(find_circle(&graph), None);
    assert_eq!(
        references("use crate::scene::Aabb; // crate::shadows\nlet x = crate::frame::f();"),
        vec![("scene".to_string(), 1), ("frame".to_string(), 2)]
    );
    let exports = root_exports("pub use scene::{\n    Aabb, Light,\n};\npub use shadows::MAX_LIGHTS;");
    assert_eq!(exports.get("Light").map(String::as_str), Some("scene"));
    assert_eq!(exports.get("MAX_LIGHTS").map(String::as_str), Some("shadows"));
}

/// The screen-space stages live in `src/screen/`, one module each, declared in its `mod.rs`,
/// and each method's chain in `src/screen/chains/`, which makes and wires them: a file of the
/// folder that no `mod` line names would be left out of the build without a word, and a stage
/// no chain makes would never run.
#[test]
fn every_screen_stage_is_declared_and_made_by_a_chain() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/screen");
    let front = std::fs::read_to_string(dir.join("mod.rs")).expect("src/screen/mod.rs");
    let mut chains = String::new();
    for entry in std::fs::read_dir(dir.join("chains")).expect("src/screen/chains") {
        let path = entry.expect("directory entry").path();
        chains += &std::fs::read_to_string(&path).unwrap();
    }
    assert!(
        chains.contains("pub(crate) struct ScreenChain"),
        "ScreenChain is not in src/screen/chains/"
    );
    let mut stages = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("src/screen") {
        let path = entry.expect("directory entry").path();
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        if stem == "mod" || path.extension().is_none_or(|e| e != "rs") {
            continue;
        }
        assert!(
            front.lines().any(|l| l.trim() == format!("mod {stem};")),
            "{} is not declared in src/screen/mod.rs",
            path.display()
        );
        let text = std::fs::read_to_string(&path).unwrap();
        for line in text.lines() {
            if let Some(rest) = line.strip_prefix("impl ScreenStage for ") {
                stages.push(rest.trim_end_matches(" {").trim_end_matches(" {}").to_string());
            }
        }
    }
    assert!(stages.len() >= 6, "too few stages found: {stages:?}");
    for stage in &stages {
        assert!(
            chains.contains(&format!("{stage}::new(")),
            "{stage} is a ScreenStage, and no chain of src/screen/chains/ makes one"
        );
    }
}

/// A new screen-space stage is four files (`docs/code.md`): its shader, its module, the `mod`
/// line in `src/screen/mod.rs` and the chain that runs it. Two real stages, the
/// variable-spacing PCF's draw and PCSS, are named in the code (comments aside) of no other file
/// of `src/`: nothing else has to know them.
#[test]
fn a_screen_stage_is_named_in_its_module_the_front_and_its_chain_only() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = root.join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    for (stage, shader, chain) in [
        ("VariablePcfPass", "variable_pcf", "ours"),
        ("PcssPass", "pcss", "single_pass"),
    ] {
        let mut naming: Vec<String> = files
            .iter()
            .filter(|f| {
                let text = std::fs::read_to_string(f).unwrap();
                text.lines()
                    .map(|l| l.split("//").next().unwrap_or_default())
                    .any(|code| code.contains(stage))
            })
            .map(|f| f.strip_prefix(&src).unwrap().display().to_string())
            .collect();
        naming.sort();
        let mut expected = vec![
            format!("screen/chains/{chain}.rs"),
            "screen/mod.rs".to_string(),
            format!("screen/{shader}.rs"),
        ];
        expected.sort();
        assert_eq!(naming, expected, "the files of src/ whose code names {stage}");
        assert!(root.join(format!("shaders/{shader}.wgsl")).exists());
    }
}

/// The lines of each function of `text` (from its `fn` line to its closing brace), by name. A
/// function is a line that starts, after `pub`, `pub(crate)` and the like, with `fn `.
fn function_lengths(text: &str) -> Vec<(String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let mut rest = lines[i].trim_start();
        for prefix in ["pub(crate) ", "pub(super) ", "pub ", "const ", "unsafe "] {
            rest = rest.strip_prefix(prefix).unwrap_or(rest);
        }
        let Some(signature) = rest.strip_prefix("fn ") else {
            i += 1;
            continue;
        };
        let name: String = signature
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let (mut depth, mut opened, mut j) = (0i32, false, i);
        while j < lines.len() {
            for c in lines[j].chars() {
                match c {
                    '{' => (depth, opened) = (depth + 1, true),
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if (opened && depth == 0) || (!opened && lines[j].trim_end().ends_with(';')) {
                break;
            }
            j += 1;
        }
        if opened {
            found.push((name, j - i + 1));
        }
        i = j + 1;
    }
    found
}

/// No function of `src/` is longer than 150 lines: a longer one does several things, each of
/// which wants its own name.
#[test]
fn no_function_in_src_is_longer_than_150_lines() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut long = Vec::new();
    let mut counted = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        for (name, lines) in function_lengths(&text) {
            counted += 1;
            if lines > 150 {
                long.push(format!("{}: {name} ({lines} lines)", file.display()));
            }
        }
    }
    assert!(counted > 500, "too few functions found: {counted}");
    assert!(long.is_empty(), "functions over 150 lines: {long:#?}");
    // The counter counts: a function of 3 lines and one of 152.
    let long_one = format!("fn long() {{\n{}}}\n", "    let _ = 1;\n".repeat(150));
    let sample = format!("pub(crate) fn short(a: u32) -> u32 {{\n    a\n}}\n{long_one}");
    assert_eq!(
        function_lengths(&sample),
        [("short".to_string(), 3), ("long".to_string(), 152)]
    );
}

/// Whether `text` is a plain front: module docs, `mod` lines and re-exports (with their
/// attributes and comments), nothing defined.
fn is_front(text: &str) -> Result<(), String> {
    let mut in_use = false;
    for (number, line) in text.lines().enumerate() {
        let line = line.trim();
        if in_use {
            in_use = !line.ends_with(';');
            continue;
        }
        let allowed = line.is_empty()
            || line.starts_with("//")
            || line.starts_with("#[")
            || line.starts_with("mod ")
            || line.starts_with("pub mod ")
            || line.starts_with("pub(crate) mod ")
            || line.starts_with("use ")
            || line.starts_with("pub use ")
            || line.starts_with("pub(crate) use ");
        if !allowed {
            return Err(format!("line {}: {line}", number + 1));
        }
        in_use = (line.contains("use ") && !line.starts_with("//")) && !line.ends_with(';');
    }
    Ok(())
}

/// Each folder of `src/` opens with a `mod.rs` that is a plain front (its modules and what it
/// re-exports), so that what the folder holds is read in one screen and its code lives in
/// files named for it.
#[test]
fn every_mod_rs_is_a_plain_front() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let fronts: Vec<_> = files.iter().filter(|f| f.ends_with("mod.rs")).collect();
    assert!(fronts.len() >= 8, "too few folders found: {fronts:?}");
    let not: Vec<String> = fronts
        .iter()
        .filter_map(|f| {
            let text = std::fs::read_to_string(f).unwrap();
            is_front(&text).err().map(|e| format!("{}: {e}", f.display()))
        })
        .collect();
    assert!(not.is_empty(), "mod.rs files that define things: {not:#?}");
    assert!(is_front("//! Docs.\n\nmod a;\npub use a::{\n    B, C,\n};\n").is_ok());
    assert!(is_front("mod a;\n\npub struct S;\n").is_err());
}
