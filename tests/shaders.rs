//! Every pass's WGSL (its file in `shaders/` joined with the shared pieces in
//! `shaders/common/`) parses and validates with naga (no GPU needed), every pass file is used,
//! and the passes find their entry points.

fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name} does not parse:\n{}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name} does not validate:\n{}", e.emit_to_string(source)));
    module
}

#[test]
fn every_shader_validates() {
    for (name, source) in penumbra::shaders::ALL {
        validate(name, source);
    }
}

#[test]
fn every_shader_file_belongs_to_a_pass() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let stem = path.file_stem().unwrap().to_str().unwrap();
            assert!(
                penumbra::shaders::ALL.iter().any(|(name, _)| *name == stem),
                "{} is not composed into any pass",
                path.display()
            );
        }
    }
}

#[test]
fn passes_find_their_entry_points() {
    for (name, entry_points) in [
        (
            "shadow_map",
            &[
                "vs_opaque",
                "vs_masked",
                "fs_masked",
                "fs_exit_ccw",
                "fs_exit_cw",
                "fs_masked_exit_ccw",
                "fs_masked_exit_cw",
                "vs_exit_any",
                "fs_exit_any",
            ][..],
        ),
        ("forward", &["vs_main", "fs_main"][..]),
        ("fattened_shadow_map", &["vs_main", "fs_main"][..]),
        ("exit_map", &["vs_main", "fs_main"][..]),
        ("depth_prepass", &["vs_main", "fs_main"][..]),
        ("distance_map", &["vs_fullscreen", "fs_main", "cs_main"][..]),
        ("resolve", &["vs_fullscreen", "fs_main"][..]),
        ("pcf", &["vs_fullscreen", "fs_main", "cs_main", "cs_layer"][..]),
        (
            "variable_pcf",
            &["vs_fullscreen", "fs_main", "cs_main", "cs_distance_pcf"][..],
        ),
        ("blur", &["vs_fullscreen", "fs_main", "cs_main", "cs_layer"][..]),
        ("pcss", &["vs_fullscreen", "fs_main", "cs_main", "cs_layer"][..]),
        ("composite", &["vs_main", "fs_main"][..]),
        ("reference", &["vs_fullscreen", "fs_main"][..]),
    ] {
        let source = penumbra::shaders::ALL.iter().find(|(n, _)| *n == name).unwrap().1;
        let module = validate(name, source);
        for entry in entry_points {
            assert!(
                module.entry_points.iter().any(|e| e.name == *entry),
                "{name} has no entry point {entry}"
            );
        }
    }
}

/// On a device that stores half floats, the passes whose compute pass can write the light's
/// layer (`cs_layer`) are made from their source with the layer typed R16F, and the compute
/// path's intermediates typed R16F and RG16F (`penumbra::shaders::with_half_floats`): those
/// sources validate too, and every source as written keeps 32-bit types (valid on the web,
/// where no half float is a storage format).
#[test]
fn passes_validate_with_half_float_storage() {
    use penumbra::shaders::{HalfFloats, with_half_floats};
    let layers = HalfFloats {
        layers: true,
        intermediates: false,
    };
    let intermediates = HalfFloats {
        layers: false,
        intermediates: true,
    };
    let (mut writing, mut storing) = (Vec::new(), Vec::new());
    for (name, source) in penumbra::shaders::ALL {
        // R16F and RG16F are not storage formats everywhere (the web has neither).
        assert!(
            !source.contains("<r16float, write") && !source.contains("<rg16float, write"),
            "{name} stores half floats as written"
        );
        if let Some(halves) = with_half_floats(source, layers) {
            assert!(halves.contains("alias LayerStorage = texture_storage_2d<r16float, write>;"));
            let module = validate(name, &halves);
            assert!(module.entry_points.iter().any(|e| e.name == "cs_layer"), "{name}");
            writing.push(*name);
        }
        if let Some(halves) = with_half_floats(source, intermediates) {
            assert!(halves.contains("alias VisibilityStorage = texture_storage_2d<r16float, write>;"));
            assert!(halves.contains("alias SigmaStorage = texture_storage_2d<rg16float, write>;"));
            assert!(halves.contains("alias DistanceStorage = texture_storage_2d<r16float, write>;"));
            validate(name, &halves);
            let both = with_half_floats(
                source,
                HalfFloats {
                    layers: true,
                    intermediates: true,
                },
            )
            .unwrap();
            validate(name, &both);
            storing.push(*name);
        }
    }
    assert_eq!(writing, ["blur", "pcf", "pcss"]);
    assert_eq!(
        storing,
        [
            "blur",
            "distance_map",
            "group_unpack",
            "pcf",
            "pcss",
            "tile_classify",
            "variable_pcf"
        ]
    );
}

