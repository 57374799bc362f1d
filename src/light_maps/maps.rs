//! [`LightMaps`]: the maps one light's chain draws from the light.

use super::atlas::{FarPlaneFill, MapLayout, MapUpload};
use super::dilated_map::DilatedMapPass;
use super::exit_in_shadow_pass;
use super::exit_map::ExitMapPass;
use super::fattened_shadow_map::FattenedShadowMapPass;
use super::pool::{MapPools, Moved};
use super::shadow_map::ShadowMapPass;
use crate::casters::Casters;
use crate::chain::{Chain, run};
use crate::frame::{DerivedSpreads, MapLayersUniform};
use crate::light_space::LightView;
use crate::pipeline_cache::CachedDevice;
use crate::settings::ShadowMapSettings;

/// A light's maps drawn from the light: the shadow map, and for the distance-map method the
/// fattened map (drawn, or derived from the shadow map) and the exit map (kept by the shadow
/// map's pass, or drawn by a pass of its own), all made with one set of casters' vertex layouts
/// and one atlas layout.
pub(crate) struct LightMaps {
    pub shadow: ShadowMapPass,
    pub fattened: Option<FattenedMap>,
    /// The exit map's own pass, where the shadow map's does not keep it.
    pub exit: Option<ExitMapPass>,
    /// The casters (id) the passes were made for.
    casters: u64,
}

/// A light's maps as its screen passes bind them ([`LightMaps::screen_views`]).
pub(crate) struct MapViews {
    /// The shadow map (compared, and read as depths).
    pub shadow: wgpu::TextureView,
    /// The fattened map and its occluder offsets, for the distance-map method.
    pub fattened: Option<(wgpu::TextureView, wgpu::TextureView)>,
    /// The exit map, where the light has one.
    pub exit: Option<wgpu::TextureView>,
}

/// A light's fattened map: the casters drawn again, pushed out, or derived from the shadow map
/// in compute ([`crate::Fattening`]).
pub(crate) enum FattenedMap {
    // Both boxed: each pass holds hundreds of bytes of handles, and they differ by more.
    Drawn(Box<FattenedShadowMapPass>),
    Dilated(Box<DilatedMapPass>),
}

impl FattenedMap {
    fn new(
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
        layouts: &crate::layouts::SceneLayouts,
        map: MapLayout,
        chain: &Chain,
    ) -> Self {
        if chain.draws_fattened_map() {
            FattenedMap::Drawn(Box::new(FattenedShadowMapPass::new(
                (device, pools),
                layouts,
                map,
            )))
        } else {
            FattenedMap::Dilated(Box::new(DilatedMapPass::new((device, pools), map)))
        }
    }

    /// Whether this is the kind `chain` uses.
    fn fits(&self, chain: &Chain) -> bool {
        matches!(self, FattenedMap::Drawn(_)) == chain.draws_fattened_map()
    }

    fn resize(&mut self, (device, pools): (&CachedDevice<'_>, &mut MapPools), map: MapLayout) {
        match self {
            FattenedMap::Drawn(f) => f.resize((device, pools), map),
            FattenedMap::Dilated(d) => d.resize((device, pools), map),
        }
    }

    fn allocated_bytes(&self) -> u64 {
        match self {
            FattenedMap::Drawn(f) => f.allocated_bytes(),
            FattenedMap::Dilated(d) => d.allocated_bytes(),
        }
    }

    /// The map the distance map and the tile classification test against.
    pub fn view(&self) -> &wgpu::TextureView {
        match self {
            FattenedMap::Drawn(f) => f.atlas.view(),
            FattenedMap::Dilated(d) => d.view(),
        }
    }

    /// The layer of [`FattenedMap::texture`] that holds this light's map.
    pub fn layer(&self) -> u32 {
        match self {
            FattenedMap::Drawn(f) => f.atlas.layer(),
            FattenedMap::Dilated(d) => d.layer(),
        }
    }

    /// Points the map at its arrays as they are now ([`MapPools::refresh`]); `shadow`: what
    /// became of the shadow map (a derived map reads it).
    fn refresh(&mut self, pools: &MapPools, shadow: Moved) -> Moved {
        match self {
            FattenedMap::Drawn(f) => f.refresh(pools),
            FattenedMap::Dilated(d) => {
                let moved = d.refresh(pools);
                if moved != Moved::No || shadow != Moved::No {
                    d.unbind();
                }
                moved
            }
        }
    }

    /// The map's texture.
    pub fn texture(&self) -> &wgpu::Texture {
        match self {
            FattenedMap::Drawn(f) => f.atlas.texture(),
            FattenedMap::Dilated(d) => d.texture(),
        }
    }

    /// How far behind the fattened surface the caster lies, texel by texel.
    pub fn occluder_offset(&self) -> &wgpu::TextureView {
        match self {
            FattenedMap::Drawn(f) => f.occluder_offset(),
            FattenedMap::Dilated(d) => d.occluder_offset(),
        }
    }

    /// The occluder offsets' array (a stand-in of one texel for a derived map) and this
    /// light's layer of it.
    fn occluder_offset_layer(&self) -> (&wgpu::Texture, u32) {
        match self {
            FattenedMap::Drawn(f) => f.occluder_offset_layer(),
            FattenedMap::Dilated(d) => d.occluder_offset_layer(),
        }
    }
}

impl LightMaps {
    /// GPU memory the maps take, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        self.shadow.allocated_bytes()
            + self.fattened.as_ref().map_or(0, FattenedMap::allocated_bytes)
            + self.exit.as_ref().map_or(0, |exit| exit.atlas.allocated_bytes())
    }

