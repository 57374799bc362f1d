//! The passes' WGSL sources. Each pass has one file in `shaders/`; the pieces several passes
//! share (the frame uniform and light-space helpers, a point light's cube faces, the
//! full-screen triangle, the screen tiles' quads and list, the receiver plane, where the fattened shadow falls, the instance and material uniforms) live in `shaders/common/` and are joined to the
//! pass's file at compile time, so there is one copy of each.

// One const per file of `shaders/` (its name in upper case) and `ALL`, written by `build.rs`
// from the files themselves: a pass's first line names the pieces of `shaders/common/` it is
// joined after (`// after: frame cube fullscreen`), so a new pass's shader is its file alone.
include!(concat!(env!("OUT_DIR"), "/shaders.rs"));

/// A shader module from one of the sources above.
pub(crate) fn module(device: &wgpu::Device, label: &str, source: &'static str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(std::borrow::Cow::Borrowed(source)),
    })
}

/// The line of `shaders/common/layer_out.wgsl` that types the light's layer as a storage
/// texture, as written (32-bit, which every device can store), and the line it becomes on a
/// device that stores half floats.
const LAYER_AS_WRITTEN: (&str, &str) = (
    "alias LayerStorage = texture_storage_2d<r32float, write>;",
    "alias LayerStorage = texture_storage_2d<r16float, write>;",
);

/// The lines of `shaders/common/screen_storage.wgsl` that type the compute path's visibility,
/// deviations and distance map as storage textures, as written (32-bit), and as single or
/// paired half floats.
const INTERMEDIATES_AS_WRITTEN: [(&str, &str); 3] = [
    (
        "alias VisibilityStorage = texture_storage_2d<r32float, write>;",
        "alias VisibilityStorage = texture_storage_2d<r16float, write>;",
    ),
    (
        "alias SigmaStorage = texture_storage_2d<rg32float, write>;",
        "alias SigmaStorage = texture_storage_2d<rg16float, write>;",
    ),
    (
        "alias DistanceStorage = texture_storage_2d<r32float, write>;",
        "alias DistanceStorage = texture_storage_2d<r16float, write>;",
    ),
];

/// How a pass's module types the storage textures it writes, on a device that stores half
/// floats ([`with_half_floats`]); both false everywhere else.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct HalfFloats {
    /// The light's layer (`LayerStorage`, R16F): the pass's `cs_layer` entry point then writes
    /// the layer itself.
    pub layers: bool,
    /// The compute path's visibility, the blur's deviations and the distance map
    /// (`VisibilityStorage` R16F, `SigmaStorage` RG16F, `DistanceStorage` R16F), in place of
    /// 32-bit floats.
    pub intermediates: bool,
}

/// `source` (a pass joined after `shaders/common/layer_out.wgsl` or
/// `shaders/common/screen_storage.wgsl`) with the storage textures `half` names typed as half
/// floats. `None` where the source has none of them.
pub fn with_half_floats(source: &str, half: HalfFloats) -> Option<String> {
    let mut lines: Vec<(&str, &str)> = Vec::new();
    if half.layers {
        lines.push(LAYER_AS_WRITTEN);
    }
    if half.intermediates {
        lines.extend(INTERMEDIATES_AS_WRITTEN);
    }
    lines
        .iter()
        .any(|(written, _)| source.contains(written))
        .then(|| {
            lines
                .iter()
                .fold(source.to_owned(), |s, (written, half)| s.replace(written, half))
        })
}

/// The light's maps the screen passes read, each with the field of the frame uniform's
/// `MapLayers` (`shaders/common/frame.wgsl`) that names its layer: the shadow map (compared,
/// and read as depths), the fattened map, its occluder offsets and the exit map.
const LIGHT_MAPS: [(&str, &str); 5] = [
    ("shadow_map", "frame.maps.shadow"),
    ("shadow_depths", "frame.maps.shadow"),
    ("fattened_map", "frame.maps.fattened"),
    ("occluder_offset", "frame.maps.occluder_offset"),
    ("exit_map", "frame.maps.exit"),
];

