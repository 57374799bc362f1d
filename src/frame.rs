//! The per-frame uniform shared by the camera and screen-space passes (the camera, the light
//! and what the method's passes share, as named structs), and each pass's own parameters.
//!
//! The physical mode is evaluated per pixel in the shaders from these numbers: the penumbra
//! width is `size_term * d` for a directional light (`2 tan(theta / 2) d`) and
//! `size_term * d / (D - d)` for a spot light (`2 R d / D_occluder`).

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::bounds::Aabb;
use crate::light_space::{LightView, MAX_TILES, ProjectionKind, tile_matrix, tile_viewport};
use crate::lights::Light;
use crate::settings::{ShadowMethod, ShadowSettings, SpreadMode};
use crate::view::{CameraMatrices, DepthConvention};

/// Mirrors `struct View` in `shaders/common/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct ViewUniform {
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub toward_camera: [f32; 4],
    pub depth_to_view: [f32; 4],
    pub size: [f32; 2],
    pub inv_size: [f32; 2],
    pub pixels_per_unit: f32,
    pub reversed_depth: u32,
    pub has_receiver_mask: u32,
    pub has_distance_map: u32,
}

/// Mirrors `struct ShadowLight`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct ShadowLightUniform {
    pub view_proj: [[f32; 4]; 4],
    pub direction: [f32; 3],
    pub spot: u32,
    pub position: [f32; 3],
    pub cos_outer: f32,
    pub radiance: [f32; 3],
    pub cos_inner: f32,
    pub near: f32,
    pub far: f32,
    pub perspective: u32,
    pub resolution: f32,
    pub extent: [f32; 2],
    pub tan_half_fov: f32,
    pub size_term: f32,
    /// An area light's half-axis along its width (xyz, world units); w: its shape, 0 none (a
    /// round light: its penumbrae as wide every way), 1 rectangle, 2 disk.
    pub area_u: [f32; 4],
    /// An area light's half-axis along its height (xyz, world units).
    pub area_v: [f32; 4],
}

/// Mirrors `struct Penumbra`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct PenumbraUniform {
    pub fatten_distance: f32,
    pub physical: u32,
    pub indirect_weight: f32,
    pub indirect_half_distance: f32,
    pub pcf_share: f32,
    pub sigma_per_width: f32,
    pub normal_offset: f32,
    /// The configured map resolution over the one drawn.
    pub map_scale: f32,
    /// The variable PCF's taps per side and least spacing (texels): the umbra test's reach.
    pub taps_per_side: u32,
    pub base_spacing: f32,
    /// 1: the tile classification may list tiles deep in the umbra apart
    /// ([`crate::PenumbraSettings::skip_umbra_tiles`] and a light and mode the test serves).
    pub umbra_tiles: u32,
    pub _pad: f32,
}

/// Mirrors `struct Cascades`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct CascadesUniform {
    /// Each cascade's (or cube face's) light view-projection into its own tile of the atlas.
    pub view_proj: [[[f32; 4]; 4]; MAX_TILES],
    /// xy: the window's size (world units; a face's at its near plane), z: the view distance
    /// where it ends, w: where its blend band begins.
    pub extent_end: [[f32; 4]; MAX_TILES],
    /// The tile's uv rectangle (min xy, max zw), half a texel inside its edges.
    pub tile: [[f32; 4]; MAX_TILES],
    /// xyz: the unit direction the tile looks along.
    pub axis: [[f32; 4]; MAX_TILES],
    /// The atlas's columns and rows of tiles.
    pub grid: [f32; 2],
    pub count: u32,
    pub _pad: f32,
}

impl CascadesUniform {
    /// The cascades of `lv`, placed in the tiles of its atlas (`resolution` texels a tile).
    pub fn new(lv: &LightView, resolution: u32) -> Self {
        let grid = lv.grid;
        let mut out = CascadesUniform::zeroed();
        let cascades = lv.cascades();
        out.count = cascades.len() as u32;
        out.grid = [grid.cols.max(1) as f32, grid.rows.max(1) as f32];
        let (width, height) = grid.size(resolution);
        let (width, height) = (width as f32, height as f32);
        for (i, c) in cascades.iter().enumerate() {
            out.view_proj[i] = (tile_matrix(grid, i as u32) * c.view_projection).to_cols_array_2d();
            out.extent_end[i] = [c.extent.x, c.extent.y, c.end, c.blend_start];
            out.axis[i] = c.axis.normalize_or(glam::Vec3::NEG_Z).extend(0.0).to_array();
            let [x, y, w, h] = tile_viewport(grid, i as u32, resolution);
            out.tile[i] = [
                (x as f32 + 0.5) / width,
                (y as f32 + 0.5) / height,
                ((x + w) as f32 - 0.5) / width,
                ((y + h) as f32 - 0.5) / height,
            ];
        }
        out
    }
}

