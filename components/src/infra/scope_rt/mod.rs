//! `scope_rt`: the realtime half of halscope. `loadrt scope_rt
//! [num_samples=N]` makes a shared region of `N` sample words and the
//! function `scope.sample`, which a configuration adds to a thread
//! (`addf scope.sample servo-thread`). halscope, in another process,
//! writes a capture's settings into the region (channels, sample rate
//! multiplier, trigger, record length) and arms it; `scope.sample`
//! records into the ring and says when the record is complete.
//!
//! Modules: [`layout`] (the shared region, both sides), `sample` (the
//! realtime state machine).

pub mod layout;
mod sample;

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{HalError, Host, Result};

use layout::{DEFAULT_NUM_SAMPLES, HEADER_WORDS, MAX_NUM_SAMPLES, REGION};

const PARAMS: &[ParamDecl] = &[ParamDecl {
    name: "num_samples",
    kind: ParamKind::Long,
    help: "Number of samples in the shared memory block",
}];

/// The `scope_rt` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "scope_rt",
    params: PARAMS,
    help: "the realtime half of halscope: samples up to 16 channels into shared memory",
    load,
};

/// `num_samples`, checked: 1 to [`MAX_NUM_SAMPLES`].
fn num_samples(args: &ModuleArgs) -> Result<u64> {
    let n = args.int("num_samples").unwrap_or(DEFAULT_NUM_SAMPLES);
    if !(1..=MAX_NUM_SAMPLES).contains(&n) {
        return Err(HalError::ModuleParam {
            module: "scope_rt".into(),
            param: "num_samples".into(),
            reason: format!("{n}: give 1 to {MAX_NUM_SAMPLES} sample words"),
        });
    }
    Ok(n as u64)
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let buf_len = num_samples(args)?;
    let mut b = host.new_rt_component("scope_rt")?;
    let region = b
        .component()
        .region(REGION, (HEADER_WORDS + buf_len as usize) * 8)?;
    layout::init(region.words(), buf_len);
    let mut sampler = sample::Sampler::new(region);
    b.funct("scope.sample", false, move |ctx| sampler.run(ctx.period()))?;
    b.ready()
}

#[cfg(test)]
mod tests;
