//! The baseline's screen-space chain: fixed-spacing PCF, a fixed Gaussian blur, a resolve. As
//! compute passes over the screen ([`TraditionalChain`]), or as draws
//! ([`TraditionalDrawChain`]).

use super::screen_chain::{ChainKey, Mark, MethodChain, ScreenInputs, with_blur};
use crate::chain::{Chain, FRAME_SIZE, run};
use crate::frame::PassParams;
use crate::screen::{
    BlurCompute, BlurInput, BlurPass, Cleared, ComputeTargets, PcfPass, ResolvePass, ScreenStage,
    TileListTargets, VisibilityPass,
};

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
        let blur = chain.blur();
        ChainKey {
            pcf: params.pcf_switches,
            blur: blur.then_some(params.blur_switches),
            layer_writes: blur && params.layer_writes,
            ..ChainKey::bare(chain, kind)
        }
    }

    pub fn new(device: &wgpu::Device, key: &ChainKey) -> Self {
        Self {
            pcf: PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, (true, false)),
            blur: key
                .blur
                .map(|switches| BlurCompute::new(device, FRAME_SIZE, switches, key.layer_writes)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
            targets: None,
        }
    }
}

impl MethodChain for TraditionalChain {
    fn stages(&self) -> Vec<&dyn ScreenStage> {
        with_blur(vec![&self.pcf, &self.resolve], self.blur.as_ref().map(|b| b as _))
    }

    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
        with_blur(
            vec![&mut self.pcf, &mut self.resolve],
            self.blur.as_mut().map(|b| b as _),
        )
    }

    fn unbind(&mut self) {
        self.targets = None;
    }

    fn bind(&mut self, device: &wgpu::Device, inputs: &ScreenInputs) {
        let ScreenInputs {
            frame,
            depth,
            mask,
            maps,
            dummy,
            compute,
            layer,
        } = *inputs;
        let Some(all) = compute else {
            return;
        };
        self.targets = Some(all.clone());
        let shadow_map = maps.shadow.atlas.view();
        self.pcf
            .bind(device, frame, depth, shadow_map, Some(&all.visibility), None);
        let visibility = &all.visibility.view;
        match (&mut self.blur, &all.blurred) {
            (Some(blur), Some(blurred)) => blur.bind(
                device,
                &blurred.view,
                frame,
                (depth, mask),
                (visibility, dummy, dummy),
                layer,
            ),
            _ => self.resolve.bind(device, frame, depth, dummy, visibility, mask),
        }
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        _maps_drawn: bool,
        layer: &wgpu::TextureView,
        mark: Mark,
    ) {
        run(encoder, mark, "pcf", &|e| self.pcf.encode(e));
        let targets = self.targets.as_ref();
        let listed = targets
            .and_then(|t| t.every_tile.as_ref())
            .map(TileListTargets::listed);
        match (&self.blur, listed, targets) {
            (Some(blur), Some(listed), Some(targets)) => run(encoder, mark, "blur", &|e| {
                targets.clear(e, Cleared::Blurred);
                blur.encode(e, listed, (None, false), layer)
            }),
            _ => run(encoder, mark, "resolve", &|e| self.resolve.encode(e, layer)),
        }
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pcf.visibility_texture()
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
        ChainKey {
            pcf: params.pcf_switches,
            blur: chain.blur().then_some(params.blur_switches),
            ..ChainKey::bare(chain, kind)
        }
    }

    pub fn new(device: &wgpu::Device, key: &ChainKey) -> Self {
        Self {
            pcf: PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, (false, false)),
            blur: key
                .blur
                .map(|switches| BlurPass::new(device, FRAME_SIZE, switches)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl MethodChain for TraditionalDrawChain {
    fn stages(&self) -> Vec<&dyn ScreenStage> {
        with_blur(vec![&self.pcf, &self.resolve], self.blur.as_ref().map(|b| b as _))
    }

    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
        with_blur(
            vec![&mut self.pcf, &mut self.resolve],
            self.blur.as_mut().map(|b| b as _),
        )
    }

    fn bind(&mut self, device: &wgpu::Device, inputs: &ScreenInputs) {
        let ScreenInputs {
            frame,
            depth,
            mask,
            maps,
            dummy,
            ..
        } = *inputs;
        self.pcf
            .bind(device, frame, depth, maps.shadow.atlas.view(), None, None);
        let Some(mut visibility) = self.pcf.visibility() else {
            return;
        };
        if let Some(blur) = &mut self.blur {
            let input = BlurInput {
                visibility,
                distance_map: dummy,
                blur_sigma: dummy,
            };
            blur.bind(device, frame, (depth, mask), &input);
            visibility = blur.blurred().unwrap_or(visibility);
        }
        self.resolve.bind(device, frame, depth, dummy, visibility, mask);
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        _maps_drawn: bool,
        layer: &wgpu::TextureView,
        mark: Mark,
    ) {
        run(encoder, mark, "pcf", &|e| self.pcf.encode(e));
        if let Some(blur) = &self.blur {
            run(encoder, mark, "blur", &|e| blur.encode(e, None, layer));
        }
        run(encoder, mark, "resolve", &|e| self.resolve.encode(e, layer));
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pcf.visibility_texture()
    }

    fn blurred_visibility(&self) -> Option<&wgpu::Texture> {
        self.blur.as_ref().and_then(BlurPass::blurred_texture)
    }
}
