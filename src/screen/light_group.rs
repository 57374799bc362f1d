//! [`LightGroup`]: the screen-space passes of several lights alike run as one
//! ([`crate::ExecutionSettings::light_groups`]).

use super::tile_classify::{REDUCE, TILE};
use super::{
    BlurCompute, DistanceMaps, ScreenStage, TileList, TileListPass, TileListTargets, VariablePcfCompute,
};
use super::{ChainKey, Mark, StorageClear};
use crate::chain::FRAME_SIZE;
use crate::frame::{FrameSlots, PassParams};
use crate::gpu_helpers::{entry, texture_bytes};
use crate::pipeline_cache::CachedDevice;

/// Bytes of the header in [`LightGroup`]'s buffer of lists (`GROUP_HEADER` words in
/// `shaders/common/tile_groups.wgsl`), and of each round's block before it: 256, so that every
/// round's binding and every list starts where a storage binding may.
const HEADER_BYTES: u64 = 256;

/// Words of the header (`shaders/common/tile_groups.wgsl`): the pool's tiles, the screen's
/// tiles across and in all, the rounds recorded, the inspected member, where each round starts.
const POOL_TILES_WORD: usize = 35;
const ACROSS_WORD: usize = 36;
const PER_LAYER_WORD: usize = 37;
const ROUNDS_WORD: usize = 38;
const INSPECTED_WORD: usize = 39;

/// The header's entry for no inspected member.
const NO_MEMBER: u32 = u32::MAX;

/// The lights a group can hold: the header's room for their slots (words 2 to 17) and where
/// their tiles start (words 18 to 34).
pub(crate) const MAX_MEMBERS: usize = 16;

/// The members' tile classification as one dispatch, after one of the reduction of their
/// fattened maps where one was drawn: `shaders/tile_classify.wgsl` made over the group
/// ([`crate::shaders::with_light_group_classification`]), each workgroup's z its member.
struct GroupClassification {
    reduce: std::sync::Arc<wgpu::ComputePipeline>,
    classify: std::sync::Arc<wgpu::ComputePipeline>,
    reduce_layout: wgpu::BindGroupLayout,
    classify_layout: wgpu::BindGroupLayout,
    /// A layer a member: its reduced fattened map (sized at [`LightGroup::bind`]) and its tile
    /// classes.
    reduced: (wgpu::Texture, wgpu::TextureView),
    classes: (wgpu::Texture, wgpu::TextureView),
    gather: wgpu::Sampler,
    /// The classification's and the reduction's, once bound.
    groups: Option<(wgpu::BindGroup, wgpu::BindGroup)>,
    /// No reduction since the group was bound.
    reduce_pending: std::sync::atomic::AtomicBool,
}