#[test]
fn opaque_shadow_shader_is_depth_only() {
    // The opaque caster shader must stay minimal: a vertex stage reading only the position.
    let module = validate("shadow_map", penumbra::shaders::SHADOW_MAP);
    let vs = module
        .entry_points
        .iter()
        .find(|e| e.name == "vs_opaque")
        .unwrap();
    assert_eq!(
        vs.function.arguments.len(),
        1,
        "vs_opaque should take the position only"
    );
}

/// Where the lights' maps share arrays, the compute passes read them as layers of those arrays
/// (`penumbra::shaders::with_map_arrays`): the screen passes that read a light's maps validate
/// so too, every map they declare is typed as an array, and every read of a map takes the
/// light's layer from the frame uniform (none is left reading a 2D map).
#[test]
fn passes_validate_with_the_maps_as_arrays() {
    use penumbra::shaders::{HalfFloats, with_half_floats, with_map_arrays};
    let maps = [
        "shadow_map",
        "shadow_depths",
        "fattened_map",
        "occluder_offset",
        "exit_map",
    ];
    let mut arrayed = Vec::new();
    for (name, source) in penumbra::shaders::ALL {
        let Some(arrays) = with_map_arrays(source) else {
            continue;
        };
        arrayed.push(*name);
        let module = validate(name, &arrays);
        for (_, var) in module.global_variables.iter() {
            let Some(var_name) = var.name.as_deref() else {
                continue;
            };
            if maps.contains(&var_name) {
                assert!(
                    matches!(
                        module.types[var.ty].inner,
                        naga::TypeInner::Image { arrayed: true, .. }
                    ),
                    "{name}: {var_name} is not an array"
                );
            }
        }
        // Each read of a map as written gains the layer: as many layer expressions as reads.
        let reads: usize = maps
            .iter()
            .map(|map| {
                ["textureLoad(", "textureSampleCompareLevel(", "textureGather(0, "]
                    .iter()
                    .map(|call| source.matches(&format!("{call}{map},")).count())
                    .sum::<usize>()
            })
            .sum();
        assert!(reads > 0, "{name} reads none of the maps");
        assert_eq!(
            arrays.matches("frame.maps.").count(),
            source.matches("frame.maps.").count() + reads,
            "{name}: not every read of a map takes its layer"
        );
        // With the storage textures as half floats as well, as a device that stores them makes
        // the passes.
        let half = HalfFloats {
            layers: true,
            intermediates: true,
        };
        if let Some(halves) = with_half_floats(source, half) {
            validate(name, &with_map_arrays(&halves).unwrap());
        }
    }
    assert_eq!(
        arrayed,
        [
            "distance_map",
            "pcf",
            "pcss",
            "reference",
            "tile_classify",
            "variable_pcf"
        ]
    );
}

/// A pass over several lights reads each light's frame from the frame uniforms bound whole
/// (`penumbra::shaders::with_light_frames`): every screen pass that reads the frame validates so
/// too (with the maps as arrays, as such a pass binds them), reads the frame nowhere else, and
/// the array is sized at run time, its stride a frame slot's, 1,280 bytes.
#[test]
fn passes_validate_reading_one_of_several_lights_frames() {
    use penumbra::shaders::{with_light_frames, with_map_arrays};
    let mut made = Vec::new();
    for (name, source) in penumbra::shaders::ALL {
        let arrays = with_map_arrays(source).unwrap_or_else(|| source.to_string());
        let Some(frames) = with_light_frames(&arrays) else {
            continue;
        };
        made.push(*name);
        let module = validate(name, &frames);
        let code: String = frames
            .lines()
            .filter(|l| !l.trim_start().starts_with("//"))
            .collect::<Vec<_>>()
            .join("\n");
        let left = code.match_indices("frame.").filter(|(at, _)| {
            !code[..*at]
                .chars()
                .last()
                .is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
        });
        assert_eq!(left.count(), 0, "{name} still reads `frame`");
        let (_, frames_var) = module
            .global_variables
            .iter()
            .find(|(_, v)| v.name.as_deref() == Some("frames"))
            .unwrap_or_else(|| panic!("{name} has no `frames`"));
        match module.types[frames_var.ty].inner {
            // Sized at run time: the buffer grows with the lights a `Shadows` holds.
            naga::TypeInner::Array {
                size: naga::ArraySize::Dynamic,
                stride,
                ..
            } => {
                assert_eq!(stride, 1280, "{name}: a frame is not a slot's 1,280 bytes");
            }
            ref other => panic!("{name}: `frames` is {other:?}"),
        }
    }
    assert_eq!(
        made,
        [
            "blur",
            "composite",
            "depth_prepass",
            "distance_map",
            "group_unpack",
            "pcf",
            "pcss",
            "reference",
            "resolve",
            "tile_classify",
            "variable_pcf"
        ]
    );
}

