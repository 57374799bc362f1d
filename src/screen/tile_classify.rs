//! Tile classification: which 16 x 16 pixel tiles of the screen the light's fattened shadow can
//! reach. Owned by [`super::DistanceMapPass`], which then draws only those tiles: on a
//! software rasterizer a full-screen pass costs about as much whatever its shader does (on
//! lavapipe at 1280x1024 the distance map's triangle cost 38 ms with a shader returning at
//! once, 54 ms with the whole test), so the work saved is the pixels not drawn at all.
//!
//! Input: the frame uniform, the camera depth and the fattened shadow map. Outputs: the
//! fattened map reduced by [`REDUCE`] x [`REDUCE`] texels to their least depth (R16F, redrawn
//! when the light's maps are), and one texel per screen tile ([`TILE`] pixels a side, R8): 1
//! where a pixel may lie inside the fattened shadow, from the tile's depth range and the least
//! fattened depth under its footprint in each cascade or cube face it can use; 0 where none
//! can (conservative: see `shaders/tile_classify.wgsl`).

use super::{DistanceMapCompute, LIGHT_KIND, tiles_layout};
use crate::frame::FrameSlot;
use crate::gpu_helpers::{Target, texture_bytes};
use crate::gpu_helpers::{Tiles, entry, screen_target};
use crate::pipeline_cache::CachedDevice;
use crate::pipeline_cache::Fullscreen;

/// Screen pixels per tile side (`TILE` in the shader).
pub const TILE: u32 = 16;
/// Fattened-map texels per reduced texel side (`REDUCE` in the shader).
pub const REDUCE: u32 = 8;

/// Half floats render everywhere, GL included (R32F does not); the shader rounds the least
/// depth down before storing it, so the stored value never lies behind the true one.
const REDUCED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
const CLASS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

pub(crate) struct TileClassifyPass {
    layout: wgpu::BindGroupLayout,
    tiles_layout: wgpu::BindGroupLayout,
    /// The classes as the kept tiles' bind group, and the number of tiles.
    tiles: (wgpu::BindGroup, u32),
    reduce_layout: wgpu::BindGroupLayout,
    classify: std::sync::Arc<wgpu::RenderPipeline>,
    reduce: std::sync::Arc<wgpu::RenderPipeline>,
    reduced: Target,
    classes: Target,
    groups: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    gather: wgpu::Sampler,
}

