//! The headless `render` example, run as a user would: good invocations write the PNG asked
//! for; bad ones exit non-zero with a plain message naming what is wrong, never a panic.

mod common;

use std::path::PathBuf;
use std::process::Command;

/// `cargo test` builds the examples next to the test binaries: target/<profile>/examples/.
fn render_example() -> PathBuf {
    common::example_exe("render")
}

fn run(args: &[&str]) -> (bool, String) {
    let out = Command::new(render_example()).args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "the example panicked:\n{stderr}");
    (out.status.success(), stderr)
}

#[test]
fn renders_a_scene_file_and_a_model_to_png() {
    let dir = common::scratch_dir("render_example");
    let scene = common::asset("scenes/character.ron");
    let out = dir.join("character.png");
    let (ok, stderr) = run(&[
        "--scene",
        scene.to_str().unwrap(),
        "--view",
        "2",
        "--size",
        "160x120",
        "--method",
        "hard",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(image::image_dimensions(&out).unwrap(), (160, 120));

    let model = common::models().join("Fox.glb");
    let out = dir.join("fox.png");
    let (ok, stderr) = run(&[
        "--scene",
        model.to_str().unwrap(),
        "--view",
        "1",
        "--size",
        "96x64",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{stderr}");
    assert_eq!(image::image_dimensions(&out).unwrap(), (96, 64));
}

#[test]
fn bad_arguments_get_plain_errors() {
    let scene = common::asset("scenes/teapot.ron");
    let scene = scene.to_str().unwrap();
    for (args, needle) in [
        (vec!["--scene", "no/such/scene.ron"], "no/such/scene.ron"),
        (vec!["--scene", scene, "--size", "800by600"], "WIDTHxHEIGHT"),
        (vec!["--scene", scene, "--size", "0x600"], "at least 1"),
        (vec!["--scene", scene, "--method", "vsm"], "unknown method `vsm`"),
        (
            vec!["--scene", scene, "--view", "7"],
            "viewpoint 7 does not exist",
        ),
        (vec!["--scene", scene, "--shadow-map", "1000"], "power of two"),
        (
            vec!["--scene", scene, "--size", "32x24", "--time", "0"],
            "--time 0",
        ),
    ] {
        let (ok, stderr) = run(&args);
        assert!(!ok, "{args:?} should fail");
        assert!(
            stderr.contains(needle),
            "{args:?}: expected `{needle}` in:\n{stderr}"
        );
    }
}

#[test]
fn no_adapter_names_the_package_to_install() {
    // On Linux there is no DirectX 12: asking for it alone leaves no adapter at all.
    if !cfg!(target_os = "linux") {
        return;
    }
    let scene = common::asset("scenes/teapot.ron");
    let out = Command::new(render_example())
        .args(["--scene", scene.to_str().unwrap(), "--size", "8x8"])
        .env("WGPU_BACKEND", "dx12")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("no graphics adapter") && stderr.contains("mesa-vulkan-drivers"),
        "{stderr}"
    );
}

#[test]
fn every_method_and_debug_view_writes_a_png() {
    let dir = common::scratch_dir("render_example_methods");
    let scene = common::asset("scenes/teapot.ron");
    let scene = scene.to_str().unwrap();
    for method in ["ours", "ours-fast", "traditional", "pcss", "hard", "hw2x2"] {
        let out = dir.join(format!("{method}.png"));
        let (ok, stderr) = run(&[
            "--scene",
            scene,
            "--size",
            "64x48",
            "--method",
            method,
            "--light-size",
            "4",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{method}: {stderr}");
        assert_eq!(image::image_dimensions(&out).unwrap(), (64, 48));
        if method == "ours" {
            assert!(stderr.contains("took no shadow-map taps"), "{stderr}");
        }
    }
    for view in ["shadow-map", "fattened-map", "distance", "mask", "pcf", "blur"] {
        let out = dir.join(format!("debug-{view}.png"));
        let (ok, stderr) = run(&[
            "--scene",
            scene,
            "--size",
            "64x48",
            "--debug-view",
            view,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{view}: {stderr}");
        let image = image::open(&out).unwrap().to_rgba8();
        let first = *image.get_pixel(0, 0);
        assert!(
            image.pixels().any(|p| *p != first),
            "{view}: the debug view is one color"
        );
    }
}

#[test]
fn comparing_to_the_reference_prints_metrics_and_writes_a_heat_map() {
    let dir = common::scratch_dir("render_example_compare");
    let scene = common::asset("scenes/character.ron");
    let out = dir.join("ours.png");
    let output = Command::new(render_example())
        .args([
            "--scene",
            scene.to_str().unwrap(),
            "--size",
            "96x72",
            "--method",
            "ours",
        ])
        .args(["--compare-to-reference", "16", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stdout.contains("visibility RMSE") && stdout.contains("penumbra RMSE") && stdout.contains("FLIP"),
        "{stdout}"
    );
    assert_eq!(
        image::image_dimensions(dir.join("ours.heat.png")).unwrap(),
        (96, 72)
    );
}

#[test]
fn the_gl_backend_renders_every_real_time_method_and_refuses_the_rest_in_words() {
    let dir = common::scratch_dir("render_example_gl");
    let scene = common::asset("scenes/teapot.ron");
    let scene = scene.to_str().unwrap();
    let gl = |args: &[&str]| {
        let out = Command::new(render_example())
            .args(args)
            .env("WGPU_BACKEND", "gl")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!stderr.contains("panicked"), "{args:?} panicked on GL:\n{stderr}");
        (out.status.success(), stderr)
    };
    for method in ["ours", "ours-fast", "traditional", "pcss", "hard", "hw2x2"] {
        let out = dir.join(format!("{method}.png"));
        let (ok, stderr) = gl(&[
            "--scene",
            scene,
            "--size",
            "64x48",
            "--method",
            method,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{method} on GL: {stderr}");
    }
    // GL cannot render to R32F (the reference) nor copy depth (depth debug views): errors, not panics.
    let out = dir.join("x.png");
    let (ok, stderr) = gl(&[
        "--scene",
        scene,
        "--size",
        "64x48",
        "--method",
        "reference",
        "--samples",
        "4",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("`reference`"), "{stderr}");
    let (ok, stderr) = gl(&[
        "--scene",
        scene,
        "--size",
        "64x48",
        "--debug-view",
        "shadow-map",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok && stderr.contains("cannot be read back"), "{stderr}");
}

/// `--time N` prints the median frame and per-pass times of N frames, the light turning (every
/// pass runs) or, with `--still-light`, still (the light-space maps are kept).
#[test]
fn timing_prints_each_pass() {
    let dir = common::scratch_dir("render_example_time");
    let scene = common::asset("scenes/teapot.ron");
    let out = dir.join("timed.png");
    for still in [false, true] {
        let mut args = vec![
            "--scene",
            scene.to_str().unwrap(),
            "--size",
            "96x72",
            "--out",
            out.to_str().unwrap(),
            "--time",
            "3",
        ];
        if still {
            args.push("--still-light");
        }
        let output = Command::new(render_example()).args(&args).output().unwrap();
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        let stdout = String::from_utf8_lossy(&output.stdout);
        let line = stdout
            .lines()
            .find(|l| l.starts_with("time: 3 frames"))
            .unwrap_or_else(|| panic!("no timing line in:\n{stdout}"));
        for pass in ["distance map", "pcf", "blur", "composite"] {
            assert!(line.contains(pass), "{pass} missing from: {line}");
        }
        // The maps are drawn only when the light moves.
        assert_eq!(line.contains("fattened shadow map"), !still, "{line}");
    }
}

/// `--no-nearest-caster` reaches the settings: `ours`' image changes beside the teapot's shadow
/// (the search shortens the distance there), and only there.
#[test]
fn no_nearest_caster_turns_the_search_off() {
    let dir = common::scratch_dir("render_example_nearest");
    let scene = common::asset("scenes/teapot.ron");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "--scene",
            scene.to_str().unwrap(),
            "--size",
            "240x192",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let (ok, stderr) = run(&args);
        assert!(ok, "{stderr}");
        image::open(&out).unwrap().to_rgba8()
    };
    let with = render("with.png", &[]);
    let without = render("without.png", &["--no-nearest-caster"]);
    let differing = with
        .pixels()
        .zip(without.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 2))
        .count();
    let total = (with.width() * with.height()) as usize;
    assert!(differing > 0, "the flag changed nothing");
    assert!(
        differing < total / 20,
        "{differing} of {total} pixels differ: more than a penumbra's band"
    );
}
