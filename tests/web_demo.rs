//! The web demo in a real browser: `penumbra-web`'s serve command builds the demo for
//! wasm32-unknown-unknown and serves it on 127.0.0.1; headless Chromium (WebGPU on its
//! SwiftShader adapter), driven through chromedriver's WebDriver protocol, opens the teapot's
//! view 0 with `ours` and then with `hard`, waits for frames drawn, and takes a screenshot. The
//! canvas must show what the renderer draws natively (lavapipe) for the same scene, view, size
//! and method, and switching the method must change the shadow as it changes natively. Then the
//! split view (`ours` left, `hard` right): each side its method's native frame.
//!
//! Needs Debian's `chromium` and `chromium-driver` and the wasm32 target (the README's
//! prerequisites; `.ci/run` installs them). The build takes a target directory of its own
//! (`target/web-demo`).

mod common;

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use penumbra::{Quality, ShadowMethod, ShadowSettings, load_scene};
use serde_json::{Value, json};

/// The canvas's place on the page (`penumbra-web/static/index.html`: 12 px of padding) and size.
const CANVAS: (u32, u32, u32, u32) = (12, 12, 800, 600);

/// A child process killed when dropped.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// Starts the serve command; returns it and the address it serves.
fn serve(root: &Path, out: &Path) -> (Running, String) {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut child = Command::new(cargo)
        .current_dir(root)
        // Its own profile: the bindings generator unoptimised, which builds in a third of the
        // time (Cargo.toml, `profile.web-serve`).
        .args([
            "run",
            "--locked",
            "--profile",
            "web-serve",
            "-p",
            "penumbra-web",
            "--bin",
            "serve",
        ])
        .args(["--", "--port", "0", "--out"])
        .arg(out)
        .env("CARGO_TARGET_DIR", root.join("target").join("web-demo"))
        .stdout(Stdio::piped())
        .spawn()
        .expect("cargo runs");
    let stdout = child.stdout.take().unwrap();
    let running = Running(child);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let deadline = Instant::now() + Duration::from_secs(1500);
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        let line = rx
            .recv_timeout(left)
            .expect("the serve command printed no address (it failed to build or to listen: see above)");
        if let Some(at) = line.find("http://") {
            let address = line[at..].split_whitespace().next().unwrap().to_string();
            return (running, address);
        }
    }
}

/// One WebDriver request to chromedriver on `port`; the JSON it answers.
fn webdriver(port: u16, method: &str, path: &str, body: Option<Value>) -> Value {
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    let mut stream = TcpStream::connect(("127.0.0.1", port)).expect("chromedriver listens");
    stream.set_read_timeout(Some(Duration::from_secs(300))).unwrap();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    // The head, then a body of Content-Length bytes or in chunks (chromedriver may keep the
    // connection open whatever the request says).
    let mut reader = BufReader::new(stream);
    let mut length = None;
    let mut chunked = false;
    loop {
        let mut line = String::new();
        reader.read_line(&mut line).unwrap();
        let lower = line.to_ascii_lowercase();
        if let Some(v) = lower.strip_prefix("content-length:") {
            length = v.trim().parse::<usize>().ok();
        }
        chunked |= lower.starts_with("transfer-encoding:") && lower.contains("chunked");
        if line == "\r\n" || line.is_empty() {
            break;
        }
    }
    let mut payload = Vec::new();
    if chunked {
        loop {
            let mut size = String::new();
            reader.read_line(&mut size).unwrap();
            let n = usize::from_str_radix(size.trim(), 16).unwrap_or(0);
            if n == 0 {
                break;
            }
            let mut chunk = vec![0; n + 2];
            reader.read_exact(&mut chunk).unwrap();
            payload.extend_from_slice(&chunk[..n]);
        }
    } else if let Some(n) = length {
        payload.resize(n, 0);
        reader.read_exact(&mut payload).unwrap();
    } else {
        reader.read_to_end(&mut payload).unwrap();
    }
    let payload = String::from_utf8_lossy(&payload);
    let value: Value =
        serde_json::from_str(&payload).unwrap_or_else(|e| panic!("chromedriver: {e}: {payload}"));
    assert!(
        value["value"]["error"].is_null(),
        "chromedriver refused {method} {path}: {}",
        value["value"]
    );
    value
}

