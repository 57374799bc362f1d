//! The exit map kept by the shadow map's own pass: no second drawing of the casters for it.
//!
//! Input: the shadow map pass's draws (`shaders/shadow_map.wgsl`'s `fs_exit_*` entry points).
//! Output: an R32F texture of half the shadow map's texels a side, like the exit map's own pass
//! ([`super::exit_map::ExitMapPass`]) draws: the nearest depth of the casters' faces turned
//! away from the light, texel by texel. While the shadow map's pass draws, each fragment of such
//! a face takes the atomic maximum of its depth's bits inverted into a buffer of one `u32` a
//! texel (a depth in [0, 1] orders as its bits do, so the largest inverted bits are the nearest
//! depth, and 0, a buffer's first value, is no face at all); after the pass a compute pass
//! (`shaders/exit_resolve.wgsl`) copies the tiles drawn into the texture and sets them back to 0
//! for the next draw.
//!
//! It needs a device whose fragment shaders can write storage buffers, and a shadow map that
//! culls no face ([`crate::ShadowMapSettings::cull_mode`] `None`, the default): elsewhere the
//! exit map's own pass draws it ([`crate::ExecutionSettings::exit_in_shadow_pass`]). It differs
//! from that pass's map where a texel's 2 x 2 texels of the shadow map see different back faces
//! (it keeps the nearest of the four where the other keeps the one at its centre), by the
//! rounding of the shadow map's depth format (this one keeps 32-bit floats), and on a device
//! whose fragment shaders read the depth before the rasterizer adds the depth bias, by that
//! bias (`tests/execution.rs` compares the two).

use bytemuck::{Pod, Zeroable};

use super::atlas::{MapLayout, depth_state, support_map_resolution};
use super::pipelines::{CasterPipelines, SecondStream};
use crate::casters::{Casters, Cull, OutwardWinding, Streams};
use crate::gpu_helpers::{Target, entry, texture_bytes};
use crate::layouts::SceneLayouts;
use crate::light_space::AtlasGrid;
use crate::settings::ExitFaces;

/// What the resolve reads besides the buffer (`shaders/exit_resolve.wgsl`'s `Resolve`).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ResolveUniform {
    /// Texels a row of the buffer, texels a side of one tile, tiles a row, the tiles redrawn.
    layout: [u32; 4],
}

/// Whether `device` can keep the exit map in the shadow map's pass: its fragment shaders write
/// storage buffers (not wgpu's GL backend, where OpenGL ES 3.0 and WebGL2 have none).
pub(crate) fn supported(device: &wgpu::Device) -> bool {
    device.adapter_info().backend != wgpu::Backend::Gl
        && device.limits().max_storage_buffers_per_shader_stage >= 1
}

/// Whether the buffer for `grid`'s tiles of `tile` shadow-map texels fits `device`'s storage
/// bindings.
pub(crate) fn fits(device: &wgpu::Device, (_, grid, tile): MapLayout) -> bool {
    let side = support_map_resolution(tile);
    let bytes = u64::from(grid.cols.max(1) * side) * u64::from(grid.rows.max(1) * side) * 4;
    let limits = device.limits();
    bytes <= u64::from(limits.max_storage_buffer_binding_size).min(limits.max_buffer_size)
}

/// The shadow map's pipelines that keep the back faces too, the buffer they keep them in, the
/// exit map it is resolved into, and the bind groups of both.
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
    /// The layout of the draws' group 3: the buffer and its row length.
    pub draw_layout: wgpu::BindGroupLayout,
    draw_group: wgpu::BindGroup,
    /// One `u32` a texel of `map`, rows of `stride` texels.
    bits: wgpu::Buffer,
    stride: u32,
    /// The exit map: R32F, half the shadow map's texels a side.
    map: Target,
    /// Its row length for the draws (`exit_layout`).
    draw_uniform: wgpu::Buffer,
    resolve: wgpu::ComputePipeline,
    resolve_layout: wgpu::BindGroupLayout,
    resolve_group: wgpu::BindGroup,
    resolve_uniform: wgpu::Buffer,
    /// Tiles a row, and texels a side of one tile of `map`.
    grid: AtlasGrid,
    tile: u32,
}

