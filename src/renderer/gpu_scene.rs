//! A [`Scene`] uploaded to the GPU: one vertex buffer per attribute stream (so the depth-only
//! passes read positions alone), instance transforms in a dynamic-offset uniform buffer, and one
//! bind group per material.

use glam::{Mat4, Vec3, Vec4};
use wgpu::util::DeviceExt;

use crate::bounds::Aabb;
use crate::error::{PenumbraError, Result};
use crate::layouts::{MaterialUniform, SceneLayouts, SurfaceUniform};
use crate::lights::{Exposure, Light};
use crate::scene::{
    AlphaMode, FilterMode, LightingMode, LightmapFilter, LightmapImage, Scene, Shading, TextureSampler,
    WrapMode,
};

/// One mesh's vertex streams.
pub struct GpuMesh {
    pub positions: wgpu::Buffer,
    pub normals: wgpu::Buffer,
    pub uvs: wgpu::Buffer,
    /// The second UV set (zeros when the mesh has none).
    pub lightmap_uvs: wgpu::Buffer,
    /// Vertex colours (white when the mesh has none).
    pub colors: wgpu::Buffer,
    /// Tangents (zeros when the mesh has none: no normal mapping).
    pub tangents: wgpu::Buffer,
    pub smoothed_normals: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub index_count: u32,
}

/// A drawable instance: which mesh and material, its place among the casters, and its flags.
#[derive(Debug, Clone, Copy)]
pub struct GpuInstance {
    pub mesh: usize,
    pub material: usize,
    pub id: crate::casters::InstanceId,
    pub caster: bool,
    pub receiver: bool,
    pub masked: bool,
    /// Drawn blended, after the opaque instances ([`GpuScene::draw_blended`]).
    pub blended: bool,
    /// The mesh's bounding-box centre, in its own frame (for sorting blended instances).
    pub center: Vec3,
    /// Where it is now.
    pub transform: Mat4,
}

/// A scene on the GPU. Made once per scene; the light can be changed with [`GpuScene::set_light`].
///
/// ```no_run
/// # fn main() -> penumbra::Result<()> {
/// use glam::{Mat4, Vec3};
/// use penumbra::{Camera, GpuScene, Material, Mesh, Renderer, Scene, ShadowSettings};
///
/// // A scene built in code: a 4 x 4 floor and a 1 x 1 card one unit above it.
/// let quad = |name: &str, half: f32| {
///     let corners = [(-half, -half), (half, -half), (half, half), (-half, half)];
///     let positions = corners.map(|(x, z)| Vec3::new(x, 0.0, z)).to_vec();
///     Mesh::new(name, positions, None, None, vec![0, 2, 1, 0, 3, 2])
/// };
/// let mut scene = Scene::default();
/// let floor = scene.add_mesh(quad("floor", 2.0)?);
/// let card = scene.add_mesh(quad("card", 0.5)?);
/// let grey = scene.add_material(Material::colored("grey", [0.8, 0.8, 0.8]));
/// scene.add_instance(floor, grey, Mat4::IDENTITY);
/// scene.add_instance(card, grey, Mat4::from_translation(Vec3::Y));
///
/// let gpu = penumbra::HeadlessGpu::new()?;
/// let format = wgpu::TextureFormat::Rgba8UnormSrgb;
/// let mut renderer = Renderer::new(&gpu.device, format, ShadowSettings::default())?;
/// // Uploaded once, with the layouts of the renderer that draws it.
/// let mut gpu_scene = GpuScene::new(&gpu.device, &gpu.queue, renderer.layouts(), &scene)?;
/// assert_eq!(gpu_scene.instances.len(), 2);
///
/// // Moving instance 1 (the card) uploads its transform alone.
/// gpu_scene.set_transform(&gpu.queue, 1, Mat4::from_translation(Vec3::new(0.5, 1.5, 0.0)))?;
/// let camera = Camera::look_at(Vec3::new(0.0, 3.0, 5.0), Vec3::ZERO);
/// let image = penumbra::render_to_image(&gpu, &mut renderer, &gpu_scene, &camera, 320, 240)?;
/// assert_eq!(image.dimensions(), (320, 240));
/// # Ok(()) }
/// ```
pub struct GpuScene {
    /// Bumped when the light changes.
    light_revision: u64,
    /// The scene's meshes' vertex and index buffers, in the order of [`Scene::meshes`].
    pub meshes: Vec<GpuMesh>,
    /// One bind group per material (its uniform, base colour texture and sampler), in the
    /// order of [`Scene::materials`].
    pub materials: Vec<wgpu::BindGroup>,
    /// The drawable instances, in the order of [`Scene::instances`] (the index that
    /// [`GpuScene::set_transform`] takes).
    pub instances: Vec<GpuInstance>,
    /// The instances' transforms and flags, and the casters drawn from the light: the same
    /// registry an engine fills through [`crate::Casters`].
    casters: crate::casters::Casters,
    light: Light,
    /// The scene's further lights.
    more_lights: Vec<Light>,
    ambient: Vec3,
    bounds: Aabb,
    triangle_count: usize,
    lightmaps: GpuLightmaps,
    /// Per instance: its lightmap in the current lighting mode (group 3 of the lit passes).
    lightmap_groups: Vec<wgpu::BindGroup>,
    lighting: LightingMode,
    lightmap_exposure: f32,
    lightmap_filter: LightmapFilter,
    /// The camera's exposure for the lights.
    exposure: Exposure,
}