/// The texture types of the light's maps as written, and as layers of an array.
const MAP_TYPES: [(&str, &str); 2] = [
    ("texture_depth_2d;", "texture_depth_2d_array;"),
    ("texture_2d<f32>;", "texture_2d_array<f32>;"),
];

/// `source` (a pass joined after `shaders/common/frame.wgsl`) with the light's maps it declares
/// (`shadow_map`, `shadow_depths`, `fattened_map`, `occluder_offset`, `exit_map`) typed as 2D
/// arrays and every read of them taking the light's layer from the frame uniform
/// (`frame.maps`): a light's maps are then bound as the arrays every light's maps are layers of
/// (where they share arrays: not on wgpu's GL backend), which passes over several lights need. `textureLoad`,
/// `textureSampleCompareLevel`, `textureGather` and `textureDimensions` are the reads the
/// passes make. `None` where the source declares none of the maps or has no frame uniform.
pub fn with_map_arrays(source: &str) -> Option<String> {
    if !source.contains("struct MapLayers") {
        return None;
    }
    let mut out = source.to_owned();
    let mut declared = Vec::new();
    for (name, layer) in LIGHT_MAPS {
        for (written, arrayed) in MAP_TYPES {
            let declaration = format!("var {name}: {written}");
            if out.contains(&declaration) {
                out = out.replace(&declaration, &format!("var {name}: {arrayed}"));
                declared.push((name, layer));
            }
        }
    }
    if declared.is_empty() {
        return None;
    }
    for builtin in ["textureLoad", "textureSampleCompareLevel", "textureGather"] {
        out = with_layer_arguments(&out, builtin, &declared);
    }
    Some(out)
}

/// The frame uniform's declaration in `shaders/common/frame.wgsl`.
const ONE_FRAME: &str = "@group(0) @binding(0) var<uniform> frame: Frame;";

/// `source` (a pass joined after `shaders/common/frame.wgsl`) reading the frame of one of
/// several lights: the frame uniforms' buffer (a slot a light, each light's passes bind one
/// slot of; it grows with the lights) bound whole as a read-only storage buffer, a runtime-sized
/// array of every light's frame (a uniform binding may be as small as 16 KiB, and sixteen slots
/// take 20; `struct Frame` is padded so
/// that the array's stride is the slots', and its layout is a uniform's), and each read of `frame` reading
/// `frames[frame_light]`, where `frame_light` (a private variable, 0 until set) is the light
/// the invocation works for: a pass over several lights' tiles sets it from the tile's entry
/// before it reads the frame. Apply it after [`with_map_arrays`] (whose layers are frame reads
/// too). `None` where the source has no frame uniform.
pub fn with_light_frames(source: &str) -> Option<String> {
    if !source.contains(ONE_FRAME) {
        return None;
    }
    let declaration = "@group(0) @binding(0) var<storage, read> frames: array<Frame>;\n\
         // The light this invocation works for (`penumbra::shaders::with_light_frames`).\n\
         var<private> frame_light: u32 = 0u;";
    let source = source.replace(ONE_FRAME, declaration);
    let mut out = String::with_capacity(source.len() + source.len() / 8);
    let mut rest = source.as_str();
    while let Some(at) = rest.find("frame.") {
        let preceded = rest[..at].chars().last().or_else(|| out.chars().last());
        out.push_str(&rest[..at]);
        let inside_a_name = preceded.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        out.push_str(if inside_a_name {
            "frame."
        } else {
            "frames[frame_light]."
        });
        rest = &rest[at + "frame.".len()..];
    }
    out.push_str(rest);
    Some(out)
}

/// `shaders/common/tile_list.wgsl` as the passes are joined after it, and what
/// [`with_light_groups`] puts in its place.
const TILE_LIST: &str = include_str!("../shaders/common/tile_list.wgsl");
const TILE_GROUPS: &str = include_str!("../shaders/common/tile_groups.wgsl");

/// The storage textures' aliases (`shaders/common/screen_storage.wgsl`, `layer_out.wgsl`), as
/// [`with_half_floats`] leaves them, up to their texel format.
const STORAGE_ALIASES: [&str; 4] = [
    "alias VisibilityStorage = texture_storage_2d<",
    "alias SigmaStorage = texture_storage_2d<",
    "alias DistanceStorage = texture_storage_2d<",
    "alias LayerStorage = texture_storage_2d<",
];

