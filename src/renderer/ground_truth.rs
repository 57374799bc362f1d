//! The ground truth, kept apart from the real-time chain: each area light replaced by N point
//! lights on it, one hard shadow map each, the hard visibilities averaged per pixel (weighted
//! as [`crate::light_samples`] says) by
//! [`crate::light_maps::ReferencePass`], one average per light of the scene. The convenience [`crate::Renderer`] drives it
//! ([`crate::Renderer::render_reference`]); [`crate::Shadows`] never does.

use super::depth_prepass::DepthPrepass;
use super::gpu_scene::GpuScene;
use super::reference::{GeometricNormals, ReferencePass};
use crate::bounds::Aabb;
use crate::camera::Camera;
use crate::error::Result;
use crate::gpu_helpers::Target;
use crate::light_maps::{MapPools, MapUpload, ShadowMapPass};
use crate::light_samples::{Emitter, light_sample};
use crate::light_space::{AtlasGrid, CUBE_AXES, FitInputs, LightView, atlas_grid, tile_resolution};
use crate::lights::Light;
use crate::settings::{ShadowMapSettings, ShadowSettings};
use crate::view::CameraMatrices;
use glam::Vec3;

/// How far a progressive reference has come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReferenceProgress {
    /// Light samples averaged so far.
    pub done: u32,
    /// Light samples the settings ask for.
    pub total: u32,
}

impl ReferenceProgress {
    /// True once every sample the settings ask for has been averaged (`done >= total`).
    pub fn is_complete(&self) -> bool {
        self.done >= self.total
    }
}

/// What a progressive reference's average depends on.
#[derive(Debug, Clone, PartialEq)]
struct ReferenceKey {
    camera: Camera,
    lights: Vec<Light>,
    scene: (u64, u64, u64),
    size: (u32, u32),
    settings: ShadowSettings,
}

/// What one accumulation step reads: the scene and view, the camera's frame uniform (already
/// written) and the prepass that gives the camera depth.
pub(crate) struct SampleInputs<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub scene: &'a GpuScene,
    pub camera: &'a Camera,
    pub settings: &'a ShadowSettings,
    pub size: (u32, u32),
    pub frame: &'a wgpu::Buffer,
    pub prepass: &'a DepthPrepass,
}

/// The shadow-map resolution the reference renders `light`'s samples at, for the real-time
/// maps' `resolution`. A point light's cube faces get twice the real-time faces' texels a side
/// (the whole `resolution` a face) as far as their 3 x 2 atlas fits the device's `max_side`: a
/// face spans 90 degrees, so at the real-time size a penumbra at contact is only a texel or two
/// wide, and every sample's hard edge, quantized to those texels, widened the reference's
/// (`docs/reference.md`). Suns' and spots' maps are fitted to the view and keep `resolution`.
pub(crate) fn sample_resolution(light: &Light, resolution: u32, max_side: u32) -> u32 {
    match light {
        l if l.uses_cube() => {
            // Six faces in a 3 x 2 atlas: three across.
            let face_limit = (max_side / 3).max(1);
            // The largest power of two that fits, as the settings' resolutions are.
            let face = resolution.min(1 << face_limit.ilog2());
            (2 * face).max(resolution)
        }
        _ => resolution,
    }
}

/// Every face of a cube map, as bits in [`CUBE_AXES`]' order.
const ALL_FACES: u32 = (1 << 6) - 1;

/// The cube faces (bits in [`CUBE_AXES`]' order) that a point of `region` can fall in as seen
/// from `source`, by the rule the reference's shader picks a face with (`cube_face`: the axis
/// along which the point lies farthest). A face holds the points whose coordinate along its
/// axis is at least the absolute value of the other two; it is left out only when the whole of
/// `region` lies on the wrong side of one of the four planes through `source` that bound it, so
/// no face a point of `region` falls in is ever left out. An empty region keeps every face.
fn faces_holding(source: Vec3, region: &Aabb) -> u32 {
    if region.is_empty() {
        return ALL_FACES;
    }
    let (low, high) = (region.min - source, region.max - source);
    // The largest value of `n . p` over the box.
    let largest = |n: Vec3| (n * low).max(n * high).element_sum();
    let scale = low.abs().max(high.abs()).max_element();
    let tolerance = 1e-4 * scale;
    let mut faces = 0;
    for (face, axis) in CUBE_AXES.iter().enumerate() {
        let across = [Vec3::X, Vec3::Y, Vec3::Z]
            .into_iter()
            .filter(|e| e.dot(*axis) == 0.0);
        let holds = across
            .flat_map(|e| [*axis - e, *axis + e])
            .all(|n| largest(n) >= -tolerance);
        if holds {
            faces |= 1 << face;
        }
    }
    faces
}