/// What an instance's material adds in the lit passes, as the surface group binds it: its
/// occlusion, emissive, metallic-roughness and normal textures and their uniform rows.
struct InstanceSurface {
    /// A linear view (white when the material has none).
    view: wgpu::TextureView,
    /// The material's sampler.
    sampler: wgpu::Sampler,
    /// [`SurfaceUniform::occlusion`] and [`SurfaceUniform::occlusion_transform`].
    params: [f32; 4],
    transform: [[f32; 4]; 2],
    /// The material's emissive texture (sRGB view; white when none) and light.
    emissive_view: wgpu::TextureView,
    emissive: [f32; 4],
    /// The metallic-roughness and normal textures (linear views; white and flat when none).
    metallic_roughness_view: wgpu::TextureView,
    normal_view: wgpu::TextureView,
    /// [`SurfaceUniform::shading`].
    shading: [f32; 4],
}

/// An atlas and a rectangle of it (min xy, max xy).
type AtlasRect = (usize, [f32; 4]);

/// What the lit passes add to each instance: the scene's lightmap atlases on the GPU, which
/// instance samples which, per mode, and each instance's occlusion texture.
struct GpuLightmaps {
    layout: wgpu::BindGroupLayout,
    /// RGBA16F, one per atlas.
    atlases: Vec<wgpu::TextureView>,
    /// What instances without a lightmap bind.
    black: wgpu::TextureView,
    sampler: wgpu::Sampler,
    /// Per instance, for mixed and for baked lighting: the atlas and its rectangle (min, max).
    assigned: Vec<[Option<AtlasRect>; 2]>,
    /// Per instance.
    uniforms: Vec<wgpu::Buffer>,
    /// Per instance: its material's occlusion, emissive, metallic-roughness and normal
    /// textures, the material's sampler, and the uniform's rows for them.
    surfaces: Vec<InstanceSurface>,
}

/// The vertex streams a camera pass of [`GpuScene::draw`] binds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CameraStreams {
    /// Positions (slot 0) and uvs (slot 1): depth passes that alpha-test.
    PositionUv,
    /// Positions, shading normals, uvs, lightmap uvs, colours and tangents (slots 0 to 5), and
    /// the instance's surface (lightmap, textures) at group 3: lit passes.
    Lit,
}

