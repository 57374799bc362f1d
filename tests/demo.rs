//! The interactive demo, run in a real window under Xvfb on the software adapter: its
//! `--screenshot` image has the window's size, shows the 3D view, and the split view's two
//! methods differ where the penumbra is. Without a display it exits with a plain message.
//!
//! The window tests need `xvfb-run` (`.ci/run` installs it). Where it is missing they are
//! skipped with a note, except under CI (the `CI` variable set), where that is a failure.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

fn demo_example() -> PathBuf {
    common::example_exe("demo")
}

fn have_xvfb() -> bool {
    let found = Command::new("sh")
        .args(["-c", "command -v xvfb-run"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !found {
        assert!(
            std::env::var_os("CI").is_none(),
            "xvfb-run is missing under CI: .ci/run must install xvfb and xauth"
        );
        eprintln!("skipped: xvfb-run is not installed (apt-get install xvfb xauth)");
    }
    found
}

/// Runs the demo under xvfb-run with `args`, killing it after `limit`.
fn run_in_xvfb(args: &[&str], limit: Duration) -> Output {
    let runtime = std::env::temp_dir().join(format!("penumbra-demo-runtime-{}", std::process::id()));
    std::fs::create_dir_all(&runtime).unwrap();
    let mut command = Command::new("timeout");
    command
        .arg(limit.as_secs().to_string())
        .args(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"])
        .arg(demo_example())
        .args(args)
        .env("XDG_RUNTIME_DIR", &runtime);
    let out = command.output().expect("run timeout/xvfb-run");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "the demo panicked:\n{stderr}");
    assert!(
        out.status.success(),
        "the demo failed ({}):\n{stderr}",
        out.status
    );
    out
}

struct Shot {
    image: image::RgbImage,
    /// The 3D view: x, y, width, height in pixels.
    view: [u32; 4],
    divider: u32,
}

fn screenshot(dir: &Path, name: &str, extra: &[&str]) -> Shot {
    let png = dir.join(format!("{name}.png"));
    let mut args = vec![
        "--screenshot",
        png.to_str().unwrap(),
        "--frames",
        "3",
        "--size",
        "960x640",
    ];
    args.extend_from_slice(extra);
    run_in_xvfb(&args, Duration::from_secs(300));
    let image = image::open(&png).unwrap().to_rgb8();
    let layout: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(png.with_extension("json")).unwrap()).unwrap();
    let view: Vec<u32> = layout["view"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap().round() as u32)
        .collect();
    assert_eq!(
        (image.width(), image.height()),
        (
            layout["width"].as_u64().unwrap() as u32,
            layout["height"].as_u64().unwrap() as u32
        )
    );
    Shot {
        image,
        view: [view[0], view[1], view[2], view[3]],
        divider: layout["divider"].as_f64().unwrap().round() as u32,
    }
}

fn luma(p: &image::Rgb<u8>) -> f32 {
    0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32
}

/// Pixels of the view whose x lies in `xs`, with their coordinates.
fn region(shot: &Shot, xs: std::ops::Range<u32>) -> Vec<(u32, u32)> {
    let [_, y0, _, h] = shot.view;
    xs.flat_map(|x| (y0..y0 + h).map(move |y| (x, y))).collect()
}

#[test]
fn split_view_screenshot_shows_both_methods() {
    if !have_xvfb() {
        return;
    }
    let dir = common::scratch_dir("demo_split");
    let split = screenshot(&dir, "ours_traditional", &["--split", "ours,traditional"]);
    let same = screenshot(&dir, "ours_ours", &["--split", "ours,ours"]);

    // The window's size (960x640 points at one pixel per point under Xvfb).
    assert_eq!(split.image.dimensions(), (960, 640));
    let [x0, y0, w, h] = split.view;
    assert!(w > 400 && h > 400, "view {:?} too small", split.view);
    assert!(x0 + w <= 960 && y0 + h <= 640);

    // The 3D view is there: not blank, not one color, with lit and shadowed parts.
    let lumas: Vec<f32> = region(&split, x0..x0 + w)
        .into_iter()
        .map(|(x, y)| luma(split.image.get_pixel(x, y)))
        .collect();
    let mean = lumas.iter().sum::<f32>() / lumas.len() as f32;
    let spread = (lumas.iter().map(|l| (l - mean).powi(2)).sum::<f32>() / lumas.len() as f32).sqrt();
    let distinct: std::collections::HashSet<[u8; 3]> = region(&split, x0..x0 + w)
        .into_iter()
        .map(|(x, y)| split.image.get_pixel(x, y).0)
        .collect();
    eprintln!(
        "view luma mean {mean:.1}, spread {spread:.1}, {} colors",
        distinct.len()
    );
    assert!(
        spread > 20.0,
        "the view is nearly uniform (luma spread {spread:.1})"
    );
    assert!(distinct.len() > 500, "only {} colors in the view", distinct.len());
    assert!(
        lumas.iter().filter(|l| **l < 60.0).count() > lumas.len() / 100,
        "no shadow in the view"
    );

    // Same camera, same light: the left halves (ours in both) match, and the right halves
    // (traditional vs ours) differ, in the shadow's soft edges.
    assert_eq!(split.divider, same.divider);
    let margin = 4;
    let diff = |xs: std::ops::Range<u32>| -> (usize, usize) {
        let pixels = region(&split, xs);
        let differing = pixels
            .iter()
            .filter(|(x, y)| {
                (luma(split.image.get_pixel(*x, *y)) - luma(same.image.get_pixel(*x, *y))).abs() > 6.0
            })
            .count();
        (differing, pixels.len())
    };
    let (left_diff, left_n) = diff(x0 + 70..split.divider - margin);
    let (right_diff, right_n) = diff(split.divider + margin..x0 + w - 90);
    eprintln!("differing pixels: left {left_diff}/{left_n}, right {right_diff}/{right_n}");
    assert!(
        left_diff * 1000 <= left_n,
        "the left halves (both ours) differ in {left_diff} pixels"
    );
    assert!(
        right_diff * 200 > right_n,
        "traditional and ours look the same on the right ({right_diff} of {right_n} pixels differ)"
    );
    // The differences sit in partly shadowed pixels, not in the fully lit or the umbra.
    let soft = region(&split, split.divider + margin..x0 + w - 90)
        .into_iter()
        .filter(|(x, y)| {
            (luma(split.image.get_pixel(*x, *y)) - luma(same.image.get_pixel(*x, *y))).abs() > 6.0
        })
        .filter(|(x, y)| {
            let l = luma(same.image.get_pixel(*x, *y)).min(luma(split.image.get_pixel(*x, *y)));
            l > 15.0
        })
        .count();
    assert!(
        soft * 2 > right_diff,
        "the differences are not in the penumbra ({soft} of {right_diff})"
    );
}

#[test]
fn intermediate_map_and_resizing_to_zero() {
    if !have_xvfb() {
        return;
    }
    let dir = common::scratch_dir("demo_map");
    let shot = screenshot(&dir, "distance", &["--map", "distance", "--exercise-resize"]);
    assert_eq!(shot.image.dimensions(), (960, 640));
    // The distance map's false colors: strongly saturated pixels in the view.
    let [x0, _, w, _] = shot.view;
    let saturated = region(&shot, x0..x0 + w)
        .into_iter()
        .filter(|(x, y)| {
            let p = shot.image.get_pixel(*x, *y).0;
            let (hi, lo) = (*p.iter().max().unwrap() as i32, *p.iter().min().unwrap() as i32);
            hi - lo > 120
        })
        .count();
    assert!(
        saturated > 5000,
        "no false-color distance map in the view ({saturated} saturated pixels)"
    );
}

/// The settings a screenshot run records load back with `--settings`, overriding `--split`.
#[test]
fn settings_saved_by_one_run_load_in_the_next() {
    if !have_xvfb() {
        return;
    }
    let dir = common::scratch_dir("demo_settings");
    screenshot(&dir, "first", &["--split", "pcss,hard", "--single"]);
    let saved = dir.join("first.settings.ron");
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(text.contains("Pcss") && text.contains("Hard"), "{text}");
    screenshot(
        &dir,
        "second",
        &[
            "--split",
            "ours,traditional",
            "--settings",
            saved.to_str().unwrap(),
        ],
    );
    let layout: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("second.json")).unwrap()).unwrap();
    assert_eq!(layout["left"], "pcss");
    assert_eq!(layout["right"], "hard");
    assert_eq!(layout["split"], false);
}