impl TileClassifyPass {
    /// GPU memory this pass allocated: its textures and buffers, in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.reduced.texture) + texture_bytes(&self.classes.texture)
    }

    /// Made for one light kind ([`crate::frame::light_kind`]), like the distance map.
    pub fn new(device: &CachedDevice<'_>, frame_size: usize, light_kind: u32) -> Self {
        let shader = device.module("tile_classify.wgsl", crate::shaders::TILE_CLASSIFY);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let layout = device.bind_group_layout(
            "TileClassifyPass::layout",
            &[
                entry::fragment_uniform(0, frame_size),
                entry::texture_2d(1, unfilterable),
                entry::texture_2d(2, unfilterable),
                entry::sampler(4, wgpu::SamplerBindingType::NonFiltering),
            ],
        );
        let reduce_layout = device.bind_group_layout(
            "TileClassifyPass::reduce_layout",
            &[
                entry::texture_2d(3, unfilterable),
                entry::sampler(4, wgpu::SamplerBindingType::NonFiltering),
            ],
        );
        let constants = [(LIGHT_KIND, light_kind as f64)];
        let pipeline = |label, layout: &wgpu::BindGroupLayout, format: wgpu::TextureFormat, entry| {
            Fullscreen {
                label,
                shader: &shader,
                bind_group_layouts: &[Some(layout)],
                targets: &[Some(format.into())],
                depth: None,
                constants: &constants,
            }
            .pipeline_at(device, entry)
        };
        let tiles_layout = tiles_layout(device);
        let classes = screen_target(device, "TileClassifyPass::classes", 1, 1, CLASS_FORMAT);
        Self {
            tiles: (Self::tiles_group(device, &tiles_layout, &classes.view), 1),
            tiles_layout,
            classify: pipeline("TileClassifyPass::classify", &layout, CLASS_FORMAT, "fs_classify"),
            reduce: pipeline(
                "TileClassifyPass::reduce",
                &reduce_layout,
                REDUCED_FORMAT,
                "fs_reduce",
            ),
            layout,
            reduce_layout,
            reduced: screen_target(device, "TileClassifyPass::reduced", 1, 1, REDUCED_FORMAT),
            classes,
            groups: None,
            gather: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("TileClassifyPass::gather"),
                ..Default::default()
            }),
        }
    }

    /// Tiles across and down a `width` x `height` screen.
    pub fn tiles(width: u32, height: u32) -> (u32, u32) {
        (width.div_ceil(TILE), height.div_ceil(TILE))
    }

    /// Sizes the classes for a screen; the pass must then be bound again.
    pub fn resize(&mut self, device: &CachedDevice<'_>, width: u32, height: u32) {
        let (x, y) = Self::tiles(width, height);
        self.classes = screen_target(device, "TileClassifyPass::classes", x, y, CLASS_FORMAT);
        self.tiles = (
            Self::tiles_group(device, &self.tiles_layout, &self.classes.view),
            x * y,
        );
        self.groups = None;
    }

    fn tiles_group(
        device: &CachedDevice<'_>,
        layout: &wgpu::BindGroupLayout,
        classes: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        crate::gpu_helpers::bind_group(device, "TileClassifyPass::tiles", layout, &[classes])
    }

    /// The kept tiles, for the passes that draw only them.
    pub fn kept(&self) -> Tiles<'_> {
        Tiles {
            group: &self.tiles.0,
            count: self.tiles.1,
        }
    }

    /// Points the pass at its inputs; `fattened_map` is `fattened_size` texels (width, height).
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        frame: &FrameSlot,
        camera_depth: &wgpu::TextureView,
        fattened_map: &wgpu::TextureView,
        fattened_size: (u32, u32),
    ) {
        let size = (fattened_size.0.div_ceil(REDUCE), fattened_size.1.div_ceil(REDUCE));
        if (self.reduced.texture.width(), self.reduced.texture.height()) != size {
            self.reduced = screen_target(
                device,
                "TileClassifyPass::reduced",
                size.0,
                size.1,
                REDUCED_FORMAT,
            );
        }
        let classify = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("TileClassifyPass::classify"),
            layout: &self.layout,
            entries: &[
                crate::gpu_helpers::Binding::resource(frame),
                wgpu::BindingResource::TextureView(camera_depth),
                wgpu::BindingResource::TextureView(&self.reduced.view),
            ]
            .into_iter()
            .enumerate()
            .map(|(i, resource)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource,
            })
            .chain([wgpu::BindGroupEntry {
                binding: 4,
                resource: wgpu::BindingResource::Sampler(&self.gather),
            }])
            .collect::<Vec<_>>(),
        });
        let reduce = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("TileClassifyPass::reduce"),
            layout: &self.reduce_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(fattened_map),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&self.gather),
                },
            ],
        });
        self.groups = Some((classify, reduce));
    }

    pub fn classes_texture(&self) -> &wgpu::Texture {
        &self.classes.texture
    }

    /// Records the reduction of the fattened map (`maps_drawn`: the light's maps were drawn
    /// since the last one) and the classification.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, maps_drawn: bool) {
        let Some((classify, reduce)) = &self.groups else {
            return;
        };
        if maps_drawn {
            super::draw_fullscreen(
                encoder,
                "TileClassifyPass::reduce",
                &self.reduce,
                &[reduce],
                &self.reduced.view,
            );
        }
        super::draw_fullscreen(
            encoder,
            "TileClassifyPass::classify",
            &self.classify,
            &[classify],
            &self.classes.view,
        );
    }
}