impl GpuScene {
    /// Validates and uploads `scene`.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &SceneLayouts,
        scene: &Scene,
    ) -> Result<Self> {
        PenumbraError::scoped(
            device,
            || "uploading the scene".into(),
            || Self::new_now(device, queue, layouts, scene),
        )
    }

    fn new_now(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layouts: &SceneLayouts,
        scene: &Scene,
    ) -> Result<Self> {
        scene.validate()?;
        let meshes: Vec<GpuMesh> = scene
            .meshes
            .iter()
            .map(|mesh| upload_mesh(device, mesh))
            .collect();

        let tex = SceneTextures::upload(device, queue, scene)?;
        let materials = scene
            .materials
            .iter()
            .map(|m| material_group(device, layouts, m, &tex))
            .collect();

        let (casters, instances) = add_casters(device, queue, layouts, scene, &meshes, &tex)?;
        let lightmaps = GpuLightmaps {
            layout: layouts.surface.clone(),
            atlases: scene
                .lightmaps
                .iter()
                .map(|l| upload_lightmap(device, queue, &l.image))
                .collect::<Result<_>>()?,
            black: upload_lightmap(
                device,
                queue,
                &LightmapImage::with_finite_texels("no lightmap", 1, 1, vec![[0.0; 3]]),
            )?,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("GpuScene::lightmap_sampler"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                // Between the levels a file has (trilinear); one level: the full size.
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            assigned: (0..scene.instances.len())
                .map(|k| {
                    [LightingMode::Mixed, LightingMode::Baked].map(|mode| {
                        scene
                            .lightmap_of(k, mode)
                            .map(|(atlas, r)| (atlas, [r.min.x, r.min.y, r.max.x, r.max.y]))
                    })
                })
                .collect(),
            surfaces: scene
                .instances
                .iter()
                .map(|inst| instance_surface(&scene.materials[inst.material], &tex))
                .collect(),
            uniforms: (0..scene.instances.len())
                .map(|_| {
                    crate::gpu_helpers::uniform_buffer(
                        device,
                        "GpuScene::surface",
                        size_of::<SurfaceUniform>() as u64,
                    )
                })
                .collect(),
        };
        let mut gpu_scene = Self {
            lightmaps,
            lightmap_groups: Vec::new(),
            lighting: LightingMode::Dynamic,
            lightmap_exposure: 1.0,
            lightmap_filter: scene.lightmap_filter,
            exposure: scene.exposure,
            light_revision: 0,
            meshes,
            materials,
            instances,
            casters,
            light: scene.light,
            more_lights: scene.more_lights.clone(),
            ambient: scene.ambient,
            bounds: scene.bounds(),
            triangle_count: scene
                .instances
                .iter()
                .map(|i| scene.meshes[i.mesh].triangle_count())
                .sum(),
        };
        gpu_scene.set_lighting(device, queue, scene.lighting, scene.lightmap_exposure)?;
        Ok(gpu_scene)
    }

    /// How the scene is lit now, and the lightmaps' exposure.
    pub fn lighting(&self) -> (LightingMode, f32) {
        (self.lighting, self.lightmap_exposure)
    }

    /// True when some instance has a lightmap for `mode`.
    pub fn has_lightmaps(&self, mode: LightingMode) -> bool {
        let slot = match mode {
            LightingMode::Dynamic => return false,
            LightingMode::Mixed => 0,
            LightingMode::Baked => 1,
        };
        self.lightmaps.assigned.iter().any(|a| a[slot].is_some())
    }

    /// True when the lit passes must sample lightmaps or occlusion textures: some instance has
    /// a lightmap in the current mode, or a material an occlusion texture. Otherwise they use
    /// pipelines that leave both out.
    pub fn samples_surface_maps(&self) -> bool {
        let l = &self.lightmaps;
        self.has_lightmaps(self.lighting)
            || l.surfaces.iter().any(|o| {
                o.params[0] > 0.0
                    || o.emissive[..3].iter().any(|c| *c > 0.0)
                    || o.shading[2] > 0.0
                    || o.shading[3] != 0.0
            })
    }

    /// The camera's exposure for the lights ([`crate::Scene::exposure`]).
    pub fn exposure(&self) -> Exposure {
        self.exposure
    }

    /// Sets the camera's exposure for the lights (validated).
    pub fn set_exposure(&mut self, exposure: Exposure) -> Result<()> {
        exposure.validate()?;
        self.exposure = exposure;
        Ok(())
    }

    /// How lightmaps are read between their texels now.
    pub fn lightmap_filter(&self) -> LightmapFilter {
        self.lightmap_filter
    }

    /// Switches how lightmaps are read between their texels (bilinear or bicubic).
    pub fn set_lightmap_filter(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        filter: LightmapFilter,
    ) -> Result<()> {
        self.lightmap_filter = filter;
        self.set_lighting(device, queue, self.lighting, self.lightmap_exposure)
    }

    /// Switches the lighting mode and the lightmaps' exposure (finite, >= 0). Instances with no
    /// lightmap for the mode are lit dynamically.
    pub fn set_lighting(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mode: LightingMode,
        exposure: f32,
    ) -> Result<()> {
        if !(exposure >= 0.0 && exposure.is_finite()) {
            return Err(PenumbraError::Scene(format!(
                "lightmap exposure {exposure} must be finite and >= 0"
            )));
        }
        let bicubic = (self.lightmap_filter == LightmapFilter::Bicubic) as u32 as f32;
        let l = &self.lightmaps;
        self.lightmap_groups = l
            .assigned
            .iter()
            .zip(&l.uniforms)
            .zip(&l.surfaces)
            .map(|((assigned, buffer), surface)| {
                let (code, slot) = match mode {
                    LightingMode::Dynamic => (0.0, None),
                    LightingMode::Mixed => (1.0, assigned[0]),
                    LightingMode::Baked => (2.0, assigned[1]),
                };
                let uniform = match slot {
                    Some((_, rect)) => SurfaceUniform {
                        rect,
                        params: [exposure, code, bicubic, 0.0],
                        occlusion: surface.params,
                        occlusion_transform: surface.transform,
                        emissive: surface.emissive,
                        shading: surface.shading,
                    },
                    None => SurfaceUniform {
                        occlusion: surface.params,
                        occlusion_transform: surface.transform,
                        emissive: surface.emissive,
                        shading: surface.shading,
                        ..Default::default()
                    },
                };
                queue.write_buffer(buffer, 0, bytemuck::bytes_of(&uniform));
                let view = slot.map_or(&l.black, |(atlas, _)| &l.atlases[atlas]);
                crate::gpu_helpers::bind_group(
                    device,
                    "GpuScene::surface",
                    &l.layout,
                    &[
                        &buffer,
                        view,
                        &l.sampler,
                        &surface.view,
                        &surface.sampler,
                        &surface.emissive_view,
                        &surface.metallic_roughness_view,
                        &surface.normal_view,
                    ],
                )
            })
            .collect();
        self.lighting = mode;
        self.lightmap_exposure = exposure;
        Ok(())
    }

    /// The key light ([`Scene::light`]): the one the reference, the error metrics and the
    /// debug views measure.
    pub fn light(&self) -> &Light {
        &self.light
    }

    /// Replaces the light (validated).
    pub fn set_light(&mut self, light: Light) -> Result<()> {
        light.validate()?;
        if light != self.light {
            self.light = light;
            self.light_revision += 1;
        }
        Ok(())
    }

    /// The further lights beside the key light ([`GpuScene::light`]).
    pub fn more_lights(&self) -> &[Light] {
        &self.more_lights
    }

    /// Replaces the further lights (each validated; at most [`crate::MAX_LIGHTS`] lights in all).
    pub fn set_more_lights(&mut self, lights: Vec<Light>) -> Result<()> {
        crate::scene::check_light_count(1 + lights.len())?;
        for light in &lights {
            light.validate()?;
        }
        if lights != self.more_lights {
            self.more_lights = lights;
            self.light_revision += 1;
        }
        Ok(())
    }

    /// Moves instance `index` (in the scene's order): only its instance data is uploaded, and
    /// the shadow maps are re-rendered only by lights that see the change.
    pub fn set_transform(&mut self, queue: &wgpu::Queue, index: usize, transform: Mat4) -> Result<()> {
        let instance = self.instances.get(index).ok_or_else(|| {
            PenumbraError::input(
                format!("instance {index}"),
                format!("the scene has {} instances", self.instances.len()),
            )
        })?;
        self.casters.set_transform(queue, instance.id, transform)?;
        self.instances[index].transform = transform;
        Ok(())
    }

    /// (casters id, casters revision, light revision): changes whenever anything the shadow
    /// maps or the reference depend on changes.
    pub fn revision(&self) -> (u64, u64, u64) {
        (self.casters.id(), self.casters.revision(), self.light_revision)
    }

    /// The instances as shadow casters and receivers.
    pub fn casters(&self) -> &crate::casters::Casters {
        &self.casters
    }

    /// Draws every instance with `streams` into `pass`, whose group 0 is set: instance data at
    /// group 1, material at group 2.
    pub(crate) fn draw(&self, pass: &mut wgpu::RenderPass<'_>, streams: CameraStreams) {
        let opaque = (0..self.instances.len()).filter(|&k| !self.instances[k].blended);
        self.draw_instances(pass, streams, opaque);
    }

    /// Draws the opaque and alpha-masked instances (not the blended ones) whose material is
    /// alpha-masked (`masked` true) or not (false): a depth pass draws each kind with its own
    /// pipeline.
    pub(crate) fn draw_masked(&self, pass: &mut wgpu::RenderPass<'_>, streams: CameraStreams, masked: bool) {
        let kind = (0..self.instances.len())
            .filter(|&k| !self.instances[k].blended && self.instances[k].masked == masked);
        self.draw_instances(pass, streams, kind);
    }

    /// True when some instance is drawn blended.
    pub(crate) fn has_blended(&self) -> bool {
        self.instances.iter().any(|i| i.blended)
    }

    /// Draws the blended instances with the lit streams, farthest from `eye` first.
    pub(crate) fn draw_blended(&self, pass: &mut wgpu::RenderPass<'_>, eye: Vec3) {
        let distance = |k: usize| {
            let inst = &self.instances[k];
            inst.transform.transform_point3(inst.center).distance_squared(eye)
        };
        let mut blended: Vec<usize> = (0..self.instances.len())
            .filter(|&k| self.instances[k].blended)
            .collect();
        blended.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)));
        self.draw_instances(pass, CameraStreams::Lit, blended.into_iter());
    }

    fn draw_instances(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        streams: CameraStreams,
        order: impl Iterator<Item = usize>,
    ) {
        for index in order {
            let inst = &self.instances[index];
            let mesh = &self.meshes[inst.mesh];
            let Some(offset) = self.casters.offset(inst.id) else {
                continue;
            };
            if mesh.index_count == 0 {
                continue;
            }
            pass.set_bind_group(1, self.casters.bind_group(), &[offset]);
            pass.set_bind_group(2, &self.materials[inst.material], &[]);
            pass.set_vertex_buffer(0, mesh.positions.slice(..));
            match streams {
                CameraStreams::PositionUv => pass.set_vertex_buffer(1, mesh.uvs.slice(..)),
                CameraStreams::Lit => {
                    pass.set_vertex_buffer(1, mesh.normals.slice(..));
                    pass.set_vertex_buffer(2, mesh.uvs.slice(..));
                    pass.set_vertex_buffer(3, mesh.lightmap_uvs.slice(..));
                    pass.set_vertex_buffer(4, mesh.colors.slice(..));
                    pass.set_vertex_buffer(5, mesh.tangents.slice(..));
                    pass.set_bind_group(3, &self.lightmap_groups[index], &[]);
                }
            }
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..1);
        }
    }

    /// The scene's constant ambient light ([`Scene::ambient`], linear RGB), added unshadowed to
    /// surfaces that have no lightmap in the current lighting mode; not scaled by the exposure.
    pub fn ambient(&self) -> Vec3 {
        self.ambient
    }

    /// What the light's projection is fitted around: casters and receivers.
    pub fn shadow_bounds(&self) -> Aabb {
        self.casters.shadow_bounds()
    }

    /// World bounds of each instance that casts or receives shadows: the light's near and far
    /// planes enclose the parts of these inside its frustum.
    pub fn shadow_parts(&self) -> Vec<Aabb> {
        self.casters.shadow_parts()
    }

    /// The scene's bounds as loaded (for framing cameras).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// World bounds of the instances that cast shadows, where they are now (moves included).
    pub fn caster_bounds(&self) -> Aabb {
        self.casters.caster_bounds()
    }

    /// World bounds of each caster instance.
    pub(crate) fn caster_parts(&self) -> Vec<Aabb> {
        self.casters.caster_parts()
    }

    /// Triangles drawn per camera pass.
    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }
}

