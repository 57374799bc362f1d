//! `cargo run -p penumbra-web --bin serve [-- --port 8080] [--out DIR] [--build-only]`:
//! builds the web demo (the `penumbra-web` library for wasm32-unknown-unknown, in release),
//! writes its JavaScript bindings beside the page (`wasm-bindgen`'s library, so nothing else
//! needs installing), and serves the page on http://127.0.0.1:PORT/ until stopped. Port 0 takes
//! any free port; the first line printed names the address.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    if let Err(e) = native::run() {
        eprintln!("serve: {e}");
        std::process::exit(1);
    }
}

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::io::{BufRead, BufReader, Write};
    use std::net::{TcpListener, TcpStream};
    use std::path::{Path, PathBuf};
    use std::process::Command;

    const PAGE: &str = include_str!("../static/index.html");

    struct Args {
        port: u16,
        out: PathBuf,
        build_only: bool,
    }

    fn workspace() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .expect("penumbra-web lies in the workspace")
            .to_path_buf()
    }

    fn args() -> Result<Args, String> {
        let mut out = Args {
            port: 8080,
            out: workspace().join("target").join("penumbra-web"),
            build_only: false,
        };
        let mut it = std::env::args().skip(1);
        while let Some(a) = it.next() {
            match a.as_str() {
                "--port" => {
                    let v = it.next().ok_or("--port needs a number")?;
                    out.port = v.parse().map_err(|_| format!("--port {v}: expected 0-65535"))?;
                }
                "--out" => out.out = it.next().ok_or("--out needs a directory")?.into(),
                "--build-only" => out.build_only = true,
                other => {
                    return Err(format!(
                        "unknown argument `{other}`; expected --port N, --out DIR or --build-only"
                    ));
                }
            }
        }
        Ok(out)
    }

    pub fn run() -> Result<(), String> {
        let args = args()?;
        build(&args.out)?;
        if args.build_only {
            println!("built {}", args.out.display());
            return Ok(());
        }
        serve(&args.out, args.port)
    }

    /// Builds the module, binds it and writes the page into `out`.
    fn build(out: &Path) -> Result<(), String> {
        let root = workspace();
        let target_dir = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| root.join("target"));
        let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
        eprintln!("serve: building the web demo for wasm32-unknown-unknown (release)...");
        let status = Command::new(&cargo)
            .current_dir(&root)
            .args([
                "build",
                "--release",
                "--locked",
                "-p",
                "penumbra-web",
                "--lib",
                "--target",
                "wasm32-unknown-unknown",
            ])
            .arg("--target-dir")
            .arg(&target_dir)
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !status.success() {
            return Err(format!(
                "cargo build for wasm32-unknown-unknown failed ({status}); is the target installed? \
                 `rustup target add wasm32-unknown-unknown`"
            ));
        }
        let wasm = target_dir.join("wasm32-unknown-unknown/release/penumbra_web.wasm");
        std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
        let mut bindgen = wasm_bindgen_cli_support::Bindgen::new();
        bindgen
            .input_path(&wasm)
            .web(true)
            .map_err(|e| format!("wasm-bindgen: {e}"))?
            .typescript(false)
            .omit_default_module_path(false)
            .generate(out)
            .map_err(|e| format!("wasm-bindgen on {}: {e}", wasm.display()))?;
        std::fs::write(out.join("index.html"), PAGE)
            .map_err(|e| format!("cannot write {}: {e}", out.join("index.html").display()))?;
        Ok(())
    }

    /// Serves the files of `dir` on 127.0.0.1:`port`, each connection on a thread of its own.
    fn serve(dir: &Path, port: u16) -> Result<(), String> {
        let listener = TcpListener::bind(("127.0.0.1", port))
            .map_err(|e| format!("cannot listen on 127.0.0.1:{port}: {e}"))?;
        let address = listener.local_addr().map_err(|e| e.to_string())?;
        println!("serving the web demo on http://{address}/ (Ctrl-C stops)");
        std::io::stdout().flush().ok();
        for stream in listener.incoming().flatten() {
            let dir = dir.to_path_buf();
            std::thread::spawn(move || {
                let _ = answer(stream, &dir);
            });
        }
        Ok(())
    }

    fn answer(mut stream: TcpStream, dir: &Path) -> std::io::Result<()> {
        let mut line = String::new();
        let mut reader = BufReader::new(stream.try_clone()?);
        reader.read_line(&mut line)?;
        // The rest of the request's head.
        let mut header = String::new();
        while reader.read_line(&mut header)? > 2 {
            header.clear();
        }
        let path = line.split_whitespace().nth(1).unwrap_or("/");
        let path = path.split(['?', '#']).next().unwrap_or("/");
        let name = if path == "/" {
            "index.html"
        } else {
            path.trim_start_matches('/')
        };
        let file = (!name.split('/').any(|p| p == ".." || p.is_empty()))
            .then(|| dir.join(name))
            .and_then(|p| std::fs::read(p).ok());
        let Some(body) = file else {
            let text = format!("{name}: not found\n");
            return write!(
                stream,
                "HTTP/1.1 404 Not Found\r\nContent-Type: text/plain\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{text}",
                text.len()
            );
        };
        let kind = match Path::new(name).extension().and_then(|e| e.to_str()) {
            Some("html") => "text/html; charset=utf-8",
            Some("js") => "text/javascript",
            Some("wasm") => "application/wasm",
            _ => "application/octet-stream",
        };
        write!(
            stream,
            "HTTP/1.1 200 OK\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n",
            body.len()
        )?;
        stream.write_all(&body)
    }
}
