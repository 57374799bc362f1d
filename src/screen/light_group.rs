//! [`LightGroup`]: the screen-space passes of several lights alike run as one
//! ([`crate::ExecutionSettings::light_groups`]).

use super::{
    BlurCompute, DistanceMaps, ScreenStage, TileList, TileListPass, TileListTargets, VariablePcfCompute,
};
use super::{ChainKey, Mark};
use crate::chain::FRAME_SIZE;
use crate::frame::{FrameSlots, PassParams};
use crate::gpu_helpers::{entry, layer_view, texture_bytes};

/// Bytes before the first member's list in [`LightGroup`]'s buffer of lists: the header
/// (`GROUP_HEADER` words in `shaders/common/tile_groups.wgsl`), 256 bytes, so that every
/// list starts where a storage binding may.
const HEADER_BYTES: u64 = 256;

/// The lights a group can hold: the header's room for their slots (words 2 to 17) and where
/// their tiles start (words 18 to 34).
pub(crate) const MAX_MEMBERS: usize = 16;

/// What a member's chain binds in place of the intermediates lights share: its tile list (a
/// region of the group's) and its layers of the group's distance map and of the blur's
/// horizontal result, which its classification clears where it lists nothing.
pub(crate) struct GroupMember {
    pub tiles: TileListTargets,
    pub distance: wgpu::TextureView,
    pub blurred: wgpu::TextureView,
}

/// Several lights whose distance-map chains are alike (one [`ChainKey`], maps in the same
/// arrays) as one chain after their classifications: each light's tile classification (its own
/// chain's) writes its list into a region of one buffer, then one dispatch sums the lists'
/// lengths into where each member's tiles start and the passes' size
/// (`shaders/group_args.wgsl`), and the variable PCF and each blur axis run once over every
/// member's tiles, one workgroup a tile (`shaders/common/tile_groups.wgsl`). Each pass reads a member's
/// frame from the frame uniforms bound whole, and keeps its intermediates in the member's
/// layer of the group's arrays; the PCF and the blur's vertical axis write the light's layer
/// of the visibility.
pub(crate) struct LightGroup {
    key: ChainKey,
    /// The members' light slots, in member order.
    slots: Vec<usize>,
    size: (u32, u32),
    lists: wgpu::Buffer,
    /// `lists` as the passes' list group.
    lists_group: wgpu::BindGroup,
    /// The passes' indirect arguments.
    args: wgpu::Buffer,
    args_pipeline: wgpu::ComputePipeline,
    args_group: wgpu::BindGroup,
    /// A layer a member: the distance map, the deviations, the blur's horizontal result.
    distance: (wgpu::Texture, wgpu::TextureView),
    sigma: (wgpu::Texture, wgpu::TextureView),
    blurred: (wgpu::Texture, wgpu::TextureView),
    members: Vec<GroupMember>,
    pcf: VariablePcfCompute,
    blur: BlurCompute,
    /// The passes were bound to the members' maps and the visibility since they were made.
    pub bound: bool,
}

