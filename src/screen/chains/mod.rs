//! Each method's screen-space chain, one struct per method (and path: compute or draws), built
//! from a [`ChainKey`]: it owns its passes, connects them and records them in order. A light
//! holds its chain as a [`ScreenChain`].
//!
//! | chain | method | passes |
//! |---|---|---|
//! | [`ours::OursChain`] | `ours`, compute | tile list (+ distance map), variable PCF, blur or resolve |
//! | [`ours::OursDrawChain`] | `ours`, draws | distance map, variable PCF, blur or resolve |
//! | [`traditional::TraditionalChain`] | the baseline, compute | PCF, blur or resolve |
//! | [`traditional::TraditionalDrawChain`] | the baseline, draws | PCF, blur, resolve |
//! | [`single_pass::PcssChain`] | PCSS | PCSS, resolve unless it writes the layer |
//! | [`single_pass::HardChain`] | hard shadows | one PCF tap, resolve unless it writes the layer |

mod ours;
mod screen_chain;
mod single_pass;
mod traditional;

pub(crate) use screen_chain::{ChainKey, Mark, ScreenChain, ScreenInputs};
