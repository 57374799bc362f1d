//! The exit map kept by the shadow map's own pass: no second drawing of the casters for it.
//!
//! Input: the shadow map pass's draws (`shaders/shadow_map.wgsl`'s `fs_exit_*` entry points).
//! Output: an R32F texture of half the shadow map's texels a side, like the exit map's own pass
//! ([`super::exit_map::ExitMapPass`]) draws: the nearest depth of the casters' faces turned
//! away from the light, texel by texel. While the shadow map's pass draws, each fragment of such
//! a face takes the atomic minimum of its depth's bits into a buffer of one `u32` a texel (a
//! depth in [0, 1] orders as its bits do), tile by tile (cascades, cube faces). Before the pass
//! each tile to redraw is set to the far plane by a copy from a buffer of 1.0's; after it, each
//! is copied into the texture. Copies, not compute passes: on lavapipe a compute pass over the
//! teapot's 2048 x 2048 exit atlas took 40 ms, as long as the shadow map's whole pass.
//!
//! It needs a device whose fragment shaders can write storage buffers, a shadow map that culls
//! no face ([`crate::ShadowMapSettings::cull_mode`] `None`, the default), and tiles of at least
//! 128 texels (the copies' rows are 256 bytes or more): elsewhere the exit map's own pass draws
//! it ([`crate::ExecutionSettings::exit_map_draw`]). It differs from that pass's map
//! where a texel's 2 x 2 texels of the shadow map see different back faces (it keeps the
//! nearest of the four where the other keeps the one at its centre), by the rounding of the
//! shadow map's depth format (this one keeps 32-bit floats), and on a device whose fragment
//! shaders read the depth before the rasterizer adds the depth bias, by that bias
//! (`tests/execution.rs` compares the two).

use super::atlas::{MapLayout, depth_state, support_map_resolution};
use super::pipelines::{CasterPipelines, SecondStream};
use super::pool::{MapPools, MapSlot, Moved, PoolKey};
use crate::casters::{Casters, Cull, OutwardWinding, Streams};
use crate::gpu_helpers::entry;
use crate::layouts::SceneLayouts;
use crate::light_space::AtlasGrid;
use crate::pipeline_cache::CachedDevice;
use crate::settings::ExitFaces;

/// A depth of 1.0 (the far plane) as the buffer keeps it: no face turned away from the light.
const NO_EXIT: u32 = 0x3f80_0000;

/// Whether `device` can keep the exit map in the shadow map's pass: its fragment shaders write
/// storage buffers (not wgpu's GL backend, where OpenGL ES 3.0 and WebGL2 have none).
pub(crate) fn supported(device: &wgpu::Device) -> bool {
    device.adapter_info().backend != wgpu::Backend::Gl
        && device.limits().max_storage_buffers_per_shader_stage >= 1
}

/// Whether `map`'s atlas can keep its exit map in the shadow map's pass on `device`: each
/// tile's rows can be copied (a multiple of 256 bytes) and the buffer fits the device's storage
/// bindings.
pub(crate) fn fits(device: &CachedDevice<'_>, (_, grid, tile): MapLayout) -> bool {
    let side = support_map_resolution(tile);
    let limits = device.limits();
    (side * 4).is_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        && buffer_bytes(grid, side) <= limits.max_storage_buffer_binding_size.min(limits.max_buffer_size)
}

/// Bytes of the buffer for `grid`'s tiles of `side` texels.
fn buffer_bytes(grid: AtlasGrid, side: u32) -> u64 {
    u64::from(grid.cols.max(1) * grid.rows.max(1)) * u64::from(side) * u64::from(side) * 4
}