/// The part of the scene `camera` can see, as a box: its frustum's corners (an infinite far
/// plane stopped beyond the scene's farthest corner) within the scene's bounds, grown by a
/// hundredth of its size and a thousandth of its farthest view distance: more than the
/// reference's offset of each receiver toward the light (2e-4 of its view distance).
fn seen_region(camera: &CameraMatrices, scene: &Aabb) -> Aabb {
    if scene.is_empty() {
        return Aabb::EMPTY;
    }
    let eye = camera.view.inverse().w_axis.truncate();
    let beyond = scene
        .corners()
        .iter()
        .map(|c| c.distance(eye))
        .fold(0.0, f32::max)
        * 1.01
        + 1.0;
    let frustum = Aabb::from_points(&camera.frustum_corners(0.0, beyond));
    let region = frustum.intersection(scene);
    if region.is_empty() {
        return region;
    }
    let grow = Vec3::splat(0.01 * (region.max - region.min).max_element() + 1e-3 * beyond);
    Aabb {
        min: region.min - grow,
        max: region.max + grow,
    }
}

/// What a light's map pass was made for: its atlas, the casters and the map settings.
type MapKey = (AtlasGrid, u32, u64, ShadowMapSettings);

/// The reference's running means, one per light (the key light first), and what they were
/// averaged for.
pub(crate) struct GroundTruth {
    passes: Vec<ReferencePass>,
    /// Each light's map pass, its atlas made for the light's kind, rendered once per sample.
    maps: Vec<(ShadowMapPass, MapKey)>,
    frame_size: usize,
    size: (u32, u32),
    key: Option<ReferenceKey>,
    /// Every light's mean, one layer each, as the composite binds them (copied from the passes).
    array: Option<Target>,
    /// The receivers' triangle normals, drawn after the prepass (made on the first step, with
    /// the scene's layouts).
    normals: Option<GeometricNormals>,
    /// The pipelines the lights' map passes share.
    pipelines: crate::pipeline_cache::PipelineCache,
}

impl GroundTruth {
    pub fn new(device: &wgpu::Device, frame_size: usize, size: (u32, u32)) -> Self {
        let mut truth = Self {
            passes: Vec::new(),
            maps: Vec::new(),
            frame_size,
            size,
            key: None,
            array: None,
            normals: None,
            pipelines: crate::pipeline_cache::PipelineCache::new(device),
        };
        truth.ensure_lights(device, 1);
        truth
    }

    /// One average per light.
    fn ensure_lights(&mut self, device: &wgpu::Device, count: usize) {
        self.passes.truncate(count.max(1));
        while self.passes.len() < count {
            let mut pass = ReferencePass::new(device, self.frame_size);
            pass.resize(device, self.size.0, self.size.1);
            self.passes.push(pass);
        }
    }

    pub fn resize(&mut self, device: &wgpu::Device, width: u32, height: u32) {
        self.size = (width, height);
        for pass in &mut self.passes {
            pass.resize(device, width, height);
        }
        self.array = None;
        self.key = None;
    }

    /// Forgets the average: the next step starts again.
    pub fn restart(&mut self) {
        self.key = None;
    }

    /// Every light's mean so far, one layer each in the lights' order, as a 2D-array view (how
    /// the composite binds visibility); the copies are recorded in `encoder`.
    pub fn visibility_array(
        &mut self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
    ) -> wgpu::TextureView {
        let layers = self.passes.len() as u32;
        let size = wgpu::Extent3d {
            width: self.size.0.max(1),
            height: self.size.1.max(1),
            depth_or_array_layers: layers,
        };
        if self.array.as_ref().is_none_or(|a| a.texture.size() != size) {
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("GroundTruth::visibility_array"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: self.passes[0].visibility_texture().format(),
                usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                view_formats: &[],
            });
            let view = texture.create_view(&wgpu::TextureViewDescriptor {
                label: Some("GroundTruth::visibility_array"),
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            });
            self.array = Some(Target { texture, view });
        }
        let Target { texture: array, view } = self.array.as_ref().expect("made above");
        for (layer, pass) in self.passes.iter().enumerate() {
            let source = pass.visibility_texture();
            encoder.copy_texture_to_texture(
                source.as_image_copy(),
                wgpu::TexelCopyTextureInfo {
                    texture: array,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: 0,
                        z: layer as u32,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::Extent3d {
                    depth_or_array_layers: 1,
                    ..size
                },
            );
        }
        view.clone()
    }