impl ExitInShadowPass {
    /// The pipelines of the shadow map's `shader` (its light uniform's layout `light`) that
    /// keep the back faces, and the buffer and map for `map`'s atlas.
    pub fn new(
        device: &wgpu::Device,
        layouts: &SceneLayouts,
        (shader, light): (&wgpu::ShaderModule, &wgpu::BindGroupLayout),
        map: MapLayout,
    ) -> Self {
        let (settings, grid, tile) = map;
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let draw_layout = crate::gpu_helpers::layout(
            device,
            "ExitInShadowPass::draw",
            &[
                entry::storage_buffer(0, fragment, false),
                entry::uniform(1, fragment, 16, false),
            ],
        );
        let primitive = wgpu::PrimitiveState::default();
        let opaque = |label, fs| {
            CasterPipelines::new(
                device,
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
                device,
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
            device,
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
        let resolve_layout = crate::gpu_helpers::layout(
            device,
            "ExitInShadowPass::resolve",
            &[
                entry::storage_buffer(0, wgpu::ShaderStages::COMPUTE, false),
                entry::storage_texture(1, wgpu::TextureFormat::R32Float),
                entry::uniform(2, wgpu::ShaderStages::COMPUTE, size_of::<ResolveUniform>(), false),
            ],
        );
        let shader = crate::shaders::module(device, "exit_resolve.wgsl", crate::shaders::EXIT_RESOLVE);
        let resolve = crate::gpu_helpers::compute_pipeline(
            device,
            "ExitInShadowPass::resolve",
            &shader,
            &[Some(&resolve_layout)],
            "cs_main",
            &[],
        );
        let draw_uniform = crate::gpu_helpers::uniform_buffer(device, "ExitInShadowPass::draw", 16);
        let resolve_uniform = crate::gpu_helpers::uniform_buffer(
            device,
            "ExitInShadowPass::resolve",
            size_of::<ResolveUniform>() as u64,
        );
        let (bits, stride, map_target) = Self::targets(device, grid, support_map_resolution(tile));
        let (draw_group, resolve_group) = Self::groups(
            device,
            (&draw_layout, &resolve_layout),
            (&bits, &map_target, &draw_uniform, &resolve_uniform),
        );
        Self {
            opaque_ccw: opaque("ExitInShadowPass::opaque_ccw", "fs_exit_ccw"),
            opaque_cw: opaque("ExitInShadowPass::opaque_cw", "fs_exit_cw"),
            masked_ccw: masked("ExitInShadowPass::masked_ccw", "fs_masked_exit_ccw"),
            masked_cw: masked("ExitInShadowPass::masked_cw", "fs_masked_exit_cw"),
            any,
            faces: settings.exit_faces,
            draw_layout,
            draw_group,
            bits,
            stride,
            map: map_target,
            draw_uniform,
            resolve,
            resolve_layout,
            resolve_group,
            resolve_uniform,
            grid,
            tile: support_map_resolution(tile),
        }
    }

    /// The buffer (no face kept), its row length, and the exit map, for `grid`'s tiles
    /// of `tile` texels a side.
    fn targets(device: &wgpu::Device, grid: AtlasGrid, tile: u32) -> (wgpu::Buffer, u32, Target) {
        let (width, height) = (grid.cols.max(1) * tile, grid.rows.max(1) * tile);
        // Zeros, as wgpu makes every buffer: no face kept.
        let bits = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ExitInShadowPass::bits"),
            size: u64::from(width) * u64::from(height) * 4,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let map = crate::gpu_helpers::texture_2d(
            device,
            "ExitInShadowPass::exit_map",
            (width, height),
            wgpu::TextureFormat::R32Float,
            wgpu::TextureUsages::STORAGE_BINDING,
        );
        (bits, width, map)
    }

    fn groups(
        device: &wgpu::Device,
        (draw_layout, resolve_layout): (&wgpu::BindGroupLayout, &wgpu::BindGroupLayout),
        (bits, map, draw_uniform, resolve_uniform): (&wgpu::Buffer, &Target, &wgpu::Buffer, &wgpu::Buffer),
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let draw = crate::gpu_helpers::bind_group(
            device,
            "ExitInShadowPass::draw",
            draw_layout,
            &[bits, draw_uniform],
        );
        let resolve = crate::gpu_helpers::bind_group(
            device,
            "ExitInShadowPass::resolve",
            resolve_layout,
            &[bits, &map.view, resolve_uniform],
        );
        (draw, resolve)
    }

    /// Makes the buffer and the map again for a shadow map of `grid`'s tiles of `tile` texels;
    /// the map must then be drawn and bound again.
    pub fn resize(&mut self, device: &wgpu::Device, map: MapLayout) {
        let (_, grid, tile) = map;
        let tile = support_map_resolution(tile);
        (self.bits, self.stride, self.map) = Self::targets(device, grid, tile);
        (self.draw_group, self.resolve_group) = Self::groups(
            device,
            (&self.draw_layout, &self.resolve_layout),
            (&self.bits, &self.map, &self.draw_uniform, &self.resolve_uniform),
        );
        (self.grid, self.tile) = (grid, tile);
    }

    /// Makes the pipelines for the vertex layouts of `casters`.
    pub fn prepare_pipelines(&mut self, device: &wgpu::Device, casters: &Casters) {
        let opaque = casters.draw_layouts(Streams::OpaqueDepth);
        let masked = casters.draw_layouts(Streams::MaskedDepth);
        if self.faces == ExitFaces::Winding {
            self.opaque_ccw.prepare(device, &opaque);
            self.opaque_cw.prepare(device, &opaque);
            self.masked_ccw.prepare(device, &masked);
            self.masked_cw.prepare(device, &masked);
        }
        self.any
            .prepare(device, &casters.draw_layouts(Streams::Fattened));
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
    pub fn prepare(&self, queue: &wgpu::Queue, redrawn: u32) {
        queue.write_buffer(
            &self.draw_uniform,
            0,
            bytemuck::bytes_of(&[self.stride, 0, 0, 0]),
        );
        let resolve = ResolveUniform {
            layout: [self.stride, self.tile, self.grid.cols.max(1), redrawn],
        };
        queue.write_buffer(&self.resolve_uniform, 0, bytemuck::bytes_of(&resolve));
    }

    /// Records the resolve, after the shadow map's pass: the tiles drawn into the exit map,
    /// the buffer back to 0.
    pub fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ExitInShadowPass::resolve"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.resolve);
        pass.set_bind_group(0, &self.resolve_group, &[]);
        let (w, h) = (self.map.texture.width(), self.map.texture.height());
        pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
    }

    /// The exit map.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.map.view
    }

    /// The exit map's texture.
    pub fn texture(&self) -> &wgpu::Texture {
        &self.map.texture
    }

    /// GPU memory the buffer and the map take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.bits.size() + texture_bytes(&self.map.texture) + 16 + size_of::<ResolveUniform>() as u64
    }
}