/// Mirrors `struct Frame` (a test compares every field's offset with the WGSL layout).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug)]
pub(crate) struct FrameUniform {
    pub view: ViewUniform,
    pub light: ShadowLightUniform,
    pub penumbra: PenumbraUniform,
    pub ambient: [f32; 4],
    pub cascades: CascadesUniform,
    pub maps: MapLayersUniform,
    pub _pad: [[f32; 4]; 9],
}

/// The bytes between two lights' frames in [`FrameSlots`]: a multiple of 256, the largest
/// offset alignment a device may ask of a uniform binding, and the frame's own size, so that an
/// array of frames in WGSL has the same stride.
pub(crate) const FRAME_STRIDE: u64 = size_of::<FrameUniform>() as u64;
const _: () = assert!(
    FRAME_STRIDE.is_multiple_of(256),
    "pad `struct Frame` (shaders/common/frame.wgsl) and FrameUniform to a multiple of 256 bytes"
);

/// Every light's frame uniform, one slot a light, in one buffer: [`FIRST_SLOTS`] slots at first,
/// twice as many each time a light's slot lies past them ([`FrameSlots::reserve`]).
pub(crate) struct FrameSlots {
    buffer: wgpu::Buffer,
}

/// The slots [`FrameSlots`] starts with (20 KiB): the lights of Bevy's `spotlight` example.
pub(crate) const FIRST_SLOTS: usize = 16;

impl FrameSlots {
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            buffer: frames_buffer(device, FIRST_SLOTS),
        }
    }

    /// Slots the buffer holds.
    pub fn capacity(&self) -> usize {
        (self.buffer.size() / FRAME_STRIDE) as usize
    }

    /// Makes the buffer hold at least `slots` slots, doubling it as often as needed. True where
    /// it was made again: every [`FrameSlot`] taken before names the old buffer, so the lights
    /// must take their slots again and their passes be bound again. Nothing is copied: each
    /// light's frame is uploaded every frame before its passes run.
    pub fn reserve(&mut self, device: &wgpu::Device, slots: usize) -> bool {
        let mut capacity = self.capacity();
        if slots <= capacity {
            return false;
        }
        while capacity < slots {
            capacity *= 2;
        }
        self.buffer = frames_buffer(device, capacity);
        true
    }

    /// Light slot `slot`'s frame.
    pub fn slot(&self, slot: usize) -> FrameSlot {
        FrameSlot {
            buffer: self.buffer.clone(),
            offset: FRAME_STRIDE * slot as u64,
            size: FRAME_STRIDE,
        }
    }

    /// Every slot, bound whole: a pass over several lights reads each one's frame from it
    /// ([`crate::shaders::with_light_frames`]).
    pub fn whole(&self) -> FrameSlot {
        FrameSlot {
            buffer: self.buffer.clone(),
            offset: 0,
            size: self.buffer.size(),
        }
    }

    /// GPU memory the slots take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.buffer.size()
    }
}

/// A buffer of `slots` frame uniforms; a storage buffer too: a pass over several lights binds it
/// whole as one ([`crate::shaders::with_light_frames`]).
fn frames_buffer(device: &wgpu::Device, slots: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("Shadows::frames"),
        size: FRAME_STRIDE * slots as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// One light's frame uniform: its slot of [`FrameSlots`], which the light's passes bind (or
/// every slot, [`FrameSlots::whole`]).
#[derive(Clone, Debug)]
pub(crate) struct FrameSlot {
    buffer: wgpu::Buffer,
    offset: u64,
    size: u64,
}

impl FrameSlot {
    /// Uploads `frame` into the slot.
    pub fn write(&self, queue: &wgpu::Queue, frame: &FrameUniform) {
        queue.write_buffer(&self.buffer, self.offset, bytemuck::bytes_of(frame));
    }
}

impl crate::gpu_helpers::Binding for FrameSlot {
    fn resource(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: self.offset,
            size: wgpu::BufferSize::new(self.size),
        })
    }
}

