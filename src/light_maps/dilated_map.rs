//! The fattened map derived from the shadow map, in compute ([`crate::Fattening::Dilation`]):
//! no second geometry pass.
//!
//! Input: the light's shadow map (its atlas of cascades or cube faces), the [`LightView`] and
//! the fatten distance (with a spot or point light's nearest caster). Output, at a quarter of the
//! shadow map's resolution (the geometric fattened map has half) and read where it is: an RG32F
//! map. x: the least depth of the shadow map's silhouettes within the fatten distance of the
//! texel across the light (its own tile's; for a spot or point light, the fatten distance at
//! each silhouette's own distance from the light, up to twice that), and of the caster under
//! it: where a shadow can fall. y: the depth of the silhouette nearest the texel (in texels of
//! the map), from which the distance map takes the distance beside a shadow. No occluder offset
//! (a texel of 0, see the shader).
//!
//! One compute pass (`shaders/dilated_map.wgsl`):
//! - level 0: the shadow map at a quarter of its resolution, where a silhouette (a step of more
//!   than four texels along the light between two neighbouring texels) lies among the texels
//!   it covers or beside them; the far plane elsewhere. A surface seen from the light spreads
//!   only at its outline, as the drawn map pushes a caster out along its normals;
//! - the blocks of 8 x 8 texels within reach of one of those silhouettes (the widest tile's
//!   window, or half again its radius where that is wider), listed: the steps below are
//!   dispatched over that list, and what they would find elsewhere (the far plane, no
//!   silhouette near) is stored there by one dispatch over the other blocks. Where more than
//!   three blocks in four are near, every texel is dispatched instead (the list's indirection
//!   then costs more than it saves). On lavapipe at 1280x1024 the pass took 133-160 ms on the
//!   teapot against 228-239 without the list, 218-240 on the character against 260-286, and
//!   219-224 in the room (every block near) against 219-258; the frames were byte-identical;
//! - levels of least depths over squares of 2, 4, 8, ... texels (as many as the widest tile's
//!   window needs, in two textures used in turn); for a spot or point light each also tries the
//!   window the level before covers for silhouettes that spread to the texel (a buffer of one
//!   float a texel: the least depth under the texel, and of those silhouettes);
//! - with each level, in the same dispatch, a round of a jump flood from level 0's silhouettes
//!   (jumps of 2^(levels-1) texels down to one, two RG32Uint textures used in turn): the nearest
//!   silhouette's texel and depth;
//! - the dilation: four reads of the last level that cover each texel's window exactly, and the
//!   nearest silhouette where it lies within the radius.

use crate::pipeline_cache::CachedDevice;
use bytemuck::{Pod, Zeroable};

use super::atlas::MapLayout;
use super::pool::{MapPools, MapSlot, Moved, PoolKey};
use crate::frame::DerivedSpreads;
use crate::gpu_helpers::{Target, entry, texture_bytes};
use crate::light_space::{AtlasGrid, LightView, MAX_TILES, ProjectionKind};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct DilationUniform {
    shape: [u32; 4],
    depth: [f32; 4],
    tiles: [[f32; 4]; MAX_TILES],
}

/// The most levels a fattened map's side can use (a tile of 2^13 texels).
const MAX_LEVELS: u32 = 14;

/// The bytes between two levels' `Step` uniforms (a dynamic offset's alignment).
const STEP_STRIDE: u64 = 256;