/// Opens `url` in a new headless Chromium, waits until the page has drawn `frames` frames and
/// returns the canvas as the screenshot shows it.
/// The whole page is saved as `name` in the tests' output directory.
fn screenshot(driver: u16, url: &str, frames: u32, name: &str) -> image::RgbaImage {
    let args = [
        "--headless=new",
        "--no-sandbox",
        "--enable-unsafe-webgpu",
        "--enable-features=Vulkan",
        "--use-vulkan=swiftshader",
        "--use-webgpu-adapter=swiftshader",
        "--use-gl=angle",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--window-size=1200,800",
    ];
    let session = webdriver(
        driver,
        "POST",
        "/session",
        Some(json!({"capabilities": {"alwaysMatch": {"goog:chromeOptions": {"args": args}}}})),
    );
    let id = session["value"]["sessionId"].as_str().unwrap().to_string();
    webdriver(
        driver,
        "POST",
        &format!("/session/{id}/url"),
        Some(json!({ "url": url })),
    );
    let started = Instant::now();
    let status = loop {
        let state = webdriver(
            driver,
            "POST",
            &format!("/session/{id}/execute/sync"),
            Some(json!({
                "script": "return [document.body.dataset.frames || '0', document.getElementById('status').textContent]",
                "args": []
            })),
        );
        let drawn: u32 = state["value"][0].as_str().unwrap_or("0").parse().unwrap_or(0);
        let status = state["value"][1].as_str().unwrap_or("").to_string();
        assert!(!status.starts_with("error"), "{url}: the page says {status}");
        if drawn >= frames {
            break status;
        }
        assert!(
            started.elapsed() < Duration::from_secs(180),
            "{url}: {drawn} frames in 3 minutes; the page says {status}"
        );
        std::thread::sleep(Duration::from_millis(500));
    };
    eprintln!(
        "{url}: {status}, {frames} frames after {:.1} s",
        started.elapsed().as_secs_f32()
    );
    let shot = webdriver(driver, "GET", &format!("/session/{id}/screenshot"), None);
    webdriver(driver, "DELETE", &format!("/session/{id}"), None);
    use base64::Engine;
    let png = base64::engine::general_purpose::STANDARD
        .decode(shot["value"].as_str().unwrap())
        .unwrap();
    let page = image::load_from_memory(&png).unwrap().to_rgba8();
    page.save(common::output_dir().join(name)).unwrap();
    let (x, y, w, h) = CANVAS;
    assert!(
        page.width() >= x + w && page.height() >= y + h,
        "the screenshot ({}x{}) does not hold the canvas",
        page.width(),
        page.height()
    );
    image::imageops::crop_imm(&page, x, y, w, h).to_image()
}

/// Each pixel's luminance in [0, 1] (of the 8-bit, sRGB-encoded values).
fn luminance(image: &image::RgbaImage) -> Vec<f32> {
    image
        .pixels()
        .map(|p| (0.2126 * p[0] as f32 + 0.7152 * p[1] as f32 + 0.0722 * p[2] as f32) / 255.0)
        .collect()
}

/// The mean absolute difference of two luminance images, and the share of pixels that differ
/// by more than 0.05.
fn difference(a: &[f32], b: &[f32]) -> (f32, f32) {
    let n = a.len() as f32;
    let mean = a.iter().zip(b).map(|(x, y)| (x - y).abs()).sum::<f32>() / n;
    let far = a.iter().zip(b).filter(|(x, y)| (*x - *y).abs() > 0.05).count() as f32 / n;
    (mean, far)
}