impl GroupClassification {
    /// For the `n` members of a group of `key` over a screen of `size`, whose buffer of lists
    /// the passes bind (binding 18).
    fn new(device: &CachedDevice<'_>, key: &ChainKey, n: u32, size: (u32, u32)) -> Self {
        let half = key.half_floats();
        let halves = crate::shaders::with_half_floats(crate::shaders::TILE_CLASSIFY, half);
        let text = halves.as_deref().unwrap_or(crate::shaders::TILE_CLASSIFY);
        let source = crate::shaders::with_light_group_classification(text)
            .expect("tile_classify.wgsl is the classification");
        let shader = device.module("tile_classify.wgsl (group)", &source);
        let compute = wgpu::ShaderStages::COMPUTE;
        let sampled_array = |binding| {
            entry::and_compute(entry::texture(
                binding,
                entry::UNFILTERABLE,
                wgpu::TextureViewDimension::D2Array,
            ))
        };
        let frames = entry::storage_buffer(0, compute, true);
        let lists = entry::storage_buffer(18, compute, false);
        let map = entry::and_compute(entry::light_map(3, entry::UNFILTERABLE, true));
        let gather = entry::and_compute(entry::sampler(4, wgpu::SamplerBindingType::NonFiltering));
        let intermediates = half.intermediates;
        let classify_layout = device.bind_group_layout(
            "LightGroup::classify_layout",
            &[
                frames,
                entry::and_compute(entry::texture_2d(1, entry::UNFILTERABLE)),
                sampled_array(2),
                map,
                gather,
                entry::storage_texture_in(8, REDUCED_FORMAT, true),
                entry::and_compute(entry::texture_2d(11, entry::UNFILTERABLE)),
                entry::storage_texture_in(12, super::DistanceMapCompute::format(intermediates), true),
                entry::storage_texture_in(13, super::visibility_storage(intermediates), true),
                entry::storage_texture_in(14, super::visibility_storage(intermediates), true),
                entry::and_compute(entry::texture_2d(17, entry::UNFILTERABLE)),
                lists,
            ],
        );
        let reduce_layout = device.bind_group_layout(
            "LightGroup::reduce_layout",
            &[
                frames,
                map,
                gather,
                entry::storage_texture_in(6, REDUCED_FORMAT, true),
                lists,
            ],
        );
        let on = |b: bool| if b { 1.0 } else { 0.0 };
        // As each member's own classification is made (`TileListPass::new`): by workgroups,
        // clearing the intermediates, the visibility its layer.
        let constants = [
            (super::LIGHT_KIND, f64::from(key.kind)),
            ("CLASSIFY", 1.0),
            ("FACING", on(key.distance.facing_away)),
            ("UMBRA", 0.0),
            ("WIDE", 1.0),
            ("CLEARS", 1.0),
            // The distance map and the blur's horizontal result are pooled by listed tile: the
            // PCF and the blur write every pixel of their tiles, and the map says where the
            // others are not listed.
            ("CLEAR_BLURRED", 0.0),
            ("CLEAR_DISTANCE", 0.0),
            ("CLEAR_LAYER", 1.0),
            super::row_threads(device),
        ];
        let pipeline = |label, layout: &wgpu::BindGroupLayout, entry| {
            device.compute_pipeline(label, &shader, &[Some(layout)], entry, &constants)
        };
        let tiles = (size.0.div_ceil(TILE), size.1.div_ceil(TILE));
        Self {
            reduce: pipeline("LightGroup::reduce", &reduce_layout, "cs_reduce"),
            classify: pipeline("LightGroup::classify", &classify_layout, "cs_classify_wide"),
            reduce_layout,
            classify_layout,
            reduced: layers(device, "LightGroup::reduced", ((1, 1), n), REDUCED_FORMAT),
            classes: layers(device, "LightGroup::classes", (tiles, n), REDUCED_FORMAT),
            gather: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("LightGroup::gather"),
                ..Default::default()
            }),
            groups: None,
            reduce_pending: std::sync::atomic::AtomicBool::new(true),
        }
    }
}