/// Mirrors `struct MapLayers`: the layer of each of the light's maps in the array it shares
/// with other lights ([`crate::light_maps::LightMaps::layers`]; 0 for a texture of its own).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, Default, PartialEq, Eq)]
pub(crate) struct MapLayersUniform {
    pub shadow: u32,
    pub fattened: u32,
    pub occluder_offset: u32,
    pub exit: u32,
}

/// Mirrors `struct Pcf` in `shaders/common/pcf_taps.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub(crate) struct PcfUniform {
    pub taps_per_side: u32,
    pub base_spacing: f32,
    pub spread: f32,
    pub _pad: f32,
}

/// Mirrors `struct Pcss` in `shaders/pcss.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, Debug, PartialEq)]
pub(crate) struct PcssUniform {
    pub blocker_samples: u32,
    pub pcf_samples: u32,
    pub _pad: [f32; 2],
}

/// The PCF pass's compile-time switches (WGSL override constants): changing one makes a new
/// pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct PcfSwitches {
    pub rotate_taps: bool,
    pub mask_early_out: bool,
    /// After the distance map: draw only the screen tiles its tile classification kept.
    pub tiles: bool,
    /// The distance-map method: PCF at half resolution where the penumbra is wide.
    pub half_resolution: bool,
}

/// The distance map's compile-time switches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct DistanceSwitches {
    pub mask_early_out: bool,
    /// Beside a shadow, the distance to the nearest caster (a second draw).
    pub nearest_caster: bool,
    /// Draw only the screen tiles the tile classification keeps.
    pub tiles: bool,
    /// The compute path: list the kept tiles turned away from the light apart (0 without taps).
    pub facing_away: bool,
    /// The compute path: list the kept tiles deep in the umbra apart (0 without taps).
    pub umbra: bool,
    /// The compute path: how the tile classification tests the kept tiles' pixels.
    pub tile_pixels: crate::settings::TilePixels,
    /// Inside a shadow, the exit map's back faces are read (it is drawn).
    pub exit_map: bool,
    /// The fattened map is derived from the shadow map ([`crate::Fattening::Dilation`]).
    pub dilated_map: bool,
}

impl DistanceSwitches {
    /// The override constants of the distance's shader code (`common/distance.wgsl`).
    pub fn constants(&self) -> [(&'static str, f64); 4] {
        let on = |b: bool| if b { 1.0 } else { 0.0 };
        [
            ("MASK_EARLY_OUT", on(self.mask_early_out)),
            ("NEAREST_CASTER", on(self.nearest_caster)),
            ("EXIT_MAP", on(self.exit_map)),
            ("DILATED_MAP", on(self.dilated_map)),
        ]
    }
}

/// The blur's compile-time switches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct BlurSwitches {
    pub fixed_step: bool,
    pub depth_aware: bool,
    /// After the distance-map pass: skip the pixels it found nothing to blur at (depth test)
    /// and write the light's output layer from the vertical draw (the resolve).
    pub after_distance_map: bool,
    /// After the distance map: draw only the screen tiles its tile classification kept.
    pub tiles: bool,
}

/// The blur's parameters besides its axis and weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BlurParams {
    pub taps: u32,
    /// Fixed step: pixels between taps; manual mode: pixels per world unit of distance.
    pub step: f32,
}

/// Each screen-space pass's parameters for `settings` (whose method is the one drawn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PassParams {
    pub pcf: PcfUniform,
    pub pcf_switches: PcfSwitches,
    pub distance_switches: DistanceSwitches,
    pub blur: BlurParams,
    pub blur_switches: BlurSwitches,
    pub pcss: PcssUniform,
    /// The compute path classifies its tiles (`Auto` is on for every device there: a tile
    /// list costs nothing where no tile is dropped).
    pub list_tiles: bool,
    /// The compute passes that finish a light's visibility write its layer themselves (the
    /// device stores half floats and the layer allows it, `crate::Shadows` decides); otherwise
    /// a draw writes it.
    pub layer_writes: bool,
    /// The compute path's variable PCF reads the distance to the occluder itself
    /// ([`crate::ExecutionSettings::distance_in_pcf`]).
    pub distance_in_pcf: bool,
    /// The compute path's intermediates are stored in half floats (the device stores them and
    /// [`crate::ExecutionSettings::half_intermediates`] is on; `crate::Shadows` decides).
    pub half_intermediates: bool,
    /// The compute path's passes bind the light's maps as the arrays every light's maps are
    /// layers of, and read the light's layers (the maps share arrays; `crate::Shadows`
    /// decides).
    pub map_arrays: bool,
}

