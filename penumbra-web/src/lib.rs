//! penumbra's demo in a browser: the project's scenes under WebGPU, with the methods, the
//! light's size and direction, and a frame-rate readout. `static/index.html` is the page; the
//! module draws into its canvas every animation frame through [`penumbra::Renderer`].
//!
//! Build and serve it with `cargo run -p penumbra-web --bin serve` (see `docs/web.md`). The page
//! reads its first settings from the address's query (`?scene=teapot&view=0&method=ours`), so a
//! link or a test can open a given view.
//!
//! Natively the library is empty (the serve command needs none of it); its unit tests build it
//! natively.
#![cfg(any(target_arch = "wasm32", test))]

use penumbra::{Light, Scene, SceneFile, ShadowMethod};

/// The scenes the page offers, by name, with their scene files (built in: the page has no file
/// system). Each is made of the renderer's own primitives, no model file.
pub const SCENES: [(&str, &str); 3] = [
    ("teapot", include_str!("../../assets/scenes/teapot.ron")),
    ("character", include_str!("../../assets/scenes/character.ron")),
    ("room", include_str!("../../assets/scenes/room.ron")),
];

/// The methods the page offers: the real-time ones a user compares.
pub const METHODS: [ShadowMethod; 4] = [
    ShadowMethod::Ours,
    ShadowMethod::Pcss,
    ShadowMethod::Traditional,
    ShadowMethod::Hard,
];

/// What the page asks for: a scene and view, a method, and the light.
#[derive(Debug, Clone, PartialEq)]
pub struct Choice {
    /// One of [`SCENES`]' names.
    pub scene: String,
    /// The scene's viewpoint.
    pub view: usize,
    /// One of [`METHODS`].
    pub method: ShadowMethod,
    /// The light's size relative to the scene file's: 1 keeps it.
    pub light_scale: f32,
    /// The light's direction turned about the vertical axis, degrees (suns and spots).
    pub turn_deg: f32,
    /// The split view's right side: another of [`METHODS`], or none (one method over the
    /// whole canvas). Default: the traditional baseline, as in the native demo.
    pub compare: Option<ShadowMethod>,
    /// Where the split view divides the canvas, as a share of its width from the left.
    pub divider: f32,
}

impl Default for Choice {
    fn default() -> Self {
        Self {
            scene: "teapot".into(),
            view: 0,
            method: ShadowMethod::Ours,
            light_scale: 1.0,
            turn_deg: 0.0,
            compare: Some(ShadowMethod::Traditional),
            divider: 0.5,
        }
    }
}

impl Choice {
    /// Reads `scene`, `view`, `method`, `light` (scale), `turn`, `compare` (a method or
    /// `none`) and `divider` (0 to 1) from an address's query string (`?scene=room&method=pcss`);
    /// a key missing keeps its default, a bad value is an error naming the key.
    pub fn from_query(query: &str) -> Result<Self, String> {
        let mut choice = Self::default();
        for pair in query.trim_start_matches('?').split('&').filter(|p| !p.is_empty()) {
            let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
            let bad = |why: &str| format!("the address's `{key}={value}`: {why}");
            match key {
                "scene" => {
                    if !SCENES.iter().any(|(name, _)| *name == value) {
                        return Err(bad("no such scene; choose teapot, character or room"));
                    }
                    choice.scene = value.into();
                }
                "view" => choice.view = value.parse().map_err(|_| bad("expected 0, 1 or 2"))?,
                "method" => choice.method = offered(value).map_err(|e| bad(&e))?,
                "compare" => {
                    choice.compare = match value {
                        "" | "none" => None,
                        v => Some(offered(v).map_err(|e| bad(&e))?),
                    }
                }
                "divider" => {
                    choice.divider = value
                        .parse()
                        .ok()
                        .filter(|d: &f32| (0.0..=1.0).contains(d))
                        .ok_or_else(|| bad("expected a share of the width in [0, 1]"))?
                }
                "light" => {
                    choice.light_scale = value
                        .parse()
                        .ok()
                        .filter(|s: &f32| s.is_finite() && *s > 0.0 && *s <= 8.0)
                        .ok_or_else(|| bad("expected a scale in (0, 8]"))?
                }
                "turn" => {
                    choice.turn_deg = value
                        .parse()
                        .ok()
                        .filter(|t: &f32| t.is_finite())
                        .ok_or_else(|| bad("expected degrees"))?
                }
                _ => {}
            }
        }
        Ok(choice)
    }
}

/// The address's `frames=N`: draw N frames, then stop (a still, for a screenshot: a software
/// GPU takes seconds a frame, and the browser gives up waiting for a screenshot behind one).
/// `None` without it: draw on.
pub fn frame_limit(query: &str) -> Result<Option<u32>, String> {
    for pair in query.trim_start_matches('?').split('&') {
        if let Some(value) = pair.strip_prefix("frames=") {
            return value
                .parse()
                .ok()
                .filter(|n: &u32| *n > 0)
                .map(Some)
                .ok_or_else(|| {
                    format!("the address's `frames={value}`: expected a number of frames, at least 1")
                });
        }
    }
    Ok(None)
}

