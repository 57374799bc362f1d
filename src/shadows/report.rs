//! What [`Shadows`](crate::Shadows)(super::Shadows) names its lights by and tells of them: a light's id (its
//! layer), its report of the frame last prepared, and the intermediate textures a debug view
//! reads.

use crate::chain::Chain;
use crate::frame::DerivedSpreads;
use crate::light_space::LightView;
use crate::map_resolution::PenumbraWidths;

/// A light added to [`Shadows`](crate::Shadows); also its layer in [`Shadows::visibility`](crate::Shadows::visibility).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct LightId(pub(super) u32);

impl LightId {
    /// The layer of the visibility array that holds this light's visibility.
    pub fn layer(self) -> u32 {
        self.0
    }
}

/// What one light's frame does, from [`crate::Shadows::prepare`] on (its fit, spreads and
/// chain are known before the frame is encoded); kept until the next prepare.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightReport {
    /// The light reported on.
    pub light: LightId,
    /// The passes its frame ran (a method that needs a light size falls back to hard
    /// shadows under a light without one).
    pub chain: Chain,
    /// False when the shadow map and fattened map were reused from an earlier frame.
    pub shadow_maps_rendered: bool,
    /// Which tiles of the maps were redrawn, one bit per cascade or cube face (bit 0 the
    /// nearest cascade, or the first face); the others kept what an earlier frame drew. 0 when
    /// nothing was redrawn.
    pub tiles_rendered: u32,
    /// The filter spreads the frame used (derived from the light's size in physical mode).
    pub spreads: DerivedSpreads,
    /// The light's projection, fitted to the casters and the view, with its cascades.
    pub light_view: LightView,
    /// Texels a side of one tile of the light's maps as drawn this frame (cascade or cube
    /// face): [`crate::ShadowMapSettings::resolution`] (half of it for a point light's faces),
    /// or a half or a quarter of that with [`crate::MapResolution::FromPenumbra`].
    pub map_resolution: u32,
    /// The penumbra widths last measured for the map resolution
    /// ([`crate::MapResolution::FromPenumbra`] on the compute path; `None` before the first
    /// comes back, and for the other methods).
    pub penumbra_widths: Option<PenumbraWidths>,
    /// A sun's smallest caster in view whose shadow its map cannot hold (narrower than a
    /// texel, typically under a map spread over a ground far wider than the view: set a shadow
    /// distance). `None` when every caster in view has a texel or more, and for other lights.
    pub unheld_caster: Option<crate::light_space::UnheldCaster>,
}

/// An intermediate texture of one light, for debug views.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LightTexture {
    /// Depth of the casters from the light (an atlas of cascades or cube faces).
    ShadowMap,
    /// Depth of the casters fattened by the penumbra's reach (the distance-map method): drawn,
    /// at half the shadow map's resolution; derived ([`crate::Fattening::Dilation`]), RG32F at a
    /// quarter, x the least depth within the reach and y the nearest silhouette's.
    FattenedMap,
    /// Depth of the casters' back faces (the distance-map method).
    ExitMap,
    /// R = distance to the occluder (world units), G = mask (1 inside the fattened shadow, 0
    /// outside, -1 on non-receivers, -2 where nothing was drawn; with the tile classification,
    /// -1 and -2 only on the tiles it kept, the others 0). RG16F. The compute path's holds one
    /// value a pixel (R16F where the device stores half floats, else R32F): the distance
    /// inside the fattened shadow, and elsewhere -0.25 where a shadow can still fall (the
    /// mask's early out off), -1 where none can (its clear value), -2 on non-receivers, -3
    /// where nothing was drawn. [`crate::debug::distance_and_mask`] reads either.
    DistanceMap,
    /// Raw PCF or PCSS visibility (R16F; the compute path's is R32F where the device cannot
    /// store half floats, [`crate::ExecutionSettings::half_intermediates`]). `None` for the
    /// distance-map method where its PCF writes the light's layer ([`crate::Chain::pcf_in_layer`],
    /// unless [`crate::ExecutionSettings::raw_visibility`]).
    Visibility,
    /// Blurred visibility (R16F). After the distance map, the blur writes the light's layer
    /// directly: this is then the whole visibility array ([`Shadows::visibility_texture`](crate::Shadows::visibility_texture)).
    BlurredVisibility,
    /// The tile classification (R8, one texel per 16 x 16 pixel screen tile): 1 where the
    /// distance map ran, 0 where no shadow can fall ([`crate::PenumbraSettings::tiles`]). The
    /// compute path's is R32F, 1 where a tile was listed (every tile with the classification
    /// off), 0.25 where it was listed apart as turned away from the light
    /// ([`crate::PenumbraSettings::skip_tiles_facing_away`]).
    TileClasses,
}

impl LightTexture {
    /// Every texture of a light, in the order its passes make them.
    pub const ALL: [LightTexture; 7] = [
        LightTexture::ShadowMap,
        LightTexture::FattenedMap,
        LightTexture::ExitMap,
        LightTexture::TileClasses,
        LightTexture::DistanceMap,
        LightTexture::Visibility,
        LightTexture::BlurredVisibility,
    ];
}