/// The tile classification of the compute path: the same test, one invocation per screen tile,
/// which appends the tiles it keeps to a list (every tile with the classification off), and
/// the indirect arguments of the passes that run over that list ([`super::TileList`]): a
/// dispatch of one 16 x 16 workgroup per listed tile, a draw of one quad per listed tile. So
/// the distance map, PCF and blur cost what the listed tiles do, on a GPU as on a software
/// rasterizer.
///
/// A kept tile's pixels are then tested one by one (`pixel_flags` in the shader): a tile none of
/// whose pixels lies inside the fattened shadow, as the distance map tests it, is dropped after
/// all (the passes would find no shadow there). With `facing_away`, a kept tile whose every pixel
/// lies on a surface turned away from the light goes to a second list instead
/// ([`TileListTargets::away`]): the passes write 0 there without taps.
///
/// Inputs: the frame uniform, the camera depth, the receiver mask and the fattened shadow map.
/// Outputs: the reduced fattened map (R32F, the light's own, redrawn when its maps are) and,
/// into [`TileListTargets`] that the lights share, the lists, their arguments and the classes.
pub(crate) struct TileListPass {
    classify_layout: wgpu::BindGroupLayout,
    reduce_layout: wgpu::BindGroupLayout,
    reduce: std::sync::Arc<wgpu::ComputePipeline>,
    /// The shadow map's least and greatest depth per block, for the umbra test (with `umbra`).
    depth_range_pass: Option<(std::sync::Arc<wgpu::ComputePipeline>, wgpu::BindGroupLayout)>,
    classify: std::sync::Arc<wgpu::ComputePipeline>,
    finish: std::sync::Arc<wgpu::ComputePipeline>,
    /// One invocation per tile with the umbra test: the kept tiles' count into the test's
    /// dispatch, and the test over them (`cs_candidates_finish`, `cs_umbra`).
    umbra_pass: Option<(
        std::sync::Arc<wgpu::ComputePipeline>,
        std::sync::Arc<wgpu::ComputePipeline>,
    )>,
    /// `cs_umbra`'s bindings: the classification's but the arguments, which its dispatch reads.
    umbra_layout: wgpu::BindGroupLayout,
    umbra_group: Option<wgpu::BindGroup>,
    /// The kept tiles the umbra test decides (one invocation per tile; its dispatch's arguments
    /// at [`CANDIDATE_ARGS`] in the lists' arguments): one tile's room where the test does not
    /// run so.
    candidates: wgpu::Buffer,
    /// The pixels tested by a workgroup per tile ([`pixels_by_workgroup`]); the same
    /// dispatch then clears the compute path's intermediates ([`Self::clears`]).
    wide: bool,
    /// With `wide`: the blur's horizontal result is cleared too (the chain blurs).
    clears_blurred: bool,
    reduced: Target,
    /// The shadow map's least and greatest depth per [`UMBRA_BLOCK`] x [`UMBRA_BLOCK`] texels
    /// (RG32F; 1 x 1 without the umbra test).
    depth_range: Target,
    /// The list written, as bound.
    targets: Option<TileListTargets>,
    groups: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    depth_range_group: Option<wgpu::BindGroup>,
    gather: wgpu::Sampler,
}

/// The compute path's intermediates a [`TileListPass`] clears where it does
/// ([`TileListPass::clears`]): the distance map, the visibility (the light's layer where the
/// variable PCF writes there) and, where the chain blurs, the blur's horizontal result.
pub(crate) struct ClearedByList<'a> {
    pub distance: &'a wgpu::TextureView,
    pub visibility: &'a wgpu::TextureView,
    pub blurred: Option<&'a wgpu::TextureView>,
}

/// A tile list for one screen: the list (a count, the running count the classification
/// appends with, then one `x | y << 16` per tile), the indirect arguments, the classes (R32F,
/// one texel per tile, 1 where listed, 0.25 where listed apart as turned away from the light:
/// the debug view's and the bench's tile share) and the list's bind group for the passes over
/// it; the same for the tiles turned away from the light.
/// Lights whose chains run one after the other share one.
#[derive(Clone)]
pub(crate) struct TileListTargets {
    list: wgpu::Buffer,
    args: wgpu::Buffer,
    classes: Target,
    /// The list as group [`super::TILE_LIST_GROUP`].
    group: wgpu::BindGroup,
    /// The tiles turned away from the light (or deep in the umbra): list, group (their
    /// arguments at [`AWAY_ARGS`] in `args`).
    away: (wgpu::Buffer, wgpu::BindGroup),
}