/// The method `name`, if the page offers it.
fn offered(name: &str) -> Result<ShadowMethod, String> {
    let method = ShadowMethod::from_name(name).map_err(|e| e.to_string())?;
    if !METHODS.contains(&method) {
        return Err("the page offers ours, pcss, traditional and hard".into());
    }
    Ok(method)
}

/// The columns of a `width`-pixel canvas the split view's right side covers: from the divider
/// to the right edge (empty without a comparison).
pub fn right_side(choice: &Choice, width: u32) -> std::ops::Range<u32> {
    match choice.compare {
        None => width..width,
        Some(_) => ((choice.divider * width as f32).round() as u32).min(width)..width,
    }
}

/// Builds the scene `name` from its built-in scene file.
pub fn scene(name: &str) -> Result<Scene, String> {
    let (_, text) = SCENES
        .iter()
        .find(|(n, _)| *n == name)
        .ok_or_else(|| format!("no scene `{name}`"))?;
    let path = std::path::PathBuf::from(format!("{name}.ron"));
    let file = SceneFile::parse(text, &path).map_err(|e| e.to_string())?;
    file.build(std::path::Path::new(""), &path)
        .map_err(|e| e.to_string())
}

/// `light` with its size scaled by `scale` (a rectangle's both sides) and the way it shines
/// turned `turn_deg` about the vertical axis (suns, spots, rectangles and disks; every light
/// keeps its position, and a point light has no direction to turn).
pub fn adjusted_light(light: &Light, scale: f32, turn_deg: f32) -> Light {
    let turn = glam::Quat::from_rotation_y(turn_deg.to_radians());
    match *light {
        Light::Directional(mut l) => {
            l.angular_diameter_deg = (l.angular_diameter_deg * scale).min(60.0);
            l.direction = turn * l.direction;
            Light::Directional(l)
        }
        Light::Spot(mut l) => {
            l.radius *= scale;
            l.direction = turn * l.direction;
            Light::Spot(l)
        }
        Light::Point(mut l) => {
            l.radius *= scale;
            Light::Point(l)
        }
        Light::Rect(mut l) => {
            l.width *= scale;
            l.height *= scale;
            l.up = turn * penumbra::scene::light_axes(l.direction, l.up).1;
            l.direction = turn * l.direction;
            Light::Rect(l)
        }
        Light::Disk(mut l) => {
            l.radius *= scale;
            l.direction = turn * l.direction;
            Light::Disk(l)
        }
    }
}

#[cfg(target_arch = "wasm32")]
mod web;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_limit_comes_from_the_address() {
        assert_eq!(frame_limit("?scene=room&frames=3"), Ok(Some(3)));
        assert_eq!(frame_limit("?scene=room"), Ok(None));
        assert!(frame_limit("?frames=0").unwrap_err().contains("frames=0"));
        assert!(frame_limit("?frames=x").is_err());
    }

    #[test]
    fn every_scene_builds_from_its_built_in_file() {
        for (name, _) in SCENES {
            let s = scene(name).unwrap();
            assert!(!s.instances.is_empty(), "{name}");
            assert!(s.view(0).is_ok(), "{name}");
        }
    }

    #[test]
    fn the_query_sets_the_choice_and_names_a_bad_key() {
        let c =
            Choice::from_query("?scene=room&view=1&method=pcss&light=2&turn=30&compare=hard&divider=0.25")
                .unwrap();
        assert_eq!(c.compare, Some(ShadowMethod::Hard));
        assert_eq!(c.divider, 0.25);
        assert_eq!(right_side(&c, 800), 200..800);
        assert_eq!(right_side(&Choice::default(), 800), 400..800);
        assert_eq!(
            right_side(&Choice::from_query("?compare=none").unwrap(), 800),
            800..800
        );
        assert!(Choice::from_query("?compare=reference").is_err());
        assert!(Choice::from_query("?divider=2").is_err());
        assert_eq!(Choice::from_query("?compare=none").unwrap().compare, None);
        assert_eq!(c.scene, "room");
        assert_eq!(c.view, 1);
        assert_eq!(c.method, ShadowMethod::Pcss);
        assert_eq!(c.light_scale, 2.0);
        assert_eq!(c.turn_deg, 30.0);
        assert_eq!(Choice::from_query("").unwrap(), Choice::default());
        let e = Choice::from_query("?method=vsm").unwrap_err();
        assert!(e.contains("method=vsm"), "{e}");
        let e = Choice::from_query("?method=reference").unwrap_err();
        assert!(e.contains("ours, pcss"), "{e}");
        let e = Choice::from_query("?scene=moon").unwrap_err();
        assert!(e.contains("scene=moon"), "{e}");
        assert!(Choice::from_query("?light=0").is_err());
    }

    #[test]
    fn the_light_scales_and_turns() {
        let s = scene("teapot").unwrap();
        let Light::Directional(before) = s.light else {
            panic!("the teapot's light is a sun")
        };
        let Light::Directional(after) = adjusted_light(&s.light, 2.0, 90.0) else {
            unreachable!()
        };
        assert!((after.angular_diameter_deg - 2.0 * before.angular_diameter_deg).abs() < 1e-5);
        assert!((after.direction.y - before.direction.y).abs() < 1e-5);
        assert!(after.direction.dot(before.direction) < before.direction.y.powi(2) + 1e-3);
    }
}
