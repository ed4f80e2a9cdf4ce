//! A host-free stepgen: the three functions over plain values, in the
//! same arrangement as the HAL glue (shared DDS registers, the
//! module-wide periods, parameters that the functions rewrite). The one
//! entry point for tests and benchmarks that run stepgen without a host.

use super::freq::{self, FreqCtl, FreqParams, FreqTiming, INITIAL_PERIOD_NS, INITIAL_SCALE_CACHE};
use super::pulses::{Dds, PulseGen, PulseTiming};
use super::ChannelConfig;
use crate::cmath::ScaleCache;

/// One channel: its pins and parameters as plain fields, and its state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelChannel {
    /// make-pulses' state.
    pub gen: PulseGen,
    /// update-freq's state.
    pub ctl: FreqCtl,
    /// The DDS registers both share.
    pub dds: Dds,
    /// The scale reciprocal update-freq and capture-position share.
    pub cache: ScaleCache,
    /// The channel's parameters (timing, limits, scale, `frequency`).
    pub params: FreqParams,
    /// `enable` pin.
    pub enable: bool,
    /// `position-cmd` or `velocity-cmd` pin.
    pub cmd: f64,
    /// `rawcounts` param.
    pub rawcounts: i32,
    /// `counts` pin.
    pub counts: i32,
    /// `position-fb` pin.
    pub position_fb: f64,
    /// Output pins as bits (see [`PulseGen::outputs`]).
    pub outputs: u8,
}

impl ModelChannel {
    /// A channel in its load-time state.
    pub fn new(cfg: &ChannelConfig) -> ModelChannel {
        let st = &cfg.step_type;
        ModelChannel {
            gen: PulseGen::new(*st),
            ctl: FreqCtl::new(st, cfg.velocity_mode),
            dds: Dds::default(),
            cache: INITIAL_SCALE_CACHE,
            params: FreqParams {
                setup: u32::from(st.has_setup()),
                stepspace: u32::from(st.has_stepspace()),
                ..FreqParams::default()
            },
            enable: false,
            cmd: 0.0,
            rawcounts: 0,
            counts: 0,
            position_fb: 0.0,
            outputs: 0,
        }
    }
}

/// The whole module: channels plus the module-wide period state.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepgen {
    /// The channels, in channel order.
    pub chans: Vec<ModelChannel>,
    /// make-pulses' last period (50 µs until it first runs).
    pub periodns: i64,
    /// update-freq's derived time constants.
    pub timing: FreqTiming,
}

impl Stepgen {
    /// The module as loaded with `cfg`.
    pub fn new(cfg: &[ChannelConfig]) -> Stepgen {
        Stepgen {
            chans: cfg.iter().map(ModelChannel::new).collect(),
            periodns: INITIAL_PERIOD_NS,
            timing: FreqTiming::default(),
        }
    }

    /// `stepgen.make-pulses` in a thread of `period` ns; returns how many
    /// channels stepped.
    pub fn make_pulses(&mut self, period: i64) -> usize {
        self.periodns = period;
        let mut steps = 0;
        for c in &mut self.chans {
            let params = &c.params;
            let timing = || PulseTiming {
                steplen: params.steplen,
                hold: params.hold,
                setup: params.setup,
            };
            let r = c.gen.update(period, c.enable, timing, &mut c.dds);
            if r.advanced {
                c.rawcounts = c.dds.counts();
            }
            steps += usize::from(r.step);
            c.outputs = c.gen.outputs();
        }
        steps
    }

    /// `stepgen.update-freq` in a thread of `period` ns.
    pub fn update_freq(&mut self, period: i64) {
        let newperiod = self.timing.update(self.periodns, period);
        for c in &mut self.chans {
            c.ctl
                .update(
                    &self.timing,
                    newperiod,
                    self.periodns,
                    &mut c.cache,
                    &mut c.params,
                    c.enable,
                    c.cmd,
                    c.dds.accum,
                )
                .apply(&mut c.dds);
        }
    }

    /// `stepgen.capture-position`.
    pub fn capture_position(&mut self) {
        for c in &mut self.chans {
            let (counts, fb) =
                freq::capture(c.dds.accum, &mut c.params.position_scale, &mut c.cache);
            c.counts = counts;
            c.position_fb = fb;
        }
    }
}
