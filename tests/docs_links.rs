//! Every relative link and image of the README and the `docs/` pages resolves to a file of the
//! repository (web links and links inside a page are not checked).

use std::path::{Path, PathBuf};

/// The Markdown files: the README and every `.md` under `docs/`.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = vec![root.join("README.md")];
    walk(&root.join("docs"), &mut out);
    out
}

/// The targets of the `[text](target)` and `![alt](target)` links in `text` outside code, each
/// with its line (1-based).
fn link_targets(text: &str) -> Vec<(String, usize)> {
    let mut found = Vec::new();
    let mut in_code = false;
    for (number, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        for (at, _) in line.match_indices("](") {
            let rest = &line[at + 2..];
            if let Some(end) = rest.find(')') {
                found.push((rest[..end].trim().to_string(), number + 1));
            }
        }
    }
    found
}

#[test]
fn every_relative_link_and_image_resolves() {
    let pages = pages();
    assert!(pages.len() > 10, "too few pages: {pages:?}");
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap();
        for (target, line) in link_targets(&text) {
            if target.is_empty()
                || target.starts_with('#')
                || target.starts_with("http://")
                || target.starts_with("https://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            let file = target.split('#').next().unwrap_or_default();
            let resolved = page.parent().unwrap().join(file);
            checked += 1;
            if !resolved.exists() {
                broken.push(format!("{}:{line}: {target}", page.display()));
            }
        }
    }
    assert!(checked > 20, "only {checked} relative links found");
    assert!(
        broken.is_empty(),
        "links that lead nowhere:\n{}",
        broken.join("\n")
    );
}

#[test]
fn the_readme_is_a_front_page() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 180,
        "README.md has {lines} lines; new material goes into docs/"
    );
    // The two set-up commands CI and newcomers run.
    assert!(readme.contains("cargo run --release --example demo"));
    assert!(readme.contains(
        "cargo test --locked && cargo +nightly test --locked -p penumbra-bevy --ignore-rust-version"
    ));
}

/// CI installs what the README tells a newcomer to install, no more and no less, and runs the
/// README's test command.
#[test]
fn ci_installs_the_readmes_prerequisites_and_runs_its_test_command() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let ci = std::fs::read_to_string(root.join(".ci/run")).unwrap();
    let words = |line: &str| -> Vec<String> {
        let mut words: Vec<String> = line.split_whitespace().map(str::to_string).collect();
        words.sort();
        words
    };
    let ci_packages = ci
        .lines()
        .find_map(|l| l.strip_prefix("PACKAGES=\""))
        .and_then(|l| l.strip_suffix('"'))
        .expect(".ci/run sets PACKAGES=\"...\"");
    // The README's packages: every `apt-get install` of its set-up section.
    let setup = &readme[readme.find("## Set-up").expect("a set-up section")..];
    let setup = &setup[..setup[3..].find("\n## ").map_or(setup.len(), |end| end + 3)];
    // Shell continuation lines joined.
    let setup = setup.replace("\\\n", " ");
    let mut readme_packages: Vec<String> = setup
        .lines()
        .filter_map(|l| l.split("apt-get install").nth(1))
        .flat_map(str::split_whitespace)
        .map(|w| w.trim_end_matches(['`', ';', ',']).to_string())
        .filter(|w| !w.starts_with('-'))
        .collect();
    readme_packages.sort();
    readme_packages.dedup();
    assert_eq!(
        readme_packages,
        words(ci_packages),
        "the README's set-up installs other packages than .ci/run"
    );
    let command =
        "cargo test --locked && cargo +nightly test --locked -p penumbra-bevy --ignore-rust-version";
    assert!(readme.contains(command));
    let last = ci.lines().rev().find(|l| !l.trim().is_empty()).unwrap();
    assert_eq!(
        last.trim(),
        command,
        ".ci/run's last line is the README's test command"
    );
}

#[test]
fn the_link_finder_finds_links_and_skips_code() {
    let text = "see [a](docs/a.md) and ![b](b.png#x)\n```\n[c](c.md)\n```\n[d](https://x.y)";
    assert_eq!(
        link_targets(text),
        vec![
            ("docs/a.md".to_string(), 1),
            ("b.png#x".to_string(), 1),
            ("https://x.y".to_string(), 5)
        ]
    );
}
