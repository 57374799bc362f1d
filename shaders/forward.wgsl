// after: scene cube surface
// Forward lit pass: Lambert diffuse plus ambient on the base color (texture x factor), with the
// direct light attenuated by a shadow-map lookup.
//
// The shadow lookup is one `textureSampleCompareLevel` on the depth shadow map. The method is
// chosen by the comparison sampler bound with it: nearest filtering gives a hard one-tap test,
// linear filtering the hardware's 2x2 percentage-closer filter.

struct ForwardFrame {
    view_proj: mat4x4<f32>,
    // each cascade's (or cube face's) light view-projection into its tile of the map atlas
    light_view_proj: array<mat4x4<f32>, 6>,
    // the camera view distance where each cascade ends
    cascade_end: vec4<f32>,
    // each cascade's normal offset in world units (orthographic light) or world units per unit
    // of distance from the light (spot and point lights: the first)
    cascade_offset: vec4<f32>,
    // x: cascades in use, y: tiles per side of the map atlas
    cascade_count: vec4<u32>,
    // xyz: eye
    camera_position: vec4<f32>,
    // xyz: direction the light travels; w: 0 directional, 1 spot, 2 point
    light_direction: vec4<f32>,
    // xyz: spot or point position; w: cosine of the cone's outer angle
    light_position: vec4<f32>,
    // rgb: color x intensity x exposure; w: cosine of the cone's inner (full-intensity) angle
    light_radiance: vec4<f32>,
    // rgb: ambient; w: a spot's or point light's range (0: none)
    ambient: vec4<f32>,
    // an area light's half-axis along its width (xyz); w: its shape, 0 none, 1 rectangle,
    // 2 disk
    area_u: vec4<f32>,
    // an area light's half-axis along its height
    area_v: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: ForwardFrame;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
@group(1) @binding(0) var<uniform> instance: Instance;
@group(2) @binding(0) var<uniform> material: Material;
@group(2) @binding(1) var base_color_texture: texture_2d<f32>;
@group(2) @binding(2) var base_color_sampler: sampler;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
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
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (instance.normal * vec4<f32>(normal, 0.0)).xyz;
    out.uv = uv;
    out.uv1 = uv1;
    out.color = color;
    out.tangent = vec4<f32>((instance.model * vec4<f32>(tangent.xyz, 0.0)).xyz, tangent.w);
    return out;
}

// The cascade for a point `view_distance` from the camera.
fn cascade_at(view_distance: f32) -> u32 {
    var k = 0u;
    while k + 1u < min(frame.cascade_count.x, 4u) && view_distance >= frame.cascade_end[k] {
        k += 1u;
    }
    return k;
}

// 1 where the light reaches `world`, 0 where a caster blocks it; beside the shadow map or in
// front of its near plane, 1. Beyond its far plane `world` lies behind every caster the map
// holds: compared as on the far plane, where an empty texel (1) leaves it lit.
fn shadow_visibility(world: vec3<f32>, cascade: u32) -> f32 {
    let clip = frame.light_view_proj[cascade] * vec4<f32>(world, 1.0);
    let w = max(clip.w, 1e-20);
    let ndc = clip.xyz / w;
    let uv = ndc.xy * vec2<f32>(0.5, -0.5) + vec2<f32>(0.5);
    // Inside the cascade's own tile of the atlas (columns y, rows z).
    let cols = max(frame.cascade_count.y, 1u);
    let size = 1.0 / vec2<f32>(f32(cols), f32(max(frame.cascade_count.z, 1u)));
    let tile = vec2<f32>(f32(cascade % cols), f32(cascade / cols)) * size;
    let inside = clip.w > 0.0 && all(uv >= tile) && all(uv <= tile + size) && ndc.z >= 0.0;
    let visibility = textureSampleCompareLevel(shadow_map, shadow_sampler, uv, min(ndc.z, 1.0));
    return select(1.0, visibility, inside);
}

@fragment
fn fs_main(in: VsOut) -> @location(0) vec4<f32> {
    let n = camera_side_normal(in.normal, in.world, frame.camera_position.xyz - in.world);
    // Sample before any discard so the implicit derivatives stay in uniform control flow.
    let base = material.base_color * in.color * textureSample(base_color_texture, base_color_sampler, in.uv);
    let baked = baked_light(in.uv1);
    let occlusion = ambient_occlusion(in.uv, in.uv1);
    let emission = emitted(in.uv);
    let r = reflectance(base.rgb, in.uv, n, in.tangent, normalize(frame.camera_position.xyz - in.world));
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
    var to_light = -frame.light_direction.xyz;
    var cone = 1.0;
    if frame.light_direction.w > 0.5 {
        // Spots and points: candela over the squared distance, windowed by the range.
        let offset = frame.light_position.xyz - in.world;
        to_light = normalize(offset);
        cone = falloff(dot(offset, offset), frame.ambient.w);
    }
    if frame.light_direction.w > 0.5 && frame.light_direction.w < 1.5 {
        let cos_angle = dot(-to_light, frame.light_direction.xyz);
        cone *= smoothstep(frame.light_position.w, frame.light_radiance.w, cos_angle);
    }
    // The shadow lookup is offset along the vertex normal; the shading uses the mapped one.
    var n_dot_l = max(dot(n, to_light), 0.0);
    var lit = reflected(r, to_light);
    if AREA_LIGHTS && frame.area_u.w > 0.5 {
        // An area light (see the composite): no inverse square, the light's solid angle.
        let offset = frame.light_position.xyz - in.world;
        let d2 = max(dot(offset, offset), 1e-8);
        cone = falloff(d2, frame.ambient.w) * d2;
        lit = area_reflected(r, in.world, frame.light_position.xyz, frame.area_u.xyz, frame.area_v.xyz, frame.light_direction.xyz, u32(frame.area_u.w + 0.5));
        // Lit where any of it is above the horizon.
        n_dot_l = select(0.0, 1.0, any(lit.diffuse > vec3<f32>(0.0)) || any(lit.specular > vec3<f32>(0.0)));
    }
    var visibility = 1.0;
    if instance.flags.x > 0.5 && n_dot_l > 0.0 {
        // Normal-offset bias: look the shadow map up a little off the surface.
        var cascade = cascade_at((frame.view_proj * vec4<f32>(in.world, 1.0)).w);
        var offset = frame.cascade_offset[min(cascade, 3u)];
        if frame.light_direction.w > 1.5 {
            // A point light: the cube face, and the distance from the light for the offset.
            cascade = cube_face(in.world - frame.light_position.xyz);
            offset = frame.cascade_offset[0] * length(in.world - frame.light_position.xyz);
        } else if frame.light_direction.w > 0.5 {
            offset *= max(dot(in.world - frame.light_position.xyz, frame.light_direction.xyz), 0.0);
        }
        visibility = shadow_visibility(in.world + n * offset, cascade);
    }
    // Shadows multiply the light's direct light only; the indirect light's specular share is
    // its colour at normal incidence (see the composite).
    let light = frame.light_radiance.rgb * (lit.diffuse * cone * visibility) + indirect;
    let specular = frame.light_radiance.rgb * (lit.specular * cone * visibility) + indirect * r.f0;
    return vec4<f32>(r.diffuse * light + specular + emission, alpha);
}