impl TileListTargets {
    /// For a `width` x `height` screen.
    pub fn new(device: &CachedDevice<'_>, (width, height): (u32, u32)) -> Self {
        let tiles = TileClassifyPass::tiles(width, height);
        let buffer = |label, size, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let list_usage = wgpu::BufferUsages::STORAGE;
        let args_usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT;
        // The count, the running count the classification appends with, the tiles.
        let words = list_bytes(tiles);
        let list = buffer("TileListTargets::list", words, list_usage);
        let group = Self::list_group(device, "TileListTargets::list", &list);
        let away = buffer("TileListTargets::away", words, list_usage);
        let away_group = Self::list_group(device, "TileListTargets::away", &away);
        Self {
            // The list's arguments, the tiles turned away's, the umbra test's dispatch.
            args: buffer("TileListTargets::args", CANDIDATE_ARGS + 16, args_usage),
            away: (away, away_group),
            classes: super::storage_target(
                device,
                "TileListTargets::classes",
                tiles,
                REDUCED_STORAGE_FORMAT,
                false,
            ),
            list,
            group,
        }
    }

    /// The bytes of one screen's list (`width` x `height`): the count, the running count the
    /// classification appends with, one word a tile.
    pub fn list_bytes((width, height): (u32, u32)) -> u64 {
        list_bytes(TileClassifyPass::tiles(width, height))
    }

    /// Every tile of a `width` x `height` screen, listed once (a pass over the whole screen).
    pub fn every_tile(device: &CachedDevice<'_>, (width, height): (u32, u32)) -> Self {
        let (across, down) = TileClassifyPass::tiles(width, height);
        let count = across * down;
        let words: Vec<u32> = [count, 0]
            .into_iter()
            .chain((0..down).flat_map(|y| (0..across).map(move |x| x | (y << 16))))
            .collect();
        let filled = |label, usage, contents: &[u32]| {
            wgpu::util::DeviceExt::create_buffer_init(
                &**device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(contents),
                    usage,
                },
            )
        };
        let list = filled("TileListTargets::every_tile", wgpu::BufferUsages::STORAGE, &words);
        // As `cs_finish` writes them.
        let dispatch = [count.min(65535), count.div_ceil(65535), 1, 0];
        // No tile is turned away (the classification does not run): none at AWAY_ARGS.
        let args = filled(
            "TileListTargets::every_tile_args",
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            &[
                dispatch[0],
                dispatch[1],
                dispatch[2],
                dispatch[3],
                6,
                count,
                0,
                0,
                0,
                0,
                1,
                0,
                6,
                0,
                0,
                0,
                0,
                1,
                1,
                0,
            ],
        );
        let group = Self::list_group(device, "TileListTargets::every_tile", &list);
        // No tile is turned away: the classification does not run.
        let away = filled(
            "TileListTargets::no_tile",
            wgpu::BufferUsages::STORAGE,
            &[0, 0, 0],
        );
        let away_group = Self::list_group(device, "TileListTargets::no_tile", &away);
        Self {
            list,
            args,
            away: (away, away_group),
            classes: super::storage_target(
                device,
                "TileListTargets::classes",
                (1, 1),
                REDUCED_STORAGE_FORMAT,
                false,
            ),
            group,
        }
    }

    /// `list` as group [`super::TILE_LIST_GROUP`] of the passes over it.
    fn list_group(device: &CachedDevice<'_>, label: &str, list: &wgpu::Buffer) -> wgpu::BindGroup {
        crate::gpu_helpers::bind_group(
            device,
            label,
            &TileListPass::list_layout(device),
            &[&list.as_entire_binding()],
        )
    }

    pub fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.classes.texture) + self.list.size() + self.args.size() + self.away.0.size()
    }

    /// One texel per screen tile: 1 where it was listed.
    pub fn classes_texture(&self) -> &wgpu::Texture {
        &self.classes.texture
    }

    /// The list, for the passes over it.
    pub fn listed(&self) -> super::TileList<'_> {
        super::TileList {
            group: &self.group,
            args: &self.args,
            offset: 0,
        }
    }

    /// The tiles listed apart as turned away from the light, for the passes that write 0 there.
    pub fn away(&self) -> super::TileList<'_> {
        super::TileList {
            group: &self.away.1,
            args: &self.args,
            offset: AWAY_ARGS,
        }
    }
}

