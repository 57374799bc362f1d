// after: frame cube scene surface
// Composite pass of the convenience renderer: the lit scene from the camera. Each light's
// direct light (Lambert, or glTF's metallic-roughness model: `surface.wgsl`; spot cone) times
// its screen-space visibility (its layer of the
// visibility array, resolved: the indirect-light attenuation is already in it), summed, on top
// of the base color (texture x factor), plus ambient, or the instance's lightmap in its place
// (mixed lighting); with baked lighting a lightmapped instance shows its lightmap alone. Depth is tested against the prepass
// (equal geometry, `@invariant` positions).

// One light as the composite shades it (mirrors `ShadedLight` in src/passes/composite.rs).
struct ShadedLight {
    // the direction the light travels
    direction: vec3<f32>,
    // 0 directional, 1 spot, 2 point
    spot: u32,
    position: vec3<f32>,
    cos_outer: f32,
    // color x intensity
    radiance: vec3<f32>,
    cos_inner: f32,
    // its layer of the visibility array
    layer: u32,
    // a spot's or point light's range (0: none)
    range: f32,
    _pad1: u32,
    _pad2: u32,
    // an area light's half-axis along its width (xyz); w: its shape, 0 none, 1 rectangle,
    // 2 disk
    area_u: vec4<f32>,
    // an area light's half-axis along its height
    area_v: vec4<f32>,
}

struct ShadedLights {
    count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    // `penumbra::MAX_LIGHTS`
    lights: array<ShadedLight, 16>,
}

@group(0) @binding(1) var visibility: texture_2d_array<f32>;
@group(0) @binding(2) var<uniform> shaded: ShadedLights;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) uv1: vec2<f32>,
    @location(4) color: vec4<f32>,
    // xyz: the tangent in world space; w: the bitangent's sign
    @location(5) tangent: vec4<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) uv1: vec2<f32>,
    @location(4) color: vec4<f32>,
    @location(5) tangent: vec4<f32>,
) -> VsOut {
    let world = instance.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = frame.view.view_proj * world;
    out.world = world.xyz;
    out.normal = (instance.normal * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.uv1 = uv1;
    out.color = color;
    out.tangent = vec4<f32>((instance.model * vec4<f32>(tangent.xyz, 0.0)).xyz, tangent.w);
    return out;
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let v_dir = normalize(to_camera(in.world));
    let n = camera_side_normal(in.normal, in.world, to_camera(in.world));
    let base = material.base_color * in.color * textureSample(base_color_texture, base_color_sampler, in.uv);
    let baked = baked_light(in.uv1);
    let occlusion = ambient_occlusion(in.uv, in.uv1);
    let emission = emitted(in.uv);
    let r = reflectance(base.rgb, in.uv, n, in.tangent, v_dir);
    if material.alpha.x >= 0.0 && base.a < material.alpha.x {
        discard;
    }
    // Lightmapped (mixed or baked): the lightmap in place of the ambient light; baked: alone
    // (a bake holds its own occlusion). The occlusion darkens the indirect light only.
    // Blended materials (alpha.y = 1) keep their alpha for the blend.
    let alpha = select(1.0, base.a, material.alpha.y > 0.5);
    if baked.w > 1.5 {
        return vec4<f32>(base.rgb * baked.rgb + emission, alpha);
    }
    let indirect = select(frame.ambient.rgb, baked.rgb, baked.w > 0.5) * occlusion;
    // The diffuse light (times the diffuse colour at the end) and the specular light; the
    // indirect light's specular share is its colour at normal incidence (a uniform
    // surrounding, no environment map).
    var light = indirect;
    var specular = indirect * r.f0;
    let pixel = vec2<i32>(in.clip.xy);
    for (var k = 0u; k < min(shaded.count, 16u); k++) {
        let l = shaded.lights[k];
        var to_light = -l.direction;
        var cone = 1.0;
        if l.spot != 0u {
            // Spots and points: candela over the squared distance, windowed by the range.
            let offset = l.position - in.world;
            to_light = normalize(offset);
            cone = falloff(dot(offset, offset), l.range);
        }
        if l.spot == 1u {
            cone *= smoothstep(l.cos_outer, l.cos_inner, dot(-to_light, l.direction));
        }
        var lit = reflected(r, to_light);
        if AREA_LIGHTS && l.area_u.w > 0.5 {
            // An area light: its luminance times the light its surface sends here
            // (`area_reflected`), windowed by the range (no inverse square: the solid angle
            // holds it).
            let offset = l.position - in.world;
            let d2 = max(dot(offset, offset), 1e-8);
            cone = falloff(d2, l.range) * d2;
            lit = area_reflected(r, in.world, l.position, l.area_u.xyz, l.area_v.xyz, l.direction, u32(l.area_u.w + 0.5));
        }
        var v = 1.0;
        // The screen-space visibility belongs to the opaque surface behind a blended one.
        if instance.flags.x > 0.5 && material.alpha.y < 0.5 {
            v = textureLoad(visibility, pixel, l.layer, 0).x;
        }
        // Shadows multiply each light's direct light only.
        light += l.radiance * (lit.diffuse * cone * v);
        specular += l.radiance * (lit.specular * cone * v);
    }
    return vec4<f32>(r.diffuse * light + specular + emission, alpha);
}