/// Further lights saved in the settings come back: the layout counts them, and the picture
/// changes where the second light's shadow falls.
#[test]
fn saved_settings_bring_further_lights() {
    if !have_xvfb() {
        return;
    }
    let dir = common::scratch_dir("demo_lights");
    let one = screenshot(&dir, "one", &["--single"]);
    let saved = std::fs::read_to_string(dir.join("one.settings.ron")).unwrap();
    assert!(saved.contains("more_lights: []"), "{saved}");
    let two_lights = saved.replace(
        "more_lights: []",
        "more_lights: [Directional((direction: (0.8, -1.0, 0.3), angular_diameter_deg: 2.0, \
         color: (1.0, 1.0, 1.0), intensity: 0.8))]",
    );
    let path = dir.join("two.ron");
    std::fs::write(&path, two_lights).unwrap();
    let two = screenshot(&dir, "two", &["--single", "--settings", path.to_str().unwrap()]);
    let layout: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("two.json")).unwrap()).unwrap();
    assert_eq!(layout["lights"], 2);
    let [x, y, w, h] = two.view;
    let changed = (y..y + h)
        .flat_map(|py| (x..x + w).map(move |px| (px, py)))
        .filter(|&(px, py)| {
            (luma(one.image.get_pixel(px, py)) - luma(two.image.get_pixel(px, py))).abs() > 3.0
        })
        .count();
    assert!(
        changed > 1000,
        "only {changed} pixels changed with a second light"
    );
}

#[test]
fn without_a_display_the_demo_says_so() {
    let out = Command::new(demo_example())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("DISPLAY") && stderr.contains("--example render"),
        "{stderr}"
    );
}

#[test]
fn bad_arguments_get_plain_errors() {
    for (args, needle) in [
        (&["--split", "ours"][..], "--split"),
        (&["--split", "ours,sharp"][..], "sharp"),
        (&["--map", "nothing"][..], "nothing"),
        (&["--render-scale", "2"][..], "--render-scale"),
        (&["--size", "10x10"][..], "--size"),
        (
            &["--settings", "no/such/settings.ron"][..],
            "no/such/settings.ron",
        ),
        (&["--settings", "Cargo.toml"][..], "Cargo.toml"),
    ] {
        let out = Command::new(demo_example()).args(args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
    }
}
