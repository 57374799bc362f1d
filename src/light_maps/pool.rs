//! [`MapPools`]: every light's maps of one kind as the layers of one array texture.
//!
//! A light's depth atlas (the shadow map, and the drawn fattened and exit maps) is one layer of
//! an array texture that every light whose atlas has the same label, format and size shares: a
//! pass that draws or reads one light binds a 2D view of its layer (so the light-space passes
//! and the screen-space chains see a texture of their own, as before), and a pass that reads
//! several lights at once can bind the whole array. Lights of another size (another cascade
//! count, or a resolution `MapResolution::FromPenumbra` chose) get an array of their own.
//!
//! An array grows when a light needs a layer and none is free: it is made again with half as
//! many layers again, at most 8 more (spare ones for the lights to come, so that lights added
//! one by one make a few arrays, not one each), each map copied into its layer of the new
//! array, and each holder finds its view outdated ([`MapPools::refresh`]): its passes must then
//! be bound again, and the maps are kept. A layer is free again once its [`MapSlot`] is dropped; [`MapPools::trim`] then
//! copies the layers above it one down into an array made without it (or its spare layers), and
//! drops an array no map holds, so that the memory follows the lights. The copies are recorded
//! as the arrays are made and submitted by [`MapPools::flush`], before the frame's passes; an
//! array made again before they are goes without copies of its own (the copies into it go into
//! its successor), so that the arrays between are never used and go at once. A format that
//! cannot be copied (24-bit depth) loses its maps instead: they must be drawn again.
//!
//! Each array made and dropped leaves a hole in the driver's memory blocks that the lights' small
//! buffers then fill, and a block lives while any of them does: on lavapipe, with wgpu's default
//! memory hints, 16 suns added one a frame left 1.7 GB of blocks reserved for 0.25 GB of
//! resources while the arrays grew a layer at a time, 0.75 GB for 0.28 GB growing by half
//! (`docs/limits.md`).
//!
//! An array holds at most [`MAX_ARRAY_BYTES`] (and the device's layer limit): the maps of one
//! kind past that go into another array of the same kind. One array of 256 spots' 2048-texel
//! maps (2 GiB) was more than lavapipe could allocate: the texture came out invalid and every
//! pass on it failed.
//!
//! Where the device runs no compute passes, or its backend is GL (which cannot bind one layer of
//! an array as a 2D texture), each map keeps a texture of its own.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Weak};

use crate::gpu_helpers::{Target, texture_bytes};

/// The most bytes one array holds: 1 GiB. Drivers cap a single allocation (Vulkan's
/// `maxMemoryAllocationSize`, at least 1 GiB by the specification; lavapipe refused 2 GiB), and
/// an array made again copies all of it.
pub(crate) const MAX_ARRAY_BYTES: u64 = 1 << 30;

/// What maps share an array: the same label (the kind of map), format, size and usages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PoolKey {
    pub label: &'static str,
    pub format: wgpu::TextureFormat,
    pub size: (u32, u32),
    pub usage: wgpu::TextureUsages,
}

/// One light's layer of an array, and the 2D view of it that its passes bind.
#[derive(Debug)]
pub(crate) struct MapSlot {
    /// The array's texture and the view of this layer as a 2D texture.
    pub target: Target,
    /// The layer this map holds.
    pub layer: u32,
    /// The array it is a layer of ([`Pool::id`]; 0: a texture of its own).
    pool: u64,
    /// The array's generation the view was made from (0: a texture of its own).
    generation: u64,
    /// The layer the array keeps for this map (it may move it down, [`MapPools::trim`]), held
    /// while the slot lives: the layer is taken while it does.
    holder: Arc<AtomicU32>,
}

impl MapSlot {
    /// GPU memory this map's layer takes, in bytes.
    pub fn allocated_bytes(&self) -> u64 {
        texture_bytes(&self.target.texture) / self.target.texture.depth_or_array_layers().max(1) as u64
    }
}

