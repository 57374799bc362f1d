//! The light's maps at a resolution chosen from its penumbrae
//! ([`crate::MapResolution::FromPenumbra`]).
//!
//! A wide penumbra hides a coarse map: where every penumbra a light throws spans many of its
//! map's texels, the distance-map method draws its shadow map (and its fattened and exit maps)
//! at half [`crate::ShadowMapSettings::resolution`], and the light-space passes, which cost what
//! their texels do, cost about a quarter. The compute path's PCF pass
//! measures the widths: it counts the pixels that lie in a penumbra and those whose penumbra
//! is narrower than a few texels of the map as drawn (`WidthProbe`). The counts come back
//! to the CPU a frame or two later, without a wait; [`next_level`] then picks the level the
//! next frames draw at, and [`crate::Shadows::settle`] waits for them where a tool renders a
//! single frame.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

/// What a light's penumbrae measured in one frame: of the pixels in a penumbra (their PCF
/// visibility between 0.02 and 0.98), how many had a penumbra narrower than
/// [`Self::limits_texels`] texels of the map as it was drawn.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PenumbraWidths {
    /// Pixels in a penumbra.
    pub pixels: u32,
    /// Of those, how many had a penumbra narrower than each limit.
    pub narrower: [u32; 3],
    /// The limits, in texels of the map as drawn: the narrowest width the setting allows, and
    /// twice and four times that (what the narrowest would be at half and a quarter of the
    /// resolution).
    pub limits_texels: [f32; 3],
    /// The map resolution the frame drew at (texels a side of one tile).
    pub resolution: u32,
}

/// Share of the penumbra pixels that may have a penumbra narrower than the setting's texels
/// for a coarser level to be taken.
pub const NARROW_SHARE: f32 = 0.05;

/// Share above which the level goes back to a finer one (twice [`NARROW_SHARE`]: a light whose
/// share hovers near the bar does not switch back and forth).
pub const TOO_NARROW_SHARE: f32 = 2.0 * NARROW_SHARE;

/// Fewer penumbra pixels than this measure nothing: the level stays.
pub const LEAST_PIXELS: u32 = 64;

/// The coarsest level: half the configured resolution. At a quarter, the room's lamp shade
/// (`tests/accuracy/near_blocker.rs`), a thin rim right under a small light, was found less precisely by
/// the distance map's silhouette search: its penumbra on the wall came out 0.89x the
/// reference's width on one line (0.93x at half, 0.93-0.99x at the configured 1024 texels a
/// cube face).
pub const MAX_LEVEL: u32 = 1;

/// The least resolution a level may bring a map to.
pub const LEAST_RESOLUTION: u32 = 256;

/// The level (the configured resolution divided by `2^level`) after a frame measured at
/// `level` gave `widths`, for a configured tile of `configured` texels: coarser while the
/// narrow penumbrae stay rare at the coarser resolution, finer once they are not rare at this
/// one.
pub fn next_level(level: u32, widths: &PenumbraWidths, configured: u32) -> u32 {
    if widths.pixels < LEAST_PIXELS {
        return level;
    }
    let share = |n: u32| n as f32 / widths.pixels as f32;
    if share(widths.narrower[0]) > TOO_NARROW_SHARE {
        return level.saturating_sub(1);
    }
    let coarsest = (0..=MAX_LEVEL)
        .rev()
        .find(|&l| configured >> l >= LEAST_RESOLUTION)
        .unwrap_or(0);
    let mut next = level;
    // One level coarser halves every width in texels: what was narrower than twice the
    // limit is narrower than it there.
    for step in 1..=MAX_LEVEL.min(2) {
        let l = level + step;
        if l > coarsest || share(widths.narrower[step as usize]) > NARROW_SHARE {
            break;
        }
        next = l;
    }
    next
}

/// The GPU side of the measurement, for one light: a storage buffer the PCF pass counts into
/// (four counts, then the three limits), and a buffer it is copied into to be read.
pub(crate) struct WidthProbe {
    counts: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// What the readback buffer holds: [`IDLE`], [`MAPPING`], [`MAPPED`] or [`FAILED`].
    state: Arc<AtomicU8>,
    /// The frame whose counts [`Self::counts`] holds was recorded (with these limits and this
    /// resolution), and not copied yet.
    recorded: Option<([f32; 3], u32)>,
    /// The limits and resolution of the counts being read back.
    reading: Option<([f32; 3], u32)>,
}

const IDLE: u8 = 0;
const MAPPING: u8 = 1;
const MAPPED: u8 = 2;
const FAILED: u8 = 3;

/// Bytes of the counts buffer: four u32 counts, then a vec4 of limits.
const PROBE_BYTES: u64 = 32;