impl TileListPass {
    /// GPU memory this pass allocated (its reduced maps), in bytes.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.reduced.texture)
            + texture_bytes(&self.depth_range.texture)
            + self.candidates.size()
    }

    /// The layout of the list's bind group (`shaders/common/tile_list.wgsl`), for the passes
    /// over it.
    pub(crate) fn list_layout(device: &CachedDevice<'_>) -> wgpu::BindGroupLayout {
        device.bind_group_layout(
            "TileListPass::list_layout",
            // The fragment stage too: over a group, the blur's module reads the pooled
            // horizontal result through the members' maps in the list's buffer, in each of its
            // entry points (the copy's are made, never recorded, there).
            &[entry::storage_buffer(
                0,
                wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE,
                true,
            )],
        )
    }

    /// Made for one light kind ([`crate::frame::light_kind`]); `classify` false lists every
    /// tile; `facing_away` lists the kept tiles turned away from the light apart, `umbra` those
    /// deep in the umbra (`shaders/common/umbra.wgsl`, where the frame uniform allows it);
    /// `blurred`:
    /// the chain blurs (where the classification clears the intermediates, it clears the
    /// blur's too), `half`: they are stored in half floats ([`super::visibility_storage`]),
    /// `layer`: the visibility it clears is the light's layer (the variable PCF writes there,
    /// [`crate::Chain::pcf_in_layer`]); `pixels`: how the kept tiles' pixels are tested
    /// ([`crate::ExecutionSettings::tile_pixels`]); `arrays`: it reads the light's maps as
    /// layers of arrays ([`crate::shaders::with_map_arrays`]).
    pub fn new(
        device: &CachedDevice<'_>,
        (frame_size, arrays): (usize, bool),
        light_kind: u32,
        (classify, facing_away, umbra): (bool, bool, bool),
        (blurred, half, layer): (bool, bool, bool),
        pixels: crate::settings::TilePixels,
    ) -> Self {
        let storage = crate::shaders::HalfFloats {
            layers: false,
            intermediates: half,
        };
        let shader = crate::shaders::module_for(
            device,
            "tile_classify.wgsl",
            crate::shaders::TILE_CLASSIFY,
            (storage, arrays),
        );
        let per_pixel = classify && pixels.by_workgroup(device);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let compute = wgpu::ShaderStages::COMPUTE;
        // The intermediates the classification by workgroups clears (bindings 12 to 14).
        let mut cleared = Vec::new();
        if per_pixel {
            cleared.push(entry::storage_texture(12, DistanceMapCompute::format(half)));
            cleared.push(entry::storage_texture(13, super::visibility_storage(half)));
            if blurred {
                cleared.push(entry::storage_texture(14, super::visibility_storage(half)));
            }
        }
        let mut classify_entries = vec![
            entry::uniform(0, compute, frame_size, false),
            entry::and_compute(entry::texture_2d(1, unfilterable)),
            entry::and_compute(entry::texture_2d(2, unfilterable)),
            entry::and_compute(entry::sampler(4, wgpu::SamplerBindingType::NonFiltering)),
            entry::storage_buffer(5, compute, false),
            entry::storage_buffer(7, compute, false),
            entry::storage_texture(8, REDUCED_STORAGE_FORMAT),
            entry::storage_buffer(9, compute, false),
            entry::storage_buffer(10, compute, false),
            entry::and_compute(entry::texture_2d(11, unfilterable)),
            entry::and_compute(entry::light_map(3, unfilterable, arrays)),
            entry::and_compute(entry::texture_2d(17, unfilterable)),
        ];
        classify_entries.extend(cleared);
        let classify_layout = device.bind_group_layout("TileListPass::classify_layout", &classify_entries);
        let umbra_entries: Vec<_> = classify_entries
            .iter()
            .filter(|e| e.binding != 7)
            .cloned()
            .collect();
        let umbra_layout = device.bind_group_layout("TileListPass::umbra_layout", &umbra_entries);
        let reduce_layout = device.bind_group_layout(
            "TileListPass::reduce_layout",
            &[
                // The frame uniform: the light's layers where the maps are read as arrays.
                entry::uniform(0, compute, frame_size, false),
                entry::and_compute(entry::light_map(3, unfilterable, arrays)),
                entry::and_compute(entry::sampler(4, wgpu::SamplerBindingType::NonFiltering)),
                entry::storage_texture(6, REDUCED_STORAGE_FORMAT),
            ],
        );
        let constants = [
            (LIGHT_KIND, light_kind as f64),
            ("CLASSIFY", if classify { 1.0 } else { 0.0 }),
            ("FACING", if classify && facing_away { 1.0 } else { 0.0 }),
            ("UMBRA", if classify && umbra { 1.0 } else { 0.0 }),
            ("WIDE", if per_pixel { 1.0 } else { 0.0 }),
            ("CLEARS", if per_pixel { 1.0 } else { 0.0 }),
            ("CLEAR_BLURRED", if per_pixel && blurred { 1.0 } else { 0.0 }),
            ("CLEAR_LAYER", if per_pixel && layer { 1.0 } else { 0.0 }),
            super::row_threads(device),
        ];
        let pipeline = |label, layout: &wgpu::BindGroupLayout, entry| {
            device.compute_pipeline(label, &shader, &[Some(layout)], entry, &constants)
        };
        let depth_range_pass = (classify && umbra).then(|| {
            let layout = device.bind_group_layout(
                "TileListPass::depth_range_layout",
                &[
                    entry::uniform(0, compute, frame_size, false),
                    entry::and_compute(entry::sampler(4, wgpu::SamplerBindingType::NonFiltering)),
                    entry::and_compute(entry::light_map(15, unfilterable, arrays)),
                    entry::storage_texture(16, DEPTH_RANGE_FORMAT),
                ],
            );
            let pipeline = pipeline("TileListPass::depth_range", &layout, "cs_depth_range");
            (pipeline, layout)
        });
        Self {
            reduce: pipeline("TileListPass::reduce", &reduce_layout, "cs_reduce"),
            depth_range_pass,
            classify: if per_pixel {
                pipeline("TileListPass::classify", &classify_layout, "cs_classify_wide")
            } else {
                pipeline("TileListPass::classify", &classify_layout, "cs_classify")
            },
            wide: per_pixel,
            clears_blurred: per_pixel && blurred,
            finish: pipeline("TileListPass::finish", &classify_layout, "cs_finish"),
            umbra_pass: (classify && umbra && !per_pixel).then(|| {
                (
                    pipeline(
                        "TileListPass::candidates_finish",
                        &classify_layout,
                        "cs_candidates_finish",
                    ),
                    pipeline("TileListPass::umbra", &umbra_layout, "cs_umbra"),
                )
            }),
            umbra_layout,
            umbra_group: None,
            candidates: candidate_list(device, (1, 1)),
            classify_layout,
            reduce_layout,
            reduced: super::storage_target(
                device,
                "TileListPass::reduced",
                (1, 1),
                REDUCED_STORAGE_FORMAT,
                false,
            ),
            depth_range: super::storage_target(
                device,
                "TileListPass::depth_range",
                (1, 1),
                DEPTH_RANGE_FORMAT,
                false,
            ),
            targets: None,
            groups: None,
            depth_range_group: None,
            gather: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("TileListPass::gather"),
                ..Default::default()
            }),
        }
    }

    /// Points the pass at its inputs (`fattened_map` is `fattened_size` texels, width and
    /// height, `shadow_map` `shadow_size`), the lists it writes and the intermediates it clears
    /// where it does ([`Self::clears`]).
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        (targets, cleared): (&TileListTargets, &ClearedByList),
        frame: &FrameSlot,
        (camera_depth, receiver_mask): (&wgpu::TextureView, &wgpu::TextureView),
        (fattened_map, fattened_size): (&wgpu::TextureView, (u32, u32)),
        (shadow_map, shadow_size): (&wgpu::TextureView, (u32, u32)),
    ) {
        let size = (fattened_size.0.div_ceil(REDUCE), fattened_size.1.div_ceil(REDUCE));
        if (self.reduced.texture.width(), self.reduced.texture.height()) != size {
            self.reduced = super::storage_target(
                device,
                "TileListPass::reduced",
                size,
                REDUCED_STORAGE_FORMAT,
                false,
            );
        }
        if let Some((_, layout)) = &self.depth_range_pass {
            let size = (
                shadow_size.0.div_ceil(UMBRA_BLOCK),
                shadow_size.1.div_ceil(UMBRA_BLOCK),
            );
            if (
                self.depth_range.texture.width(),
                self.depth_range.texture.height(),
            ) != size
            {
                self.depth_range = super::storage_target(
                    device,
                    "TileListPass::depth_range",
                    size,
                    DEPTH_RANGE_FORMAT,
                    false,
                );
            }
            self.depth_range_group = Some(device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("TileListPass::depth_range"),
                layout,
                entries: &entries([
                    (0, crate::gpu_helpers::Binding::resource(frame)),
                    (4, wgpu::BindingResource::Sampler(&self.gather)),
                    (15, wgpu::BindingResource::TextureView(shadow_map)),
                    (16, wgpu::BindingResource::TextureView(&self.depth_range.view)),
                ]),
            }));
        }
        // Sized for the screen only where the umbra test runs by a dispatch of its own: where it
        // does not, none is read, and the light's memory is as without it.
        let tiles = (targets.classes.texture.width(), targets.classes.texture.height());
        let tiles = if self.umbra_pass.is_some() { tiles } else { (1, 1) };
        if self.candidates.size() != list_bytes(tiles) {
            self.candidates = candidate_list(device, tiles);
        }
        let mut classify_entries = entries([
            (0, crate::gpu_helpers::Binding::resource(frame)),
            (1, wgpu::BindingResource::TextureView(camera_depth)),
            (2, wgpu::BindingResource::TextureView(&self.reduced.view)),
            (4, wgpu::BindingResource::Sampler(&self.gather)),
            (5, targets.list.as_entire_binding()),
            (7, targets.args.as_entire_binding()),
            (8, wgpu::BindingResource::TextureView(&targets.classes.view)),
            (9, targets.away.0.as_entire_binding()),
            (10, self.candidates.as_entire_binding()),
            (11, wgpu::BindingResource::TextureView(receiver_mask)),
            (3, wgpu::BindingResource::TextureView(fattened_map)),
            (17, wgpu::BindingResource::TextureView(&self.depth_range.view)),
        ])
        .to_vec();
        if self.wide {
            let view = wgpu::BindingResource::TextureView;
            classify_entries.extend(entries([
                (12, view(cleared.distance)),
                (13, view(cleared.visibility)),
            ]));
            if self.clears_blurred {
                let blurred = cleared
                    .blurred
                    .expect("a blurring chain's intermediates have the blur's");
                classify_entries.extend(entries([(14, view(blurred))]));
            }
        }
        let classify = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("TileListPass::classify"),
            layout: &self.classify_layout,
            entries: &classify_entries,
        });
        self.umbra_group = self.umbra_pass.is_some().then(|| {
            let umbra_entries: Vec<_> = classify_entries
                .iter()
                .filter(|e| e.binding != 7)
                .cloned()
                .collect();
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("TileListPass::umbra"),
                layout: &self.umbra_layout,
                entries: &umbra_entries,
            })
        });
        let reduce = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("TileListPass::reduce"),
            layout: &self.reduce_layout,
            entries: &entries([
                (0, crate::gpu_helpers::Binding::resource(frame)),
                (3, wgpu::BindingResource::TextureView(fattened_map)),
                (4, wgpu::BindingResource::Sampler(&self.gather)),
                (6, wgpu::BindingResource::TextureView(&self.reduced.view)),
            ]),
        });
        self.groups = Some((classify, reduce));
        self.targets = Some(targets.clone());
    }

    /// The classification also sets the compute path's intermediates to what the passes after
    /// it read where they write nothing (the distance map to 0, the visibility and the blur's
    /// horizontal result to 1): where it tests the pixels by workgroups, one invocation a
    /// pixel (a GPU), so that the chain needs no clears of its own. One invocation per tile (a
    /// CPU adapter) would store every texel of its tile in turn, where a render pass's clear
    /// is a memory fill.
    pub fn clears(&self) -> bool {
        self.wide
    }

    /// The list, for the passes over it (once bound).
    pub fn listed(&self) -> Option<super::TileList<'_>> {
        self.targets.as_ref().map(TileListTargets::listed)
    }

    /// The tiles turned away from the light (once bound).
    pub fn away(&self) -> Option<super::TileList<'_>> {
        self.targets.as_ref().map(TileListTargets::away)
    }

    /// Records the reduction of the fattened map (`maps_drawn`: the light's maps were drawn
    /// since the last one), the classification and the arguments (which set the lists' running
    /// counts back to 0 for the next classification: no clear of the lists).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, maps_drawn: bool) {
        let (Some((classify, reduce)), Some(targets)) = (&self.groups, &self.targets) else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("TileListPass"),
            timestamp_writes: None,
        });
        if maps_drawn {
            let (w, h) = (self.reduced.texture.width(), self.reduced.texture.height());
            pass.set_pipeline(&self.reduce);
            pass.set_bind_group(0, reduce, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            if let (Some((pipeline, _)), Some(group)) = (&self.depth_range_pass, &self.depth_range_group) {
                let (w, h) = (
                    self.depth_range.texture.width(),
                    self.depth_range.texture.height(),
                );
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
            }
        }
        let tiles = (targets.classes.texture.width(), targets.classes.texture.height());
        pass.set_pipeline(&self.classify);
        pass.set_bind_group(0, classify, &[]);
        if self.wide {
            pass.dispatch_workgroups(tiles.0, tiles.1, 1);
        } else {
            pass.dispatch_workgroups(tiles.0.div_ceil(8), tiles.1.div_ceil(8), 1);
        }
        if let (Some((finish, umbra)), Some(group)) = (&self.umbra_pass, &self.umbra_group) {
            pass.set_pipeline(finish);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(umbra);
            pass.set_bind_group(0, group, &[]);
            pass.dispatch_workgroups_indirect(&targets.args, CANDIDATE_ARGS);
            pass.set_bind_group(0, classify, &[]);
        }
        pass.set_pipeline(&self.finish);
        pass.dispatch_workgroups(1, 1, 1);
    }
}