/// What became of a map's array since its view was made ([`MapPools::refresh`]), the worse
/// last.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Moved {
    /// The view is current.
    No,
    /// The array was made again with the map copied in: bind the new view.
    Copied,
    /// The array was made again without the map's texels (a format that cannot be copied): bind
    /// the new view and draw the map again.
    Lost,
}

/// One array and who holds its layers.
struct Pool {
    key: PoolKey,
    /// Which of the arrays it is (several arrays may share a key, [`MAX_ARRAY_BYTES`]).
    id: u64,
    /// The most layers it may grow to.
    most_layers: u32,
    texture: wgpu::Texture,
    /// Layer `i` is taken while `holders[i]` lives (and holds `i`); `None`: a layer the array
    /// was grown with that no map has taken yet.
    holders: Vec<Option<Weak<AtomicU32>>>,
    generation: u64,
    /// The generation before which the maps' texels were lost (a format copies cannot move).
    lost_before: u64,
}

impl Pool {
    fn free_layer(&self) -> Option<usize> {
        self.holders.iter().position(|h| !held(h))
    }

    fn layer_bytes(&self) -> u64 {
        texture_bytes(&self.texture) / self.holders.len().max(1) as u64
    }
}

/// A layer to copy from an array made again into its successor: (from, to, from layer, to
/// layer).
type LayerCopy = (wgpu::Texture, wgpu::Texture, u32, u32);

/// The arrays every light's maps are layers of ([`MapSlot`]).
pub(crate) struct MapPools {
    /// false: each map a texture of its own.
    share: bool,
    pools: Vec<Pool>,
    /// The last generation handed out (each array made gets the next).
    generation: u64,
    /// The copies the arrays made again since the last [`MapPools::flush`] need.
    copies: Vec<LayerCopy>,
    /// The most bytes an array holds ([`MAX_ARRAY_BYTES`]).
    max_array_bytes: u64,
}

impl MapPools {
    /// Arrays shared by the lights where `device` runs compute passes (`compute`) and its
    /// backend is not GL; else a texture for each map.
    pub fn new(device: &wgpu::Device, compute: bool) -> Self {
        Self {
            share: compute && device.adapter_info().backend != wgpu::Backend::Gl,
            pools: Vec::new(),
            generation: 0,
            copies: Vec::new(),
            max_array_bytes: MAX_ARRAY_BYTES,
        }
    }

    /// Each map a texture of its own (a pass outside the shadows, the reference's).
    pub fn unshared() -> Self {
        Self {
            share: false,
            pools: Vec::new(),
            generation: 0,
            copies: Vec::new(),
            max_array_bytes: MAX_ARRAY_BYTES,
        }
    }

    /// A layer for a map of `key`: a free one of its array, or one more (the array made again;
    /// the other holders then see [`MapPools::refresh`] return true).
    pub fn slot(&mut self, device: &wgpu::Device, key: PoolKey) -> MapSlot {
        let holder = Arc::new(AtomicU32::new(0));
        if !self.share {
            let texture = array_texture(device, key, 1);
            return MapSlot {
                target: layer_target(texture, 0),
                layer: 0,
                pool: 0,
                generation: 0,
                holder,
            };
        }
        // An array of the key with a free layer, or one that may grow, or a new one.
        let fits =
            |p: &Pool| p.key == key && (p.free_layer().is_some() || p.holders.len() < p.most_layers as usize);
        let index = match self
            .pools
            .iter()
            .position(|p| p.key == key && p.free_layer().is_some())
        {
            Some(i) => i,
            None => match self.pools.iter().position(fits) {
                Some(i) => i,
                None => {
                    self.generation += 1;
                    self.pools.push(Pool {
                        key,
                        id: self.generation,
                        most_layers: most_layers(device, key, self.max_array_bytes),
                        texture: array_texture(device, key, 1),
                        holders: vec![None],
                        generation: self.generation,
                        lost_before: 0,
                    });
                    self.pools.len() - 1
                }
            },
        };
        if self.pools[index].free_layer().is_none() {
            let held = self.pools[index].holders.len() as u32;
            let layers = grown(held).min(self.pools[index].most_layers);
            self.generation += 1;
            let pool = &mut self.pools[index];
            let texture = array_texture(device, key, layers);
            // Every layer is held (none was free): each keeps its number.
            let moves: Vec<(u32, u32)> = (0..held).map(|l| (l, l)).collect();
            move_layers(pool, texture, &moves, self.generation, &mut self.copies);
            pool.holders.resize(layers as usize, None);
        }
        let pool = &mut self.pools[index];
        let layer = pool.free_layer().expect("a free layer after growing");
        holder.store(layer as u32, Ordering::Relaxed);
        pool.holders[layer] = Some(Arc::downgrade(&holder));
        MapSlot {
            target: layer_target(pool.texture.clone(), layer as u32),
            layer: layer as u32,
            pool: pool.id,
            generation: pool.generation,
            holder,
        }
    }

