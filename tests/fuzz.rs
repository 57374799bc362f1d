//! Fuzz-style tests of everything that reads user files: the OBJ and glTF loaders on mutated
//! bytes of the real models in `assets/models`, and the scene-file parser and builder on
//! mutated text of the project's own scenes. Every input must give `Ok` or an error naming the
//! file; nothing may panic out of the loader, hang, or allocate without bound.
//!
//! Mutations: bit flips, byte overwrites, truncation, duplicated and inserted runs, and numbers
//! replaced by extremes (`-1`, `4294967295`, `1e38`, `nan`, ...) or, length-preserving for the
//! binary glTF, by runs of nines (huge counts and offsets). The number of cases per input is
//! `PENUMBRA_FUZZ_CASES` (default 512), so CI stays bounded; raise it for a longer run.

mod common;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

#[derive(Debug, Clone)]
enum Mutation {
    FlipBit {
        at: f64,
        bit: u8,
    },
    SetByte {
        at: f64,
        byte: u8,
    },
    Truncate {
        at: f64,
    },
    Duplicate {
        at: f64,
        len: usize,
    },
    Insert {
        at: f64,
        bytes: Vec<u8>,
    },
    /// Replace the digits of the next number by an extreme value (changes the length).
    ExtremeNumber {
        at: f64,
        value: usize,
    },
    /// Replace the digits of the next number by nines (keeps the length).
    Nines {
        at: f64,
    },
}

const EXTREMES: [&str; 9] = [
    "0",
    "-1",
    "4294967295",
    "-2147483648",
    "1e38",
    "nan",
    "inf",
    "999999999999",
    "0.0",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    let at = 0.0..1.0f64;
    prop_oneof![
        (at.clone(), 0u8..8).prop_map(|(at, bit)| Mutation::FlipBit { at, bit }),
        (at.clone(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        at.clone().prop_map(|at| Mutation::Truncate { at }),
        (at.clone(), 1usize..64).prop_map(|(at, len)| Mutation::Duplicate { at, len }),
        (at.clone(), proptest::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        (at.clone(), 0..EXTREMES.len()).prop_map(|(at, value)| Mutation::ExtremeNumber { at, value }),
        at.prop_map(|at| Mutation::Nines { at }),
    ]
}

/// The run of digits at or after `from`.
fn next_number(bytes: &[u8], from: usize) -> Option<std::ops::Range<usize>> {
    let start = from + bytes.get(from..)?.iter().position(u8::is_ascii_digit)?;
    let len = bytes[start..].iter().take_while(|b| b.is_ascii_digit()).count();
    Some(start..start + len)
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation, binary: bool) {
    if bytes.is_empty() {
        return;
    }
    let pos = |at: f64| ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
    match m {
        Mutation::FlipBit { at, bit } => {
            let i = pos(*at);
            bytes[i] ^= 1 << bit;
        }
        Mutation::SetByte { at, byte } => {
            let i = pos(*at);
            bytes[i] = *byte;
        }
        Mutation::Truncate { at } => {
            let i = pos(*at);
            bytes.truncate(i);
        }
        Mutation::Duplicate { at, len } => {
            let i = pos(*at);
            let run: Vec<u8> = bytes[i..(i + len).min(bytes.len())].to_vec();
            let j = i.min(bytes.len());
            bytes.splice(j..j, run);
        }
        Mutation::Insert { at, bytes: new } => {
            let i = pos(*at);
            bytes.splice(i..i, new.iter().copied());
        }
        Mutation::ExtremeNumber { at, value } if !binary => {
            if let Some(r) = next_number(bytes, pos(*at)) {
                bytes.splice(r, EXTREMES[*value].bytes());
            }
        }
        Mutation::ExtremeNumber { at, .. } | Mutation::Nines { at } => {
            if let Some(r) = next_number(bytes, pos(*at)) {
                for b in &mut bytes[r] {
                    *b = b'9';
                }
            }
        }
    }
}

fn cases() -> u32 {
    std::env::var("PENUMBRA_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(512)
}

/// Panics raised anywhere (including inside third-party parsers, where the loader's guard
/// turns them into errors), counted to be reported.
static PANICS: AtomicUsize = AtomicUsize::new(0);

fn count_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            PANICS.fetch_add(1, Ordering::SeqCst);
            if std::env::var_os("PENUMBRA_FUZZ_VERBOSE").is_some() {
                previous(info);
            }
        }));
    });
}

