//! The page's side: WebGPU on the page's canvas, the controls, the animation frames.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use penumbra::{GpuScene, Quality, Renderer, Scene, ShadowSettings};
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use crate::{Choice, adjusted_light, frame_limit, right_side, scene};

#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
    wasm_bindgen_futures::spawn_local(async {
        if let Err(e) = run().await {
            status(&format!("error: {e}"));
        }
    });
}

/// Shows `text` in the page's status line (and the console).
fn status(text: &str) {
    web_sys::console::log_1(&text.into());
    if let Some(e) = document().and_then(|d| d.get_element_by_id("status")) {
        e.set_text_content(Some(text));
    }
}

fn document() -> Option<web_sys::Document> {
    web_sys::window()?.document()
}

fn element<T: JsCast>(id: &str) -> Result<T, String> {
    document()
        .and_then(|d| d.get_element_by_id(id))
        .ok_or_else(|| format!("the page has no element `{id}`"))?
        .dyn_into::<T>()
        .map_err(|_| format!("the page's `{id}` is not the element expected"))
}

/// The page's controls, read every frame.
struct Controls {
    scene: web_sys::HtmlSelectElement,
    view: web_sys::HtmlSelectElement,
    method: web_sys::HtmlSelectElement,
    light: web_sys::HtmlInputElement,
    turn: web_sys::HtmlInputElement,
    compare: web_sys::HtmlSelectElement,
    divider: web_sys::HtmlInputElement,
    fps: web_sys::HtmlElement,
}

impl Controls {
    fn find() -> Result<Self, String> {
        Ok(Self {
            scene: element("scene")?,
            view: element("view")?,
            method: element("method")?,
            light: element("light")?,
            turn: element("turn")?,
            compare: element("compare")?,
            divider: element("divider")?,
            fps: element("fps")?,
        })
    }

    /// Sets the controls to `c` (the address's choice, at start).
    fn show(&self, c: &Choice) {
        self.scene.set_value(&c.scene);
        self.view.set_value(&c.view.to_string());
        self.method.set_value(c.method.name());
        self.light.set_value(&c.light_scale.to_string());
        self.turn.set_value(&c.turn_deg.to_string());
        self.compare.set_value(c.compare.map_or("none", |m| m.name()));
        self.divider.set_value(&c.divider.to_string());
    }

    fn read(&self) -> Result<Choice, String> {
        let query = format!(
            "scene={}&view={}&method={}&light={}&turn={}&compare={}&divider={}",
            self.scene.value(),
            self.view.value(),
            self.method.value(),
            self.light.value(),
            self.turn.value(),
            self.compare.value(),
            self.divider.value()
        );
        Choice::from_query(&query)
    }
}

/// Everything one frame needs.
struct App {
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    size: (u32, u32),
    renderer: Renderer,
    /// The split view's right side: its renderer (sharing the scene's layouts) and the texture
    /// it draws into, whose columns right of the divider are copied onto the canvas.
    compare: Option<(Renderer, wgpu::Texture)>,
    controls: Controls,
    /// What is drawn now, and its scene as loaded (the light before the controls' changes).
    choice: Choice,
    scene: Scene,
    gpu_scene: GpuScene,
    /// Frames the GPU has finished, and the time and count at the last readout.
    frames: Arc<AtomicU32>,
    last: (f64, u32),
    /// A frame is submitted and not finished: the next animation frame draws nothing, so work
    /// never piles up behind a slow GPU (a software one takes seconds over the room's three
    /// lights, and the browser then times out waiting for its compositor).
    in_flight: Arc<AtomicBool>,
    /// The address's `frames=N`: stop after N finished frames.
    limit: Option<u32>,
}