/// The derived fattened map of one light.
pub(crate) struct DilatedMapPass {
    /// The fattened map: RG32F, the least depth within the fatten distance of each texel (and
    /// of the caster under it), and the depth of the silhouette nearest it within that distance.
    /// A layer of an array the lights' derived maps of this size share.
    map: MapSlot,
    /// Per texel of the map, row by row: the least depth of the shadow-map texels it covers
    /// (and, for a spot or point light, of the silhouettes the levels found spreading to it;
    /// one f32).
    covered: wgpu::Buffer,
    /// Per block of 8 x 8 texels of the map: a silhouette lies in it, one lies within reach
    /// along its row; the lists of the blocks within reach of one and of the others, and their
    /// lengths (the shader's `blocks`).
    blocks: wgpu::Buffer,
    /// The two lists' running lengths (two u32).
    counts: wgpu::Buffer,
    /// The indirect dispatches over the two lists (two of four u32: x, y, z, unused).
    list_args: wgpu::Buffer,
    args_group: wgpu::BindGroup,
    /// The jump flood's two textures, used in turn (RG32Uint: the nearest silhouette's texel,
    /// and its depth's bits).
    seeds: [Target; 2],
    /// No occluder offset: one texel of 0 (the distance map reads it at any texel, 0 there).
    occluder_offset: Target,
    /// The levels, used in turn: level 0 in the second, level k in the first for odd k.
    scratch: [Target; 2],
    reduce: std::sync::Arc<wgpu::ComputePipeline>,
    /// The blocks near a silhouette, along rows then along columns (and listed), the lists'
    /// dispatches, and what the blocks far from every silhouette hold.
    near_rows: std::sync::Arc<wgpu::ComputePipeline>,
    near_columns: std::sync::Arc<wgpu::ComputePipeline>,
    args: std::sync::Arc<wgpu::ComputePipeline>,
    fill: std::sync::Arc<wgpu::ComputePipeline>,
    /// A level and a round of the flood, and the dilation: over the list of blocks near a
    /// silhouette, and over every texel (the shader's choice, one of each pair dispatched
    /// empty).
    level: [std::sync::Arc<wgpu::ComputePipeline>; 2],
    dilate: [std::sync::Arc<wgpu::ComputePipeline>; 2],
    io_layout: wgpu::BindGroupLayout,
    shared_layout: wgpu::BindGroupLayout,
    seeds_layout: wgpu::BindGroupLayout,
    /// The dilation's uniform.
    uniform: wgpu::Buffer,
    /// Each level's `Step` at `STEP_STRIDE` apart.
    steps: wgpu::Buffer,
    /// Made at [`Self::prepare`] for the shadow map it is given, dropped when the textures are
    /// made again.
    groups: Option<Groups>,
    /// The last level any tile needs this frame.
    levels: u32,
    /// The atlas's layout, and a tile's side in the map's texels.
    grid: AtlasGrid,
    tile: u32,
}

/// The bind groups of one shadow map: level 0 from it, each level from the one before (second
/// to first, first to second), the dilation from each texture, and what the steps and the
/// dilation share.
struct Groups {
    reduce: wgpu::BindGroup,
    /// Level 1 from level 0, then from the first into the second and back.
    steps: [wgpu::BindGroup; 3],
    /// The dilation from the second (level 0 or an even level) or the first (an odd level).
    dilate: [wgpu::BindGroup; 2],
    shared: wgpu::BindGroup,
    /// The flood's textures: the first written (the second read), the second written.
    seeds: [wgpu::BindGroup; 2],
}

impl DilatedMapPass {
    /// The levels' format: 32-bit float, which every compute device can store.
    const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
    /// The fattened map's: the least depth and the nearest silhouette's.
    const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
    /// The flood's: the nearest silhouette's texel and its depth's bits, as integers so that no
    /// device flushes or canonicalizes them as floats.
    const SEEDS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Uint;

