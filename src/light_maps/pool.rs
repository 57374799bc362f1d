//! [`MapPools`]: every light's maps of one kind as the layers of one array texture.
//!
//! A light's depth atlas (the shadow map, and the drawn fattened and exit maps) is one layer of
//! an array texture that every light whose atlas has the same label, format and size shares: a
//! pass that draws or reads one light binds a 2D view of its layer (so the light-space passes
//! and the screen-space chains see a texture of their own, as before), and a pass that reads
//! several lights at once can bind the whole array. Lights of another size (another cascade
//! count, or a resolution `crate::MapResolution::FromPenumbra` chose) get an array of their own.
//!
//! An array grows by a layer when a light needs one and none is free: it is made again, each
//! holder keeps its layer number and finds its map's view outdated ([`MapPools::refresh`]): its
//! maps must then be drawn and bound again. A layer is free again once its [`MapSlot`] is
//! dropped; [`MapPools::trim`] then moves the layers above it down and makes the array again
//! without it (those maps are drawn again), and drops an array no map holds, so that the memory
//! follows the lights.
//!
//! Where the device runs no compute passes, or its backend is GL (which cannot bind one layer of
//! an array as a 2D texture), each map keeps a texture of its own.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Weak};

use crate::gpu_helpers::{Target, texture_bytes};

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
    key: PoolKey,
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

/// One array and who holds its layers.
struct Pool {
    key: PoolKey,
    texture: wgpu::Texture,
    /// Layer `i` is taken while `holders[i]` lives (and holds `i`).
    holders: Vec<Weak<AtomicU32>>,
    generation: u64,
}

impl Pool {
    fn free_layer(&self) -> Option<usize> {
        self.holders.iter().position(|h| h.strong_count() == 0)
    }

    fn layer_bytes(&self) -> u64 {
        texture_bytes(&self.texture) / self.holders.len().max(1) as u64
    }
}

/// The arrays every light's maps are layers of ([`MapSlot`]).
pub(crate) struct MapPools {
    /// false: each map a texture of its own.
    share: bool,
    pools: Vec<Pool>,
    /// The last generation handed out (each array made gets the next).
    generation: u64,
}

impl MapPools {
    /// Arrays shared by the lights where `device` runs compute passes (`compute`) and its
    /// backend is not GL; else a texture for each map.
    pub fn new(device: &wgpu::Device, compute: bool) -> Self {
        Self {
            share: compute && device.adapter_info().backend != wgpu::Backend::Gl,
            pools: Vec::new(),
            generation: 0,
        }
    }