/// One mesh's vertex and index buffers.
fn upload_mesh(device: &wgpu::Device, mesh: &crate::scene::Mesh) -> GpuMesh {
    let make = |label: &str, contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage,
        })
    };
    let vertex = wgpu::BufferUsages::VERTEX;
    // wgpu rejects zero-sized vertex buffers being bound; pad empty meshes.
    let pad = |bytes: &[u8]| {
        if bytes.is_empty() {
            vec![0u8; 16]
        } else {
            bytes.to_vec()
        }
    };
    // A stream a mesh may lack: its own `count` values (bytes `own`), one per
    // vertex, or `fallback` (one vertex's bytes) for every vertex.
    fn bytes<T: bytemuck::Pod>(values: &[T]) -> (&[u8], usize) {
        (bytemuck::cast_slice(values), values.len())
    }
    let optional = |label, (own, count): (&[u8], usize), fallback: &[u8]| {
        if count == mesh.positions.len() {
            make(label, &pad(own), vertex)
        } else {
            make(label, &pad(&fallback.repeat(mesh.positions.len())), vertex)
        }
    };
    GpuMesh {
        positions: make(
            "GpuMesh::positions",
            &pad(bytemuck::cast_slice(&mesh.positions)),
            vertex,
        ),
        normals: make(
            "GpuMesh::normals",
            &pad(bytemuck::cast_slice(&mesh.normals)),
            vertex,
        ),
        uvs: make("GpuMesh::uvs", &pad(bytemuck::cast_slice(&mesh.uvs)), vertex),
        lightmap_uvs: optional("GpuMesh::lightmap_uvs", bytes(&mesh.lightmap_uvs), &[0u8; 8]),
        colors: optional(
            "GpuMesh::colors",
            bytes(&mesh.colors),
            bytemuck::bytes_of(&Vec4::ONE),
        ),
        tangents: optional("GpuMesh::tangents", bytes(&mesh.tangents), &[0u8; 16]),
        smoothed_normals: make(
            "GpuMesh::smoothed_normals",
            &pad(bytemuck::cast_slice(&mesh.smoothed_normals)),
            vertex,
        ),
        indices: make(
            "GpuMesh::indices",
            &pad(bytemuck::cast_slice(&mesh.indices)),
            wgpu::BufferUsages::INDEX,
        ),
        index_count: mesh.indices.len() as u32,
    }
}

