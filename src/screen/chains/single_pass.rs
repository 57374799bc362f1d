//! The chains of one screen-space pass: PCSS (its blocker search and filter in one pass) and
//! hard shadows (one PCF tap), each followed by a resolve unless its compute pass writes the
//! light's layer itself.

use super::screen_chain::{ChainKey, Mark, MethodChain, ScreenInputs};
use crate::chain::{Chain, FRAME_SIZE, run};
use crate::frame::PassParams;
use crate::screen::{PcfPass, PcssPass, ResolvePass, ScreenStage, VisibilityPass};

/// One screen-space pass, then a resolve unless the pass writes the layer.
pub(crate) struct SinglePassChain<P> {
    pass: P,
    resolve: ResolvePass,
}

/// PCSS's chain.
pub(crate) type PcssChain = SinglePassChain<PcssPass>;
/// The screen-space hard shadows' chain.
pub(crate) type HardChain = SinglePassChain<PcfPass>;

impl PcssChain {
    /// What the chain is made for: whether its compute pass writes the layer.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey {
            layer_writes: chain.compute() && params.layer_writes,
            ..ChainKey::bare(chain, kind)
        }
    }

    pub fn new(device: &wgpu::Device, key: &ChainKey) -> Self {
        let compute = key.chain.compute();
        Self {
            pass: PcssPass::new(device, FRAME_SIZE, key.kind, (compute, key.layer_writes)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl HardChain {
    /// What the chain is made for: the PCF's switches and whether its compute pass writes the
    /// layer.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey {
            pcf: params.pcf_switches,
            layer_writes: chain.compute() && params.layer_writes,
            ..ChainKey::bare(chain, kind)
        }
    }

    pub fn new(device: &wgpu::Device, key: &ChainKey) -> Self {
        let compute = key.chain.compute();
        Self {
            pass: PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, (compute, key.layer_writes)),
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl<P: VisibilityPass + wgpu::WasmNotSendSync> MethodChain for SinglePassChain<P> {
    fn stages(&self) -> Vec<&dyn ScreenStage> {
        vec![&self.pass, &self.resolve]
    }

    fn stages_mut(&mut self) -> Vec<&mut dyn ScreenStage> {
        vec![&mut self.pass, &mut self.resolve]
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
        let shared = compute.map(|c| &c.visibility);
        let shadow_map = maps.shadow.atlas.view();
        self.pass
            .bind(device, frame, depth, shadow_map, shared, layer.map(|l| (l, mask)));
        if let Some(visibility) = self.pass.visibility() {
            self.resolve.bind(device, frame, depth, dummy, visibility, mask);
        }
    }

    fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        _maps_drawn: bool,
        layer: &wgpu::TextureView,
        mark: Mark,
    ) {
        run(encoder, mark, P::NAME, &|e| self.pass.encode(e));
        if !self.pass.writes_layers() {
            run(encoder, mark, "resolve", &|e| self.resolve.encode(e, layer));
        }
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pass.visibility_texture()
    }
}