/// The classification's reduced fattened map and tile classes (`REDUCED_STORAGE_FORMAT` in
/// `src/screen/tile_classify.rs`).
const REDUCED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Several lights whose distance-map chains are alike (one [`ChainKey`], maps in the same
/// arrays) as one chain: one dispatch classifies every member's tiles (after one that reduces
/// their fattened maps where one was drawn, [`GroupClassification`]), each member's list and
/// its map of where the list holds each screen tile into a region of one buffer; then one
/// dispatch sums the lists' lengths into where each member's tiles start, the rounds and the
/// passes' size (`shaders/group_args.wgsl`), and the variable PCF and each blur axis run once a
/// round over every member's tiles of the round, one workgroup a tile
/// (`shaders/common/tile_groups.wgsl`). The members' own chains record nothing. Each pass reads
/// a member's frame from the frame uniforms bound whole, and keeps its intermediates (the
/// distance map, the deviations, the blur's horizontal result) in its tile's slot of the
/// group's pool, which holds a whole number of screens' tiles; where the members' listed
/// tiles outnumber the pool's, whole members wait for a later round. The PCF and the blur's
/// vertical axis write the light's layer of the visibility.
pub(crate) struct LightGroup {
    key: ChainKey,
    /// The members' light slots, in member order.
    slots: Vec<usize>,
    size: (u32, u32),
    /// The screens' worth of tiles the pool holds (the setting, 0 for every member's).
    pool_setting: u32,
    /// The rounds recorded: enough for any lists ([`rounds`]).
    rounds: u32,
    lists: wgpu::Buffer,
    /// `lists` as the passes' list group, one a round (bound from the round's block).
    lists_groups: Vec<wgpu::BindGroup>,
    /// The passes' indirect arguments, 16 bytes a round.
    args: wgpu::Buffer,
    args_pipeline: std::sync::Arc<wgpu::ComputePipeline>,
    args_group: wgpu::BindGroup,
    /// The pool: a layer a screen's worth of tiles, each tile's slot 16 x 16 texels.
    distance: (wgpu::Texture, wgpu::TextureView),
    sigma: (wgpu::Texture, wgpu::TextureView),
    blurred: (wgpu::Texture, wgpu::TextureView),
    classification: GroupClassification,
    pcf: VariablePcfCompute,
    blur: BlurCompute,
    unpack: Unpack,
    /// The passes were bound to the members' maps and the visibility since they were made.
    pub bound: bool,
}

/// The inspected member's distance map copied out of the pool after each round
/// (`shaders/group_unpack.wgsl`), for [`crate::Shadows::light_texture`]: made while a member is
/// inspected.
struct Unpack {
    pipeline: std::sync::Arc<wgpu::ComputePipeline>,
    layout: wgpu::BindGroupLayout,
    /// The distance map's format (the pool's).
    format: wgpu::TextureFormat,
    /// The inspected member, its distance map, the clear before the first round and the
    /// pass's bind group.
    member: Option<u32>,
    target: Option<(wgpu::Texture, wgpu::TextureView, StorageClear, wgpu::BindGroup)>,
    /// The frames the group was bound to (the pass reads the screen's size from them).
    frames: Option<crate::frame::FrameSlot>,
}

/// The rounds a group of `n` members records where its pool holds `pool` screens' worth of tiles
/// (0: every member's): a member lists at most a screen's tiles, so each round but the last
/// holds at least `pool` members (`shaders/group_args.wgsl`).
fn rounds(n: u32, pool: u32) -> u32 {
    n.div_ceil(pool_layers(n, pool))
}

/// The pool's layers (screens' worth of tiles) for `n` members and the setting `pool`.
fn pool_layers(n: u32, pool: u32) -> u32 {
    if pool == 0 { n } else { pool.min(n) }.max(1)
}

impl LightGroup {
    /// Whether lights with chains of `key` can run as a group: `ours` in compute, the PCF
    /// writing the layer, the distance taken in the PCF, a blur, the maps as arrays, the
    /// intermediates in half floats and the tiles' pixels tested by workgroups (which clear
    /// what the passes read where nothing is listed) on `device`, without the umbra's tiles
    /// listed apart (the group's classification leaves that test out).
    pub fn groups(key: &ChainKey, device: &wgpu::Device) -> bool {
        key.chain.compute()
            && key.chain.pcf_in_layer()
            && key.chain.distance_map()
            && key.layer_writes
            && key.half_intermediates
            && key.distance_in_pcf
            && key.map_arrays
            && key.blur.is_some_and(|b| !b.fixed_step)
            && key.distance.tiles
            && key.distance.tile_pixels.by_workgroup(device)
            && !key.distance.umbra
    }

    /// A group of the lights at `slots` (at most [`MAX_MEMBERS`]), whose chains are made for
    /// `key`, over a screen of `size`, its pool holding `pool` screens' worth of tiles (0:
    /// every member's).
    pub fn new(
        device: &CachedDevice<'_>,
        key: ChainKey,
        slots: Vec<usize>,
        size: (u32, u32),
        pool: u32,
    ) -> Self {
        let n = slots.len() as u32;
        let rounds = rounds(n, pool);
        let layers_in_pool = pool_layers(n, pool);
        let tiles = (size.0.div_ceil(TILE), size.1.div_ceil(TILE));
        let per_layer = tiles.0 * tiles.1;
        let alignment = u64::from(device.limits().min_storage_buffer_offset_alignment).max(4);
        // A member's list, then its map (a word a screen tile).
        let region =
            (TileListTargets::list_bytes(size) + 4 * u64::from(per_layer)).next_multiple_of(alignment);
        let header_at = HEADER_BYTES * u64::from(rounds);
        let lists = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightGroup::lists"),
            size: header_at + HEADER_BYTES + region * u64::from(n),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: true,
        });
        {
            let words = (HEADER_BYTES / 4) as usize;
            let mut head = vec![0u32; words * (rounds as usize + 1)];
            // Each round's block: where the header lies from it, and the round.
            for r in 0..rounds as usize {
                head[r * words] = ((rounds as usize - r) * words) as u32;
                head[r * words + 1] = r as u32;
            }
            let header = &mut head[rounds as usize * words..];
            header[0] = (region / 4) as u32;
            header[1] = n;
            for (word, slot) in header[2..2 + MAX_MEMBERS].iter_mut().zip(&slots) {
                *word = *slot as u32;
            }
            header[POOL_TILES_WORD] = layers_in_pool * per_layer;
            header[ACROSS_WORD] = tiles.0;
            header[PER_LAYER_WORD] = per_layer;
            header[ROUNDS_WORD] = rounds;
            header[INSPECTED_WORD] = NO_MEMBER;
            if let Ok(mut mapped) = lists.slice(..header_at + HEADER_BYTES).get_mapped_range_mut() {
                mapped.copy_from_slice(bytemuck::cast_slice(&head));
            }
        }
        lists.unmap();
        let list_layout = TileListPass::list_layout(device);
        let lists_groups = (0..rounds)
            .map(|r| {
                let range = from(&lists, HEADER_BYTES * u64::from(r));
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("LightGroup::lists"),
                    layout: &list_layout,
                    entries: &[wgpu::BindGroupEntry {
                        binding: 0,
                        resource: range,
                    }],
                })
            })
            .collect();
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightGroup::args"),
            size: 16 * u64::from(rounds),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let args_layout = device.bind_group_layout(
            "LightGroup::args_layout",
            &[
                // The header's starts are written.
                entry::storage_buffer(0, compute, false),
                entry::storage_buffer(1, compute, false),
            ],
        );
        let args_shader = device.module("group_args.wgsl", crate::shaders::GROUP_ARGS);
        let args_pipeline = device.compute_pipeline(
            "LightGroup::args",
            &args_shader,
            &[Some(&args_layout)],
            "cs_group_args",
            &[],
        );
        let args_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("LightGroup::args"),
            layout: &args_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: from(&lists, header_at),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: args.as_entire_binding(),
                },
            ],
        });
        let half = key.half_floats();
        let pool_size = (tiles.0 * TILE, tiles.1 * TILE);
        let array = |label, format| self::layers(device, label, (pool_size, layers_in_pool), format);
        let distance = array(
            "LightGroup::distance",
            super::DistanceMapCompute::format(half.intermediates),
        );
        let sigma = array("LightGroup::sigma", super::sigma_storage(half.intermediates));
        let blurred = array(
            "LightGroup::blurred",
            super::visibility_storage(half.intermediates),
        );
        // Unused where the frames are a storage buffer (as over a group).
        let frames = FRAME_SIZE;
        let pcf = VariablePcfCompute::new(
            device,
            frames,
            (key.pcf, Some(key.distance)),
            key.kind,
            (half.intermediates, true, true),
        );
        let blur_switches = key.blur.unwrap_or_default();
        let blur = BlurCompute::new(device, frames, blur_switches, half, (true, true));
        Self {
            key,
            slots,
            size,
            pool_setting: pool,
            rounds,
            lists,
            lists_groups,
            args,
            args_pipeline,
            args_group,
            distance,
            sigma,
            blurred,
            classification: GroupClassification::new(device, &key, n, size),
            pcf,
            blur,
            unpack: Unpack::new(device, half),
            bound: false,
        }
    }

    /// This group is the lights at `slots` with chains of `key`, over a screen of `size`.
    pub fn fits(&self, key: &ChainKey, slots: &[usize], size: (u32, u32), pool: u32) -> bool {
        self.key == *key && self.slots == slots && self.size == size && self.pool_setting == pool
    }

    /// The members' light slots, in member order.
    pub fn slots(&self) -> &[usize] {
        &self.slots
    }

    /// The distance map of the light at `slot` where it is the inspected member (copied out of
    /// the pool, one layer) and the members' tile classes (a layer a member) with its layer;
    /// none where it is not a member.
    pub fn member_intermediates(&self, slot: usize) -> Option<(Option<&wgpu::Texture>, &wgpu::Texture, u32)> {
        let g = u32::try_from(self.slots.iter().position(|&s| s == slot)?).ok()?;
        let distance = self
            .unpack
            .target
            .as_ref()
            .filter(|_| self.unpack.member == Some(g))
            .map(|t| &t.0);
        Some((distance, &self.classification.classes.0, g))
    }

    /// Makes the light at `slot` (if a member) the inspected one, whose distance map is copied
    /// out of the pool each frame; a member no longer inspected gives its copy up.
    pub fn inspect(&mut self, device: &CachedDevice<'_>, queue: &wgpu::Queue, slot: Option<usize>) {
        let member = slot
            .and_then(|slot| self.slots.iter().position(|&s| s == slot))
            .and_then(|g| u32::try_from(g).ok());
        if member == self.unpack.member && (member.is_none() || self.unpack.target.is_some()) {
            return;
        }
        self.unpack.member = member;
        let word = HEADER_BYTES * u64::from(self.rounds) + 4 * INSPECTED_WORD as u64;
        queue.write_buffer(
            &self.lists,
            word,
            bytemuck::bytes_of(&member.unwrap_or(NO_MEMBER)),
        );
        self.unpack.target = None;
        if member.is_some() {
            self.unpack.make_target(device, self.size, &self.distance.1);
        }
    }

    /// Points the passes at their inputs: every light's frame, the camera's depth and the
    /// receiver mask, the members' maps (the arrays every member's maps are layers of), the
    /// visibility (its array, the lights' layers) and a stand-in.
    pub fn bind(
        &mut self,
        device: &CachedDevice<'_>,
        frames: &FrameSlots,
        (depth, mask, dummy): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
        maps: &DistanceMaps,
        visibility: &wgpu::TextureView,
    ) {
        let frames = frames.whole();
        self.bind_classification(device, &frames, (depth, mask, dummy), maps, visibility);
        self.unpack.frames = Some(frames.clone());
        if self.unpack.member.is_some() {
            self.unpack.make_target(device, self.size, &self.distance.1);
        }
        let distance = &self.distance.1;
        self.pcf.bind(
            device,
            (visibility, &self.sigma.1),
            &frames,
            (depth, mask),
            (distance, dummy),
            maps,
        );
        let read = (visibility, &self.sigma.1, distance);
        self.blur.bind(
            device,
            &self.blurred.1,
            &frames,
            (depth, mask),
            read,
            Some(visibility),
        );
        self.bound = true;
    }

    /// Points the classification and the reduction at their inputs (see [`Self::bind`]); the
    /// reduced maps are made at the fattened maps' size.
    fn bind_classification(
        &mut self,
        device: &CachedDevice<'_>,
        frames: &crate::frame::FrameSlot,
        (depth, mask, dummy): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
        maps: &DistanceMaps,
        visibility: &wgpu::TextureView,
    ) {
        let c = &mut self.classification;
        let n = self.slots.len() as u32;
        let size = (
            maps.fattened_size.0.div_ceil(REDUCE),
            maps.fattened_size.1.div_ceil(REDUCE),
        );
        if (c.reduced.0.width(), c.reduced.0.height()) != size {
            c.reduced = layers(device, "LightGroup::reduced", (size, n), REDUCED_FORMAT);
        }
        let view = wgpu::BindingResource::TextureView;
        // From the header (the rounds' blocks before it are the passes').
        let lists = from(&self.lists, HEADER_BYTES * u64::from(self.rounds));
        let frame = crate::gpu_helpers::Binding::resource(frames);
        let group = |label, layout, entries: &[(u32, wgpu::BindingResource)]| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries: &entries
                    .iter()
                    .map(|(binding, resource)| wgpu::BindGroupEntry {
                        binding: *binding,
                        resource: resource.clone(),
                    })
                    .collect::<Vec<_>>(),
            })
        };
        let classify = group(
            "LightGroup::classify",
            &c.classify_layout,
            &[
                (0, frame.clone()),
                (1, view(depth)),
                (2, view(&c.reduced.1)),
                (3, view(maps.fattened_map)),
                (4, wgpu::BindingResource::Sampler(&c.gather)),
                (8, view(&c.classes.1)),
                (11, view(mask)),
                // Pooled: not cleared over a group (`CLEAR_DISTANCE`, `CLEAR_BLURRED` off).
                (12, view(&self.distance.1)),
                (13, view(visibility)),
                (14, view(&self.blurred.1)),
                // The umbra test's reduced shadow map: groups leave the test out.
                (17, view(dummy)),
                (18, lists.clone()),
            ],
        );
        let reduce = group(
            "LightGroup::reduce",
            &c.reduce_layout,
            &[
                (0, frame),
                (3, view(maps.fattened_map)),
                (4, wgpu::BindingResource::Sampler(&c.gather)),
                (6, view(&c.reduced.1)),
                (18, lists),
            ],
        );
        c.groups = Some((classify, reduce));
        c.reduce_pending.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Uploads the passes' parameters.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        self.pcf.prepare(queue, params);
        self.blur.prepare(queue, params);
    }

    /// Records the members' classification (with the reduction of their fattened maps before
    /// it where `maps_drawn`, one of them was drawn, or none was reduced since the group was
    /// bound) marked "distance map", then the arguments and the first round's PCF marked
    /// "pcf", its blur's axes "blur", and each later round's PCF and blur (each a round of
    /// members whose tiles the pool could not hold beside the earlier rounds'; no workgroups
    /// where every member's fit) marked "blur" too. The inspected member's distance map is
    /// copied out of the pool after each round's PCF.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        visibility: &wgpu::TextureView,
        maps_drawn: bool,
        mark: Mark,
    ) {
        let c = &self.classification;
        let Some((classify, reduce)) = &c.groups else {
            return;
        };
        let n = self.slots.len() as u32;
        let pending = c.reduce_pending.swap(false, std::sync::atomic::Ordering::Relaxed);
        crate::chain::run(encoder, &mut *mark, "distance map", |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("LightGroup::classify"),
                timestamp_writes: None,
            });
            if maps_drawn || pending {
                let (w, h) = (c.reduced.0.width(), c.reduced.0.height());
                pass.set_pipeline(&c.reduce);
                pass.set_bind_group(0, reduce, &[]);
                pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), n);
            }
            let (w, h) = (c.classes.0.width(), c.classes.0.height());
            pass.set_pipeline(&c.classify);
            pass.set_bind_group(0, classify, &[]);
            pass.dispatch_workgroups(w, h, n);
        });
        let round = |r: usize| TileList {
            group: &self.lists_groups[r],
            args: &self.args,
            offset: 16 * r as u64,
        };
        crate::chain::run(encoder, &mut *mark, "pcf", |e| {
            let mut pass = e.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("LightGroup::args"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&self.args_pipeline);
            pass.set_bind_group(0, &self.args_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            drop(pass);
            self.unpack.clear(e);
            self.pcf.encode(e, round(0), None);
            self.unpack.encode(e, round(0));
        });
        crate::chain::run(encoder, &mut *mark, "blur", |e| {
            self.blur.encode(e, round(0), (None, true), visibility);
            for r in 1..self.lists_groups.len() {
                self.pcf.encode(e, round(r), None);
                self.unpack.encode(e, round(r));
                self.blur.encode(e, round(r), (None, true), visibility);
            }
        });
    }

    /// GPU memory the group allocated (the members' lists, maps and classes, the pool, the
    /// inspected member's distance map, the passes' parameters), in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.lists.size()
            + self.args.size()
            + [
                &self.distance.0,
                &self.sigma.0,
                &self.blurred.0,
                &self.classification.reduced.0,
                &self.classification.classes.0,
            ]
            .into_iter()
            .map(texture_bytes)
            .sum::<u64>()
            + self.unpack.target.as_ref().map_or(0, |t| texture_bytes(&t.0))
            + self.pcf.allocated_bytes()
            + self.blur.allocated_bytes()
    }
}