impl LightGroup {
    /// Whether lights with chains of `key` can run as a group: `ours` in compute, the PCF
    /// writing the layer, the distance taken in the PCF, a blur, the maps as arrays, the
    /// intermediates in half floats and the tiles' pixels tested by workgroups (which clear
    /// what the passes read where nothing is listed) on `device`.
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
    }

    /// A group of the lights at `slots` (at most [`MAX_MEMBERS`]), whose chains are made for
    /// `key`, over a screen of `size`.
    pub fn new(device: &wgpu::Device, key: ChainKey, slots: Vec<usize>, size: (u32, u32)) -> Self {
        let n = slots.len() as u32;
        let alignment = u64::from(device.limits().min_storage_buffer_offset_alignment).max(4);
        let region = TileListTargets::list_bytes(size).next_multiple_of(alignment);
        let lists = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightGroup::lists"),
            size: HEADER_BYTES + region * u64::from(n),
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: true,
        });
        {
            let mut header = [0u32; (HEADER_BYTES / 4) as usize];
            header[0] = (region / 4) as u32;
            header[1] = n;
            for (word, slot) in header[2..2 + MAX_MEMBERS].iter_mut().zip(&slots) {
                *word = *slot as u32;
            }
            if let Ok(mut mapped) = lists.slice(..HEADER_BYTES).get_mapped_range_mut() {
                mapped.copy_from_slice(bytemuck::cast_slice(&header));
            }
        }
        lists.unmap();
        let list_layout = TileListPass::list_layout(device);
        let lists_group =
            crate::gpu_helpers::bind_group(device, "LightGroup::lists", &list_layout, &[&lists]);
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("LightGroup::args"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let compute = wgpu::ShaderStages::COMPUTE;
        let args_layout = crate::gpu_helpers::layout(
            device,
            "LightGroup::args_layout",
            &[
                // The header's starts are written.
                entry::storage_buffer(0, compute, false),
                entry::storage_buffer(1, compute, false),
            ],
        );
        let args_shader = crate::shaders::module(device, "group_args.wgsl", crate::shaders::GROUP_ARGS);
        let args_pipeline = super::compute_pipeline(
            device,
            "LightGroup::args",
            &args_shader,
            &[Some(&args_layout)],
            "cs_group_args",
            &[],
        );
        let args_group =
            crate::gpu_helpers::bind_group(device, "LightGroup::args", &args_layout, &[&lists, &args]);
        let half = key.half_floats();
        let array = |label, format| layers(device, label, (size, n), format);
        let distance = array(
            "LightGroup::distance",
            super::DistanceMapCompute::format(half.intermediates),
        );
        let sigma = array("LightGroup::sigma", super::sigma_storage(half.intermediates));
        let blurred = array(
            "LightGroup::blurred",
            super::visibility_storage(half.intermediates),
        );
        let members = (0..n)
            .map(|g| GroupMember {
                tiles: TileListTargets::in_region(device, size, &lists, HEADER_BYTES + region * u64::from(g)),
                distance: layer_view(&distance.0, "LightGroup::distance_layer", g),
                blurred: layer_view(&blurred.0, "LightGroup::blurred_layer", g),
            })
            .collect();
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
            lists,
            lists_group,
            args,
            args_pipeline,
            args_group,
            distance,
            sigma,
            blurred,
            members,
            pcf,
            blur,
            bound: false,
        }
    }

    /// This group is the lights at `slots` with chains of `key`, over a screen of `size`.
    pub fn fits(&self, key: &ChainKey, slots: &[usize], size: (u32, u32)) -> bool {
        self.key == *key && self.slots == slots && self.size == size
    }

    /// The members' light slots, in member order.
    pub fn slots(&self) -> &[usize] {
        &self.slots
    }

    /// What the light at `slot` binds as a member (none where it is not one).
    pub fn member(&self, slot: usize) -> Option<&GroupMember> {
        let g = self.slots.iter().position(|&s| s == slot)?;
        self.members.get(g)
    }

    /// The light at `slot`'s intermediate `which` where the group holds it, and its layer
    /// there: the distance map (the member's layer of the group's) and the tile classes (the
    /// member's own). `None` for the others and where the light is not a member.
    pub fn member_texture(&self, slot: usize, which: crate::LightTexture) -> Option<(&wgpu::Texture, u32)> {
        let g = self.slots.iter().position(|&s| s == slot)?;
        match which {
            crate::LightTexture::DistanceMap => Some((&self.distance.0, u32::try_from(g).ok()?)),
            crate::LightTexture::TileClasses => Some((self.members.get(g)?.tiles.classes_texture(), 0)),
            _ => None,
        }
    }

    /// Points the passes at their inputs: every light's frame, the camera's depth and the
    /// receiver mask, the members' maps (the arrays every member's maps are layers of), the
    /// visibility (its array, the lights' layers) and a stand-in.
    pub fn bind(
        &mut self,
        device: &wgpu::Device,
        frames: &FrameSlots,
        (depth, mask, dummy): (&wgpu::TextureView, &wgpu::TextureView, &wgpu::TextureView),
        maps: &DistanceMaps,
        visibility: &wgpu::TextureView,
    ) {
        let frames = frames.whole();
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

    /// Uploads the passes' parameters.
    pub fn prepare(&self, queue: &wgpu::Queue, params: &PassParams) {
        self.pcf.prepare(queue, params);
        self.blur.prepare(queue, params);
    }

    /// Records the passes over every member's list (after the members' classifications): the
    /// arguments and the PCF marked "pcf", both blur axes "blur".
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, visibility: &wgpu::TextureView, mark: Mark) {
        let tiles = TileList {
            group: &self.lists_group,
            args: &self.args,
            offset: 0,
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
            self.pcf.encode(e, tiles, None);
        });
        let tiles = TileList {
            group: &self.lists_group,
            args: &self.args,
            offset: 0,
        };
        crate::chain::run(encoder, &mut *mark, "blur", |e| {
            self.blur.encode(e, tiles, (None, true), visibility)
        });
    }

    /// GPU memory the group allocated (the members' lists and their classes, the arrays, the
    /// passes' parameters), in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.lists.size()
            + self.args.size()
            + [&self.distance.0, &self.sigma.0, &self.blurred.0]
                .into_iter()
                .map(texture_bytes)
                .sum::<u64>()
            + self
                .members
                .iter()
                .map(|m| m.tiles.allocated_bytes() - TileListTargets::list_bytes(self.size))
                .sum::<u64>()
            + self.pcf.allocated_bytes()
            + self.blur.allocated_bytes()
    }
}

/// A storage texture of `n` layers of `size`, and its view as an array.
fn layers(
    device: &wgpu::Device,
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