    /// Whether the maps share arrays: their screen passes can then read them as arrays
    /// ([`crate::light_maps::LightMaps::screen_views`]).
    pub fn shares(&self) -> bool {
        self.share
    }

    /// The last generation handed out: it changes whenever an array is made.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Records the copies of the arrays made again since the last flush, in order, and
    /// submits them: call it before the frame's passes are submitted.
    pub fn flush(&mut self, device: &wgpu::Device, queue: &wgpu::Queue) {
        if self.copies.is_empty() {
            return;
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("MapPools::copies"),
        });
        for (from, to, from_layer, to_layer) in self.copies.drain(..) {
            let at = |texture, layer| wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: 0, z: layer },
                aspect: wgpu::TextureAspect::All,
            };
            let size = wgpu::Extent3d {
                depth_or_array_layers: 1,
                ..from.size()
            };
            encoder.copy_texture_to_texture(at(&from, from_layer), at(&to, to_layer), size);
        }
        queue.submit([encoder.finish()]);
    }

    /// Points `slot` at its array as it is now, and says what became of its map since.
    pub fn refresh(&self, slot: &mut MapSlot) -> Moved {
        if slot.generation == 0 {
            return Moved::No;
        }
        let Some(pool) = self.pools.iter().find(|p| p.id == slot.pool) else {
            return Moved::No;
        };
        if pool.generation == slot.generation {
            return Moved::No;
        }
        let lost = slot.generation < pool.lost_before;
        slot.layer = slot.holder.load(Ordering::Relaxed);
        slot.target = layer_target(pool.texture.clone(), slot.layer);
        slot.generation = pool.generation;
        if lost { Moved::Lost } else { Moved::Copied }
    }

    /// Makes each array with free layers again without them, the layers above each moved
    /// down in order, and drops the arrays no map holds a layer of (the holders of an array
    /// made again then see [`MapPools::refresh`] return true).
    pub fn trim(&mut self, device: &wgpu::Device) {
        self.pools.retain(|p| p.holders.iter().any(held));
        for pool in &mut self.pools {
            // Only a layer a map gave back makes the array again: the layers it was grown with
            // are kept for the lights to come.
            if !pool.holders.iter().flatten().any(|h| h.strong_count() == 0) {
                continue;
            }
            let held: Vec<Arc<AtomicU32>> = pool.holders.iter().flatten().filter_map(Weak::upgrade).collect();
            let mut moves = Vec::new();
            for (layer, holder) in held.iter().enumerate() {
                moves.push((holder.swap(layer as u32, Ordering::Relaxed), layer as u32));
            }
            pool.holders = held.iter().map(|h| Some(Arc::downgrade(h))).collect();
            self.generation += 1;
            let texture = array_texture(device, pool.key, held.len() as u32);
            move_layers(pool, texture, &moves, self.generation, &mut self.copies);
        }
    }

    /// GPU memory the arrays' layers no map holds take, in bytes (the held ones count with
    /// their maps, [`MapSlot::allocated_bytes`]).
    pub fn unused_bytes(&self) -> u64 {
        self.pools
            .iter()
            .map(|p| {
                let free = p.holders.iter().filter(|h| !held(h)).count() as u64;
                free * p.layer_bytes()
            })
            .sum()
    }

    /// How many arrays hold how many layers each, for tests: (label, size, layers, held).
    #[cfg(all(test, feature = "renderer"))]
    fn layout(&self) -> Vec<(&'static str, (u32, u32), usize, usize)> {
        self.pools
            .iter()
            .map(|p| {
                let taken = p.holders.iter().filter(|h| held(h)).count();
                (p.key.label, p.key.size, p.holders.len(), taken)
            })
            .collect()
    }
}

