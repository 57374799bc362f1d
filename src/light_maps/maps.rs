//! [`LightMaps`]: the maps one light's chain draws from the light.

use super::atlas::{FarPlaneFill, MapUpload};
use super::exit_map::ExitMapPass;
use super::fattened_shadow_map::FattenedShadowMapPass;
use super::shadow_map::ShadowMapPass;
use crate::casters::Casters;
use crate::chain::{Chain, run};
use crate::light_space::LightView;
use crate::settings::ShadowMapSettings;

/// A light's maps drawn from the light: the shadow map, and for the distance-map method the
/// fattened map and the exit map, all made with one set of casters' vertex layouts and one
/// atlas layout.
pub(crate) struct LightMaps {
    pub shadow: ShadowMapPass,
    pub fattened: Option<(FattenedShadowMapPass, ExitMapPass)>,
    /// The casters (id) the passes were made for.
    casters: u64,
}

impl LightMaps {
    /// GPU memory the maps take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.shadow.atlas.allocated_bytes()
            + self.fattened.as_ref().map_or(0, |(fattened, exit)| {
                fattened.allocated_bytes() + exit.atlas.allocated_bytes()
            })
    }

    /// Makes or keeps the maps `chain` needs for a light fitted as `light_view` (its atlas's
    /// tiles and their size); true when any was made (they must then be drawn and bound again).
    pub fn allocate(
        maps: &mut Option<LightMaps>,
        device: &wgpu::Device,
        casters: &Casters,
        settings: &ShadowMapSettings,
        light_view: &LightView,
        chain: &Chain,
    ) -> bool {
        let (grid, tile) = (light_view.grid, light_view.tile);
        let layouts = casters.layouts();
        let mut made = false;
        let maps = match maps {
            Some(m) if m.casters == casters.id() => {
                // Another layout (the cascades in use) or resolution
                // (`crate::MapResolution::FromPenumbra`): new textures, the same pipelines.
                if (m.shadow.atlas.grid, m.shadow.atlas.tile) != (grid, tile) {
                    m.shadow.resize(device, (settings, grid, tile));
                    if let Some((fattened, exit)) = &mut m.fattened {
                        fattened.resize(device, (settings, grid, tile));
                        exit.resize(device, (settings, grid, tile));
                    }
                    made = true;
                }
                m
            }
            _ => {
                made = true;
                maps.insert(LightMaps {
                    shadow: ShadowMapPass::new(device, layouts, (settings, grid, tile)),
                    fattened: None,
                    casters: casters.id(),
                })
            }
        };
        if chain.fattened_map() != maps.fattened.is_some() {
            maps.fattened = chain.fattened_map().then(|| {
                (
                    FattenedShadowMapPass::new(device, layouts, (settings, grid, tile)),
                    ExitMapPass::new(device, layouts, (settings, grid, tile)),
                )
            });
            made = true;
        }
        made
    }

    /// Uploads the light's fit (and fatten distance) for the next draw, which redraws only the
    /// tiles (cascades, cube faces) whose bit is set in `tiles` and draws only the casters on
    /// `layers`.
    pub fn prepare(&mut self, upload: &MapUpload, fatten_distance: f32, tiles: u32) {
        self.shadow.prepare(upload);
        self.shadow.atlas.redraw_only(tiles);
        if let Some((fattened, exit)) = &mut self.fattened {
            fattened.prepare(upload, fatten_distance);
            fattened.atlas.redraw_only(tiles);
            exit.prepare(upload);
            exit.atlas.redraw_only(tiles);
        }
    }

    /// Bytes a [`FarPlaneFill`] needs to fill the largest of these maps.
    pub fn fill_bytes(&self) -> u64 {
        let support = self.fattened.as_ref().map_or(0, |(fattened, exit)| {
            fattened.atlas.fill_bytes().max(exit.atlas.fill_bytes())
        });
        self.shadow.atlas.fill_bytes().max(support)
    }

    /// Draws the maps, calling `mark(encoder, pass)` after each; `fill` sets a whole atlas to
    /// the far plane where it can.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        casters: &Casters,
        fill: Option<&FarPlaneFill>,
        mark: &mut dyn FnMut(&mut wgpu::CommandEncoder, &'static str),
    ) {
        run(encoder, mark, "shadow map", |e| {
            self.shadow.encode(e, (casters, fill))
        });
        if let Some((fattened, exit)) = &self.fattened {
            run(encoder, mark, "fattened shadow map", |e| {
                fattened.encode(e, (casters, fill))
            });
            run(encoder, mark, "exit map", |e| exit.encode(e, (casters, fill)));
        }
    }
}