#[test]
fn the_web_demo_draws_the_teapots_soft_shadow_in_headless_chromium() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for tool in ["chromium", "chromedriver"] {
        assert!(
            Command::new(tool).arg("--version").output().is_ok(),
            "`{tool}` is not installed: `apt-get install chromium chromium-driver` (the README's prerequisites)"
        );
    }
    let out = common::scratch_dir("web_demo");
    let (_server, address) = serve(root, &out);
    let port = free_port();
    let _driver = Running(
        Command::new("chromedriver")
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .spawn()
            .expect("chromedriver starts"),
    );
    let started = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            started.elapsed() < Duration::from_secs(30),
            "chromedriver does not listen"
        );
        std::thread::sleep(Duration::from_millis(100));
    }

    let scene = load_scene(&common::asset("scenes/teapot.ron")).unwrap();
    let camera = scene.view(0).unwrap();
    let gpu = common::gpu();
    let (_, _, w, h) = CANVAS;
    let mut web = Vec::new();
    let mut native = Vec::new();
    for method in [ShadowMethod::Ours, ShadowMethod::Hard] {
        // Three frames: the first draws the light's maps, the ones after reuse them, as a
        // user's frames do.
        let page = screenshot(
            port,
            &format!(
                "{address}?scene=teapot&view=0&method={}&compare=none&frames=3",
                method.name()
            ),
            3,
            &format!("web_demo_page_{}.png", method.name()),
        );
        let here = common::render(
            &gpu,
            &scene,
            &camera,
            ShadowSettings::preset(method, Quality::Medium),
            w,
            h,
        );
        page.save(common::output_dir().join(format!("web_demo_{}.png", method.name())))
            .unwrap();
        let (a, b) = (luminance(&page), luminance(&here));
        let (mean, far) = difference(&a, &b);
        eprintln!(
            "{}: the canvas against the native frame: mean |difference| {mean:.4}, {:.3}% of pixels off by more than 0.05",
            method.name(),
            far * 100.0
        );
        // The same shaders on another rasterizer (SwiftShader against lavapipe): the first
        // runs read 0.0002 and 0.01%. The bounds leave room for rounding at edges, not for
        // another picture: the native frame against itself moved by one pixel reads 0.0014
        // and 0.36%, `ours` against `hard` natively 0.0011 and 0.86%.
        assert!(
            mean < 0.001,
            "{}: the canvas differs from the native frame by {mean} on average",
            method.name()
        );
        assert!(
            far < 0.002,
            "{}: {:.2}% of the canvas differs from the native frame",
            method.name(),
            far * 100.0
        );
        web.push(a);
        native.push(b);
    }
    // Switching from hard shadows to `ours` softens the shadow's edges: the pixels that change,
    // and by how much, must be what they are natively.
    let changed = |ours: &[f32], hard: &[f32]| {
        let n = ours
            .iter()
            .zip(hard)
            .filter(|(o, h)| (*o - *h).abs() > 0.03)
            .count();
        let sum: f32 = ours.iter().zip(hard).map(|(o, h)| (o - h).abs()).sum();
        (n, sum)
    };
    let (web_n, web_sum) = changed(&web[0], &web[1]);
    let (native_n, native_sum) = changed(&native[0], &native[1]);
    eprintln!(
        "ours against hard: {web_n} pixels change in the browser, {native_n} natively (summed {web_sum:.1} and {native_sum:.1})"
    );
    assert!(
        native_n > 2000,
        "natively, ours and hard differ on only {native_n} pixels"
    );
    assert!(
        (web_n as f32 / native_n as f32 - 1.0).abs() < 0.05 && (web_sum / native_sum - 1.0).abs() < 0.05,
        "switching the method changes {web_n} pixels (summed {web_sum}) in the browser, {native_n} ({native_sum}) natively"
    );
    // The room, lit by a point light, a spot and a rectangle (the area light's shading and
    // anisotropic kernels through the browser's shader compiler): its canvas against the
    // native frame.
    let room = load_scene(&common::asset("scenes/room.ron")).unwrap();
    let page = screenshot(
        port,
        &format!("{address}?scene=room&view=0&method=ours&compare=none&frames=3"),
        3,
        "web_demo_page_room.png",
    );
    let here = common::render(
        &gpu,
        &room,
        &room.view(0).unwrap(),
        ShadowSettings::preset(ShadowMethod::Ours, Quality::Medium),
        w,
        h,
    );
    let (mean, far) = difference(&luminance(&page), &luminance(&here));
    eprintln!(
        "room: the canvas against the native frame: mean |difference| {mean:.4}, {:.3}% of pixels off by more than 0.05",
        far * 100.0
    );
    assert!(
        mean < 0.001 && far < 0.002,
        "room: the canvas differs from the native frame: {mean}, {far}"
    );
    // The split view: `ours` left of the divider at 0.4 of the width, `hard` right of it. Each
    // side must be its method's native frame there.
    let page = screenshot(
        port,
        &format!("{address}?scene=teapot&view=0&method=ours&compare=hard&divider=0.4&frames=3"),
        3,
        "web_demo_page_split.png",
    );
    let split = luminance(&page);
    let divider = (0.4 * w as f32).round() as usize;
    let side = |image: &[f32], right: bool| -> Vec<f32> {
        image
            .chunks(w as usize)
            .flat_map(|row| if right { &row[divider..] } else { &row[..divider] })
            .copied()
            .collect()
    };
    for (right, name, expected) in [(false, "ours", &native[0]), (true, "hard", &native[1])] {
        let (mean, far) = difference(&side(&split, right), &side(expected, right));
        eprintln!(
            "split view, {name}'s side: mean |difference| {mean:.4}, {:.3}% off by more than 0.05",
            far * 100.0
        );
        assert!(
            mean < 0.001 && far < 0.002,
            "the split view's {name} side differs from the native frame: {mean}, {far}"
        );
    }
}
