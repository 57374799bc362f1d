//! Every WGSL file in `shaders/` parses and validates with naga (no GPU needed), and declares
//! the entry points the passes use.

use std::path::Path;

fn validate(path: &Path) -> naga::Module {
    let source = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| {
        panic!(
            "{} does not parse:\n{}",
            path.display(),
            e.emit_to_string(&source)
        )
    });
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| {
        panic!(
            "{} does not validate:\n{}",
            path.display(),
            e.emit_to_string(&source)
        )
    });
    module
}

#[test]
fn every_shader_validates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).expect("shaders/ exists") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            validate(&path);
            count += 1;
        }
    }
    assert!(
        count >= 2,
        "expected at least the shadow map and forward shaders, found {count}"
    );
}

#[test]
fn passes_find_their_entry_points() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    for (file, entry_points) in [
        ("shadow_map.wgsl", &["vs_opaque", "vs_masked", "fs_masked"][..]),
        ("forward.wgsl", &["vs_main", "fs_main"][..]),
        ("fattened_shadow_map.wgsl", &["vs_main"][..]),
        ("distance_map.wgsl", &["vs_main", "fs_depth", "fs_distance"][..]),
        ("pcf.wgsl", &["vs_fullscreen", "fs_main"][..]),
        ("blur.wgsl", &["vs_fullscreen", "fs_main"][..]),
        ("pcss.wgsl", &["vs_fullscreen", "fs_main"][..]),
        ("composite.wgsl", &["vs_main", "fs_main"][..]),
        ("reference.wgsl", &["vs_fullscreen", "fs_main"][..]),
    ] {
        let module = validate(&dir.join(file));
        for name in entry_points {
            assert!(
                module.entry_points.iter().any(|e| e.name == *name),
                "{file} has no entry point {name}"
            );
        }
    }
}

#[test]
fn opaque_shadow_shader_is_depth_only() {
    // The opaque caster shader must stay minimal: a vertex stage reading only the position.
    let module = validate(&Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/shadow_map.wgsl"));
    let vs = module
        .entry_points
        .iter()
        .find(|e| e.name == "vs_opaque")
        .unwrap();
    assert_eq!(
        vs.function.arguments.len(),
        1,
        "vs_opaque should take the position only"
    );
}
