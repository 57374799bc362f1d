// Shared by the convenience renderer's lit passes (composite, forward): what an instance adds
// to its material there (mirrors `SurfaceUniform` in src/layouts.rs): its lightmap, sampled
// with the mesh's second UV set, its material's ambient-occlusion, emissive,
// metallic-roughness and normal textures, and how the material reflects the lights (Lambert,
// or glTF's metallic-roughness model).

struct Surface {
    // the lightmap's atlas rectangle: xy min, zw max (texture space)
    rect: vec4<f32>,
    // x: exposure; y: 0 no lightmap, 1 mixed (indirect light baked), 2 baked (all light baked);
    // z: 1 bicubic filtering, 0 bilinear
    params: vec4<f32>,
    // x: occlusion strength (0: none); y: the UV set it reads
    occlusion: vec4<f32>,
    // the occlusion UVs' affine transform: u' = dot(row 0 .xyz, (u, v, 1)), v' likewise
    occlusion_transform: array<vec4<f32>, 2>,
    // rgb: the material's emissive light (times the emissive texture)
    emissive: vec4<f32>,
    // x: metallic, y: roughness (times the metallic-roughness texture's blue and green);
    // z: 1 metallic-roughness model, 0 Lambert; w: the normal map's scale (0: none)
    shading: vec4<f32>,
}

// Whether the pipeline samples lightmaps and occlusion textures at all: one made for a scene
// with neither leaves both out (a SIMD rasterizer pays for samples whatever they read).
override SURFACE_MAPS: bool = true;

// Whether the pipeline shades area lights (`area_reflected`): one made for lights without an
// area leaves that code out. A SIMD rasterizer runs the code of a branch that no pixel takes
// (masked) too: llvmpipe's composite took about twice as long with it in its light loop.
override AREA_LIGHTS: bool = true;

@group(3) @binding(0) var<uniform> surface: Surface;
@group(3) @binding(1) var lightmap_atlas: texture_2d<f32>;
@group(3) @binding(2) var lightmap_sampler: sampler;
@group(3) @binding(3) var occlusion_texture: texture_2d<f32>;
@group(3) @binding(4) var occlusion_sampler: sampler;
@group(3) @binding(5) var emissive_texture: texture_2d<f32>;
@group(3) @binding(6) var metallic_roughness_texture: texture_2d<f32>;
@group(3) @binding(7) var normal_texture: texture_2d<f32>;

const PI: f32 = 3.14159265;

// How the surface at one point reflects light.
struct Reflectance {
    // the shading normal (normal-mapped), on the camera's side
    n: vec3<f32>,
    // toward the camera
    v: vec3<f32>,
    // the diffuse colour: the base colour (Lambert), base x (1 - metallic) (metallic-roughness)
    diffuse: vec3<f32>,
    // the specular colour at normal incidence (metallic-roughness; 0 for Lambert)
    f0: vec3<f32>,
    // GGX alpha: roughness squared
    alpha: f32,
    // the metallic-roughness model (false: Lambert, diffuse only)
    specular: bool,
}

// The surface's reflectance at a point of base colour `base`, texture coordinates `uv0`,
// camera-side vertex normal `n` (unit), tangent `tangent` (xyz world, w the bitangent's sign)
// and direction to the camera `v`. Samples in every case: call it in uniform control flow.
fn reflectance(base: vec3<f32>, uv0: vec2<f32>, n: vec3<f32>, tangent: vec4<f32>, v: vec3<f32>) -> Reflectance {
    var r: Reflectance;
    r.n = n;
    r.v = v;
    r.diffuse = base;
    r.f0 = vec3<f32>(0.0);
    r.alpha = 1.0;
    r.specular = surface.shading.z > 0.5;
    if !SURFACE_MAPS {
        return r;
    }
    let texel = textureSample(metallic_roughness_texture, occlusion_sampler, uv0);
    let mapped = textureSample(normal_texture, occlusion_sampler, uv0).xyz * 2.0 - 1.0;
    let t = tangent.xyz - n * dot(n, tangent.xyz);
    if surface.shading.w != 0.0 && dot(t, t) > 1e-12 {
        // Tangent space (glTF): the bitangent is cross(normal, tangent) times w.
        let tu = normalize(t);
        let bu = cross(n, tu) * select(1.0, -1.0, tangent.w < 0.0);
        let m = vec3<f32>(mapped.xy * surface.shading.w, mapped.z);
        r.n = normalize(tu * m.x + bu * m.y + n * max(m.z, 0.0));
    }
    if r.specular {
        let metallic = clamp(surface.shading.x * texel.b, 0.0, 1.0);
        let roughness = clamp(surface.shading.y * texel.g, 0.0, 1.0);
        r.diffuse = base * (1.0 - metallic);
        r.f0 = mix(vec3<f32>(0.04), base, metallic);
        // As in glTF's reference viewer, roughness kept above 0.045 so the lobe stays finite.
        let a = max(roughness, 0.045);
        r.alpha = a * a;
    }
    return r;
}