    pub fn new((device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) -> Self {
        let (_, grid, tile) = map;
        let shader = device.module("dilated_map.wgsl", crate::shaders::DILATED_MAP);
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let compute = wgpu::ShaderStages::COMPUTE;
        let io_layout = device.bind_group_layout(
            "DilatedMapPass::io",
            &[
                entry::and_compute(entry::texture_2d(0, unfilterable)),
                entry::storage_texture(1, Self::FORMAT),
                entry::uniform(2, compute, 16, true),
            ],
        );
        let shared_layout = device.bind_group_layout(
            "DilatedMapPass::shared",
            &[
                entry::uniform(0, compute, size_of::<DilationUniform>(), false),
                entry::storage_buffer(1, compute, false),
                entry::storage_texture(2, Self::MAP_FORMAT),
                entry::storage_buffer(3, compute, false),
                entry::storage_buffer(4, compute, false),
            ],
        );
        let args_layout = device.bind_group_layout(
            "DilatedMapPass::args",
            &[entry::storage_buffer(0, compute, false)],
        );
        let seeds_layout = device.bind_group_layout(
            "DilatedMapPass::seeds",
            &[
                entry::and_compute(entry::texture_2d(0, wgpu::TextureSampleType::Uint)),
                entry::storage_texture(1, Self::SEEDS_FORMAT),
            ],
        );
        let pipeline = |entry: &str| {
            let label = format!("DilatedMapPass::{entry}");
            device.compute_pipeline(
                &label,
                &shader,
                &[Some(&io_layout), Some(&shared_layout), Some(&seeds_layout)],
                entry,
                &[],
            )
        };
        let uniform = crate::gpu_helpers::uniform_buffer(
            device,
            "DilatedMapPass::uniform",
            size_of::<DilationUniform>() as u64,
        );
        // Each level's number, `STEP_STRIDE` bytes apart.
        let mut bytes = vec![0u8; (STEP_STRIDE * MAX_LEVELS as u64) as usize];
        for level in 0..MAX_LEVELS {
            let at = (level as u64 * STEP_STRIDE) as usize;
            bytes[at..at + 4].copy_from_slice(&level.to_le_bytes());
        }
        let steps = wgpu::util::DeviceExt::create_buffer_init(
            &**device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("DilatedMapPass::steps"),
                contents: &bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            },
        );
        let (map, occluder_offset, scratch, seeds) = Self::textures((device, pools), grid, tile);
        let (covered, blocks) = Self::buffers(device, grid, tile);
        let small = |label, bytes, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let counts = small("DilatedMapPass::counts", 8, wgpu::BufferUsages::empty());
        let list_args = small("DilatedMapPass::list_args", 48, wgpu::BufferUsages::INDIRECT);
        let args_group =
            crate::gpu_helpers::bind_group(device, "DilatedMapPass::args", &args_layout, &[&list_args]);
        let list_args_pipeline = device.compute_pipeline(
            "DilatedMapPass::cs_list_args",
            &shader,
            &[None, Some(&shared_layout), None, Some(&args_layout)],
            "cs_list_args",
            &[],
        );
        Self {
            map,
            covered,
            blocks,
            counts,
            list_args,
            args_group,
            seeds,
            occluder_offset,
            scratch,
            reduce: pipeline("cs_reduce"),
            near_rows: pipeline("cs_near_rows"),
            near_columns: pipeline("cs_near_columns"),
            args: list_args_pipeline,
            fill: pipeline("cs_fill"),
            level: [pipeline("cs_level"), pipeline("cs_level_all")],
            dilate: [pipeline("cs_dilate"), pipeline("cs_dilate_all")],
            io_layout,
            shared_layout,
            seeds_layout,
            uniform,
            steps,
            groups: None,
            levels: 0,
            grid,
            tile: dilated_resolution(tile),
        }
    }

    /// The least depths' buffer and the blocks' for `grid`'s tiles of a shadow map `tile`
    /// texels a side.
    fn buffers(device: &CachedDevice<'_>, grid: AtlasGrid, tile: u32) -> (wgpu::Buffer, wgpu::Buffer) {
        let (width, height) = grid.size(dilated_resolution(tile));
        let buffer = |label, bytes: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(4),
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let blocks = width.div_ceil(8) as u64 * height.div_ceil(8) as u64;
        (
            buffer("DilatedMapPass::covered", width as u64 * height as u64 * 4),
            buffer("DilatedMapPass::blocks", (blocks * 4 + 2) * 4),
        )
    }