/// The scene's samplers and textures, and the stand-ins for a texture a material lacks.
struct SceneTextures {
    samplers: std::collections::HashMap<TextureSampler, wgpu::Sampler>,
    /// Each texture as sRGB, and as linear data where a material reads data from it.
    textures: Vec<(wgpu::TextureView, Option<wgpu::TextureView>)>,
    /// A white texel, sRGB and linear.
    white: (wgpu::TextureView, Option<wgpu::TextureView>),
    /// A normal map's "no change".
    flat_normal: wgpu::TextureView,
}

impl SceneTextures {
    fn upload(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Result<Self> {
        // One sampler per distinct setting (glTF's samplers).
        let mut samplers: std::collections::HashMap<TextureSampler, wgpu::Sampler> = Default::default();
        for m in &scene.materials {
            samplers
                .entry(m.sampler)
                .or_insert_with(|| make_sampler(device, &m.sampler));
        }
        let max_side = device.limits().max_texture_dimension_2d;
        // Each texture as sRGB (base colour) and, when a material reads data from it (occlusion,
        // metallic-roughness, normals), as linear data too (a second upload: view formats are
        // not on every backend).
        let data_textures: std::collections::HashSet<usize> = scene
            .materials
            .iter()
            .flat_map(|m| {
                [
                    m.occlusion_texture,
                    m.metallic_roughness_texture,
                    m.normal_texture,
                ]
            })
            .flatten()
            .collect();
        let textures: Vec<(wgpu::TextureView, Option<wgpu::TextureView>)> = scene
            .textures
            .iter()
            .enumerate()
            .map(|(k, t)| {
                if t.width > max_side || t.height > max_side {
                    return Err(PenumbraError::Texture {
                        name: t.name.clone(),
                        reason: format!("{}x{} exceeds the device limit of {max_side}", t.width, t.height),
                    });
                }
                let upload =
                    |format| upload_texture(device, queue, &t.name, t.width, t.height, &t.rgba8, format);
                Ok((
                    upload(wgpu::TextureFormat::Rgba8UnormSrgb),
                    data_textures
                        .contains(&k)
                        .then(|| upload(wgpu::TextureFormat::Rgba8Unorm)),
                ))
            })
            .collect::<Result<_>>()?;
        let white = upload_texture(
            device,
            queue,
            "white",
            1,
            1,
            &[255; 4],
            wgpu::TextureFormat::Rgba8Unorm,
        );
        let white = (white.clone(), Some(white));
        // A normal map's "no change": (0.5, 0.5, 1) is the unperturbed normal.
        let flat_normal = upload_texture(
            device,
            queue,
            "flat normal",
            1,
            1,
            &[128, 128, 255, 255],
            wgpu::TextureFormat::Rgba8Unorm,
        );
        Ok(Self {
            samplers,
            textures,
            white,
            flat_normal,
        })
    }

    /// The sRGB view of texture `t`, or white.
    fn srgb(&self, t: Option<usize>) -> &wgpu::TextureView {
        t.map_or(&self.white.0, |t| &self.textures[t].0)
    }
}

/// A material's bind group: its uniform, its base colour texture and sampler.
fn material_group(
    device: &wgpu::Device,
    layouts: &SceneLayouts,
    m: &crate::scene::Material,
    tex: &SceneTextures,
) -> wgpu::BindGroup {
    let uniform = MaterialUniform {
        base_color: m.base_color.to_array(),
        alpha: [
            match m.alpha_mode {
                AlphaMode::Opaque | AlphaMode::Blend => -1.0,
                AlphaMode::Mask { cutoff } => cutoff,
            },
            if m.alpha_mode == AlphaMode::Blend {
                1.0
            } else {
                0.0
            },
            0.0,
            0.0,
        ],
    };
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("GpuScene::material"),
        contents: bytemuck::bytes_of(&uniform),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let view = tex.srgb(m.base_color_texture);
    let sampler = &tex.samplers[&m.sampler];
    crate::gpu_helpers::bind_group(
        device,
        "GpuScene::material",
        &layouts.material,
        &[&buffer, view, sampler],
    )
}

/// The scene's meshes as casters and its instances placed among them.
fn add_casters(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    layouts: &SceneLayouts,
    scene: &Scene,
    meshes: &[GpuMesh],
    tex: &SceneTextures,
) -> Result<(crate::casters::Casters, Vec<GpuInstance>)> {
    let mut casters = crate::casters::Casters::with_layouts(device, layouts.clone());
    let mesh_ids: Vec<crate::casters::MeshId> = scene
        .meshes
        .iter()
        .zip(meshes)
        .map(|(mesh, gpu): (&crate::scene::Mesh, &GpuMesh)| {
            casters.add_prepared_mesh(
                &mesh.name,
                &gpu.positions,
                &gpu.smoothed_normals,
                &gpu.indices,
                (gpu.index_count, mesh.vertex_count() as u32),
                mesh.bounds,
                crate::casters::normals::outward_winding(
                    &mesh.positions,
                    &mesh.indices,
                    &mesh.smoothed_normals,
                ),
            )
        })
        .collect();
    let mut instances = Vec::with_capacity(scene.instances.len());
    for inst in &scene.instances {
        let placed = crate::casters::CasterInstance {
            mesh: mesh_ids[inst.mesh],
            transform: inst.transform,
            caster: inst.caster,
            receiver: inst.receiver,
        };
        let material = &scene.materials[inst.material];
        let id = match material.alpha_mode.shadow_cutoff() {
            Some(cutoff) => {
                let mesh: &GpuMesh = &meshes[inst.mesh];
                let mask = crate::casters::AlphaMask {
                    uvs: crate::casters::VertexStream {
                        buffer: &mesh.uvs,
                        offset: 0,
                        stride: 8,
                        format: wgpu::VertexFormat::Float32x2,
                    },
                    texture: tex.srgb(material.base_color_texture),
                    alpha_factor: material.base_color.w,
                    cutoff,
                };
                casters.add_masked_instance(device, queue, placed, &mask)?
            }
            None => casters.add_instance(device, queue, placed)?,
        };
        instances.push(GpuInstance {
            mesh: inst.mesh,
            material: inst.material,
            id,
            caster: inst.caster,
            receiver: inst.receiver,
            masked: material.is_masked(),
            blended: material.alpha_mode == AlphaMode::Blend,
            center: scene.meshes[inst.mesh].bounds.center(),
            transform: inst.transform,
        });
    }
    Ok((casters, instances))
}

/// What the lit pass reads of material `m` beside its lightmap.
fn instance_surface(m: &crate::scene::Material, tex: &SceneTextures) -> InstanceSurface {
    let view = m
        .occlusion_texture
        .and_then(|t| tex.textures[t].1.as_ref())
        .or(tex.white.1.as_ref())
        .expect("white has a linear view");
    let strength = if m.occlusion_texture.is_some() {
        m.occlusion_strength
    } else {
        0.0
    };
    let t = m.occlusion_uv_transform;
    // The emissive texture is sRGB, like the base colour's.
    let emissive_view = tex.srgb(m.emissive_texture);
    let linear = |t: Option<usize>, none: &wgpu::TextureView| {
        t.and_then(|t| tex.textures[t].1.clone())
            .unwrap_or_else(|| none.clone())
    };
    let white_linear = tex.white.1.as_ref().expect("white has a linear view");
    let (model, metallic, roughness) = match m.shading {
        Shading::Lambert => (0.0, 0.0, 1.0),
        Shading::MetallicRoughness { metallic, roughness } => (1.0, metallic, roughness),
    };
    let normal_scale = if m.normal_texture.is_some() {
        m.normal_scale
    } else {
        0.0
    };
    InstanceSurface {
        metallic_roughness_view: linear(m.metallic_roughness_texture, white_linear),
        normal_view: linear(m.normal_texture, &tex.flat_normal),
        shading: [metallic, roughness, model, normal_scale],
        view: view.clone(),
        sampler: tex.samplers[&m.sampler].clone(),
        emissive_view: emissive_view.clone(),
        emissive: [m.emissive.x, m.emissive.y, m.emissive.z, 0.0],
        params: [strength, m.occlusion_uv_set as f32, 0.0, 0.0],
        transform: [
            [t.matrix2.x_axis.x, t.matrix2.y_axis.x, t.translation.x, 0.0],
            [t.matrix2.x_axis.y, t.matrix2.y_axis.y, t.translation.y, 0.0],
        ],
    }
}

/// One mip level of a lightmap: its texels and its size.
type MipLevel<'a> = (&'a [[f32; 3]], (u32, u32));