impl PassParams {
    pub fn new(s: &ShadowSettings) -> Self {
        let p = &s.penumbra;
        let manual = match p.spreads {
            SpreadMode::Physical => None,
            SpreadMode::Manual {
                pcf_spread,
                blur_spread,
                ..
            } => Some((pcf_spread, blur_spread)),
        };
        let (pcf, fixed, blur) = match s.method {
            // One fixed tap, no blur: the screen-space hard shadow of the embedding path.
            ShadowMethod::Hard | ShadowMethod::Hardware2x2 => (
                PcfUniform {
                    taps_per_side: 1,
                    base_spacing: 0.0,
                    spread: 0.0,
                    _pad: 0.0,
                },
                true,
                BlurParams { taps: 1, step: 0.0 },
            ),
            ShadowMethod::Traditional => {
                let t = &s.traditional;
                (
                    PcfUniform {
                        taps_per_side: t.pcf_kernel.side(),
                        base_spacing: 0.0,
                        spread: t.pcf_spacing,
                        _pad: 0.0,
                    },
                    true,
                    BlurParams {
                        taps: t.blur_taps,
                        step: t.blur_step,
                    },
                )
            }
            method => (
                PcfUniform {
                    taps_per_side: if method == ShadowMethod::OursFast {
                        1
                    } else {
                        p.pcf_kernel.side()
                    },
                    base_spacing: p.pcf_base_spacing,
                    spread: manual.map_or(0.0, |m| m.0),
                    _pad: 0.0,
                },
                false,
                BlurParams {
                    taps: p.blur_taps,
                    step: manual.map_or(0.0, |m| m.1),
                },
            ),
        };
        // Without the early out every receiver pixel is classified: no tile is dropped. Auto
        // counts as on here; `Shadows` turns it off on a GPU.
        let tiles = p.tiles != crate::settings::TileClassification::Off && p.mask_early_out;
        PassParams {
            pcf,
            pcf_switches: PcfSwitches {
                rotate_taps: p.rotate_taps,
                mask_early_out: p.mask_early_out,
                tiles,
                // Only a physical penumbra says how wide it is in pixels; the fast mode takes
                // one tap.
                half_resolution: p.reduced_resolution
                    && !fixed
                    && manual.is_none()
                    && s.method != ShadowMethod::OursFast,
            },
            distance_switches: DistanceSwitches {
                mask_early_out: p.mask_early_out,
                nearest_caster: p.nearest_caster,
                tiles,
                facing_away: tiles && p.skip_tiles_facing_away,
                umbra: tiles && p.skip_umbra_tiles,
                tile_pixels: s.execution.tile_pixels,
                exit_map: p.exit_map,
                // The chain decides (`crate::Chain::Ours`'s `dilated`).
                dilated_map: false,
            },
            blur,
            blur_switches: BlurSwitches {
                fixed_step: fixed,
                // The baseline is the paper's plain fixed Gaussian.
                depth_aware: p.depth_aware_blur && !fixed,
                after_distance_map: !fixed,
                tiles: tiles && !fixed,
            },
            pcss: PcssUniform {
                blocker_samples: s.pcss.blocker_samples,
                pcf_samples: s.pcss.pcf_samples,
                _pad: [0.0; 2],
            },
            list_tiles: tiles,
            layer_writes: false,
            half_intermediates: false,
            map_arrays: false,
            distance_in_pcf: s.execution.distance_in_pcf,
        }
    }
}

/// The physical spreads for a frame, as derived on the CPU (reported to users; the shaders
/// apply the same formulas per pixel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DerivedSpreads {
    /// World units the casters are pushed out for the fattened map.
    pub fatten_distance: f32,
    /// Penumbra width per world unit of receiver-to-occluder distance, at the nearest
    /// occluder distance for a spot light.
    pub penumbra_per_distance: f32,
    /// A spot or point light's nearest caster, its distance from the light (world units,
    /// rounded down to steps of 2^(1/8)): where the fattened map's texels are narrowest across
    /// the light. 0 for a directional light.
    pub nearest_caster: f32,
}

/// The light's kind as the shaders take it: 0 directional, 1 spot, 2 point.
pub(crate) fn light_kind(light: &Light) -> u32 {
    match light {
        Light::Directional(_) => 0,
        Light::Spot(_) => 1,
        // Area lights' maps are a point light's cube; their shape is in `area_u` and `area_v`.
        Light::Point(_) | Light::Rect(_) | Light::Disk(_) => 2,
    }
}