/// The textures the variable PCF's compute pass over a group of lights binds as arrays
/// ([`with_light_groups`]): it writes the light's layer of the visibility, and its tile's slot of
/// the pool ([`POOLED`]) of the deviations and the distance map.
pub const PCF_GROUP_LAYERS: [(&str, &str); 3] = [
    ("visibility_out", "frame_light"),
    ("sigma_out", POOLED),
    ("distance_out", POOLED),
];

/// The same for the blur's two axes over a group: the horizontal one reads the light's layer
/// of the visibility (which the PCF wrote) into its tile's slot of the pool of the axis's
/// result; the vertical one reads that, at its neighbours too ([`POOLED_ANYWHERE`]), into the
/// light's layer. Both read the distance map and the deviations at their own pixel.
pub const BLUR_GROUP_LAYERS: [[(&str, &str); 5]; 2] = [
    [
        ("source", "frame_light"),
        ("distance_map", POOLED),
        ("blur_sigma", POOLED),
        ("blur_out", POOLED),
        ("layer_out", "frame_light"),
    ],
    [
        ("source", POOLED_ANYWHERE),
        ("distance_map", POOLED),
        ("blur_sigma", POOLED),
        ("blur_out", POOLED),
        ("layer_out", "frame_light"),
    ],
];

/// The same for the copy of the inspected member's distance map out of the pool
/// (`shaders/group_unpack.wgsl`): its own pixel of the pool into a texture of one layer.
pub const UNPACK_GROUP_LAYERS: [(&str, &str); 2] = [("pooled_distance", POOLED), ("inspected_distance", "0")];

/// In [`with_light_groups`]' layers: a texture held per listed tile in the group's pool
/// (`shaders/common/tile_groups.wgsl`), read and written only at the invocation's own pixel,
/// which its tile's slot holds: each access takes the pixel's texel and layer in the pool.
pub const POOLED: &str = "pool";

/// In [`with_light_groups`]' layers: a pooled texture read anywhere on the screen: each load
/// finds the pixel's tile in the member's map, and reads 1 where the tile is not listed and 0
/// where it is turned away from the light (what the tile classification clears an unpooled
/// intermediate to).
pub const POOLED_ANYWHERE: &str = "pool anywhere";

