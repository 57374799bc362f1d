//! How a light's maps lay out their tiles (cascades, cube faces) in one atlas.

use crate::lights::Light;
use crate::settings::CascadeSettings;
use glam::{Mat4, Vec4};

/// How a light's maps lay out their tiles (cascades, cube faces): `cols` x `rows` square tiles
/// of the same size, tile `i` at column `i % cols`, row `i / cols` (row 0 at the top, like
/// texture rows). The maps are `cols` tiles wide and `rows` high.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AtlasGrid {
    /// Tiles across.
    pub cols: u32,
    /// Tiles down.
    pub rows: u32,
}

impl AtlasGrid {
    /// One tile.
    pub const SINGLE: AtlasGrid = AtlasGrid { cols: 1, rows: 1 };

    /// A point light's six cube faces: 3 x 2 tiles, every one used. (A square 3 x 3 atlas
    /// left three unused, half as many texels again to clear and hold.)
    pub const CUBE: AtlasGrid = AtlasGrid { cols: 3, rows: 2 };

    /// `n` x `n` tiles.
    pub const fn square(n: u32) -> AtlasGrid {
        AtlasGrid { cols: n, rows: n }
    }

    /// The smallest grid of at most two columns that holds `count` cascades: 1 x 1, 2 x 1,
    /// then 2 x 2 (a third cascade leaves one tile unused). The maps cost what their texels
    /// do, so a view that needs two cascades draws half a 2 x 2 atlas's.
    pub fn for_cascades(count: u32) -> AtlasGrid {
        match count {
            0 | 1 => AtlasGrid::SINGLE,
            2 => AtlasGrid { cols: 2, rows: 1 },
            _ => AtlasGrid::square(2),
        }
    }

    /// Tiles it holds.
    pub fn tiles(self) -> u32 {
        self.cols * self.rows
    }

    /// Width and height in texels with tiles of `tile` texels a side.
    pub fn size(self, tile: u32) -> (u32, u32) {
        (tile * self.cols.max(1), tile * self.rows.max(1))
    }
}

/// The largest grid a light's maps can take under `cascades`: 2 x 2 for a directional light
/// with two or more cascades, 3 x 2 for a point light's six faces ([`AtlasGrid::CUBE`]), one
/// tile otherwise. A directional light's maps take the grid of the cascades in use
/// ([`AtlasGrid::for_cascades`], [`LightView::grid`](crate::LightView::grid)).
pub fn atlas_grid(light: &Light, cascades: &CascadeSettings) -> AtlasGrid {
    match light {
        Light::Directional(_) if cascades.count > 1 => AtlasGrid::square(2),
        l if l.uses_cube() => AtlasGrid::CUBE,
        _ => AtlasGrid::SINGLE,
    }
}

/// Texels per side of one tile of a light's atlas, for a shadow-map `resolution`: a point
/// light's cube faces take half of it (six of them cost 1.5 maps' texels), other tiles all.
pub fn tile_resolution(light: &Light, resolution: u32) -> u32 {
    match light {
        l if l.uses_cube() => (resolution / 2).max(32),
        _ => resolution,
    }
}

/// Where tile `index` of `grid` lies: clip space of the whole window mapped into the tile.
pub fn tile_matrix(grid: AtlasGrid, index: u32) -> Mat4 {
    if grid.tiles() <= 1 {
        return Mat4::IDENTITY;
    }
    let cols = grid.cols.max(1);
    let (sx, sy) = (1.0 / cols as f32, 1.0 / grid.rows.max(1) as f32);
    let (col, row) = ((index % cols) as f32, (index / cols) as f32);
    Mat4::from_cols(
        Vec4::new(sx, 0.0, 0.0, 0.0),
        Vec4::new(0.0, sy, 0.0, 0.0),
        Vec4::Z,
        Vec4::new(
            -1.0 + sx * (2.0 * col + 1.0),
            1.0 - sy * (2.0 * row + 1.0),
            0.0,
            1.0,
        ),
    )
}

/// The texel rectangle of tile `index` of `grid`, with tiles `tile` texels a side: x, y,
/// width, height.
pub fn tile_viewport(grid: AtlasGrid, index: u32, tile: u32) -> [u32; 4] {
    let cols = grid.cols.max(1);
    let (col, row) = (index % cols, index / cols);
    [col * tile, row * tile, tile, tile]
}