/// Light size term: directional `2 tan(theta / 2)`, spot and point `2 R`, an area light the
/// diameter of the sphere that holds it (the widest its penumbra can be: what the fattened
/// map, the distance map's search and the tile classification must allow for).
pub(crate) fn light_size_term(light: &Light) -> f32 {
    match light {
        Light::Directional(l) => 2.0 * (l.angular_diameter_deg.to_radians() * 0.5).tan(),
        _ => 2.0 * light.enclosing_radius(),
    }
}

/// An area light's half-axes as the shaders take them (`ShadowLight::area_u`, `area_v`): xyz
/// the half-axis, `area_u`'s w its shape (1 rectangle, 2 disk); zero for other lights.
pub(crate) fn area_axes(light: &Light) -> ([f32; 4], [f32; 4]) {
    match light.area() {
        Some(a) => {
            let shape = match a.shape {
                crate::AreaShape::Rect => 1.0,
                crate::AreaShape::Disk => 2.0,
            };
            (a.u.extend(shape).to_array(), a.v.extend(0.0).to_array())
        }
        None => ([0.0; 4], [0.0; 4]),
    }
}

/// True when the light has no size: every method then degenerates to hard shadows.
pub(crate) fn has_no_size(light: &Light) -> bool {
    light_size_term(light) <= 0.0
}

/// Derives the fatten distance: half the widest penumbra the scene allows (the deepest
/// receiver behind the casters' nearest point along the light), plus two texels of the fattened map
/// (four of the shadow map: the fattened map has half its resolution). For a spot or point
/// light the width `2 R d / D` grows without bound as the occluder's distance `D` shrinks, but
/// where the fattened map marks it, at the caster's own distance, a penumbra reaches at most
/// the light's radius beside the caster: the fatten distance is about `R`. It stays under half
/// the nearest caster's distance from the light (more would swallow the light). That distance
/// is each caster's own ([`light_to_box`]), not the distance to the casters' union, which a
/// lamp's shade, its stand and the desk below enclose the bulb in (the union held the light, the
/// distance fell to the map's near plane and the fatten distance to millimetres: the outer part
/// of every penumbra lay outside the fattened shadow). Never more than the scene's radius.
pub(crate) fn derive_spreads(
    light: &Light,
    light_view: &LightView,
    shadow_bounds: &Aabb,
    caster_parts: &[Aabb],
    map_scale: f32,
) -> DerivedSpreads {
    let size = light_size_term(light);
    let depth_range = (light_view.far - light_view.near).max(0.0);
    // A texel of the map as drawn: coarser by `map_scale` than the fit's
    // (`crate::MapResolution::FromPenumbra`).
    let mut texel = map_scale * light_view.extent.max_element() / light_view.tile.max(1) as f32;
    // A spot or point light's casters, pushed out past half their distance from it, would
    // swallow the light itself.
    let mut cap = shadow_bounds.radius().max(1e-6);
    let mut nearest_caster = 0.0;
    let (per_distance, widest) = match light {
        Light::Directional(_) => {
            // The deepest receiver lies at most `far`, the nearest caster no nearer than the
            // casters' box.
            let mut range = depth_range;
            let casters = caster_parts.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
            if !casters.is_empty() {
                let nearest_caster = casters
                    .corners()
                    .iter()
                    .map(|c| -light_view.view.transform_point3(*c).z)
                    .fold(f32::INFINITY, f32::min);
                range = range.min((light_view.far - nearest_caster).max(0.0));
            }
            (size, size * range)
        }
        _ => {
            let position = light.position().unwrap_or_default();
            let nearest_part = caster_parts
                .iter()
                .filter(|b| !b.is_empty())
                .map(|b| light_to_box(position, b))
                .fold(f32::INFINITY, f32::min);
            let nearest = if nearest_part.is_finite() {
                nearest_part.max(light_view.near).max(1e-6)
            } else {
                light_view.near.max(1e-6)
            };
            // Down to steps of 2^(1/8), so a caster moving a little elsewhere does not change
            // every light's fatten distance (and with it its maps).
            let nearest = ((nearest.log2() * 8.0).floor() / 8.0).exp2();
            nearest_caster = nearest;
            // No caster pushed toward the light by the fatten distance reaches it (at half, a
            // plate touching the light lost the outer half of its penumbra past 0.45 of its
            // 1.15 units: tests/robustness/light_extremes.rs).
            cap = cap.min(0.8 * nearest);
            // Where the fattened map marks it, at the caster's own distance from the light, a
            // penumbra reaches only R (D - d) / D beside the caster (D the receiver's distance,
            // d the caster's): never past the light's radius, however wide it grows on the
            // receiver. Fattening further only makes nearer casters' fattened copies cover rays
            // they do not shadow.
            let radius = size * 0.5;
            let far = light_view.far.max(nearest);
            // A perspective map's texel grows with the distance: at the nearest caster.
            texel *= nearest / light_view.near.max(1e-6);
            (size / nearest, 2.0 * radius * (far - nearest) / far)
        }
    };
    let fatten = if size > 0.0 {
        // Two texels of the half-resolution fattened map.
        (widest * 0.5 + 4.0 * texel).min(cap)
    } else {
        0.0
    };
    DerivedSpreads {
        fatten_distance: fatten,
        penumbra_per_distance: per_distance,
        nearest_caster,
    }
}