async fn run() -> Result<(), String> {
    let canvas: web_sys::HtmlCanvasElement = element("penumbra")?;
    let controls = Controls::find()?;
    let query = web_sys::window()
        .ok_or("no window")?
        .location()
        .search()
        .map_err(|_| "cannot read the address")?;
    let choice = Choice::from_query(&query)?;
    let limit = frame_limit(&query)?;
    controls.show(&choice);
    let size = (canvas.width().max(1), canvas.height().max(1));
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    descriptor.backends = wgpu::Backends::BROWSER_WEBGPU;
    let instance = wgpu::Instance::new(descriptor);
    let surface = instance
        .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
        .map_err(|e| format!("no WebGPU canvas: {e}"))?;
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            compatible_surface: Some(&surface),
            ..Default::default()
        })
        .await
        .map_err(|e| format!("this browser gives no WebGPU adapter ({e}); see docs/web.md"))?;
    let (device, queue) = adapter
        .request_device(&penumbra::device_descriptor(&adapter))
        .await
        .map_err(|e| format!("the WebGPU adapter gives no device: {e}"))?;
    let caps = surface.get_capabilities(&adapter);
    // The browser's preferred canvas format comes first.
    let canvas_format = *caps.formats.first().ok_or("the canvas offers no format")?;
    // The renderer writes linear colour into an sRGB view of the canvas.
    let format = canvas_format.add_srgb_suffix();
    surface.configure(
        &device,
        &wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_DST,
            format: canvas_format,
            width: size.0,
            height: size.1,
            present_mode: wgpu::PresentMode::Fifo,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes[0],
            view_formats: vec![format],
            color_space: wgpu::SurfaceColorSpace::Auto,
        },
    );
    let mut renderer = Renderer::new(&device, format, settings(&choice)).map_err(|e| e.to_string())?;
    renderer.resize(&device, size.0, size.1);
    let scene = scene(&choice.scene)?;
    let gpu_scene = upload(&device, &queue, &renderer, &scene, &choice)?;
    let compare = comparison(&device, &renderer, &choice, size)?;
    let app = App {
        surface,
        device,
        queue,
        format,
        size,
        renderer,
        compare,
        controls,
        choice,
        scene,
        gpu_scene,
        frames: Arc::new(AtomicU32::new(0)),
        last: (now(), 0),
        in_flight: Arc::new(AtomicBool::new(false)),
        limit,
    };
    status(&format!("WebGPU: {}", describe(&adapter)));
    animate(Rc::new(RefCell::new(app)));
    Ok(())
}

fn describe(adapter: &wgpu::Adapter) -> String {
    let info = adapter.get_info();
    if info.name.is_empty() {
        format!("{:?} adapter", info.device_type)
    } else {
        info.name
    }
}

fn settings(choice: &Choice) -> ShadowSettings {
    ShadowSettings::preset(choice.method, Quality::Medium)
}

/// The split view's right side for `choice`, if it has one: a renderer of the compared
/// method drawing into a texture of the canvas's size.
fn comparison(
    device: &wgpu::Device,
    main: &Renderer,
    choice: &Choice,
    size: (u32, u32),
) -> Result<Option<(Renderer, wgpu::Texture)>, String> {
    let Some(method) = choice.compare else {
        return Ok(None);
    };
    let format = main.color_format();
    let mut renderer = Renderer::with_layouts(
        device,
        format,
        ShadowSettings::preset(method, Quality::Medium),
        main.layouts().clone(),
    )
    .map_err(|e| e.to_string())?;
    renderer.resize(device, size.0, size.1);
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("split view's right side"),
        size: wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: format.remove_srgb_suffix(),
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[format],
    });
    Ok(Some((renderer, texture)))
}

fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    renderer: &Renderer,
    scene: &Scene,
    choice: &Choice,
) -> Result<GpuScene, String> {
    let mut gpu = GpuScene::new(device, queue, renderer.layouts(), scene).map_err(|e| e.to_string())?;
    gpu.set_light(adjusted_light(&scene.light, choice.light_scale, choice.turn_deg))
        .map_err(|e| e.to_string())?;
    Ok(gpu)
}

fn now() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map(|p| p.now())
        .unwrap_or(0.0)
}

/// Draws a frame, then asks for the next one.
fn animate(app: Rc<RefCell<App>>) {
    let next: Rc<RefCell<Option<Closure<dyn FnMut()>>>> = Rc::new(RefCell::new(None));
    let first = next.clone();
    *first.borrow_mut() = Some(Closure::new(move || {
        if let Err(e) = app.borrow_mut().frame() {
            status(&format!("error: {e}"));
            return;
        }
        if let (Some(window), Some(callback)) = (web_sys::window(), next.borrow().as_ref()) {
            let _ = window.request_animation_frame(callback.as_ref().unchecked_ref());
        }
    }));
    if let (Some(window), Some(callback)) = (web_sys::window(), first.borrow().as_ref()) {
        let _ = window.request_animation_frame(callback.as_ref().unchecked_ref());
    }
}

