//! Per-pass GPU timings from timestamp queries.
//!
//! The renderer writes one timestamp before its first pass and one after each pass (inside the
//! command encoder), resolves them at the end of the frame, and [`GpuTimer::read`] turns them
//! into milliseconds per pass once the frame is submitted. Devices without
//! `TIMESTAMP_QUERY_INSIDE_ENCODERS` get [`Timer::WallClock`] instead: the frame is submitted
//! after every pass and waited for, and the wall time between is the pass's time. That
//! serializes the frame, so it is only for measuring.

use crate::error::{PenumbraError, Result};

/// The most passes a light's chain marks: its shadow map, fattened (or derived) and exit maps,
/// the distance map, PCF, the blur and a resolve.
const PASSES_PER_LIGHT: u32 = 8;
/// The most passes a frame marks besides its lights': the camera's depth prepass, the lit pass
/// and room to spare.
const FRAME_PASSES: u32 = 8;
/// The most timestamps one frame writes: the frame's start, then one after each pass of
/// [`crate::MAX_LIGHTS`] lights and the frame's own. (32 once: from five lights of `ours` whose
/// maps were drawn, the last passes went untimed.)
const CAPACITY: u32 = 1 + FRAME_PASSES + PASSES_PER_LIGHT * crate::MAX_LIGHTS as u32;

/// What [`crate::Renderer::time_frames`] measured, one entry per timed frame.
#[derive(Debug, Clone, Default)]
pub struct TimedFrames {
    /// Submit to completion, CPU clock (ms).
    pub wall_ms: Vec<f64>,
    /// The frame's passes summed (ms): GPU time where timestamps exist.
    pub pass_sum_ms: Vec<f64>,
    /// Each pass's times (ms), by name: per frame, the sum over the lights that ran it.
    pub passes: std::collections::BTreeMap<&'static str, Vec<f64>>,
    /// Each pass's stage, by name.
    pub stages: std::collections::BTreeMap<&'static str, PassStage>,
}

impl TimedFrames {
    /// The median of `values` (0 for none).
    pub fn median(values: &[f64]) -> f64 {
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(0.0)
    }

    /// Each pass's median (ms), by name.
    pub fn pass_medians(&self) -> std::collections::BTreeMap<&'static str, f64> {
        self.passes.iter().map(|(k, v)| (*k, Self::median(v))).collect()
    }

    /// The sum of the medians of the passes of `stages` (ms).
    pub fn stage_ms(&self, stages: &[PassStage]) -> f64 {
        self.pass_medians()
            .iter()
            .filter(|(pass, _)| self.stages.get(*pass).is_some_and(|s| stages.contains(s)))
            .map(|(_, ms)| ms)
            .sum()
    }
}

/// Where a pass works: what a frame's passes are grouped by when they are timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PassStage {
    /// Drawn from a light: its shadow map and the maps beside it.
    LightSpace,
    /// Over the screen: a light's screen-space chain (distance map, PCF, blur, PCSS, resolve).
    ScreenSpace,
    /// The convenience renderer's own passes over the scene (depth prepass, composite,
    /// forward), which every method shares.
    Scene,
}

/// One pass's GPU time.
#[derive(Debug, Clone, PartialEq)]
pub struct PassTime {
    /// The pass's name, e.g. `depth prepass` or `composite` (the names a frame report's
    /// `passes` lists).
    pub pass: &'static str,
    /// Where it works.
    pub stage: PassStage,
    /// Time from the end of the previous pass (or the frame's start) to the end of this one.
    pub milliseconds: f64,
}

/// How a renderer times its passes.
pub enum Timer {
    /// GPU timestamps written inside the command encoder.
    Gpu(GpuTimer),
    /// Submit and wait after every pass, timing with the CPU clock.
    WallClock(WallClockTimer),
}

impl Timer {
    /// Timestamps where the device has them, submit-and-wait wall time otherwise.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        match GpuTimer::new(device, queue) {
            Some(t) => Timer::Gpu(t),
            None => Timer::WallClock(WallClockTimer::new(device, queue)),
        }
    }

    pub(crate) fn begin(&mut self, encoder: &mut wgpu::CommandEncoder) {
        match self {
            Timer::Gpu(t) => t.begin(encoder),
            Timer::WallClock(t) => t.begin(encoder),
        }
    }

    pub(crate) fn mark(&mut self, encoder: &mut wgpu::CommandEncoder, label: &'static str, stage: PassStage) {
        match self {
            Timer::Gpu(t) => t.mark(encoder, label, stage),
            Timer::WallClock(t) => t.mark(encoder, label, stage),
        }
    }

    pub(crate) fn finish(&mut self, encoder: &mut wgpu::CommandEncoder) {
        if let Timer::Gpu(t) = self {
            t.finish(encoder);
        }
    }

    /// The last frame's pass times.
    pub fn read(&self, device: &wgpu::Device) -> Result<Vec<PassTime>> {
        match self {
            Timer::Gpu(t) => t.read(device),
            Timer::WallClock(t) => Ok(t.times.clone()),
        }
    }
}