    /// The map, the offset, the two levels' textures and the flood's two for `grid`'s tiles of
    /// a shadow map `tile` texels a side.
    fn textures(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        grid: AtlasGrid,
        tile: u32,
    ) -> (MapSlot, Target, [Target; 2], [Target; 2]) {
        let size = grid.size(dilated_resolution(tile));
        let make = |label, format| {
            crate::gpu_helpers::texture_2d(device, label, size, format, wgpu::TextureUsages::STORAGE_BINDING)
        };
        // Textures start zeroed.
        let offset = crate::gpu_helpers::texture_2d(
            device,
            "DilatedMapPass::occluder_offset",
            (1, 1),
            wgpu::TextureFormat::R16Float,
            wgpu::TextureUsages::empty(),
        );
        let map = pools.slot(
            device,
            PoolKey {
                label: "DilatedMapPass::map",
                format: Self::MAP_FORMAT,
                size,
                usage: wgpu::TextureUsages::STORAGE_BINDING,
            },
        );
        (
            map,
            offset,
            [
                make("DilatedMapPass::level", Self::FORMAT),
                make("DilatedMapPass::level", Self::FORMAT),
            ],
            [
                make("DilatedMapPass::seeds", Self::SEEDS_FORMAT),
                make("DilatedMapPass::seeds", Self::SEEDS_FORMAT),
            ],
        )
    }

    /// GPU memory this pass allocated: its textures and uniforms.
    pub(crate) fn allocated_bytes(&self) -> u64 {
        self.map.allocated_bytes()
            + [
                &self.occluder_offset,
                &self.scratch[0],
                &self.scratch[1],
                &self.seeds[0],
                &self.seeds[1],
            ]
            .iter()
            .map(|t| texture_bytes(&t.texture))
            .sum::<u64>()
            + self.covered.size()
            + self.blocks.size()
            + self.counts.size()
            + self.list_args.size()
            + self.uniform.size()
            + self.steps.size()
    }