impl App {
    fn frame(&mut self) -> Result<(), String> {
        self.show_frames();
        if self.in_flight.load(Ordering::Acquire)
            || self
                .limit
                .is_some_and(|n| self.frames.load(Ordering::Acquire) >= n)
        {
            return Ok(());
        }
        let choice = self.controls.read()?;
        if choice != self.choice {
            if choice.scene != self.choice.scene {
                self.scene = scene(&choice.scene)?;
            }
            if choice.method != self.choice.method {
                self.renderer
                    .set_settings(&self.device, settings(&choice))
                    .map_err(|e| e.to_string())?;
            }
            if choice.compare != self.choice.compare {
                self.compare = comparison(&self.device, &self.renderer, &choice, self.size)?;
            }
            if choice.scene != self.choice.scene {
                self.gpu_scene = upload(&self.device, &self.queue, &self.renderer, &self.scene, &choice)?;
            } else {
                let light = adjusted_light(&self.scene.light, choice.light_scale, choice.turn_deg);
                self.gpu_scene.set_light(light).map_err(|e| e.to_string())?;
            }
            self.choice = choice;
        }
        let view = self.choice.view.min(self.scene.views.len().saturating_sub(1));
        let camera = self.scene.view(view).map_err(|e| e.to_string())?;
        let texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            // Skip this frame; the next may get one.
            _ => return Ok(()),
        };
        let target = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.format),
            ..Default::default()
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("web frame"),
            });
        self.renderer
            .render(&self.queue, &mut encoder, &self.gpu_scene, &camera, &target)
            .map_err(|e| e.to_string())?;
        if let Some((renderer, side)) = &mut self.compare {
            let view = side.create_view(&wgpu::TextureViewDescriptor {
                format: Some(self.format),
                ..Default::default()
            });
            renderer
                .render(&self.queue, &mut encoder, &self.gpu_scene, &camera, &view)
                .map_err(|e| e.to_string())?;
            let columns = right_side(&self.choice, self.size.0);
            if !columns.is_empty() {
                let origin = wgpu::Origin3d {
                    x: columns.start,
                    y: 0,
                    z: 0,
                };
                encoder.copy_texture_to_texture(
                    wgpu::TexelCopyTextureInfo {
                        texture: side,
                        mip_level: 0,
                        origin,
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::TexelCopyTextureInfo {
                        texture: &texture.texture,
                        mip_level: 0,
                        origin,
                        aspect: wgpu::TextureAspect::All,
                    },
                    wgpu::Extent3d {
                        width: columns.len() as u32,
                        height: self.size.1,
                        depth_or_array_layers: 1,
                    },
                );
            }
        }
        self.queue.submit([encoder.finish()]);
        self.queue.present(texture);
        self.in_flight.store(true, Ordering::Release);
        let (frames, in_flight) = (self.frames.clone(), self.in_flight.clone());
        self.queue.on_submitted_work_done(move || {
            frames.fetch_add(1, Ordering::AcqRel);
            in_flight.store(false, Ordering::Release);
        });
        Ok(())
    }

    /// The FPS readout and the page's `data-frames` (which the tests wait on): frames the GPU
    /// has finished.
    fn show_frames(&mut self) {
        let frames = self.frames.load(Ordering::Acquire);
        let t = now();
        if t - self.last.0 >= 500.0 {
            let fps = f64::from(frames - self.last.1) * 1000.0 / (t - self.last.0);
            self.controls.fps.set_text_content(Some(&format!(
                "{fps:.1} FPS, {}x{}, {frames} frames",
                self.size.0, self.size.1
            )));
            self.last = (t, frames);
        }
        if let Some(body) = document().and_then(|d| d.body()) {
            let _ = body.set_attribute("data-frames", &frames.to_string());
        }
    }
}