    /// Makes or keeps the maps `chain` needs for a light fitted as `light_view` (its atlas's
    /// tiles and their size); true when any was made (they must then be drawn and bound again).
    pub fn allocate(
        maps: &mut Option<LightMaps>,
        (device, pools): (&CachedDevice<'_>, &mut MapPools),
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
                    m.shadow.resize((device, pools), (settings, grid, tile));
                    if let Some(fattened) = &mut m.fattened {
                        fattened.resize((device, pools), (settings, grid, tile));
                    }
                    if let Some(exit) = &mut m.exit {
                        exit.resize((device, pools), (settings, grid, tile));
                    }
                    made = true;
                }
                m
            }
            _ => {
                made = true;
                maps.insert(LightMaps {
                    shadow: ShadowMapPass::new((device, pools), layouts, (settings, grid, tile)),
                    fattened: None,
                    exit: None,
                    casters: casters.id(),
                })
            }
        };
        let map = (settings, grid, tile);
        let fattened_fits = match &maps.fattened {
            Some(fattened) => chain.fattened_map() && fattened.fits(chain),
            None => !chain.fattened_map(),
        };
        if !fattened_fits {
            maps.fattened = chain
                .fattened_map()
                .then(|| FattenedMap::new((device, pools), layouts, map, chain));
            made = true;
        }
        // The shadow map's pass keeps the exit map where the chain asks it to and its buffer
        // fits the device's storage bindings; otherwise a pass of its own draws it.
        let kept = chain.exit_in_shadow_pass() && exit_in_shadow_pass::fits(device, map);
        made |= maps.shadow.keep_exit((device, pools), layouts, map, kept);
        let drawn = chain.exit_map() && !maps.shadow.keeps_exit();
        if drawn != maps.exit.is_some() {
            maps.exit = drawn.then(|| ExitMapPass::new((device, pools), layouts, map));
            made = true;
        }
        made
    }

    /// Points every map at its array as it is now: where an array was made again for another
    /// light's (its maps copied in, [`Moved::Copied`]) the passes must be bound again, and where
    /// the maps could not be copied ([`Moved::Lost`]) drawn again whole too.
    pub fn refresh(&mut self, pools: &MapPools) -> Moved {
        let shadow = self.shadow.atlas.refresh(pools);
        let mut moved = shadow;
        if let Some(kept) = &mut self.shadow.exit {
            moved = moved.max(kept.refresh(pools));
        }
        if let Some(fattened) = &mut self.fattened {
            moved = moved.max(fattened.refresh(pools, shadow));
        }
        if let Some(exit) = &mut self.exit {
            moved = moved.max(exit.atlas.refresh(pools));
        }
        moved
    }

    /// The exit map, wherever it is drawn.
    pub fn exit_view(&self) -> Option<&wgpu::TextureView> {
        match (&self.shadow.exit, &self.exit) {
            (Some(kept), _) => Some(kept.view()),
            (None, drawn) => drawn.as_ref().map(|exit| exit.atlas.view()),
        }
    }

    /// The layer of [`LightMaps::exit_texture`] that holds this light's exit map.
    pub fn exit_layer(&self) -> Option<u32> {
        match (&self.shadow.exit, &self.exit) {
            (Some(kept), _) => Some(kept.layer()),
            (None, drawn) => drawn.as_ref().map(|exit| exit.atlas.layer()),
        }
    }

    /// The layer of each map in its array ([`MapLayersUniform`], the frame uniform's `maps`):
    /// a map the light lacks reads as the shadow map's layer, whose array stands in for it.
    pub fn layers(&self) -> MapLayersUniform {
        let shadow = self.shadow.atlas.layer();
        let fattened = self.fattened.as_ref();
        MapLayersUniform {
            shadow,
            fattened: fattened.map_or(shadow, FattenedMap::layer),
            occluder_offset: fattened.map_or(shadow, |f| f.occluder_offset_layer().1),
            exit: self.exit_layer().unwrap_or(shadow),
        }
    }

    /// The maps as a screen pass binds them (`arrays`: the arrays whole, each read at the
    /// light's layer, [`LightMaps::layers`]; else 2D views of the light's layers). Only for
    /// maps that share arrays ([`MapPools`]) may `arrays` be set: a texture of its own has no
    /// array view on every backend.
    pub fn screen_views(&self, arrays: bool) -> MapViews {
        let view = |texture: &wgpu::Texture, layer_view: &wgpu::TextureView| {
            if arrays {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    label: Some("LightMaps::screen_views"),
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                })
            } else {
                layer_view.clone()
            }
        };
        let shadow = view(self.shadow.atlas.texture(), self.shadow.atlas.view());
        let fattened = self.fattened.as_ref().map(|f| {
            (
                view(f.texture(), f.view()),
                view(f.occluder_offset_layer().0, f.occluder_offset()),
            )
        });
        let exit = match (self.exit_texture(), self.exit_view()) {
            (Some(texture), Some(layer_view)) => Some(view(texture, layer_view)),
            _ => None,
        };
        MapViews {
            shadow,
            fattened,
            exit,
        }
    }

    /// The textures the maps are layers of (the shadow map, the fattened map, its occluder
    /// offsets, the exit map): lights with the same can be read by one pass
    /// ([`Self::screen_views`] with `arrays`).
    pub fn array_textures(&self) -> [Option<wgpu::Texture>; 4] {
        let fattened = self.fattened.as_ref();
        [
            Some(self.shadow.atlas.texture().clone()),
            fattened.map(|f| f.texture().clone()),
            fattened.map(|f| f.occluder_offset_layer().0.clone()),
            self.exit_texture().cloned(),
        ]
    }

    /// The exit map's texture, wherever it is drawn.
    pub fn exit_texture(&self) -> Option<&wgpu::Texture> {
        match (&self.shadow.exit, &self.exit) {
            (Some(kept), _) => Some(kept.texture()),
            (None, drawn) => drawn.as_ref().map(|exit| exit.atlas.texture()),
        }
    }

    /// Uploads the light's fit (and `spreads`' fatten distance) for the next draw, which
    /// redraws only the tiles (cascades, cube faces) whose bit is set in `tiles` and draws only
    /// the casters on `layers`. A derived fattened map is made again whole.
    pub fn prepare(&mut self, upload: &MapUpload, spreads: &DerivedSpreads, tiles: u32) {
        self.shadow.prepare(upload);
        self.shadow.redraw_only(upload.queue, tiles);
        match &mut self.fattened {
            Some(FattenedMap::Drawn(fattened)) => {
                fattened.prepare(upload, spreads.fatten_distance);
                fattened.atlas.redraw_only(tiles);
            }
            Some(FattenedMap::Dilated(dilated)) => {
                let gpu = (upload.device, upload.queue);
                dilated.prepare(gpu, upload.light, spreads, self.shadow.atlas.view());
            }
            None => {}
        }
        if let Some(exit) = &mut self.exit {
            exit.prepare(upload);
            exit.atlas.redraw_only(tiles);
        }
    }

    /// Bytes a [`FarPlaneFill`] needs to fill the largest of these maps.
    pub fn fill_bytes(&self) -> u64 {
        let fattened = match &self.fattened {
            Some(FattenedMap::Drawn(fattened)) => fattened.atlas.fill_bytes(),
            _ => 0,
        };
        let exit = self.exit.as_ref().map_or(0, |exit| exit.atlas.fill_bytes());
        self.shadow.atlas.fill_bytes().max(fattened).max(exit)
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
        match &self.fattened {
            Some(FattenedMap::Drawn(fattened)) => run(encoder, mark, "fattened shadow map", |e| {
                fattened.encode(e, (casters, fill))
            }),
            Some(FattenedMap::Dilated(dilated)) => {
                run(encoder, mark, "dilated shadow map", |e| dilated.encode(e))
            }
            None => {}
        }
        if let Some(exit) = &self.exit {
            run(encoder, mark, "exit map", |e| exit.encode(e, (casters, fill)));
        }
    }
}