/// A lightmap as an RGBA16F texture (one level), checked against the device's size limit.
fn upload_lightmap(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    image: &LightmapImage,
) -> Result<wgpu::TextureView> {
    let max_side = device.limits().max_texture_dimension_2d;
    if image.width > max_side || image.height > max_side || image.width == 0 || image.height == 0 {
        return Err(PenumbraError::Texture {
            name: image.name.clone(),
            reason: format!(
                "{}x{} is empty or exceeds the device limit of {max_side}",
                image.width, image.height
            ),
        });
    }
    let levels: Vec<MipLevel> = std::iter::once(&image.rgb)
        .chain(&image.mips)
        .enumerate()
        .map(|(i, texels)| (texels.as_slice(), image.level_size(i)))
        .collect();
    let full_chain = 32 - image.width.max(image.height).leading_zeros() as usize;
    if levels.len() > full_chain {
        return Err(PenumbraError::Texture {
            name: image.name.clone(),
            reason: format!(
                "{} levels, a {}x{} image has at most {full_chain}",
                levels.len(),
                image.width,
                image.height
            ),
        });
    }
    for (i, (texels, (w, h))) in levels.iter().enumerate() {
        if texels.len() != *w as usize * *h as usize {
            return Err(PenumbraError::Texture {
                name: image.name.clone(),
                reason: format!("level {i} holds {} texels, {w}x{h} need {}", texels.len(), w * h),
            });
        }
    }
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(&image.name),
        size: wgpu::Extent3d {
            width: image.width,
            height: image.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba16Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (level, (texels, (w, h))) in levels.iter().enumerate() {
        let halfs: Vec<u16> = texels
            .iter()
            .flat_map(|t| [t[0], t[1], t[2], 1.0].map(|c| half::f16::from_f32(c).to_bits()))
            .collect();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(&halfs),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 8),
                rows_per_image: Some(*h),
            },
            wgpu::Extent3d {
                width: *w,
                height: *h,
                depth_or_array_layers: 1,
            },
        );
    }
    Ok(texture.create_view(&Default::default()))
}