/// How near a caster in box `b` can come to a light at `position`: the distance to the box
/// from outside it; from inside (a shade or a room around the bulb), the distance to its
/// nearest side, where such a caster's surfaces lie.
pub(crate) fn light_to_box(position: Vec3, b: &Aabb) -> f32 {
    let outside = position.clamp(b.min, b.max).distance(position);
    if outside > 0.0 {
        return outside;
    }
    (position - b.min).min(b.max - position).min_element().max(0.0)
}

pub(crate) struct FrameInputs<'a> {
    pub camera: &'a CameraMatrices,
    pub width: u32,
    pub height: u32,
    pub light: &'a Light,
    pub ambient: Vec3,
    pub light_view: &'a LightView,
    pub settings: &'a ShadowSettings,
    pub spreads: DerivedSpreads,
    pub caster_radius: f32,
    /// A receiver mask is bound.
    pub receiver_mask: bool,
    /// A distance map is bound (the resolve applies the indirect term).
    pub distance_map: bool,
    /// The configured map resolution over the one drawn (1, 2 or 4:
    /// [`crate::MapResolution::FromPenumbra`]).
    pub map_scale: f32,
    /// The layers of the light's maps in their arrays.
    pub map_layers: MapLayersUniform,
}

impl FrameUniform {
    pub fn new(f: &FrameInputs) -> Self {
        let view_proj = f.camera.view_projection();
        let light = f.light;
        let spot = light_kind(light);
        let (position, cos_outer, cos_inner) = light.cone();
        let lv = f.light_view;
        let perspective = lv.kind == ProjectionKind::Perspective;
        let tan_half_fov = if perspective {
            1.0 / lv.projection.y_axis.y
        } else {
            0.0
        };
        let s = f.settings;
        let p = &s.penumbra;
        let fast = s.method == ShadowMethod::OursFast;
        let (physical, fatten) = match p.spreads {
            SpreadMode::Physical => (1, f.spreads.fatten_distance),
            SpreadMode::Manual { fatten_distance, .. } => (0, fatten_distance),
        };
        // Physical mode: the total filter's standard deviation matches a disk light's edge
        // profile, sigma = w / 4, split between the PCF taps and the blur (in the
        // distance-map pass).
        let share = if fast { 0.0 } else { p.pcf_variance_share };
        FrameUniform {
            view: ViewUniform {
                view_proj: view_proj.to_cols_array_2d(),
                inv_view_proj: view_proj.inverse().to_cols_array_2d(),
                toward_camera: f.camera.toward_camera(),
                depth_to_view: f.camera.depth_to_view(),
                size: [f.width as f32, f.height as f32],
                inv_size: [1.0 / f.width as f32, 1.0 / f.height as f32],
                pixels_per_unit: f.camera.pixels_per_unit(f.height),
                reversed_depth: (f.camera.depth == DepthConvention::Reversed) as u32,
                has_receiver_mask: f.receiver_mask as u32,
                has_distance_map: f.distance_map as u32,
            },
            light: ShadowLightUniform {
                view_proj: lv.view_projection.to_cols_array_2d(),
                direction: light.direction().to_array(),
                spot,
                position: position.to_array(),
                cos_outer,
                radiance: light.radiance().to_array(),
                cos_inner,
                near: lv.near,
                far: lv.far,
                perspective: perspective as u32,
                // Texels across the whole atlas (its columns): with the extents times the
                // grid (`shadow_map_world_size`), each cascade's own texel size.
                resolution: lv.grid.size(lv.tile).0 as f32,
                extent: lv.extent.to_array(),
                tan_half_fov,
                size_term: light_size_term(light),
                area_u: area_axes(light).0,
                area_v: area_axes(light).1,
            },
            penumbra: PenumbraUniform {
                fatten_distance: fatten,
                physical,
                indirect_weight: p.indirect_weight,
                indirect_half_distance: f.caster_radius.max(1e-6) * 0.5,
                pcf_share: share,
                sigma_per_width: SIGMA_PER_WIDTH,
                normal_offset: s.shadow_map.normal_offset,
                map_scale: f.map_scale,
                taps_per_side: if fast { 1 } else { p.pcf_kernel.side() },
                base_spacing: p.pcf_base_spacing,
                umbra_tiles: (p.skip_umbra_tiles
                    && p.nearest_caster
                    && physical == 1
                    && p.indirect_weight == 0.0
                    && matches!(s.method, ShadowMethod::Ours | ShadowMethod::OursFast)
                    && area_axes(light).0[3] == 0.0) as u32,
                _pad: 0.0,
            },
            ambient: f.ambient.extend(0.0).to_array(),
            cascades: CascadesUniform::new(lv, lv.tile),
            maps: f.map_layers,
            _pad: [[0.0; 4]; 9],
        }
    }
}