impl Unpack {
    fn new(device: &CachedDevice<'_>, half: crate::shaders::HalfFloats) -> Self {
        let shader = crate::shaders::module_grouped(
            device,
            "group_unpack.wgsl",
            crate::shaders::GROUP_UNPACK,
            half,
            &crate::shaders::UNPACK_GROUP_LAYERS,
        );
        let compute = wgpu::ShaderStages::COMPUTE;
        let format = super::DistanceMapCompute::format(half.intermediates);
        let layout = device.bind_group_layout(
            "LightGroup::unpack_layout",
            &[
                entry::storage_buffer(0, compute, true),
                entry::and_compute(entry::texture(
                    1,
                    entry::UNFILTERABLE,
                    wgpu::TextureViewDimension::D2Array,
                )),
                entry::storage_texture_in(2, format, true),
            ],
        );
        let list_layout = TileListPass::list_layout(device);
        let pipeline = device.compute_pipeline(
            "LightGroup::unpack",
            &shader,
            &[Some(&layout), None, None, Some(&list_layout)],
            "cs_unpack",
            &[],
        );
        Self {
            pipeline,
            layout,
            format,
            member: None,
            target: None,
            frames: None,
        }
    }

    /// Makes the inspected member's distance map over a screen of `size` (the pool's format),
    /// its clear and the pass's bind group, where the group was bound to its frames.
    fn make_target(&mut self, device: &CachedDevice<'_>, size: (u32, u32), pool: &wgpu::TextureView) {
        let Some(frames) = &self.frames else {
            return;
        };
        let format = self.format;
        let (texture, array) = layers(device, "LightGroup::inspected_distance", (size, 1), format);
        let plain = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("LightGroup::inspected_distance"),
            dimension: Some(wgpu::TextureViewDimension::D2),
            ..Default::default()
        });
        let clear = StorageClear::new(
            device,
            "LightGroup::inspected_distance clear",
            (&plain, format, size),
            [-1.0, 0.0, 0.0, 0.0],
        );
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("LightGroup::unpack"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: crate::gpu_helpers::Binding::resource(frames),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(pool),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&array),
                },
            ],
        });
        self.target = Some((texture, array, clear, group));
    }

    /// Records the distance map's clear to `NO_SHADOW_HERE` (before the first round), where a
    /// member is inspected.
    fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        if let Some((_, _, clear, _)) = &self.target {
            clear.encode(encoder);
        }
    }

    /// Records the copy of the inspected member's listed tiles of the round `tiles` out of the
    /// pool (after the round's PCF, before the next round's).
    fn encode(&self, encoder: &mut wgpu::CommandEncoder, tiles: TileList) {
        if let Some((_, _, _, group)) = &self.target {
            tiles.dispatch(encoder, "LightGroup::unpack", &self.pipeline, &[Some(group)]);
        }
    }
}

/// `buffer` bound from `offset` to its end.
fn from(buffer: &wgpu::Buffer, offset: u64) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer,
        offset,
        size: None,
    })
}

/// A storage texture of `n` layers of `size`, and its view as an array.
fn layers(
    device: &CachedDevice<'_>,
    label: &str,
    ((width, height), n): ((u32, u32), u32),
    format: wgpu::TextureFormat,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: n,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        // Copied out by the debug views (`Shadows::light_texture`).
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        label: Some(label),
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    (texture, view)
}