impl WidthProbe {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            counts: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("WidthProbe::counts"),
                size: PROBE_BYTES,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("WidthProbe::readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            state: Arc::new(AtomicU8::new(IDLE)),
            recorded: None,
            reading: None,
        }
    }

    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.counts.size() + self.readback.size()
    }

    /// The buffer the PCF pass binds.
    pub(crate) fn buffer(&self) -> &wgpu::Buffer {
        &self.counts
    }

    /// Zeroes the counts and sets the limits (texels of the map as drawn, at `resolution`
    /// texels a tile) for the next frame.
    pub(crate) fn reset(&mut self, queue: &wgpu::Queue, limits: [f32; 3]) {
        let mut bytes = [0u8; PROBE_BYTES as usize];
        for (i, l) in limits.iter().enumerate() {
            bytes[16 + 4 * i..20 + 4 * i].copy_from_slice(&l.to_le_bytes());
        }
        queue.write_buffer(&self.counts, 0, &bytes);
    }

    /// The PCF pass was recorded with the limits and resolution last given to [`Self::reset`].
    pub(crate) fn recorded(&mut self, limits: [f32; 3], resolution: u32) {
        self.recorded = Some((limits, resolution));
    }

    /// Takes what a read-back returned, if one has, and starts the next: copies the counts a
    /// recorded frame left (the engine must have submitted that frame's commands, as it has
    /// before it prepares the next) in a submission of its own, and maps the copy. Call it
    /// before this frame's [`Self::reset`]. Never waits.
    pub(crate) fn collect(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) -> Option<PenumbraWidths> {
        let mut result = None;
        match self.state.load(Ordering::Acquire) {
            MAPPED => {
                let counts: Option<[u32; 4]> = self
                    .readback
                    .get_mapped_range(..)
                    .ok()
                    .map(|view| bytemuck::pod_read_unaligned(&view[..16]));
                self.readback.unmap();
                self.state.store(IDLE, Ordering::Release);
                if let (Some((limits, resolution)), Some(counts)) = (self.reading.take(), counts) {
                    result = Some(PenumbraWidths {
                        pixels: counts[3],
                        narrower: [counts[0], counts[1], counts[2]],
                        limits_texels: limits,
                        resolution,
                    });
                }
            }
            FAILED => {
                self.state.store(IDLE, Ordering::Release);
                self.reading = None;
            }
            _ => {}
        }
        if self.state.load(Ordering::Acquire) == IDLE
            && let Some(recorded) = self.recorded.take()
        {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("WidthProbe::copy"),
            });
            encoder.copy_buffer_to_buffer(&self.counts, 0, &self.readback, 0, 16);
            queue.submit([encoder.finish()]);
            self.reading = Some(recorded);
            self.state.store(MAPPING, Ordering::Release);
            let state = self.state.clone();
            self.readback.map_async(wgpu::MapMode::Read, .., move |r| {
                state.store(if r.is_ok() { MAPPED } else { FAILED }, Ordering::Release);
            });
        }
        result
    }

    /// Whether a read-back is under way (the device must be polled for it to end).
    pub(crate) fn pending(&self) -> bool {
        self.state.load(Ordering::Acquire) == MAPPING
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn widths(pixels: u32, narrower: [u32; 3]) -> PenumbraWidths {
        PenumbraWidths {
            pixels,
            narrower,
            limits_texels: [4.0, 8.0, 16.0],
            resolution: 2048,
        }
    }

    #[test]
    fn wide_penumbrae_take_the_coarser_level_and_narrow_ones_the_finer() {
        // Few narrow penumbrae at half the resolution: half.
        assert_eq!(next_level(0, &widths(1000, [0, 10, 200]), 2048), 1);
        // Never past the coarsest level, however wide.
        assert_eq!(next_level(MAX_LEVEL, &widths(1000, [0, 0, 0]), 2048), MAX_LEVEL);
        // Too many narrow at half: stay.
        assert_eq!(next_level(0, &widths(1000, [20, 60, 600]), 2048), 0);
        // Too many narrow at this level: one finer.
        assert_eq!(next_level(1, &widths(1000, [150, 300, 600]), 2048), 0);
        // Between the two shares: stay.
        assert_eq!(next_level(1, &widths(1000, [70, 300, 600]), 2048), 1);
        // Too few pixels to tell.
        assert_eq!(next_level(1, &widths(10, [10, 10, 10]), 2048), 1);
        // Never below the least resolution.
        assert_eq!(next_level(0, &widths(1000, [0, 0, 0]), 512), 1);
        assert_eq!(next_level(0, &widths(1000, [0, 0, 0]), 256), 0);
    }
}