    /// Makes the textures again for a shadow map of `tile` texels a tile; they must then be
    /// made and bound again.
    pub(crate) fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) {
        let (_, grid, tile) = map;
        (self.map, self.occluder_offset, self.scratch, self.seeds) =
            Self::textures((device, pools), grid, tile);
        (self.covered, self.blocks) = Self::buffers(device, grid, tile);
        self.grid = grid;
        self.tile = dilated_resolution(tile);
        self.groups = None;
    }

    /// Makes the bind groups again at the next prepare (the shadow map's view changed).
    pub(crate) fn unbind(&mut self) {
        self.groups = None;
    }

    /// The derived fattened map (RG32F; its layer, as a 2D texture).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.map.target.view
    }

    /// The array the derived fattened map is a layer of ([`DilatedMapPass::layer`]).
    pub fn texture(&self) -> &wgpu::Texture {
        &self.map.target.texture
    }

    /// The derived map's layer of [`DilatedMapPass::texture`].
    pub fn layer(&self) -> u32 {
        self.map.layer
    }

    /// Points the map at its array as it is now ([`MapPools::refresh`]; where it moved, its bind
    /// groups must be made again: [`DilatedMapPass::unbind`]).
    pub(crate) fn refresh(&mut self, pools: &MapPools) -> Moved {
        pools.refresh(&mut self.map)
    }

    /// The occluder offset: none (one texel of 0).
    pub fn occluder_offset(&self) -> &wgpu::TextureView {
        &self.occluder_offset.view
    }

    /// The occluder offset's texture (one texel, one layer) and its layer, 0.
    pub fn occluder_offset_layer(&self) -> (&wgpu::Texture, u32) {
        (&self.occluder_offset.texture, 0)
    }

    /// Uploads each tile's radius for `light`'s fit and `spreads`, and makes the bind groups for
    /// `shadow_map` (the shadow map's atlas) where they are not made.
    pub(crate) fn prepare(
        &mut self,
        (device, queue): (&CachedDevice<'_>, &wgpu::Queue),
        light: &LightView,
        spreads: &DerivedSpreads,
        shadow_map: &wgpu::TextureView,
    ) {
        let mut tiles = [[0.0; 4]; MAX_TILES];
        self.levels = 0;
        // How far (texels) a texel's work can find a silhouette: its last level's square, and
        // half again its radius, which the flood's paths to the texels within the radius keep
        // to (a seed nearer than the radius across, up to sqrt 2 of it diagonally, must still
        // win where a farther one would have).
        let mut reach = 0;
        for (slot, cascade) in tiles.iter_mut().zip(light.cascades()) {
            let texel = texel_across(cascade, self.tile);
            let radius = dilation_radius(light, spreads, self.tile, texel);
            // The widest square of a level that fits in the window, 2 r + 1 texels a side.
            let window = (2 * radius.ceil() as u32 + 1).min(self.tile.max(1));
            let level = (31 - window.leading_zeros()).min(MAX_LEVELS - 1);
            self.levels = self.levels.max(level);
            reach = reach.max((1 << level).max((1.5 * radius).ceil() as u32) + 1);
            // A perspective map's silhouettes spread by the fatten distance at their own
            // distance: the radius at a unit distance.
            let unit_radius = match light.kind {
                ProjectionKind::Orthographic => 0.0,
                ProjectionKind::Perspective => spreads.fatten_distance / texel.max(1e-20),
            };
            // The shadow map's texel: a quarter of the fattened map's.
            *slot = [radius, level as f32, texel / 4.0, unit_radius];
        }
        let perspective = matches!(light.kind, ProjectionKind::Perspective);
        let uniform = DilationUniform {
            // In blocks of 8 x 8 texels, rounded up, and one more for the texel's place in its block.
            shape: [self.tile, self.grid.cols, self.levels, reach / 8 + 1],
            depth: [light.near, light.far, if perspective { 1.0 } else { 0.0 }, 0.0],
            tiles,
        };
        queue.write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        if self.groups.is_none() {
            self.groups = Some(self.bind_groups(device, shadow_map));
        }
    }

    fn bind_groups(&self, device: &CachedDevice<'_>, shadow_map: &wgpu::TextureView) -> Groups {
        let step = wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.steps,
            offset: 0,
            size: wgpu::BufferSize::new(16),
        });
        let io = |from: &wgpu::TextureView, to: &wgpu::TextureView| {
            crate::gpu_helpers::bind_group(device, "DilatedMapPass::io", &self.io_layout, &[from, to, &step])
        };
        let [first, second] = [&self.scratch[0].view, &self.scratch[1].view];
        Groups {
            reduce: io(shadow_map, second),
            steps: [io(second, first), io(first, second), io(second, first)],
            // The levels' destination is not written by the dilation.
            dilate: [io(second, first), io(first, second)],
            shared: crate::gpu_helpers::bind_group(
                device,
                "DilatedMapPass::shared",
                &self.shared_layout,
                &[
                    &self.uniform,
                    &self.covered,
                    &self.map.target.view,
                    &self.blocks,
                    &self.counts,
                ],
            ),
            seeds: [
                crate::gpu_helpers::bind_group(
                    device,
                    "DilatedMapPass::seeds",
                    &self.seeds_layout,
                    &[&self.seeds[1].view, &self.seeds[0].view],
                ),
                crate::gpu_helpers::bind_group(
                    device,
                    "DilatedMapPass::seeds",
                    &self.seeds_layout,
                    &[&self.seeds[0].view, &self.seeds[1].view],
                ),
            ],
        }
    }

    /// Records level 0, each level up to the last a tile needs, and the dilation
    /// ([`Self::prepare`] first).
    pub(crate) fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let Some(groups) = &self.groups else {
            return;
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("DilatedMapPass"),
            timestamp_writes: None,
        });
        let (x, y) = (
            self.map.target.texture.width().div_ceil(8),
            self.map.target.texture.height().div_ceil(8),
        );
        pass.set_bind_group(1, &groups.shared, &[]);
        pass.set_pipeline(&self.reduce);
        pass.set_bind_group(0, &groups.reduce, &[0]);
        // Level 0's silhouettes seed the first of the flood's textures.
        pass.set_bind_group(2, &groups.seeds[0], &[]);
        pass.dispatch_workgroups(x, y, 1);
        // The blocks near a silhouette, listed, and the dispatches over the lists.
        // One invocation a row of blocks, then a column.
        pass.set_pipeline(&self.near_rows);
        pass.dispatch_workgroups(y.div_ceil(64), 1, 1);
        pass.set_pipeline(&self.near_columns);
        pass.dispatch_workgroups(x.div_ceil(64), 1, 1);
        pass.set_pipeline(&self.args);
        pass.set_bind_group(3, &self.args_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        // The blocks far from every silhouette: the level texture and the flood's texture that
        // level 0 did not fill (the first of each), and the fattened map.
        pass.set_pipeline(&self.fill);
        pass.set_bind_group(0, &groups.steps[0], &[STEP_STRIDE as u32]);
        pass.set_bind_group(2, &groups.seeds[1], &[]);
        pass.dispatch_workgroups_indirect(&self.list_args, 16);
        // Over the blocks near a silhouette, each level from the one before (level 1 from
        // level 0 in the second, then back and forth), and with it a round of the flood: jumps
        // of 2^(levels - 1) texels (about the widest radius) down to 1, each round from the
        // texture the last wrote into the other.
        // Each pass twice, over the list and over every texel: one of the two is empty.
        let both = |pass: &mut wgpu::ComputePass, pipelines: &[std::sync::Arc<wgpu::ComputePipeline>; 2]| {
            for (pipeline, args) in pipelines.iter().zip([0, 32]) {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups_indirect(&self.list_args, args);
            }
        };
        for level in 1..=self.levels {
            let group = if level == 1 { 0 } else { 1 + (level as usize % 2) };
            pass.set_bind_group(0, &groups.steps[group], &[(level as u64 * STEP_STRIDE) as u32]);
            pass.set_bind_group(2, &groups.seeds[level as usize % 2], &[]);
            both(&mut pass, &self.level);
        }
        let rounds = self.levels;
        pass.set_bind_group(0, &groups.dilate[self.levels as usize % 2], &[0]);
        // The flood's last texture read (the other one is not written).
        pass.set_bind_group(2, &groups.seeds[1 - rounds as usize % 2], &[]);
        both(&mut pass, &self.dilate);
    }
}