/// Whether a map holds the layer of `holder`.
fn held(holder: &Option<Weak<AtomicU32>>) -> bool {
    holder.as_ref().is_some_and(|h| h.strong_count() > 0)
}

/// The layers an array of `held` layers, every one taken, is made again with: half as many
/// again, at least one more and at most 8 (at most 8 spare layers, each a light's map, where a
/// light is added: 16 suns added one by one make arrays of 2, 3, 5, 8, 12 and 18 layers).
fn grown(held: u32) -> u32 {
    held + held.div_ceil(2).clamp(1, 8)
}

/// The most layers an array of `key` may have: as many as `max_bytes` hold, within the device's
/// limit, at least one.
fn most_layers(device: &wgpu::Device, key: PoolKey, max_bytes: u64) -> u32 {
    let (block_width, block_height) = key.format.block_dimensions();
    let blocks = u64::from(key.size.0.max(1).div_ceil(block_width))
        * u64::from(key.size.1.max(1).div_ceil(block_height));
    let bytes = (blocks * u64::from(crate::gpu_helpers::block_bytes(key.format))).max(1);
    let by_bytes = (max_bytes / bytes).min(u64::from(u32::MAX)) as u32;
    by_bytes.min(device.limits().max_texture_array_layers).max(1)
}

/// Whether `format`'s texels can be copied between textures (24-bit depth cannot).
fn copyable(format: wgpu::TextureFormat) -> bool {
    !matches!(
        format,
        wgpu::TextureFormat::Depth24Plus | wgpu::TextureFormat::Depth24PlusStencil8
    )
}

/// Makes `texture` `pool`'s array of generation `generation`, its layers moved as `moves` says
/// ((from, to) layer numbers), the copies pushed on `copies` (or the texels lost where the
/// format cannot be copied).
fn move_layers(
    pool: &mut Pool,
    texture: wgpu::Texture,
    moves: &[(u32, u32)],
    generation: u64,
    copies: &mut Vec<LayerCopy>,
) {
    if copyable(pool.key.format) {
        if copies.iter().any(|c| c.1 == pool.texture) {
            // The array replaced was made since the last flush: no pass has drawn into it yet,
            // and its texels are the copies into it still to be made. Those go straight into
            // the new array, so that only the arrays of the last flush and the newest live.
            copies.retain_mut(|(_, to, _, to_layer)| {
                if *to != pool.texture {
                    return true;
                }
                match moves.iter().find(|m| m.0 == *to_layer) {
                    Some(&(_, moved_to)) => {
                        (*to, *to_layer) = (texture.clone(), moved_to);
                        true
                    }
                    None => false,
                }
            });
        } else {
            for &(from, to) in moves {
                copies.push((pool.texture.clone(), texture.clone(), from, to));
            }
        }
    } else {
        pool.lost_before = generation;
    }
    pool.texture = texture;
    pool.generation = generation;
}

/// A 2D texture of `layers` layers for maps of `key`, readable by shaders, copyable out and
/// into (from the array it succeeds).
fn array_texture(device: &wgpu::Device, key: PoolKey, layers: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(key.label),
        size: wgpu::Extent3d {
            width: key.size.0.max(1),
            height: key.size.1.max(1),
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: key.format,
        usage: key.usage
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    })
}

/// `texture` and a view of its layer `layer` as a 2D texture.
fn layer_target(texture: wgpu::Texture, layer: u32) -> Target {
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2),
        base_array_layer: layer,
        array_layer_count: Some(1),
        ..Default::default()
    });
    Target { texture, view }
}

#[cfg(all(test, feature = "renderer"))]
mod tests {
    use super::*;