/// Submits the frame after every pass and waits, timing each pass with the CPU clock.
pub struct WallClockTimer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    last: std::time::Instant,
    times: Vec<PassTime>,
}

impl WallClockTimer {
    /// A timer that submits to `queue` and waits on `device` (clones of both are kept).
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self {
            device: device.clone(),
            queue: queue.clone(),
            last: std::time::Instant::now(),
            times: Vec::new(),
        }
    }

    /// Submits what `encoder` holds, waits for it, and gives the caller a fresh encoder.
    fn flush(&self, encoder: &mut wgpu::CommandEncoder) {
        let fresh = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("WallClockTimer"),
            });
        let done = std::mem::replace(encoder, fresh);
        self.queue.submit([done.finish()]);
        // A failed wait only makes the measurement wrong, not the frame.
        let _ = crate::error::wait_for_gpu(&self.device, "timing a pass");
    }

    fn begin(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.times.clear();
        self.flush(encoder);
        self.last = std::time::Instant::now();
    }

    fn mark(&mut self, encoder: &mut wgpu::CommandEncoder, label: &'static str, stage: PassStage) {
        self.flush(encoder);
        let now = std::time::Instant::now();
        self.times.push(PassTime {
            pass: label,
            stage,
            milliseconds: (now - self.last).as_secs_f64() * 1e3,
        });
        self.last = now;
    }
}

/// Times passes with GPU timestamps written inside the command encoder (up to `CAPACITY` a
/// frame: the frame's start and a timestamp after each pass; a frame with more passes is an
/// error when read, not a shorter list); needs `TIMESTAMP_QUERY` and
/// `TIMESTAMP_QUERY_INSIDE_ENCODERS`.
pub struct GpuTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    labels: Vec<(&'static str, PassStage)>,
    period_ns: f64,
    resolved: usize,
    /// Passes the last frame marked past `CAPACITY` timestamps (untimed).
    untimed: usize,
}

impl GpuTimer {
    /// A timer, or `None` when the device cannot write timestamps inside encoders.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Option<Self> {
        let needed = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        if !device.features().contains(needed) {
            return None;
        }
        let size = CAPACITY as u64 * 8;
        Some(Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("GpuTimer::queries"),
                ty: wgpu::QueryType::Timestamp,
                count: CAPACITY,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("GpuTimer::resolve"),
                size,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("GpuTimer::readback"),
                size,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            }),
            labels: Vec::with_capacity(CAPACITY as usize),
            period_ns: queue.get_timestamp_period() as f64,
            resolved: 0,
            untimed: 0,
        })
    }

    /// Starts a frame: the first timestamp.
    pub(crate) fn begin(&mut self, encoder: &mut wgpu::CommandEncoder) {
        self.labels.clear();
        self.untimed = 0;
        encoder.write_timestamp(&self.queries, 0);
        self.labels.push(("start", PassStage::Scene));
    }

    /// Marks the end of the pass `label`.
    pub(crate) fn mark(&mut self, encoder: &mut wgpu::CommandEncoder, label: &'static str, stage: PassStage) {
        let index = self.labels.len() as u32;
        if index < CAPACITY {
            encoder.write_timestamp(&self.queries, index);
            self.labels.push((label, stage));
        } else {
            self.untimed += 1;
        }
    }

    /// Resolves the frame's timestamps into the read-back buffer.
    pub(crate) fn finish(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let count = self.labels.len() as u32;
        encoder.resolve_query_set(&self.queries, 0..count, &self.resolve, 0);
        encoder.copy_buffer_to_buffer(&self.resolve, 0, &self.readback, 0, count as u64 * 8);
        self.resolved = count as usize;
    }

    /// The last submitted frame's pass times (waits for the GPU).
    pub fn read(&self, device: &wgpu::Device) -> Result<Vec<PassTime>> {
        let gpu_error = |reason: String| PenumbraError::Gpu {
            during: "reading timestamps".into(),
            reason,
        };
        if self.untimed > 0 {
            return Err(gpu_error(format!(
                "the frame ran {} passes, {} more than the timer holds ({CAPACITY} timestamps): \
                 their times would be missing",
                self.labels.len() - 1 + self.untimed,
                self.untimed
            )));
        }
        if self.resolved < 2 {
            return Ok(Vec::new());
        }
        let bytes = self.resolved as u64 * 8;
        crate::error::map_for_reading(device, self.readback.slice(0..bytes), "reading timestamps")?;
        let ticks: Vec<u64> = {
            let view = self
                .readback
                .get_mapped_range(0..bytes)
                .map_err(|e| gpu_error(e.to_string()))?;
            view.chunks_exact(8)
                .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
                .collect()
        };
        self.readback.unmap();
        Ok(self.labels[1..self.resolved]
            .iter()
            .zip(ticks.windows(2))
            .map(|(&(pass, stage), w)| PassTime {
                pass,
                stage,
                milliseconds: w[1].saturating_sub(w[0]) as f64 * self.period_ns * 1e-6,
            })
            .collect())
    }
}