/// The side of the derived map's tiles: a quarter of the shadow map's. It bounds where a penumbra
/// can fall (each texel the least of the 4 x 4 shadow-map texels it covers, and of those within
/// the fatten distance), and a quarter of the geometric fattened map's texels make each of its
/// levels cost a quarter as much (on Mesa's software rasterizer, where every compute
/// invocation costs, the whole pass took 416 ms at half the resolution on the teapot, against
/// 24 ms for the fattened map's draw).
fn dilated_resolution(tile: u32) -> u32 {
    (tile / 4).max(1)
}

/// World units across a texel of a fattened map whose tiles are `tile` texels a side in
/// `cascade` (a cascade or cube face), its widest axis: for a spot or point light per
/// unit of distance from it.
fn texel_across(cascade: &crate::light_space::Cascade, tile: u32) -> f32 {
    // The tile's projection: its clip space per unit of its view, x and y.
    let projection = cascade.view_projection * cascade.view.inverse();
    let scale = projection
        .x_axis
        .x
        .abs()
        .min(projection.y_axis.y.abs())
        .max(1e-20);
    // World units across the tile (at a unit distance for a perspective map).
    2.0 / scale / tile.max(1) as f32
}

/// How far, in texels of a fattened map whose tiles are `tile` texels a side and `texel` world
/// units across ([`texel_across`]), the fatten distance reaches across the light: at a spot or
/// point light's nearest caster, where a texel is narrowest, so no caster's fattening is
/// missed. At most a tile.
fn dilation_radius(light: &LightView, spreads: &DerivedSpreads, tile: u32, texel: f32) -> f32 {
    let texel = match light.kind {
        ProjectionKind::Orthographic => texel,
        ProjectionKind::Perspective => {
            let distance = if spreads.nearest_caster > 0.0 {
                spreads.nearest_caster
            } else {
                light.near.max(1e-6)
            };
            texel * distance
        }
    };
    (spreads.fatten_distance / texel.max(1e-20)).clamp(0.0, tile as f32)
}