/// `source` (a pass over the tile list, `shaders/common/tile_list.wgsl`, that reads the frame)
/// as a pass over the tile lists of a group of lights in one dispatch
/// (`shaders/common/tile_groups.wgsl`): its light's maps read as layers of arrays
/// ([`with_map_arrays`]), its light's frame one of several ([`with_light_frames`]), set from the
/// workgroup's tile, and each texture `layers` names (binding, layer expression) bound as a 2D array
/// of which every read and write takes that layer: `frame_light` (the light's slot: its layer of
/// the visibility array), `member` (its place in the group), or the pool's ([`POOLED`],
/// [`POOLED_ANYWHERE`]). The storage textures' aliases all become arrays. `None` where the
/// source has no tile list, no frame, or does not declare a texture `layers` names.
pub fn with_light_groups(source: &str, layers: &[(&str, &str)]) -> Option<String> {
    if !source.contains(TILE_LIST) {
        return None;
    }
    let grouped = source.replace(TILE_LIST, TILE_GROUPS);
    let arrayed = with_map_arrays(&grouped).unwrap_or(grouped);
    let mut out = with_light_frames(&arrayed)?;
    out = with_storage_arrays(&out);
    for (name, _) in layers {
        let sampled = format!("var {name}: texture_2d<f32>;");
        if out.contains(&sampled) {
            out = out.replace(&sampled, &format!("var {name}: texture_2d_array<f32>;"));
        } else if !STORAGE_ALIASES.iter().any(|alias| {
            let alias_name = alias["alias ".len()..].split(' ').next().unwrap_or_default();
            out.contains(&format!("var {name}: {alias_name};"))
        }) {
            return None;
        }
    }
    // The pooled textures read anywhere: each load and sample through a function of its own.
    for (name, _) in layers.iter().filter(|(_, layer)| *layer == POOLED_ANYWHERE) {
        out = with_calls_replaced(&out, "textureLoad", name, &format!("pooled_{name}"));
        out = with_calls_replaced(&out, "textureSampleLevel", name, &format!("pooled_sample_{name}"));
        out.push_str(&format!(
            "\n// `{name}` held per listed tile (`penumbra::shaders::POOLED_ANYWHERE`).\n\
             fn pooled_{name}(pixel: vec2<i32>, level: i32) -> vec4<f32> {{\n\
             \x20   let at = pool_place(pixel);\n\
             \x20   if at.z < 0 {{\n\
             \x20       return vec4<f32>(select(0.0, 1.0, at.z == -1));\n\
             \x20   }}\n\
             \x20   return textureLoad({name}, at.xy, at.z, level);\n\
             }}\n\
             fn pooled_sample_{name}(linear: sampler, uv: vec2<f32>, level: f32) -> vec4<f32> {{\n\
             \x20   return pooled_{name}(vec2<i32>(uv * frames[frame_light].view.size), i32(level));\n\
             }}\n"
        ));
    }
    // The pooled textures at the invocation's own pixel: the coordinates made the pool's.
    let own: Vec<(&str, &str)> = layers
        .iter()
        .filter(|(_, layer)| *layer == POOLED)
        .map(|(name, _)| (*name, "pool_layer()"))
        .collect();
    for builtin in ["textureLoad", "textureStore"] {
        out = with_pool_coordinates(&out, builtin, &own);
    }
    let layered: Vec<(&str, &str)> = layers
        .iter()
        .filter(|(_, layer)| *layer != POOLED_ANYWHERE)
        .map(|(name, layer)| (*name, if *layer == POOLED { "pool_layer()" } else { *layer }))
        .collect();
    for builtin in ["textureLoad", "textureStore", "textureSampleLevel"] {
        out = with_layer_arguments(&out, builtin, &layered);
    }
    Some(out)
}

/// `source` with each call `builtin(name, rest)` made `function(rest)` (the texture dropped).
fn with_calls_replaced(source: &str, builtin: &str, name: &str, function: &str) -> String {
    let call = format!("{builtin}({name},");
    source.replace(&call, &format!("{function}("))
}

/// `source` with the coordinates of each call of `builtin` on one of `maps` made the pool's:
/// `pool_pixel(coordinates)` (`shaders/common/tile_groups.wgsl`).
fn with_pool_coordinates(source: &str, builtin: &str, maps: &[(&str, &str)]) -> String {
    maps.iter().fold(source.to_owned(), |out, (name, _)| {
        let call = format!("{builtin}({name},");
        let mut result = String::with_capacity(out.len());
        let mut rest = out.as_str();
        while let Some(at) = rest.find(&call) {
            let open = at + call.len();
            result.push_str(&rest[..open]);
            rest = &rest[open..];
            // The coordinates: up to the next comma at depth 0.
            let mut depth = 0usize;
            let end = rest.char_indices().find_map(|(i, c)| match c {
                '(' | '[' => {
                    depth += 1;
                    None
                }
                ')' | ']' => {
                    depth = depth.saturating_sub(1);
                    None
                }
                ',' if depth == 0 => Some(i),
                _ => None,
            });
            let Some(end) = end else {
                continue;
            };
            result.push_str(&format!(" pool_pixel({})", rest[..end].trim()));
            rest = &rest[end..];
        }
        result.push_str(rest);
        result
    })
}

/// `source` with the storage textures' aliases ([`STORAGE_ALIASES`]) typed as 2D arrays.
fn with_storage_arrays(source: &str) -> String {
    STORAGE_ALIASES.iter().fold(source.to_owned(), |out, alias| {
        out.replace(
            alias,
            &alias.replace("texture_storage_2d<", "texture_storage_2d_array<"),
        )
    })
}

/// The textures the tile classification over a group of lights binds as arrays
/// ([`with_light_group_classification`]), and their layers: the member's reduced fattened map,
/// its tile classes and its intermediates it clears, the light's layer of the visibility.
pub const CLASSIFY_GROUP_LAYERS: [(&str, &str); 6] = [
    ("reduced_map", "member"),
    ("reduced_out", "member"),
    ("classes_out", "member"),
    ("distance_cleared", "member"),
    ("visibility_cleared", "frame_light"),
    ("blurred_cleared", "member"),
];