// What the surface sends to the camera per unit of a light's irradiance from direction `l`
// (unit, toward the light), split into the diffuse factor (multiplying `diffuse`: n.l, times
// 1 - Fresnel for the metallic-roughness model) and the specular light (rgb). The irradiance
// convention is the Lambertian one these passes always used: a white Lambertian surface facing
// a light shows its irradiance, so the BRDF is scaled by pi.
struct Reflected {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

fn reflected(r: Reflectance, l: vec3<f32>) -> Reflected {
    let n_dot_l = max(dot(r.n, l), 0.0);
    if !r.specular {
        return Reflected(vec3<f32>(n_dot_l), vec3<f32>(0.0));
    }
    let n_dot_v = max(dot(r.n, r.v), 1e-4);
    let h = normalize(l + r.v);
    let n_dot_h = max(dot(r.n, h), 0.0);
    let v_dot_h = max(dot(r.v, h), 0.0);
    let fresnel = r.f0 + (1.0 - r.f0) * pow(1.0 - v_dot_h, 5.0);
    let a2 = r.alpha * r.alpha;
    let d_denominator = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    let distribution = a2 / (PI * d_denominator * d_denominator);
    // Smith's visibility, separable form (glTF appendix B): G / (4 n.l n.v).
    let visibility = 1.0 / ((n_dot_l + sqrt(a2 + (1.0 - a2) * n_dot_l * n_dot_l))
        * (n_dot_v + sqrt(a2 + (1.0 - a2) * n_dot_v * n_dot_v)));
    return Reflected((1.0 - fresnel) * n_dot_l, PI * fresnel * distribution * visibility * n_dot_l);
}

// The baked light at `uv1` times the exposure (rgb) and the mode (w: 0 none, 1 mixed,
// 2 baked). Samples in every case: call it in uniform control flow.
fn baked_light(uv1: vec2<f32>) -> vec4<f32> {
    if !SURFACE_MAPS {
        return vec4<f32>(0.0);
    }
    let uv = mix(surface.rect.xy, surface.rect.zw, uv1);
    // Between the levels the file has, where the surface shrinks the atlas (trilinear).
    var texel = textureSample(lightmap_atlas, lightmap_sampler, uv).rgb;
    // The surface uniform is the same for the whole draw: uniform control flow.
    if surface.params.z > 0.5 {
        texel = bicubic_lightmap(uv);
    }
    return vec4<f32>(texel * surface.params.x, surface.params.y);
}

// The lightmap at `uv` through a cubic B-spline over the 4 x 4 texels of its full size around
// it, as four bilinear fetches (each at the level its own derivatives pick, as one fetch would): each pair of B-spline weights along an axis becomes one fetch placed
// between its two texels in proportion to them.
fn bicubic_lightmap(uv: vec2<f32>) -> vec3<f32> {
    let size = vec2<f32>(textureDimensions(lightmap_atlas));
    let p = uv * size - 0.5;
    let base = floor(p);
    let f = p - base;
    let g = 1.0 - f;
    // B-spline weights of the texels at base - 1, base, base + 1 and base + 2.
    let w0 = g * g * g / 6.0;
    let w1 = (4.0 - 6.0 * f * f + 3.0 * f * f * f) / 6.0;
    let w2 = (1.0 + 3.0 * f + 3.0 * f * f - 3.0 * f * f * f) / 6.0;
    let w3 = f * f * f / 6.0;
    let low = w0 + w1;
    let high = w2 + w3;
    // Texel-centre coordinates of the two fetches along each axis.
    let at_low = (base - 0.5 + w1 / low) / size;
    let at_high = (base + 1.5 + w3 / high) / size;
    let s00 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_low.x, at_low.y)).rgb;
    let s10 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_high.x, at_low.y)).rgb;
    let s01 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_low.x, at_high.y)).rgb;
    let s11 = textureSample(lightmap_atlas, lightmap_sampler, vec2<f32>(at_high.x, at_high.y)).rgb;
    return low.y * (low.x * s00 + high.x * s10) + high.y * (low.x * s01 + high.x * s11);
}