/// The shadow map's pipelines that keep the back faces too, the buffer they keep them in, the
/// exit map it is copied into, and the far plane the buffer is set to.
pub(crate) struct ExitInShadowPass {
    /// Opaque casters whose outward faces turn counter-clockwise in the map (`fs_exit_ccw`),
    /// clockwise (`fs_exit_cw`), and the masked casters' twins.
    opaque_ccw: CasterPipelines,
    opaque_cw: CasterPipelines,
    masked_ccw: CasterPipelines,
    masked_cw: CasterPipelines,
    /// Every caster whose winding is not known (or every one, [`ExitFaces::Fragment`]) drawn
    /// once more, each fragment testing its side (`vs_exit_any` + `fs_exit_any`), with no depth
    /// test or write.
    any: CasterPipelines,
    faces: ExitFaces,
    /// The layout of the draws' group 3: the buffer and its layout.
    draw_layout: wgpu::BindGroupLayout,
    draw_group: wgpu::BindGroup,
    /// One `u32` a texel of `map`, tile by tile.
    bits: wgpu::Buffer,
    /// 1.0's, one tile's worth: what each tile to redraw is set to first.
    far: wgpu::Buffer,
    /// The exit map: R32F, half the shadow map's texels a side, a layer of an array the lights'
    /// kept exit maps of this size share.
    map: MapSlot,
    /// Texels a side of one tile, and tiles a row, for the draws (`exit_layout`).
    draw_uniform: wgpu::Buffer,
    grid: AtlasGrid,
    /// Texels a side of one tile of `map`.
    side: u32,
    /// The tiles the next draw redraws, a bit each.
    redrawn: u32,
}

impl ExitInShadowPass {
    /// The pipelines of the shadow map's `shader` (its light uniform's layout `light`) that
    /// keep the back faces, and the buffers and the map for `map`'s atlas; `None` where the
    /// buffer of 1.0's cannot be written.
    pub fn new(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &SceneLayouts,
        (shader, light): (&wgpu::ShaderModule, &wgpu::BindGroupLayout),
        map: MapLayout,
    ) -> Option<Self> {
        let (settings, grid, tile) = map;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let draw_layout = device.bind_group_layout(
            "ExitInShadowPass::draw",
            &[
                entry::storage_buffer(0, fragment, false),
                entry::uniform(1, fragment, 16, false),
            ],
        );
        let primitive = wgpu::PrimitiveState::default();
        let opaque = |label, fs| {
            CasterPipelines::new(
                label,
                shader,
                &[Some(light), Some(&layouts.instance), None, Some(&draw_layout)],
                "vs_opaque",
                Some((fs, None)),
                SecondStream::None,
                primitive,
                depth_state(settings),
            )
        };
        let masked = |label, fs| {
            CasterPipelines::new(
                label,
                shader,
                &[
                    Some(light),
                    Some(&layouts.instance),
                    Some(&layouts.material),
                    Some(&draw_layout),
                ],
                "vs_masked",
                Some((fs, None)),
                SecondStream::Uv,
                primitive,
                depth_state(settings),
            )
        };
        let any = CasterPipelines::new(
            "ExitInShadowPass::any",
            shader,
            &[Some(light), Some(&layouts.instance), None, Some(&draw_layout)],
            "vs_exit_any",
            Some(("fs_exit_any", None)),
            SecondStream::SmoothedNormals,
            primitive,
            // The depth bias as the other draws: where a fragment shader reads the depth with
            // the bias added (lavapipe does), both ways of telling the sides keep one depth.
            wgpu::DepthStencilState {
                depth_write_enabled: Some(false),
                depth_compare: Some(wgpu::CompareFunction::Always),
                ..depth_state(settings)
            },
        );
        let side = support_map_resolution(tile);
        let draw_uniform = crate::gpu_helpers::uniform_buffer(device, "ExitInShadowPass::draw", 16);
        let (bits, far, map_target) = Self::targets((device, pools), grid, side)?;
        let draw_group = Self::draw_group(device, &draw_layout, &bits, &draw_uniform);
        Some(Self {
            opaque_ccw: opaque("ExitInShadowPass::opaque_ccw", "fs_exit_ccw"),
            opaque_cw: opaque("ExitInShadowPass::opaque_cw", "fs_exit_cw"),
            masked_ccw: masked("ExitInShadowPass::masked_ccw", "fs_masked_exit_ccw"),
            masked_cw: masked("ExitInShadowPass::masked_cw", "fs_masked_exit_cw"),
            any,
            faces: settings.exit_faces,
            draw_layout,
            draw_group,
            bits,
            far,
            map: map_target,
            draw_uniform,
            grid,
            side,
            redrawn: u32::MAX,
        })
    }