/// The wgpu sampler for `s`.
fn make_sampler(device: &wgpu::Device, s: &TextureSampler) -> wgpu::Sampler {
    let wrap = |w: WrapMode| match w {
        WrapMode::Repeat => wgpu::AddressMode::Repeat,
        WrapMode::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        WrapMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
    };
    let filter = |f: FilterMode| match f {
        FilterMode::Nearest => wgpu::FilterMode::Nearest,
        FilterMode::Linear => wgpu::FilterMode::Linear,
    };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("GpuScene::material_sampler"),
        address_mode_u: wrap(s.wrap_u),
        address_mode_v: wrap(s.wrap_v),
        mag_filter: filter(s.mag_filter),
        min_filter: filter(s.min_filter),
        mipmap_filter: match s.mipmap_filter {
            FilterMode::Nearest => wgpu::MipmapFilterMode::Nearest,
            FilterMode::Linear => wgpu::MipmapFilterMode::Linear,
        },
        lod_max_clamp: if s.mipmaps { 32.0 } else { 0.0 },
        ..Default::default()
    })
}

/// Uploads an 8-bit RGBA image with its mip chain as `format` (sRGB for colour, linear for data
/// such as occlusion).
fn upload_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    name: &str,
    width: u32,
    height: u32,
    rgba8: &[u8],
    format: wgpu::TextureFormat,
) -> wgpu::TextureView {
    let levels = 32 - width.max(height).leading_zeros();
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let mut level_image = image::RgbaImage::from_raw(width, height, rgba8.to_vec()).expect("validated size");
    for level in 0..levels {
        let (w, h) = level_image.dimensions();
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            level_image.as_raw(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w * 4),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
        if level + 1 < levels {
            level_image = image::imageops::resize(
                &level_image,
                (w / 2).max(1),
                (h / 2).max(1),
                image::imageops::FilterType::Triangle,
            );
        }
    }
    texture.create_view(&Default::default())
}