/// The standard deviation of a disk light's edge profile as a fraction of the penumbra's
/// full width: the disk's radius over 2, so w / 4.
pub(crate) const SIGMA_PER_WIDTH: f32 = 0.268;

/// Gaussian weights for taps 0..=radius (tap k weight, unnormalized), sigma = taps / 4 in tap units.
pub(crate) fn gaussian_weights(taps: u32) -> [[f32; 4]; 4] {
    let radius = (taps / 2) as i32;
    let sigma = (taps as f32 / 4.0).max(0.5);
    let mut w = [[0.0; 4]; 4];
    for k in 0..=radius.min(15) {
        w[(k / 4) as usize][(k % 4) as usize] = (-(k * k) as f32 / (2.0 * sigma * sigma)).exp();
    }
    w
}

/// One light as the convenience renderer's composite shades it (mirrors `ShadedLight` in
/// composite.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, Pod, Zeroable)]
pub(crate) struct ShadedLight {
    pub direction: [f32; 3],
    pub spot: u32,
    pub position: [f32; 3],
    pub cos_outer: f32,
    pub radiance: [f32; 3],
    pub cos_inner: f32,
    /// Its layer of the visibility array.
    pub layer: u32,
    /// A spot's or point light's range ([`crate::SpotLight::range`]); 0: none.
    pub range: f32,
    pub _pad: [u32; 2],
    /// An area light's half-axes and shape, as [`ShadowLightUniform::area_u`].
    pub area_u: [f32; 4],
    pub area_v: [f32; 4],
}

/// Every light the composite shades (mirrors `ShadedLights` in composite.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct ShadedLights {
    pub count: u32,
    pub _pad: [u32; 3],
    pub lights: [ShadedLight; crate::MAX_LIGHTS],
}

impl ShadedLights {
    /// The lights, each with its visibility layer, their radiance times `exposure` (the
    /// camera's [`crate::Exposure::scale`]); past [`crate::MAX_LIGHTS`] they are not shaded
    /// (the callers check the count).
    pub fn new(lights: &[(Light, u32)], exposure: f32) -> Self {
        let mut shaded = ShadedLights {
            count: lights.len().min(crate::MAX_LIGHTS) as u32,
            _pad: [0; 3],
            lights: [ShadedLight::default(); crate::MAX_LIGHTS],
        };
        for (slot, (light, layer)) in shaded.lights.iter_mut().zip(lights) {
            let (position, cos_outer, cos_inner) = light.cone();
            *slot = ShadedLight {
                direction: light.direction().to_array(),
                spot: light_kind(light),
                position: position.to_array(),
                cos_outer,
                radiance: (light.radiance() * exposure).to_array(),
                cos_inner,
                layer: *layer,
                range: light.range().unwrap_or(0.0),
                _pad: [0; 2],
                area_u: area_axes(light).0,
                area_v: area_axes(light).1,
            };
        }
        shaded
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::mem::{offset_of, size_of};

    /// A WGSL struct's fields and their offsets in the Rust mirror, and the mirror's size.
    type Layout = (&'static str, Vec<(&'static str, usize)>, usize);