// The light the surface gives off itself at `uv0`: added to the frame whatever the lights.
// Samples in every case: call it in uniform control flow.
fn emitted(uv0: vec2<f32>) -> vec3<f32> {
    if !SURFACE_MAPS {
        return vec3<f32>(0.0);
    }
    return surface.emissive.rgb * textureSample(emissive_texture, occlusion_sampler, uv0).rgb;
}

// The ambient occlusion at this point, for the indirect light: mix(1, texel, strength). Samples
// in every case: call it in uniform control flow.
fn ambient_occlusion(uv0: vec2<f32>, uv1: vec2<f32>) -> f32 {
    if !SURFACE_MAPS {
        return 1.0;
    }
    let uv = vec3<f32>(select(uv0, uv1, surface.occlusion.y > 0.5), 1.0);
    let t = surface.occlusion_transform;
    let texel = textureSample(occlusion_texture, occlusion_sampler, vec2<f32>(dot(t[0].xyz, uv), dot(t[1].xyz, uv))).r;
    return mix(1.0, texel, surface.occlusion.x);
}

// A spot's or point light's lux per candela at squared distance `d2`: the inverse square,
// windowed to 0 at `range` as glTF suggests, (1 - (d / range)^4)^2 (range 0: no window).
fn falloff(d2: f32, range: f32) -> f32 {
    var window = 1.0;
    if range > 0.0 {
        let r = d2 / (range * range);
        let w = clamp(1.0 - r * r, 0.0, 1.0);
        window = w * w;
    }
    return window / max(d2, 1e-8);
}

// An area light's direct light at `world` (camera-side shading in `r`): a one-sided
// rectangle (`shape` 1) or disk (2) centred at `center` with half-axes `u` and `v`, facing
// `facing`. Times its luminance it is the light the surface reflects, as `reflected` times a
// point light's `1 / d²` is. Nothing reaches a point behind the light's plane.
//
// Diffuse: the cosine-weighted solid angle the light covers above the surface's horizon,
// exactly, by Lambert's formula for a polygon (the sum over its edges of the angle each edge
// subtends times the cosine of its plane's normal with the surface's), after clipping the
// polygon to the horizon. A disk is a 16-sided polygon of the same area. This is what the
// linearly transformed cosines of Heitz et al. (2016) reduce to for a Lambertian surface.
// Specular (metallic-roughness): Karis's representative point (2013): the light's point
// nearest the mirror direction, lit as a point light of the light's whole intensity there,
// its lobe widened by the light's size (energy normalised by (alpha / alpha')²).
fn area_reflected(r: Reflectance, world: vec3<f32>, center: vec3<f32>, u: vec3<f32>, v: vec3<f32>, facing: vec3<f32>, shape: u32) -> Reflected {
    let to_center = center - world;
    if dot(to_center, facing) >= 0.0 {
        // Behind the light (or in its plane).
        return Reflected(vec3<f32>(0.0), vec3<f32>(0.0));
    }
    let cosine_solid_angle = clipped_polygon_irradiance(to_center, u, v, shape, r.n);
    // Karis's representative point: where the mirror ray meets the light's plane, kept on the
    // light (the point nearest the centre when the ray runs away from the plane).
    let mirror = reflect(-r.v, r.n);
    let toward_plane = dot(mirror, facing);
    var p = to_center;
    if toward_plane < -1e-4 {
        p = mirror * (dot(to_center, facing) / toward_plane);
    }
    let u2 = max(dot(u, u), 1e-20);
    let v2 = max(dot(v, v), 1e-20);
    var st = vec2<f32>(dot(p - to_center, u) / u2, dot(p - to_center, v) / v2);
    if shape == 1u {
        st = clamp(st, vec2<f32>(-1.0), vec2<f32>(1.0));
    } else if dot(st, st) > 1.0 {
        st = normalize(st);
    }
    p = to_center + u * st.x + v * st.y;
    let d2 = max(dot(p, p), 1e-8);
    let l = p * inverseSqrt(d2);
    let lit = reflected(r, l);
    // The light seen from the point: its area times its cosine there, over d², is the solid
    // angle a point light of its intensity would stand for.
    let area = 4.0 * sqrt(u2 * v2) * select(0.78539816, 1.0, shape == 1u);
    let solid_angle = area * max(dot(-l, facing), 0.0) / d2;
    // The lobe widened by the light's size seen from the surface (its equivalent sphere's
    // radius over the distance).
    let widened = min(r.alpha + sqrt(area / 3.14159265) / (2.0 * sqrt(d2)), 1.0);
    let normalisation = (r.alpha * r.alpha) / max(widened * widened, 1e-8);
    // The diffuse part: the exact cosine-weighted solid angle, less what the surface reflects
    // specularly there (as `reflected` does for a point light).
    let n_dot_l = max(dot(r.n, l), 1e-4);
    let diffuse_share = select(vec3<f32>(1.0), lit.diffuse / n_dot_l, r.specular && dot(r.n, l) > 1e-4);
    return Reflected(diffuse_share * cosine_solid_angle, lit.specular * solid_angle * normalisation);
}

