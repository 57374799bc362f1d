//! The lights: each camera's lights given to its `Shadows`, and the light table its main pass
//! reads (which of Bevy's lights each visibility layer belongs to).

use super::*;

/// Adds, changes and removes penumbra's lights in each camera's shadows, and fills each
/// camera's light table.
pub(super) fn sync_lights(
    state: &mut PenumbraState,
    extracted: &Extracted,
    device: &wgpu::Device,
    clustered: Option<&GlobalClusterableObjectMeta>,
) {
    let mut messages = Vec::new();
    for camera in &extracted.cameras {
        let Some(view) = state.views.get_mut(&camera.render_entity) else {
            continue;
        };
        // Every light, whatever the camera's layers: Bevy 0.20 lights a view with a spot or
        // point light on another layer once some camera sees that light (seen in
        // `tests/plugin.rs`), and penumbra takes away what Bevy lights.
        let lights: Vec<&ExtractedLight> = extracted.lights.iter().collect();
        let ids = sync_view_lights(view, &lights, device, &mut messages);
        let mut table = GpuLights::default();
        view.layers.clear();
        for (extracted, id) in lights.iter().zip(&ids) {
            let Some(id) = id else { continue };
            let Some(row) = table_row(extracted, *id, clustered) else {
                // Not in Bevy's light list this frame. Bevy lists rectangle lights only where
                // it clusters them (with storage buffers): elsewhere it always leaves them out.
                if matches!(extracted.light, Light::Rect(_)) {
                    messages.push(format!(
                        "penumbra: {} is not among Bevy's clustered lights (it clusters \
                         rectangle lights only with storage buffers, and only visible ones): not shadowed",
                        extracted.label
                    ));
                }
                continue;
            };
            table.lights[table.count as usize] = row;
            table.count += 1;
            view.layers.push(id.layer());
        }
        view.table = table;
    }
    for message in messages {
        state.log_once(message);
    }
}

/// One camera's lights brought in step with `lights`: each light's id (`None` where it was
/// refused, with why in `messages`).
pub(super) fn sync_view_lights(
    view: &mut ViewShadows,
    lights: &[&ExtractedLight],
    device: &wgpu::Device,
    messages: &mut Vec<String>,
) -> Vec<Option<LightId>> {
    let shadows = &mut view.shadows;
    let alive: HashSet<Entity> = lights.iter().map(|l| l.entity).collect();
    view.lights.retain(|entity, (id, ..)| {
        let keep = alive.contains(entity);
        if !keep {
            let _ = shadows.remove_light(*id);
        }
        keep
    });
    lights
        .iter()
        .map(|extracted| {
            let id = match view.lights.get_mut(&extracted.entity) {
                Some((id, light, mask)) => {
                    if *light != extracted.light {
                        if let Err(e) = shadows.set_light(*id, extracted.light) {
                            messages.push(format!("penumbra: {}: {e}", extracted.label));
                            return None;
                        }
                        *light = extracted.light;
                    }
                    if *mask != extracted.mask {
                        // Its casters are those sharing a render layer with it.
                        if let Err(e) = shadows.set_light_layers(*id, extracted.mask) {
                            messages.push(format!("penumbra: {}: {e}", extracted.label));
                            return None;
                        }
                        *mask = extracted.mask;
                    }
                    *id
                }
                None => {
                    let added = shadows
                        .add_light(device, extracted.light)
                        .and_then(|id| shadows.set_light_layers(id, extracted.mask).map(|()| id));
                    match added {
                        Ok(id) => {
                            view.lights
                                .insert(extracted.entity, (id, extracted.light, extracted.mask));
                            id
                        }
                        Err(e) => {
                            messages.push(format!("penumbra: {}: {e}", extracted.label));
                            return None;
                        }
                    }
                }
            };
            Some(id)
        })
        .collect()
}

/// A light's row of the material's table: which of Bevy's lights it is, and its layer.
pub(super) fn table_row(
    extracted: &ExtractedLight,
    id: LightId,
    clustered: Option<&GlobalClusterableObjectMeta>,
) -> Option<GpuLight> {
    let (kind, index, direction) = match extracted.light {
        Light::Directional(sun) => (KIND_DIRECTIONAL, 0, -sun.direction.normalize()),
        _ => {
            // Bevy's index among its clustered lights (a rectangle light is there only where
            // Bevy clusters them: with storage buffers).
            let index = clustered?.entity_to_index.get(&extracted.render_entity)?;
            let kind = match extracted.light {
                Light::Spot(_) => KIND_SPOT,
                Light::Rect(_) => KIND_RECT,
                _ => KIND_POINT,
            };
            (kind, *index as u32, glam::Vec3::ZERO)
        }
    };
    Some(GpuLight {
        kind,
        index,
        layer: id.layer(),
        _pad: 0,
        direction_to_light: direction.extend(0.0).to_array(),
    })
}