    /// The buffer, the far plane's buffer (`None` where it cannot be written) and the exit map,
    /// for `grid`'s tiles of `side` texels.
    fn targets(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        grid: AtlasGrid,
        side: u32,
    ) -> Option<(wgpu::Buffer, wgpu::Buffer, MapSlot)> {
        let bits = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ExitInShadowPass::bits"),
            size: buffer_bytes(grid, side),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let far = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ExitInShadowPass::far"),
            size: buffer_bytes(AtlasGrid::SINGLE, side),
            usage: wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: true,
        });
        {
            let mut range = far.slice(..).get_mapped_range_mut().ok()?;
            let bytes = buffer_bytes(AtlasGrid::SINGLE, side) as usize;
            range
                .slice(..)
                .write_iter(std::iter::repeat(NO_EXIT.to_le_bytes()).flatten().take(bytes));
        }
        far.unmap();
        let (width, height) = (grid.cols.max(1) * side, grid.rows.max(1) * side);
        let map = pools.slot(
            device,
            PoolKey {
                label: "ExitInShadowPass::exit_map",
                format: wgpu::TextureFormat::R32Float,
                size: (width, height),
                usage: wgpu::TextureUsages::COPY_DST,
            },
        );
        Some((bits, far, map))
    }

    fn draw_group(
        device: &CachedDevice<'_>,
        layout: &wgpu::BindGroupLayout,
        bits: &wgpu::Buffer,
        uniform: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        crate::gpu_helpers::bind_group(device, "ExitInShadowPass::draw", layout, &[bits, uniform])
    }

    /// Makes the buffers and the map again for a shadow map of `grid`'s tiles of `tile`
    /// texels; false where the buffer of 1.0's cannot be written (the exit map must then be
    /// drawn by its own pass). The map must then be drawn and bound again.
    pub fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) -> bool {
        let (_, grid, tile) = map;
        let side = support_map_resolution(tile);
        let Some((bits, far, target)) = Self::targets((device, pools), grid, side) else {
            return false;
        };
        (self.bits, self.far, self.map) = (bits, far, target);
        self.draw_group = Self::draw_group(device, &self.draw_layout, &self.bits, &self.draw_uniform);
        (self.grid, self.side) = (grid, side);
        true
    }

    /// Makes the pipelines for the vertex layouts of `casters`.
    pub fn prepare_pipelines(&mut self, device: &CachedDevice<'_>, casters: &Casters) {
        let opaque = casters.draw_layouts(Streams::OpaqueDepth);
        let masked = casters.draw_layouts(Streams::MaskedDepth);
        if self.faces == ExitFaces::Winding {
            self.opaque_ccw.prepare(device, &opaque);
            self.opaque_cw.prepare(device, &opaque);
            self.masked_ccw.prepare(device, &masked);
            self.masked_cw.prepare(device, &masked);
        }
        self.any.prepare(device, &casters.draw_layouts(Streams::Fattened));
    }

    /// Draws one tile's casters into the shadow map's `pass` keeping their back faces:
    /// `plain` (the opaque and the masked pipelines of the shadow map alone) for the draws
    /// whose winding is not known, which are then drawn once more to keep theirs.
    pub fn draw(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        casters: &Casters,
        cull: Cull,
        (opaque, masked): (&CasterPipelines, &CasterPipelines),
    ) {
        pass.set_bind_group(3, &self.draw_group, &[]);
        let by_winding = self.faces == ExitFaces::Winding;
        casters.draw(pass, Streams::OpaqueDepth, cull, |layout, outward| {
            match (by_winding, outward) {
                (true, OutwardWinding::Ccw) => self.opaque_ccw.get(layout),
                (true, OutwardWinding::Cw) => self.opaque_cw.get(layout),
                _ => opaque.get(layout),
            }
        });
        casters.draw(pass, Streams::MaskedDepth, cull, |layout, outward| {
            match (by_winding, outward) {
                (true, OutwardWinding::Ccw) => self.masked_ccw.get(layout),
                (true, OutwardWinding::Cw) => self.masked_cw.get(layout),
                _ => masked.get(layout),
            }
        });
        casters.draw(pass, Streams::Fattened, cull, |layout, outward| {
            if by_winding && outward != OutwardWinding::Mixed {
                return None;
            }
            self.any.get(layout)
        });
    }

    /// Uploads the layout for the next draw, which redraws the tiles whose bit is set in
    /// `redrawn`.
    pub fn prepare(&mut self, queue: &wgpu::Queue, redrawn: u32) {
        let layout = [self.side, self.grid.cols.max(1), 0, 0];
        queue.write_buffer(&self.draw_uniform, 0, bytemuck::bytes_of(&layout));
        self.redrawn = redrawn;
    }

    /// The tiles the next draw redraws, and each one's place in the buffer and the map.
    fn tiles(&self) -> impl Iterator<Item = (u64, wgpu::Origin3d)> + '_ {
        let tile_bytes = buffer_bytes(AtlasGrid::SINGLE, self.side);
        let count = self.grid.cols.max(1) * self.grid.rows.max(1);
        (0..count.min(32))
            .filter(|index| self.redrawn & (1 << index) != 0)
            .map(move |index| {
                let [x, y, _, _] = crate::light_space::tile_viewport(self.grid, index, self.side);
                (
                    u64::from(index) * tile_bytes,
                    wgpu::Origin3d {
                        x,
                        y,
                        z: self.map.layer,
                    },
                )
            })
    }

    /// Records, before the shadow map's pass, the copies that set each tile to redraw to the
    /// far plane.
    pub fn encode_reset(&self, encoder: &mut wgpu::CommandEncoder) {
        let tile_bytes = buffer_bytes(AtlasGrid::SINGLE, self.side);
        for (offset, _) in self.tiles() {
            encoder.copy_buffer_to_buffer(&self.far, 0, &self.bits, offset, tile_bytes);
        }
    }

    /// Records, after the shadow map's pass, the copies of each tile drawn into the exit map.
    pub fn encode_copy(&self, encoder: &mut wgpu::CommandEncoder) {
        for (offset, origin) in self.tiles() {
            encoder.copy_buffer_to_texture(
                wgpu::TexelCopyBufferInfo {
                    buffer: &self.bits,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset,
                        bytes_per_row: Some(self.side * 4),
                        rows_per_image: Some(self.side),
                    },
                },
                wgpu::TexelCopyTextureInfo {
                    texture: &self.map.target.texture,
                    mip_level: 0,
                    origin,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::Extent3d {
                    width: self.side,
                    height: self.side,
                    depth_or_array_layers: 1,
                },
            );
        }
    }

    /// The exit map (its layer, as a 2D texture).
    pub fn view(&self) -> &wgpu::TextureView {
        &self.map.target.view
    }

    /// The array the exit map is a layer of ([`ExitInShadowPass::layer`]).
    pub fn texture(&self) -> &wgpu::Texture {
        &self.map.target.texture
    }

    /// The exit map's layer of [`ExitInShadowPass::texture`].
    pub fn layer(&self) -> u32 {
        self.map.layer
    }

    /// Points the exit map at its array as it is now ([`MapPools::refresh`]).
    pub fn refresh(&mut self, pools: &MapPools) -> Moved {
        pools.refresh(&mut self.map)
    }

    /// GPU memory the buffers and the map's layer take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.bits.size() + self.far.size() + self.map.allocated_bytes() + self.draw_uniform.size()
    }
}
