//! The baseline's screen-space chain: fixed-spacing PCF, a fixed Gaussian blur, a resolve. As
//! compute passes over the screen ([`TraditionalChain`]), or as draws
//! ([`TraditionalDrawChain`]).

use super::screen_chain::{ChainKey, MethodChain, Recorder, ScreenInputs, stage_lists};
use crate::chain::{Chain, FRAME_SIZE};
use crate::frame::PassParams;
use crate::pipeline_cache::CachedDevice;
use crate::screen::{
    BlurCompute, BlurInput, BlurPass, Cleared, ComputeTargets, PassPath, PcfPass, ResolvePass, ScreenStage,
    TileListTargets, VisibilityPass,
};
use crate::shaders::HalfFloats;

/// The baseline as compute passes over the screen (every tile listed); the blur writes the
/// layer, the resolve only without a blur.
pub(crate) struct TraditionalChain {
    pcf: PcfPass,
    blur: Option<BlurCompute>,
    resolve: ResolvePass,
    /// The shared intermediates, as bound.
    targets: Option<ComputeTargets>,
}

impl TraditionalChain {
    /// What the chain is made for: the PCF's switches, the blur's and whether it writes the
    /// layer.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey::bare(chain, kind).pcf(params).blur(params, true)
    }

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        let half = key.half_floats();
        // The PCF writes the intermediate visibility, never the layer (the blur or the
        // resolve does).
        let pcf_path = PassPath::compute(
            HalfFloats {
                layers: false,
                ..half
            },
            key.map_arrays,
        );
        Self {
            pcf: PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, pcf_path),
            blur: key
                .blur
                .map(|s| BlurCompute::new(device, FRAME_SIZE, s, half, (false, false))),
            resolve: ResolvePass::new(device, FRAME_SIZE),
            targets: None,
        }
    }
}

impl MethodChain for TraditionalChain {
    stage_lists!(pcf, resolve; blur);

    fn unbind(&mut self) {
        self.targets = None;
    }

    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        let (frame, [depth, mask, dummy]) = inputs.common();
        // The compute path's targets hold a visibility wherever a chain other than the
        // distance-map method's writing its layer runs (`ComputeNeeds`).
        let Some((all, shared)) = inputs.compute.and_then(|c| Some((c, c.visibility.as_ref()?))) else {
            return;
        };
        self.targets = Some(all.clone());
        let shadow_map = &inputs.views.shadow;
        self.pcf
            .lookup_mut()
            .bind(device, (frame, depth, shadow_map), Some(shared), None);
        let visibility = &shared.view;
        match (&mut self.blur, &all.blurred) {
            (Some(blur), Some(blurred)) => {
                let read = (visibility, dummy, dummy);
                blur.bind(device, &blurred.view, frame, (depth, mask), read, inputs.layer)
            }
            _ => self.resolve.bind(device, frame, [depth, dummy, visibility, mask]),
        }
    }

    fn encode(&self, recorder: &mut Recorder) {
        recorder.pass("pcf", |e| self.pcf.lookup().encode(e));
        let targets = self.targets.as_ref();
        let listed = targets
            .and_then(|t| t.every_tile.as_ref())
            .map(TileListTargets::listed);
        let layer = recorder.layer;
        match (&self.blur, listed, targets) {
            (Some(blur), Some(listed), Some(targets)) => recorder.pass("blur", |e| {
                targets.clear(e, Cleared::Blurred);
                blur.encode(e, listed, (None, false), layer)
            }),
            _ => recorder.pass("resolve", |e| self.resolve.encode(e, layer)),
        }
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pcf.lookup().visibility_texture()
    }
}

/// The baseline as draws.
pub(crate) struct TraditionalDrawChain {
    pcf: PcfPass,
    blur: Option<BlurPass>,
    resolve: ResolvePass,
}

impl TraditionalDrawChain {
    /// What the chain is made for: the PCF's switches and the blur's.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey::bare(chain, kind).pcf(params).blur(params, false)
    }

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        Self {
            pcf: PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, PassPath::DRAW),
            blur: key.blur.map(|s| BlurPass::new(device, FRAME_SIZE, s)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl MethodChain for TraditionalDrawChain {
    stage_lists!(pcf, resolve; blur);

    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        let (frame, [depth, mask, dummy]) = inputs.common();
        let shadow_map = &inputs.views.shadow;
        self.pcf
            .lookup_mut()
            .bind(device, (frame, depth, shadow_map), None, None);
        let Some(mut visibility) = self.pcf.lookup().visibility() else {
            return;
        };
        if let Some(blur) = &mut self.blur {
            let (distance_map, blur_sigma) = (dummy, dummy);
            let input = BlurInput {
                visibility,
                distance_map,
                blur_sigma,
            };
            blur.bind(device, frame, (depth, mask), &input);
            visibility = blur.blurred().unwrap_or(visibility);
        }
        self.resolve.bind(device, frame, [depth, dummy, visibility, mask]);
    }

    fn encode(&self, recorder: &mut Recorder) {
        recorder.pass("pcf", |e| self.pcf.lookup().encode(e));
        let layer = recorder.layer;
        if let Some(blur) = &self.blur {
            recorder.pass("blur", |e| blur.encode(e, None, layer));
        }
        recorder.pass("resolve", |e| self.resolve.encode(e, layer));
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pcf.lookup().visibility_texture()
    }

    fn blurred_visibility(&self) -> Option<&wgpu::Texture> {
        self.blur.as_ref().and_then(BlurPass::blurred_texture)
    }
}