/// The list's declaration in `shaders/tile_classify.wgsl`, its append, and the tiles turned
/// away's append.
const CLASSIFY_LIST: &str = "@group(0) @binding(5) var<storage, read_write> list_out: TileListOut;";
const CLASSIFY_APPEND: &str = "list_out.tiles[atomicAdd(&list_out.appended, 1u)] = packed;";
const CLASSIFY_AWAY_APPEND: &str = "away_out.tiles[atomicAdd(&away_out.appended, 1u)] = packed;";
/// A block's opening brace (written by its code, so that this file's braces stay in pairs).
const OPEN_BRACE: char = '\u{7b}';

/// `source` (`shaders/tile_classify.wgsl`) as the classification of a group of lights in one
/// dispatch (`cs_reduce` and `cs_classify_wide`, each workgroup's z its member): the light's
/// maps and frame read as in [`with_light_groups`], the textures [`CLASSIFY_GROUP_LAYERS`]
/// names as arrays of which each read and write takes the member's or the light's layer, and
/// each member's list appended to its region of the group's buffer of lists (binding 18,
/// `shaders/common/tile_groups.wgsl`'s layout, whose header names each member's light). The
/// tiles turned away are not listed: the classification writes their 0 itself (`CLEARS`), and
/// `shaders/group_args.wgsl` takes each list's running count for its length. `None` where the
/// source is not the classification.
pub fn with_light_group_classification(source: &str) -> Option<String> {
    if !source.contains(CLASSIFY_LIST) || !source.contains(CLASSIFY_APPEND) {
        return None;
    }
    let arrayed = with_map_arrays(source)?;
    let mut out = with_light_frames(&arrayed)?;
    out = out.replace(
        CLASSIFY_LIST,
        &format!(
            "{CLASSIFY_LIST}\n\
             // The group's lists (`penumbra::shaders::with_light_group_classification`).\n\
             @group(0) @binding(18) var<storage, read_write> group_lists: array<atomic<u32>>;\n\
             // The member the workgroup classifies for (its z).\n\
             var<private> member: u32 = 0u;\n\
             fn member_list() -> u32 {{\n    return 64u + member * atomicLoad(&group_lists[0]);\n}}\n\
             // Sets the member and its light.\n\
             fn use_member(z: u32) {{\n    member = z;\n    frame_light = atomicLoad(&group_lists[2u + z]);\n}}\n\
             // The word of the member's map (after its list) that says where the list holds\n\
             // `tile` (`shaders/common/tile_groups.wgsl`).\n\
             fn tile_map(tile: vec2<u32>) -> u32 {{\n    let across = atomicLoad(&group_lists[36]);\n    \
             return member_list() + 2u + atomicLoad(&group_lists[37]) + tile.y * across + tile.x;\n}}"
        ),
    );
    out = out.replace(
        CLASSIFY_APPEND,
        "let at = atomicAdd(&group_lists[member_list() + 1u], 1u);\n        \
         atomicStore(&group_lists[member_list() + 2u + at], packed);\n        \
         atomicStore(&group_lists[tile_map(tile)], at);",
    );
    // Every tile's entry in the map, before a listed tile's index replaces it: not listed, or
    // turned away from the light (its intermediates read 1 or 0 there).
    let at = out.find("fn list_tile(")?;
    let body = at + out[at..].find(OPEN_BRACE)? + 1;
    out.insert_str(
        body,
        "\n    let away = tile_kind == AWAY || tile_kind == UMBRA_KIND;\n    \
         atomicStore(&group_lists[tile_map(tile)], select(0xffffffffu, 0xfffffffeu, away));",
    );
    out = out.replace(CLASSIFY_AWAY_APPEND, "// (a group lists no tile turned away)");
    // Each entry point first sets its member (its workgroup's z) and its light.
    for (entry, z) in [("fn cs_reduce(", "id.z"), ("fn cs_classify_wide(", "group.z")] {
        let at = out.find(entry)?;
        let body = at + out[at..].find(OPEN_BRACE)? + 1;
        out.insert_str(body, &format!("\n    use_member({z});"));
    }
    out = with_storage_arrays(&out);
    for (name, _) in CLASSIFY_GROUP_LAYERS {
        let sampled = format!("var {name}: texture_2d<f32>;");
        let stored = format!("var {name}: texture_storage_2d<");
        if out.contains(&sampled) {
            out = out.replace(&sampled, &format!("var {name}: texture_2d_array<f32>;"));
        } else if out.contains(&stored) {
            out = out.replace(&stored, &format!("var {name}: texture_storage_2d_array<"));
        }
    }
    for builtin in ["textureLoad", "textureStore", "textureGather"] {
        out = with_layer_arguments(&out, builtin, &CLASSIFY_GROUP_LAYERS);
    }
    Some(out)
}