    /// Each map a texture of its own (a pass outside [`crate::Shadows`]).
    pub fn unshared() -> Self {
        Self {
            share: false,
            pools: Vec::new(),
            generation: 0,
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
                key,
                generation: 0,
                holder,
            };
        }
        let index = match self.pools.iter().position(|p| p.key == key) {
            Some(i) => i,
            None => {
                self.generation += 1;
                self.pools.push(Pool {
                    key,
                    texture: array_texture(device, key, 1),
                    holders: vec![Weak::new()],
                    generation: self.generation,
                });
                self.pools.len() - 1
            }
        };
        if self.pools[index].free_layer().is_none() {
            let layers = self.pools[index].holders.len() as u32 + 1;
            self.generation += 1;
            let pool = &mut self.pools[index];
            pool.texture = array_texture(device, key, layers);
            pool.holders.resize(layers as usize, Weak::new());
            pool.generation = self.generation;
        }
        let pool = &mut self.pools[index];
        let layer = pool.free_layer().expect("a free layer after growing");
        holder.store(layer as u32, Ordering::Relaxed);
        pool.holders[layer] = Arc::downgrade(&holder);
        MapSlot {
            target: layer_target(pool.texture.clone(), layer as u32),
            layer: layer as u32,
            key,
            generation: pool.generation,
            holder,
        }
    }

    /// The last generation handed out: it changes whenever an array is made.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// Whether `slot`'s view is of its array as it is now.
    pub fn is_current(&self, slot: &MapSlot) -> bool {
        slot.generation == 0
            || self
                .pools
                .iter()
                .find(|p| p.key == slot.key)
                .is_none_or(|p| p.generation == slot.generation)
    }

    /// Points `slot` at its array as it is now; true when the array was made again since (its
    /// map must then be drawn and bound again).
    pub fn refresh(&self, slot: &mut MapSlot) -> bool {
        if slot.generation == 0 {
            return false;
        }
        let Some(pool) = self.pools.iter().find(|p| p.key == slot.key) else {
            return false;
        };
        if pool.generation == slot.generation {
            return false;
        }
        slot.layer = slot.holder.load(Ordering::Relaxed);
        slot.target = layer_target(pool.texture.clone(), slot.layer);
        slot.generation = pool.generation;
        true
    }

    /// Makes each array with free layers again without them, the layers above each moved
    /// down in order, and drops the arrays no map holds a layer of (the holders of an array
    /// made again then see [`MapPools::refresh`] return true).
    pub fn trim(&mut self, device: &wgpu::Device) {
        self.pools
            .retain(|p| p.holders.iter().any(|h| h.strong_count() > 0));
        for pool in &mut self.pools {
            let held: Vec<Arc<AtomicU32>> = pool.holders.iter().filter_map(Weak::upgrade).collect();
            if held.len() == pool.holders.len() {
                continue;
            }
            for (layer, holder) in held.iter().enumerate() {
                holder.store(layer as u32, Ordering::Relaxed);
            }
            pool.holders = held.iter().map(Arc::downgrade).collect();
            pool.texture = array_texture(device, pool.key, held.len() as u32);
            self.generation += 1;
            pool.generation = self.generation;
        }
    }

    /// GPU memory the arrays' layers no map holds take, in bytes (the held ones count with
    /// their maps, [`MapSlot::allocated_bytes`]).
    pub fn unused_bytes(&self) -> u64 {
        self.pools
            .iter()
            .map(|p| {
                let free = p.holders.iter().filter(|h| h.strong_count() == 0).count() as u64;
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
                let held = p.holders.iter().filter(|h| h.strong_count() > 0).count();
                (p.key.label, p.key.size, p.holders.len(), held)
            })
            .collect()
    }
}

/// A 2D texture of `layers` layers for maps of `key`, readable by shaders and copyable out.
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
        usage: key.usage | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC,
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

    fn key(size: u32) -> PoolKey {
        PoolKey {
            label: "test map",
            format: wgpu::TextureFormat::R32Float,
            size: (size, size),
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        }
    }

    #[test]
    fn layers_are_shared_grown_freed_and_trimmed() {
        let gpu = crate::HeadlessGpu::new().expect("a device");
        let device = &gpu.device;
        let mut pools = MapPools {
            share: true,
            pools: Vec::new(),
            generation: 0,
        };
        let mut a = pools.slot(device, key(64));
        assert_eq!((a.layer, pools.layout()), (0, vec![("test map", (64, 64), 1, 1)]));
        // A second map of the same key grows the array; the first keeps its layer and is told.
        let b = pools.slot(device, key(64));
        assert_eq!(b.layer, 1);
        assert_eq!(pools.layout(), vec![("test map", (64, 64), 2, 2)]);
        assert!(pools.refresh(&mut a), "the first map's view is of the old array");
        assert!(!pools.refresh(&mut a));
        assert_eq!(a.target.texture.depth_or_array_layers(), 2);
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
        assert!(pools.refresh(&mut b));
        assert_eq!((b.layer, b.target.texture.depth_or_array_layers()), (0, 1));
        drop(b);
        pools.trim(device);
        assert!(pools.layout().is_empty());
    }

    #[test]
    fn unshared_maps_each_get_a_texture() {
        let gpu = crate::HeadlessGpu::new().expect("a device");
        let mut pools = MapPools::unshared();
        let a = pools.slot(&gpu.device, key(16));
        let b = pools.slot(&gpu.device, key(16));
        assert_eq!((a.layer, b.layer), (0, 0));
        assert_ne!(a.target.texture, b.target.texture);
        assert_eq!(a.target.texture.depth_or_array_layers(), 1);
    }
}