/// The passes over a group of lights' tile lists in one dispatch
/// (`penumbra::shaders::with_light_groups`): the variable PCF and both blur axes validate with
/// their intermediates as arrays, every read and write of them takes a layer, the frame is
/// read as one of several, and the pass that computes their dispatch validates as it is.
#[test]
fn passes_over_a_group_of_lights_validate() {
    use penumbra::shaders::{BLUR_GROUP_LAYERS, PCF_GROUP_LAYERS, with_light_groups};
    let cases = [
        (
            "variable_pcf",
            penumbra::shaders::VARIABLE_PCF,
            &PCF_GROUP_LAYERS[..],
        ),
        (
            "blur horizontal",
            penumbra::shaders::BLUR,
            &BLUR_GROUP_LAYERS[0][..],
        ),
        (
            "blur vertical",
            penumbra::shaders::BLUR,
            &BLUR_GROUP_LAYERS[1][..],
        ),
        (
            "group_unpack",
            penumbra::shaders::GROUP_UNPACK,
            &penumbra::shaders::UNPACK_GROUP_LAYERS[..],
        ),
    ];
    for (name, source, layers) in cases {
        let grouped = with_light_groups(source, layers).unwrap_or_else(|| panic!("{name}: not grouped"));
        let module = validate(name, &grouped);
        assert!(grouped.contains("var<storage, read> group_lists"), "{name}");
        assert!(!grouped.contains("tile_list:"), "{name} still binds one list");
        for (texture, layer) in layers {
            let (_, var) = module
                .global_variables
                .iter()
                .find(|(_, v)| v.name.as_deref() == Some(*texture))
                .unwrap_or_else(|| panic!("{name} has no `{texture}`"));
            match module.types[var.ty].inner {
                naga::TypeInner::Image { arrayed, .. } => {
                    assert!(arrayed, "{name}: `{texture}` is not an array")
                }
                ref other => panic!("{name}: `{texture}` is {other:?}"),
            }
            // Each call on the texture names its layer: a pooled texture's its pixel's in the
            // pool (`pool_pixel` and `pool_layer`, or where `pool_place` found it).
            let expected: &[&str] = match *layer {
                penumbra::shaders::POOLED => &["pool_pixel(", "pool_layer()"],
                penumbra::shaders::POOLED_ANYWHERE => &["at.xy, at.z"],
                other => &[other],
            };
            let mut calls = 0;
            for call in ["textureLoad(", "textureStore(", "textureSampleLevel("] {
                for (at, _) in grouped.match_indices(&format!("{call}{texture},")) {
                    let line = grouped[at..].lines().next().unwrap_or_default();
                    for part in expected {
                        assert!(line.contains(part), "{name}: `{line}` takes no {part}");
                    }
                    calls += 1;
                }
            }
            assert!(calls > 0, "{name}: no call on `{texture}`");
            // A texture read anywhere is read only through the map.
            if *layer == penumbra::shaders::POOLED_ANYWHERE {
                assert!(grouped.contains(&format!("pooled_{texture}(")), "{name}");
            }
        }
    }
    // No tile list to group: none.
    assert!(with_light_groups(penumbra::shaders::COMPOSITE, &[]).is_none());
    // A texture the pass does not declare: none.
    assert!(with_light_groups(penumbra::shaders::BLUR, &[("no_such", "member")]).is_none());
    validate("group_args", penumbra::shaders::GROUP_ARGS);
    // The tile classification over a group: its textures arrays, every call on them with its
    // layer, each member's list appended in its region of the group's, none turned away.
    let source = penumbra::shaders::TILE_CLASSIFY;
    let grouped = penumbra::shaders::with_light_group_classification(source).expect("the classification");
    let module = validate("tile_classify (group)", &grouped);
    for (texture, layer) in penumbra::shaders::CLASSIFY_GROUP_LAYERS {
        let (_, var) = module
            .global_variables
            .iter()
            .find(|(_, v)| v.name.as_deref() == Some(texture))
            .unwrap_or_else(|| panic!("the group's classification has no `{texture}`"));
        assert!(
            matches!(
                module.types[var.ty].inner,
                naga::TypeInner::Image { arrayed: true, .. }
            ),
            "`{texture}` is not an array"
        );
        for call in ["textureLoad(", "textureStore("] {
            for (at, _) in grouped.match_indices(&format!("{call}{texture},")) {
                let line = grouped[at..].lines().next().unwrap_or_default();
                assert!(line.contains(layer), "`{line}` takes no layer");
            }
        }
    }
    // Each listed tile appended to its member's list, and its index in the member's map; every
    // tile's entry in the map set first (not listed, or turned away).
    assert!(grouped.contains("atomicStore(&group_lists[member_list() + 2u + at], packed);"));
    assert!(grouped.contains("atomicStore(&group_lists[tile_map(tile)], at);"));
    assert!(grouped.contains("atomicStore(&group_lists[tile_map(tile)], select("));
    assert!(!grouped.contains("away_out.tiles[atomicAdd("));
    assert!(grouped.contains("use_member(group.z)") && grouped.contains("use_member(id.z)"));
    assert!(penumbra::shaders::with_light_group_classification(penumbra::shaders::BLUR).is_none());
}