/// `source` with each call of `builtin` on one of `maps` (name, layer expression) given the
/// layer: before the last argument (`textureLoad`'s level, `textureSampleCompareLevel`'s
/// reference depth), or after it (`textureGather`'s coordinates).
fn with_layer_arguments(source: &str, builtin: &str, maps: &[(&str, &str)]) -> String {
    let call = format!("{builtin}(");
    let mut out = String::with_capacity(source.len());
    let mut rest = source;
    while let Some(at) = rest.find(&call) {
        let open = at + call.len();
        out.push_str(&rest[..open]);
        rest = &rest[open..];
        // The arguments' commas and the closing parenthesis at depth 0 (byte offsets in rest).
        let (mut depth, mut commas, mut close) = (0usize, Vec::new(), None);
        for (i, c) in rest.char_indices() {
            match c {
                '(' | '[' => depth += 1,
                ')' | ']' if depth > 0 => depth -= 1,
                ')' => {
                    close = Some(i);
                    break;
                }
                ',' if depth == 0 => commas.push(i),
                _ => {}
            }
        }
        let Some(close) = close else {
            continue;
        };
        let mut starts = vec![0];
        starts.extend(commas.iter().map(|c| c + 1));
        let argument = |k: usize| {
            let end = commas.get(k).copied().unwrap_or(close);
            rest[starts[k]..end].trim()
        };
        // `textureGather(component, map, ...)` names the map second.
        let named = (0..starts.len().min(2)).find_map(|k| maps.iter().find(|(name, _)| argument(k) == *name));
        let Some((_, layer)) = named else {
            continue;
        };
        let (insert, text) = if builtin == "textureGather" {
            (close, format!(", {layer}"))
        } else {
            (commas.last().map_or(close, |c| c + 1), format!(" {layer},"))
        };
        out.push_str(&rest[..insert]);
        out.push_str(&text);
        rest = &rest[insert..];
    }
    out.push_str(rest);
    out
}

/// [`module`], with the storage textures `half` names typed as half floats
/// ([`with_half_floats`]) and, with `arrays`, the light's maps read as layers of arrays
/// ([`with_map_arrays`]).
pub(crate) fn module_for(
    device: &crate::pipeline_cache::CachedDevice<'_>,
    label: &str,
    source: &'static str,
    (half, arrays): (HalfFloats, bool),
) -> wgpu::ShaderModule {
    let halves = with_half_floats(source, half);
    let text = halves.as_deref().unwrap_or(source);
    let arrayed = arrays.then(|| with_map_arrays(text)).flatten();
    device.module(label, arrayed.as_deref().or(halves.as_deref()).unwrap_or(source))
}

/// [`module`] of a pass over a group of lights' tile lists ([`with_light_groups`] with
/// `layers`), its storage textures typed as `half` says ([`with_half_floats`]).
pub(crate) fn module_grouped(
    device: &crate::pipeline_cache::CachedDevice<'_>,
    label: &str,
    source: &'static str,
    half: HalfFloats,
    layers: &[(&str, &str)],
) -> wgpu::ShaderModule {
    let halves = with_half_floats(source, half);
    let text = halves.as_deref().unwrap_or(source);
    // The passes made so are named in the shader tests, which check that each is grouped.
    let grouped =
        with_light_groups(text, layers).unwrap_or_else(|| panic!("{label} is not a pass over a tile list"));
    device.module(label, &grouped)
}