// Corner `k` of an area light's polygon, as an offset from the receiver: a rectangle's 4
// corners, or the 16 corners of a polygon of the disk's area (the radius times
// sqrt(pi / (8 sin(pi / 8)))), in order around it.
fn polygon_corner(k: u32, to_center: vec3<f32>, u: vec3<f32>, v: vec3<f32>, shape: u32) -> vec3<f32> {
    if shape == 1u {
        let s = select(-1.0, 1.0, k == 1u || k == 2u);
        let t = select(-1.0, 1.0, k >= 2u);
        return to_center + u * s + v * t;
    }
    let angle = f32(k) * 0.39269908;
    return to_center + (u * cos(angle) + v * sin(angle)) * 1.0129838;
}

// One edge's term in Lambert's formula: the angle the edge from `a` to `b` (offsets from the
// receiver) subtends, times the cosine between `n` and the normal of the plane through it and
// the receiver.
fn lambert_edge(a: vec3<f32>, b: vec3<f32>, n: vec3<f32>) -> f32 {
    let a_dir = normalize(a);
    let b_dir = normalize(b);
    let c = cross(a_dir, b_dir);
    let s = length(c);
    return select(0.0, atan2(s, dot(a_dir, b_dir)) / s * dot(c, n), s > 1e-12);
}

// The cosine-weighted solid angle (∫ max(0, n·ω) dω) of an area light's polygon
// (`polygon_corner`) seen from a receiver with unit normal `n`: the polygon clipped to the
// half-space above the receiver's horizon, then Lambert's formula, half the sum of
// `lambert_edge` over the clipped polygon's edges. The polygon is convex, so the horizon cuts
// it at most twice: where it leaves the half-space and where it comes back, joined by one edge
// along the horizon. The edges are summed as they are met, without arrays: a shader with a
// dynamically indexed local array ran several times slower on a software rasterizer whether
// or not a light was an area light.
fn clipped_polygon_irradiance(to_center: vec3<f32>, u: vec3<f32>, v: vec3<f32>, shape: u32, n: vec3<f32>) -> f32 {
    let count = select(16u, 4u, shape == 1u);
    var sum = 0.0;
    // Vertices of the clipped polygon, and where it leaves and re-enters the half-space.
    var kept = 0u;
    var leaves = vec3<f32>(0.0);
    var enters = vec3<f32>(0.0);
    var crossings = 0u;
    var a = polygon_corner(0u, to_center, u, v, shape);
    for (var i = 0u; i < count; i++) {
        let b = polygon_corner((i + 1u) % count, to_center, u, v, shape);
        let ha = dot(a, n);
        let hb = dot(b, n);
        if ha >= 0.0 {
            kept += 1u;
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            // The edge crosses the horizon: the crossing is a vertex.
            let crossing = a + (b - a) * (ha / (ha - hb));
            kept += 1u;
            crossings += 1u;
            if ha >= 0.0 {
                sum += lambert_edge(a, crossing, n);
                leaves = crossing;
            } else {
                sum += lambert_edge(crossing, b, n);
                enters = crossing;
            }
        } else if ha >= 0.0 {
            sum += lambert_edge(a, b, n);
        }
        a = b;
    }
    if kept < 3u {
        return 0.0;
    }
    if crossings == 2u {
        sum += lambert_edge(leaves, enters, n);
    }
    return 0.5 * abs(sum);
}
