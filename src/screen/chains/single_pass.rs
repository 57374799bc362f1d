//! The chains of one screen-space pass: PCSS (its blocker search and filter in one pass) and
//! hard shadows (one PCF tap), each followed by a resolve unless its compute pass writes the
//! light's layer itself.

use super::screen_chain::{ChainKey, MethodChain, Recorder, ScreenInputs, stage_lists};
use crate::chain::{Chain, FRAME_SIZE};
use crate::frame::PassParams;
use crate::pipeline_cache::CachedDevice;
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

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        let pass = PcssPass::new(device, FRAME_SIZE, key.kind, key.path());
        Self::with(device, pass)
    }
}

impl HardChain {
    /// What the chain is made for: the PCF's switches and whether its compute pass writes the
    /// layer.
    pub fn key(chain: Chain, params: &PassParams, kind: u32) -> ChainKey {
        ChainKey {
            layer_writes: chain.compute() && params.layer_writes,
            ..ChainKey::bare(chain, kind).pcf(params)
        }
    }

    pub fn new(device: &CachedDevice<'_>, key: &ChainKey) -> Self {
        let pass = PcfPass::new(device, FRAME_SIZE, key.pcf, key.kind, key.path());
        Self::with(device, pass)
    }
}

impl<P> SinglePassChain<P> {
    fn with(device: &CachedDevice<'_>, pass: P) -> Self {
        Self {
            pass,
            resolve: ResolvePass::new(device, FRAME_SIZE),
        }
    }
}

impl<P: VisibilityPass + wgpu::WasmNotSendSync> MethodChain for SinglePassChain<P> {
    stage_lists!(pass, resolve);

    fn bind(&mut self, device: &CachedDevice<'_>, inputs: &ScreenInputs) {
        let (frame, [depth, mask, dummy]) = inputs.common();
        let shared = inputs.compute.and_then(|c| c.visibility.as_ref());
        let layer = inputs.layer.map(|l| (l, mask));
        let shadow_map = &inputs.views.shadow;
        self.pass
            .lookup_mut()
            .bind(device, (frame, depth, shadow_map), shared, layer);
        if let Some(visibility) = self.pass.lookup().visibility() {
            self.resolve.bind(device, frame, [depth, dummy, visibility, mask]);
        }
    }

    fn encode(&self, recorder: &mut Recorder) {
        recorder.pass(P::NAME, |e| self.pass.lookup().encode(e));
        if !self.pass.lookup().writes_layers() {
            let layer = recorder.layer;
            recorder.pass("resolve", |e| self.resolve.encode(e, layer));
        }
    }

    fn raw_visibility(&self) -> Option<&wgpu::Texture> {
        self.pass.lookup().visibility_texture()
    }
}