    /// `(wgsl name, [(field, offset in the Rust type)], size of the Rust type)` for a Rust type
    /// and the fields it shares with its WGSL struct.
    macro_rules! layout {
        ($wgsl:literal, $rust:ty, [$($field:ident),* $(,)?]) => {
            ($wgsl, vec![$((stringify!($field), offset_of!($rust, $field))),*], size_of::<$rust>())
        };
    }

    fn layouts() -> Vec<Layout> {
        vec![
            layout!(
                "Frame",
                FrameUniform,
                [view, light, penumbra, ambient, cascades, maps]
            ),
            layout!(
                "MapLayers",
                MapLayersUniform,
                [shadow, fattened, occluder_offset, exit]
            ),
            layout!(
                "Cascades",
                CascadesUniform,
                [view_proj, extent_end, tile, axis, grid, count]
            ),
            layout!(
                "View",
                ViewUniform,
                [
                    view_proj,
                    inv_view_proj,
                    toward_camera,
                    depth_to_view,
                    size,
                    inv_size,
                    pixels_per_unit,
                    reversed_depth,
                    has_receiver_mask,
                    has_distance_map
                ]
            ),
            layout!(
                "ShadowLight",
                ShadowLightUniform,
                [
                    view_proj,
                    direction,
                    spot,
                    position,
                    cos_outer,
                    radiance,
                    cos_inner,
                    near,
                    far,
                    perspective,
                    resolution,
                    extent,
                    tan_half_fov,
                    size_term,
                    area_u,
                    area_v
                ]
            ),
            layout!(
                "Penumbra",
                PenumbraUniform,
                [
                    fatten_distance,
                    physical,
                    indirect_weight,
                    indirect_half_distance,
                    pcf_share,
                    sigma_per_width,
                    normal_offset,
                    map_scale,
                    taps_per_side,
                    base_spacing,
                    umbra_tiles
                ]
            ),
            layout!(
                "ShadedLight",
                ShadedLight,
                [
                    direction, spot, position, cos_outer, radiance, cos_inner, layer, range
                ]
            ),
            layout!("ShadedLights", ShadedLights, [count, lights]),
            layout!("Pcf", PcfUniform, [taps_per_side, base_spacing, spread]),
            layout!("Pcss", PcssUniform, [blocker_samples, pcf_samples]),
            layout!(
                "Blur",
                crate::screen::BlurUniform,
                [axis, weights, taps, step, resolve, kernel_sigma]
            ),
            layout!(
                "Surface",
                crate::layouts::SurfaceUniform,
                [rect, params, occlusion, occlusion_transform, emissive, shading]
            ),
        ]
    }

    /// Every shader that declares one of the uniform structs declares each named field at the
    /// Rust mirror's offset, with the mirror's size.
    #[test]
    fn wgsl_uniform_structs_match_their_rust_mirrors_field_by_field() {
        let mut checked = std::collections::BTreeMap::new();
        for (shader, source) in crate::shaders::ALL {
            let module = naga::front::wgsl::parse_str(source).unwrap();
            let mut layouter = naga::proc::Layouter::default();
            layouter.update(module.to_ctx()).unwrap();
            for (handle, ty) in module.types.iter() {
                let Some((name, fields, size)) = layouts()
                    .into_iter()
                    .find(|(n, _, _)| ty.name.as_deref() == Some(*n))
                else {
                    continue;
                };
                let naga::TypeInner::Struct { members, .. } = &ty.inner else {
                    panic!("{shader}: {name} is not a struct");
                };
                assert_eq!(layouter[handle].size as usize, size, "{shader}: size of {name}");
                for (field, offset) in fields {
                    let member = members
                        .iter()
                        .find(|m| m.name.as_deref() == Some(field))
                        .unwrap_or_else(|| panic!("{shader}: {name} has no field {field}"));
                    assert_eq!(
                        member.offset as usize, offset,
                        "{shader}: offset of {name}.{field}"
                    );
                }
                *checked.entry(name).or_insert(0) += 1;
            }
        }
        for (name, _, _) in layouts() {
            assert!(
                checked.get(name).is_some_and(|n| *n > 0),
                "no shader declares {name}"
            );
        }
        assert!(
            checked["Frame"] >= 7,
            "only {} shaders declare Frame",
            checked["Frame"]
        );
    }

    #[test]
    fn gaussian_weights_fall_off() {
        let w = gaussian_weights(11);
        assert_eq!(w[0][0], 1.0);
        assert!(w[0][1] < 1.0 && w[1][1] < w[0][1] && w[1][1] > 0.0);
        assert_eq!(w[1][2], 0.0, "taps beyond the radius are zero");
    }
}