    /// The key light's mean so far.
    pub fn visibility_texture(&self) -> &wgpu::Texture {
        self.passes[0].visibility_texture()
    }

    /// Samples averaged so far, per light.
    pub fn progress(&self, total: u32) -> ReferenceProgress {
        ReferenceProgress {
            done: self.passes[0].accumulated(),
            total,
        }
    }

    /// Adds up to `max_samples` more light samples to the mean, restarting it when the camera,
    /// light, scene, size or settings differ from the last call. Each sample is submitted on its
    /// own, so memory does not grow with the count; `progress(done, total)` follows each.
    pub fn accumulate(
        &mut self,
        inputs: SampleInputs,
        max_samples: u32,
        progress: &mut dyn FnMut(u32, u32),
    ) -> Result<()> {
        let SampleInputs {
            device,
            queue,
            scene,
            camera,
            settings,
            size,
            frame,
            prepass,
        } = inputs;
        let lights: Vec<Light> = std::iter::once(*scene.light())
            .chain(scene.more_lights().iter().copied())
            .collect();
        let total = settings.reference.samples;
        let key = ReferenceKey {
            camera: *camera,
            lights: lights.clone(),
            scene: scene.revision(),
            size,
            settings: *settings,
        };
        self.ensure_lights(device, lights.len());
        let device = &crate::pipeline_cache::CachedDevice::new(device, &self.pipelines);
        let max_side = device.limits().max_texture_dimension_2d;
        let sample_maps: Vec<ShadowMapSettings> = lights
            .iter()
            .map(|light| ShadowMapSettings {
                resolution: sample_resolution(light, settings.shadow_map.resolution, max_side),
                // The truth does not inherit a real-time map's precision.
                depth_format: crate::settings::DepthFormat::Depth32,
                ..settings.shadow_map
            })
            .collect();
        self.maps.truncate(lights.len());
        for (i, (light, sm)) in lights.iter().zip(&sample_maps).enumerate() {
            let sm = *sm;
            let (grid, tile) = (
                atlas_grid(light, &sm.cascades),
                tile_resolution(light, sm.resolution),
            );
            let wanted = (grid, tile, scene.casters().id(), sm);
            if self.maps.get(i).is_some_and(|(_, key)| *key == wanted) {
                continue;
            }
            let map = (
                ShadowMapPass::new(
                    (device, &mut MapPools::unshared()),
                    scene.casters().layouts(),
                    (&sm, grid, tile),
                ),
                wanted,
            );
            if i < self.maps.len() {
                self.maps[i] = map;
            } else {
                self.maps.push(map);
            }
        }
        let normals = self
            .normals
            .get_or_insert_with(|| GeometricNormals::new(device, scene.casters().layouts(), self.frame_size));
        normals.prepare(device, frame, size.0, size.1);
        for (pass, (map, _)) in self.passes.iter_mut().zip(&self.maps) {
            pass.bind(device, frame, prepass.depth(), map.atlas.view(), normals.view());
        }
        if self.key.as_ref() != Some(&key) {
            let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reference: depth prepass"),
            });
            prepass.encode(&mut encoder, scene);
            normals.encode(&mut encoder, scene, prepass.depth());
            queue.submit([encoder.finish()]);
            for pass in &mut self.passes {
                pass.reset();
            }
            self.key = Some(key);
        }
        let casters = scene.casters();
        let matrices = CameraMatrices::from_camera(camera, size.0 as f32 / size.1.max(1) as f32);
        // Each caster's and receiver's box, for a spot's near and far planes as the real-time
        // maps take them. The whole scene's box alone put a spot inside a room at its nearest
        // wall: the desk under the room's monitor lay before the near plane and cast nothing.
        let parts = scene.shadow_parts();
        // A point light's sample draws only the cube faces a point the camera sees can fall in
        // (the others keep what they held, which no pixel reads).
        let seen = seen_region(&matrices, &scene.bounds());
        let first = self.passes[0].accumulated();
        let last = first.saturating_add(max_samples).min(total);
        for k in first..last {
            // Sample k of every light, so the averages stay in step.
            for (((light, sm), pass), (shadow_map, _)) in lights
                .iter()
                .zip(&sample_maps)
                .zip(&mut self.passes)
                .zip(&mut self.maps)
            {
                let sample = light_sample(light, k, total);
                // The map fitted to what the camera sees, in cascades like the real-time maps'
                // (unsnapped: each sample is rendered once).
                let view = LightView::fit_with(&FitInputs {
                    light: &sample,
                    casters: scene.caster_bounds(),
                    casters_and_receivers: scene.shadow_bounds(),
                    parts: &parts,
                    margin: 0.0,
                    fit: sm.fit,
                    camera: Some(matrices),
                    resolution: sm.resolution,
                    snap_to_texels: false,
                    cascades: sm.cascades,
                });
                // The map keeps the largest grid the light can need (square), whatever the
                // cascades in use: their tiles lie at the same columns and rows in it.
                let view = LightView {
                    grid: shadow_map.atlas.grid,
                    ..view
                };
                let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("reference: sample"),
                });
                let layers = crate::casters::ALL_LAYERS;
                shadow_map.prepare(&MapUpload {
                    device,
                    queue,
                    casters,
                    light: &view,
                    layers,
                });
                if let (true, Some(source)) = (light.uses_cube(), sample.position()) {
                    shadow_map.atlas.redraw_only(faces_holding(source, &seen));
                }
                shadow_map.encode(&mut encoder, (casters, None));
                pass.accumulate(&mut encoder, queue, &view, &Emitter::of(light));
                queue.submit([encoder.finish()]);
            }
            if k % 16 == 15 {
                crate::error::wait_for_gpu(device, "rendering the reference")?;
            }
            progress(k + 1, total);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lights::{PointLight, SpotLight};
    use glam::Vec3;

    /// The face `cube_face` (shaders/common/cube.wgsl) picks for `v`.
    fn cube_face(v: Vec3) -> usize {
        let a = v.abs();
        if a.x >= a.y && a.x >= a.z {
            return if v.x >= 0.0 { 0 } else { 1 };
        }
        if a.y >= a.z {
            return if v.y >= 0.0 { 2 } else { 3 };
        }
        if v.z >= 0.0 { 4 } else { 5 }
    }

    /// Every point of a box falls in a face the box's mask keeps, and a box below the light
    /// keeps only the faces it reaches.
    #[test]
    fn a_sample_keeps_every_face_a_point_of_the_seen_region_falls_in() {
        let source = Vec3::new(0.3, 2.0, -0.4);
        // Straight below, narrower than its depth: the lower face alone.
        let below = Aabb {
            min: Vec3::new(-0.5, 0.0, -1.0),
            max: Vec3::new(1.0, 0.5, 0.2),
        };
        assert_eq!(faces_holding(source, &below), 1 << 3);
        // Around the light: every face.
        let around = Aabb {
            min: Vec3::splat(-4.0),
            max: Vec3::splat(4.0),
        };
        assert_eq!(faces_holding(source, &around), ALL_FACES);
        assert_eq!(faces_holding(source, &Aabb::EMPTY), ALL_FACES);
        // Boxes of every size and place: each point's face is kept.
        let mut seed = 7u32;
        let mut next = move || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut fewer = 0;
        for _ in 0..400 {
            let a = Vec3::new(next(), next(), next()) * 8.0 - 4.0;
            let size = Vec3::new(next(), next(), next()) * 3.0;
            let region = Aabb {
                min: a,
                max: a + size,
            };
            let faces = faces_holding(source, &region);
            fewer += usize::from(faces != ALL_FACES);
            for _ in 0..64 {
                let t = Vec3::new(next(), next(), next());
                let p = region.min + (region.max - region.min) * t;
                let face = cube_face(p - source);
                assert!(
                    faces & (1 << face) != 0,
                    "{p} in face {face}, not in {faces:#b} of {region:?}"
                );
            }
        }
        // The mask leaves faces out of most boxes that do not surround the light.
        assert!(fewer > 200, "only {fewer} of 400 boxes left a face out");
    }

    #[test]
    fn a_point_lights_samples_get_twice_the_faces_the_atlas_allowing() {
        let point = Light::Point(PointLight {
            position: Vec3::Y,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        // Faces of 1024 texels in real time, 2048 for the reference (its atlas 6144 a side).
        assert_eq!(sample_resolution(&point, 2048, 8192), 4096);
        assert_eq!(
            tile_resolution(&point, sample_resolution(&point, 2048, 8192)),
            2048
        );
        assert_eq!(sample_resolution(&point, 512, 8192), 1024);
        // No face larger than a third of the device's limit.
        assert_eq!(sample_resolution(&point, 2048, 4096), 2048);
        let spot = Light::Spot(SpotLight {
            position: Vec3::Y,
            direction: Vec3::NEG_Y,
            cone_angle_deg: 40.0,
            radius: 0.2,
            color: Vec3::ONE,
            intensity: 1.0,
            range: None,
        });
        assert_eq!(sample_resolution(&spot, 2048, 8192), 2048);
    }
}