    /// A device of the adapter the environment names (as the crate's headless GPU picks it),
    /// and its queue.
    fn device() -> (wgpu::Device, wgpu::Queue) {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle().with_env());
        let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(
            &instance, None,
        ))
        .expect("an adapter");
        pollster::block_on(adapter.request_device(&Default::default())).expect("a device")
    }

    /// Arrays shared as on a device with compute passes.
    fn shared() -> MapPools {
        MapPools {
            share: true,
            pools: Vec::new(),
            generation: 0,
            copies: Vec::new(),
            max_array_bytes: MAX_ARRAY_BYTES,
        }
    }

    fn key(size: u32) -> PoolKey {
        PoolKey {
            label: "test map",
            format: wgpu::TextureFormat::R32Float,
            size: (size, size),
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        }
    }

    /// Maps of one key past what an array may hold go into a second array of that key, each
    /// map told its own array's changes only.
    #[test]
    fn maps_past_an_arrays_bytes_go_into_another_array() {
        let (device, queue) = &device();
        let mut pools = shared();
        // Three layers of 64 x 64 32-bit texels an array.
        pools.max_array_bytes = 3 * 64 * 64 * 4;
        let mut slots: Vec<MapSlot> = (0..5).map(|_| pools.slot(device, key(64))).collect();
        assert_eq!(
            pools.layout(),
            vec![("test map", (64, 64), 3, 3), ("test map", (64, 64), 2, 2)]
        );
        pools.flush(device, queue);
        let layers: Vec<(u32, Moved)> = slots.iter_mut().map(|s| (s.layer, pools.refresh(s))).collect();
        // The first three were told of the first array's growth, the last two of the second's
        // (the fourth saw it grow to two layers).
        assert_eq!(
            layers,
            vec![
                (0, Moved::Copied),
                (1, Moved::Copied),
                (2, Moved::No),
                (0, Moved::Copied),
                (1, Moved::No)
            ]
        );
        assert!(slots[0].target.texture != slots[3].target.texture, "two arrays");
        assert!(slots[0].target.texture == slots[2].target.texture);
        // A map given back in the first array frees a layer there, which the next map takes.
        slots.remove(1);
        pools.trim(device);
        assert_eq!(
            pools.layout(),
            vec![("test map", (64, 64), 2, 2), ("test map", (64, 64), 2, 2)]
        );
        let sixth = pools.slot(device, key(64));
        assert_eq!(
            pools.layout(),
            vec![("test map", (64, 64), 3, 3), ("test map", (64, 64), 2, 2)]
        );
        assert_eq!(sixth.layer, 2);
    }

    #[test]
    fn layers_are_shared_grown_freed_and_trimmed() {
        let (device, queue) = &device();
        let mut pools = shared();
        let mut a = pools.slot(device, key(64));
        assert_eq!((a.layer, pools.layout()), (0, vec![("test map", (64, 64), 1, 1)]));
        // A second map of the same key grows the array; the first keeps its layer and is told.
        let b = pools.slot(device, key(64));
        assert_eq!(b.layer, 1);
        assert_eq!(pools.layout(), vec![("test map", (64, 64), 2, 2)]);
        assert_eq!(
            pools.refresh(&mut a),
            Moved::Copied,
            "the first map's view is of the old array"
        );
        assert_eq!(pools.refresh(&mut a), Moved::No);
        assert_eq!(
            pools.copies.len(),
            1,
            "the first map's layer copied into the new array"
        );
        assert_eq!(a.target.texture.depth_or_array_layers(), 2);
        pools.flush(device, queue);
        // Another size: an array of its own.
        let c = pools.slot(device, key(32));
        assert_eq!(c.layer, 0);
        assert_eq!(pools.layout().len(), 2);
        // A dropped map frees its layer for the next, without growing.
        drop(a);
        assert_eq!(pools.unused_bytes(), 64 * 64 * 4);
        let d = pools.slot(device, key(64));
        assert_eq!(d.layer, 0);
        assert_eq!(pools.layout()[0], ("test map", (64, 64), 2, 2));
        assert_eq!((d.allocated_bytes(), pools.unused_bytes()), (64 * 64 * 4, 0));
        // Trimming drops an array none holds, and moves the layers above a free one down.
        drop(c);
        drop(d);
        let mut b = b;
        pools.trim(device);
        assert_eq!(pools.layout(), vec![("test map", (64, 64), 1, 1)]);
        assert_eq!(pools.unused_bytes(), 0);
        assert_eq!(pools.refresh(&mut b), Moved::Copied);
        assert_eq!((b.layer, b.target.texture.depth_or_array_layers()), (0, 1));
        let (_, _, from, to) = pools.copies.last().unwrap();
        assert_eq!((*from, *to), (1, 0), "the second map's layer moved down");
        drop(b);
        pools.trim(device);
        assert!(pools.layout().is_empty());
    }

    #[test]
    fn an_array_grows_by_half_keeps_its_spare_layers_and_copies_once_a_flush() {
        let (device, queue) = &device();
        let mut pools = shared();
        let mut maps = vec![pools.slot(device, key(16)), pools.slot(device, key(16))];
        pools.flush(device, queue);
        let flushed = pools.pools[0].texture.clone();
        // Five more maps before the next flush: the array made 3, 5 and 8 layers deep (half as
        // many again each time), the two maps of the flushed array copied straight into the
        // last, none out of the arrays between.
        for _ in 0..5 {
            maps.push(pools.slot(device, key(16)));
        }
        assert_eq!(pools.layout(), vec![("test map", (16, 16), 8, 7)]);
        let newest = pools.pools[0].texture.clone();
        let copies: Vec<(bool, bool, u32, u32)> = pools
            .copies
            .iter()
            .map(|(from, to, f, t)| (*from == flushed, *to == newest, *f, *t))
            .collect();
        assert_eq!(copies, vec![(true, true, 0, 0), (true, true, 1, 1)]);
        for map in &mut maps {
            assert_ne!(pools.refresh(map), Moved::Lost);
            assert_eq!(map.target.texture, newest);
        }
        let layers: Vec<u32> = maps.iter().map(|m| m.layer).collect();
        assert_eq!(layers, (0..7).collect::<Vec<_>>());
        pools.flush(device, queue);
        // The spare layer stays through a trim and takes the next map without growing.
        assert_eq!(pools.unused_bytes(), 16 * 16 * 4);
        pools.trim(device);
        assert_eq!(pools.layout(), vec![("test map", (16, 16), 8, 7)]);
        maps.push(pools.slot(device, key(16)));
        assert_eq!((maps[7].layer, pools.unused_bytes()), (7, 0));
        // A map given back makes the array again as deep as its maps, the layers above moved
        // down.
        maps.remove(3);
        pools.trim(device);
        assert_eq!(pools.layout(), vec![("test map", (16, 16), 7, 7)]);
        for (i, map) in maps.iter_mut().enumerate() {
            pools.refresh(map);
            assert_eq!(map.layer, i as u32);
        }
        let moved: Vec<(u32, u32)> = pools.copies.iter().map(|c| (c.2, c.3)).collect();
        assert_eq!(
            moved,
            [0, 1, 2, 4, 5, 6, 7].into_iter().zip(0..7).collect::<Vec<_>>()
        );
    }

    #[test]
    fn maps_of_a_format_that_cannot_be_copied_are_lost_when_their_array_grows() {
        let (device, _) = &device();
        let mut pools = shared();
        let depth24 = PoolKey {
            format: wgpu::TextureFormat::Depth24Plus,
            ..key(64)
        };
        let mut a = pools.slot(device, depth24);
        let _b = pools.slot(device, depth24);
        assert_eq!(pools.refresh(&mut a), Moved::Lost);
        assert!(pools.copies.is_empty());
    }

    #[test]
    fn unshared_maps_each_get_a_texture() {
        let (device, _) = device();
        let mut pools = MapPools::unshared();
        let a = pools.slot(&device, key(16));
        let b = pools.slot(&device, key(16));
        assert_eq!((a.layer, b.layer), (0, 0));
        assert_ne!(a.target.texture, b.target.texture);
        assert_eq!(a.target.texture.depth_or_array_layers(), 1);
    }
}