/// The compute path's reduced fattened map: 32-bit, which a compute pass can write everywhere
/// (a half float cannot be a storage texture on the web).
const REDUCED_STORAGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// The bytes of a list of tiles for `tiles` (across, down): a count, the running count the
/// classification appends with, one word a tile.
fn list_bytes(tiles: (u32, u32)) -> u64 {
    4 * (2 + u64::from(tiles.0 * tiles.1))
}

/// The umbra test's list of kept tiles for `tiles`.
fn candidate_list(device: &CachedDevice<'_>, tiles: (u32, u32)) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("TileListPass::candidates"),
        size: list_bytes(tiles),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

/// Where the lists' arguments (`AllArgs` in `shaders/tile_classify.wgsl`) hold the tiles turned
/// away's, and the umbra test's dispatch.
const AWAY_ARGS: u64 = 32;
const CANDIDATE_ARGS: u64 = 64;

/// The umbra test's reduced shadow map: its least and greatest depth per block.
const DEPTH_RANGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;

/// Shadow-map texels per side of a block of the umbra test's reduced map (`UMBRA_BLOCK` in
/// `shaders/common/umbra.wgsl`).
const UMBRA_BLOCK: u32 = 32;

/// Bind group entries at the given bindings.
fn entries<'a, const N: usize>(
    resources: [(u32, wgpu::BindingResource<'a>); N],
) -> [wgpu::BindGroupEntry<'a>; N] {
    resources.map(|(binding, resource)| wgpu::BindGroupEntry { binding, resource })
}