/// Runs `load` on `cases()` mutations of `original` written to a file named like `name`.
/// Returns (accepted, rejected).
fn fuzz(name: &str, original: &[u8], binary: bool, load: impl Fn(&Path) -> Result<(), String>) -> (u32, u32) {
    count_panics();
    let dir = common::scratch_dir(&format!("fuzz_{name}"));
    let path = dir.join(name);
    let mut runner = TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    });
    let counts = std::cell::Cell::new((0u32, 0u32));
    let result = runner.run(&proptest::collection::vec(mutation(), 1..6), |mutations| {
        let mut bytes = original.to_vec();
        for m in &mutations {
            apply(&mut bytes, m, binary);
        }
        std::fs::write(&path, &bytes).unwrap();
        let (ok, err) = counts.get();
        match load(&path) {
            Ok(()) => counts.set((ok + 1, err)),
            Err(message) => {
                prop_assert!(
                    message.contains(name) || message.contains("scene"),
                    "the error does not name the file: {message}"
                );
                counts.set((ok, err + 1));
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    counts.get()
}

fn load_model(path: &Path) -> Result<(), String> {
    let model = penumbra::load_model(path).map_err(|e| e.to_string())?;
    // A loaded model must be usable: finite bounds, indices in range.
    for mesh in &model.meshes {
        for index in &mesh.indices {
            assert!(
                (*index as usize) < mesh.vertex_count(),
                "index out of range in {}",
                path.display()
            );
        }
    }
    Ok(())
}

fn shared_model(file: &str) -> Option<Vec<u8>> {
    let path: PathBuf = common::models().join(file);
    match std::fs::read(&path) {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            assert!(
                std::env::var_os("CI").is_none(),
                "{} missing under CI: {e}",
                path.display()
            );
            eprintln!("skipped: {} ({e})", path.display());
            None
        }
    }
}

#[test]
fn mutated_obj_files_load_or_fail_cleanly() {
    for file in ["teapot.obj", "spot.obj"] {
        let Some(bytes) = shared_model(file) else { continue };
        let before = PANICS.load(Ordering::SeqCst);
        let (ok, err) = fuzz(file, &bytes, false, load_model);
        eprintln!(
            "{file}: {ok} loaded, {err} rejected, {} parser panics contained",
            PANICS.load(Ordering::SeqCst) - before
        );
        assert!(
            err > 0,
            "no mutation of {file} was rejected: the mutations do nothing"
        );
    }
}

#[test]
fn mutated_gltf_binaries_load_or_fail_cleanly() {
    for file in ["Fox.glb", "CornellBox.glb"] {
        let Some(bytes) = shared_model(file) else { continue };
        let before = PANICS.load(Ordering::SeqCst);
        let (ok, err) = fuzz(file, &bytes, true, load_model);
        eprintln!(
            "{file}: {ok} loaded, {err} rejected, {} parser panics contained",
            PANICS.load(Ordering::SeqCst) - before
        );
        assert!(
            err > 0,
            "no mutation of {file} was rejected: the mutations do nothing"
        );
    }
}

#[test]
fn mutated_scene_files_parse_or_fail_cleanly() {
    for file in ["teapot.ron", "character.ron"] {
        let text = std::fs::read(common::asset(&format!("scenes/{file}"))).unwrap();
        let (ok, err) = fuzz(file, &text, false, |path| {
            let scene = penumbra::load_scene(path).map_err(|e| e.to_string())?;
            scene
                .validate()
                .map_err(|e| format!("scene {}: {e}", path.display()))?;
            Ok(())
        });
        eprintln!("{file}: {ok} built, {err} rejected");
        assert!(err > 0 && ok + err == cases());
    }
}
