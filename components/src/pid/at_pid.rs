//! `at_pid`: the older PID controller with relay auto-tuning (before the
//! auto-tuner moved into `pid`). Its tunables are I/O pins the tuner
//! writes; a finished or aborted tune drives the output to 0. Channels
//! are named `pid.N` (as LinuxCNC names them, so it cannot be loaded
//! together with `pid` using default names).
//!
//! `loadrt at_pid [num_chan=N | names=...] [debug=1]`: 3 loops by
//! default, at most 16; `debug=1` adds the internal values as pins.

use hal_core::module::{ModuleArgs, ModuleDef};
use hal_core::{Host, In, Io, Out, Pin, Result};

use super::control::{DEFAULT_CHAN, MAX_CHAN, PARAMS, PI_TRUNCATED};
use crate::halcomp::channel_names;

/// `tune-type` for P, I and D gains.
pub const TYPE_PID: u32 = 0;

/// The auto-tuner's states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// Normal control.
    Pid,
    /// Tune mode, waiting for `tune-start`.
    TuneIdle,
    /// Starting the relay.
    TuneStart,
    /// Relay positive.
    TunePos,
    /// Relay negative.
    TuneNeg,
    /// Leaving the tune.
    TuneAbort,
}

/// Every tunable (the I/O pins), which the tuner may write.
#[derive(Debug, Clone, Copy, PartialEq)]
#[allow(missing_docs)]
pub struct Tunables {
    pub deadband: f64,
    pub maxerror: f64,
    pub maxerror_i: f64,
    pub maxerror_d: f64,
    pub maxcmd_d: f64,
    pub maxcmd_dd: f64,
    pub bias: f64,
    pub pgain: f64,
    pub igain: f64,
    pub dgain: f64,
    pub ff0: f64,
    pub ff1: f64,
    pub ff2: f64,
    pub maxoutput: f64,
    pub tune_effort: f64,
    pub tune_cycles: u32,
    pub tune_type: u32,
}

impl Default for Tunables {
    /// LinuxCNC's initial values.
    fn default() -> Self {
        Tunables {
            deadband: 0.0,
            maxerror: 0.0,
            maxerror_i: 0.0,
            maxerror_d: 0.0,
            maxcmd_d: 0.0,
            maxcmd_dd: 0.0,
            bias: 0.0,
            pgain: 1.0,
            igain: 0.0,
            dgain: 0.0,
            ff0: 0.0,
            ff1: 0.0,
            ff2: 0.0,
            maxoutput: 0.0,
            tune_effort: 0.5,
            tune_cycles: 50,
            tune_type: TYPE_PID,
        }
    }
}

/// The other pins of a loop.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct LoopPins {
    pub enable: bool,
    pub command: f64,
    pub feedback: f64,
    pub error: f64,
    pub output: f64,
    pub tune_mode: bool,
    pub tune_start: bool,
}

/// The internal values `debug=1` shows.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[allow(missing_docs)]
pub struct Internals {
    pub error_i: f64,
    pub error_d: f64,
    pub cmd_d: f64,
    pub cmd_dd: f64,
    pub ultimate_gain: f64,
    pub ultimate_period: f64,
}

/// One loop's state.
#[derive(Debug, Clone)]
pub struct AtPid {
    /// The internal values.
    pub internals: Internals,
    prev_error: f64,
    prev_cmd: f64,
    limit_state: f64,
    state: State,
    cycle_count: u32,
    cycle_period: u32,
    cycle_amplitude: f64,
    total_time: f64,
    avg_amplitude: f64,
}

impl Default for AtPid {
    fn default() -> Self {
        AtPid {
            internals: Internals::default(),
            prev_error: 0.0,
            prev_cmd: 0.0,
            limit_state: 0.0,
            state: State::Pid,
            cycle_count: 0,
            cycle_period: 0,
            cycle_amplitude: 0.0,
            total_time: 0.0,
            avg_amplitude: 0.0,
        }
    }
}

/// `v` limited to `[-max, max]` when `max` is not 0.
fn limit(v: f64, max: f64) -> f64 {
    if max == 0.0 {
        v
    } else if v > max {
        max
    } else if v < -max {
        -max
    } else {
        v
    }
}

impl AtPid {
    /// The tuner's state.
    pub fn state(&self) -> State {
        self.state
    }

    /// One call (`do-pid-calcs`) of a thread of `period_ns`.
    pub fn step(&mut self, p: &mut LoopPins, t: &mut Tunables, period_ns: i64) {
        if self.state != State::Pid {
            self.auto_tune(p, t, period_ns);
            return;
        }
        let mut error = p.command - p.feedback;
        p.error = error;
        let s = &mut self.internals;
        if p.tune_mode {
            s.error_i = 0.0;
            self.prev_error = 0.0;
            s.error_d = 0.0;
            self.prev_cmd = 0.0;
            self.limit_state = 0.0;
            s.cmd_d = 0.0;
            s.cmd_dd = 0.0;
            p.output = 0.0;
            self.state = State::TuneIdle;
            return;
        }
        let period = period_ns as f64 * 0.000000001;
        let recip = 1.0 / period;
        error = limit(error, t.maxerror);
        error = if error > t.deadband {
            error - t.deadband
        } else if error < -t.deadband {
            error + t.deadband
        } else {
            0.0
        };
        s.error_d = limit((error - self.prev_error) * recip, t.maxerror_d);
        self.prev_error = error;
        let prev_cmd_d = s.cmd_d;
        s.cmd_d = limit((p.command - self.prev_cmd) * recip, t.maxcmd_d);
        self.prev_cmd = p.command;
        s.cmd_dd = limit((s.cmd_d - prev_cmd_d) * recip, t.maxcmd_dd);
        if !p.enable {
            s.error_i = 0.0;
            p.output = 0.0;
            self.limit_state = 0.0;
            return;
        }
        if error * self.limit_state <= 0.0 {
            s.error_i += error * period;
        }
        s.error_i = limit(s.error_i, t.maxerror_i);
        let mut output = t.bias + t.pgain * error + t.igain * s.error_i + t.dgain * s.error_d;
        output += p.command * t.ff0 + s.cmd_d * t.ff1 + s.cmd_dd * t.ff2;
        if t.maxoutput != 0.0 {
            if output > t.maxoutput {
                output = t.maxoutput;
                self.limit_state = 1.0;
            } else if output < -t.maxoutput {
                output = -t.maxoutput;
                self.limit_state = -1.0;
            } else {
                self.limit_state = 0.0;
            }
        }
        p.output = output;
    }

    /// One half cycle of the relay has ended.
    fn cycle_end(&mut self, t: &Tunables) {
        self.cycle_count = self.cycle_count.wrapping_add(1);
        self.avg_amplitude += self.cycle_amplitude / f64::from(t.tune_cycles);
        self.cycle_amplitude = 0.0;
        self.total_time += f64::from(self.cycle_period) * 0.000000001;
        self.cycle_period = 0;
    }

    /// The relay auto-tuner.
    fn auto_tune(&mut self, p: &mut LoopPins, t: &mut Tunables, period_ns: i64) {
        let error = p.command - p.feedback;
        p.error = error;
        if !p.enable || !p.tune_mode {
            self.state = State::TuneAbort;
        }
        let effort = t.tune_effort.abs();
        match self.state {
            State::TuneIdle => {
                if p.tune_start {
                    self.state = State::TuneStart;
                }
                return;
            }
            State::TuneStart => {
                self.state = State::TunePos;
                self.cycle_count = 0;
                self.cycle_period = 0;
                self.cycle_amplitude = 0.0;
                self.total_time = 0.0;
                self.avg_amplitude = 0.0;
                self.internals.ultimate_gain = 0.0;
                self.internals.ultimate_period = 0.0;
                p.output = t.bias + effort;
                return;
            }
            State::TunePos | State::TuneNeg => {
                self.cycle_period = self.cycle_period.wrapping_add(period_ns as u32);
                if error < 0.0 {
                    if -error > self.cycle_amplitude {
                        self.cycle_amplitude = -error;
                    }
                    if self.state == State::TunePos {
                        self.state = State::TuneNeg;
                        self.cycle_end(t);
                    }
                    p.output = t.bias - effort;
                } else {
                    if error > self.cycle_amplitude {
                        self.cycle_amplitude = error;
                    }
                    if self.state == State::TuneNeg {
                        self.state = State::TunePos;
                        self.cycle_end(t);
                    }
                    p.output = t.bias + effort;
                }
                if self.cycle_count < t.tune_cycles {
                    return;
                }
                let s = &mut self.internals;
                s.ultimate_gain = (4.0 * effort) / (PI_TRUNCATED * self.avg_amplitude);
                s.ultimate_period = 2.0 * self.total_time / f64::from(t.tune_cycles);
                t.ff0 = 0.0;
                t.ff2 = 0.0;
                if t.tune_type == TYPE_PID {
                    t.pgain = 0.6 * s.ultimate_gain;
                    t.igain = t.pgain / (s.ultimate_period / 2.0);
                    t.dgain = t.pgain * (s.ultimate_period / 8.0);
                    t.ff1 = 0.0;
                } else {
                    t.pgain = 0.45 * s.ultimate_gain;
                    t.igain = t.pgain / (s.ultimate_period / 1.2);
                    t.dgain = 0.0;
                    t.ff1 = 1.0;
                }
            }
            State::TuneAbort | State::Pid => {}
        }
        p.output = 0.0;
        p.tune_start = false;
        self.state = if p.tune_mode {
            State::TuneIdle
        } else {
            State::Pid
        };
    }
}

/// The `at_pid` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "at_pid",
    params: PARAMS,
    help: "PID loop with relay auto-tuning (the older component)",
    load,
};

/// The I/O pins of a loop's tunables.
struct TunablePins {
    floats: Vec<Pin<f64, Io>>,
    tune_cycles: Pin<u32, Io>,
    tune_type: Pin<u32, Io>,
}

/// The names of the float tunables, in [`Tunables`] order.
const FLOAT_TUNABLES: [&str; 15] = [
    "deadband",
    "maxerror",
    "maxerrorI",
    "maxerrorD",
    "maxcmdD",
    "maxcmdDD",
    "bias",
    "Pgain",
    "Igain",
    "Dgain",
    "FF0",
    "FF1",
    "FF2",
    "maxoutput",
    "tune-effort",
];

impl Tunables {
    fn floats(&self) -> [f64; 15] {
        [
            self.deadband,
            self.maxerror,
            self.maxerror_i,
            self.maxerror_d,
            self.maxcmd_d,
            self.maxcmd_dd,
            self.bias,
            self.pgain,
            self.igain,
            self.dgain,
            self.ff0,
            self.ff1,
            self.ff2,
            self.maxoutput,
            self.tune_effort,
        ]
    }

    fn from_floats(f: [f64; 15], tune_cycles: u32, tune_type: u32) -> Tunables {
        let [deadband, maxerror, maxerror_i, maxerror_d, maxcmd_d, maxcmd_dd, bias, pgain, igain, dgain, ff0, ff1, ff2, maxoutput, tune_effort] =
            f;
        Tunables {
            deadband,
            maxerror,
            maxerror_i,
            maxerror_d,
            maxcmd_d,
            maxcmd_dd,
            bias,
            pgain,
            igain,
            dgain,
            ff0,
            ff1,
            ff2,
            maxoutput,
            tune_effort,
            tune_cycles,
            tune_type,
        }
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    let names = channel_names(MODULE.name, "pid", DEFAULT_CHAN, MAX_CHAN, args)?;
    let debug = args.int("debug").unwrap_or(0) > 0;
    let mut b = host.new_rt_component(MODULE.name)?;
    for prefix in names {
        let c = b.component();
        let enable: Pin<bool, In> = c.pin(&format!("{prefix}.enable"))?;
        let command: Pin<f64, In> = c.pin(&format!("{prefix}.command"))?;
        let feedback: Pin<f64, In> = c.pin(&format!("{prefix}.feedback"))?;
        let error: Pin<f64, Out> = c.pin(&format!("{prefix}.error"))?;
        let output: Pin<f64, Out> = c.pin(&format!("{prefix}.output"))?;
        let tune_mode: Pin<bool, In> = c.pin(&format!("{prefix}.tune-mode"))?;
        let tune_start: Pin<bool, Io> = c.pin(&format!("{prefix}.tune-start"))?;
        let d = Tunables::default();
        let tp = TunablePins {
            floats: FLOAT_TUNABLES
                .iter()
                .zip(d.floats())
                .map(|(n, v)| c.pin_init(&format!("{prefix}.{n}"), v))
                .collect::<Result<_>>()?,
            tune_cycles: c.pin_init(&format!("{prefix}.tune-cycles"), d.tune_cycles)?,
            tune_type: c.pin_init(&format!("{prefix}.tune-type"), d.tune_type)?,
        };
        let internals: Option<Vec<Pin<f64, Out>>> = if debug {
            Some(
                [
                    "errorI",
                    "errorD",
                    "commandD",
                    "commandDD",
                    "ultimate-gain",
                    "ultimate-period",
                ]
                .iter()
                .map(|n| c.pin(&format!("{prefix}.{n}")))
                .collect::<Result<_>>()?,
            )
        } else {
            None
        };
        let mut pid = AtPid::default();
        b.funct(&format!("{prefix}.do-pid-calcs"), true, move |ctx| {
            let floats: [f64; 15] = std::array::from_fn(|k| tp.floats[k].get());
            let mut t = Tunables::from_floats(floats, tp.tune_cycles.get(), tp.tune_type.get());
            let before = t;
            let mut p = LoopPins {
                enable: enable.get(),
                command: command.get(),
                feedback: feedback.get(),
                error: error.get(),
                output: output.get(),
                tune_mode: tune_mode.get(),
                tune_start: tune_start.get(),
            };
            let start_before = p.tune_start;
            pid.step(&mut p, &mut t, ctx.period());
            error.set(p.error);
            output.set(p.output);
            if p.tune_start != start_before {
                tune_start.set(p.tune_start);
            }
            if t != before {
                for (pin, (new, old)) in
                    tp.floats.iter().zip(t.floats().iter().zip(before.floats()))
                {
                    if *new != old {
                        pin.set(*new);
                    }
                }
            }
            if let Some(pins) = &internals {
                let s = pid.internals;
                let v = [
                    s.error_i,
                    s.error_d,
                    s.cmd_d,
                    s.cmd_dd,
                    s.ultimate_gain,
                    s.ultimate_period,
                ];
                for (pin, v) in pins.iter().zip(v) {
                    pin.set(v);
                }
            }
        })?;
    }
    b.ready()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::TestHost;
    use hal_core::Value::{Bit, Float};

    #[test]
    fn pid_terms_limits_and_anti_windup() {
        let mut pid = AtPid::default();
        let mut t = Tunables {
            pgain: 2.0,
            igain: 10.0,
            maxoutput: 1.5,
            ..Tunables::default()
        };
        let mut p = LoopPins {
            enable: true,
            command: 1.0,
            ..Default::default()
        };
        pid.step(&mut p, &mut t, 1_000_000);
        assert_eq!(p.error, 1.0);
        assert_eq!(p.output, 1.5, "limited");
        let i = pid.internals.error_i;
        pid.step(&mut p, &mut t, 1_000_000);
        assert_eq!(pid.internals.error_i, i, "no wind-up while limited");
        // Disabled: output 0 and the integrator cleared.
        p.enable = false;
        pid.step(&mut p, &mut t, 1_000_000);
        assert_eq!((p.output, pid.internals.error_i), (0.0, 0.0));
        // Deadband.
        let mut t = Tunables {
            deadband: 0.5,
            ..Tunables::default()
        };
        p.enable = true;
        p.command = 0.25;
        pid.step(&mut p, &mut t, 1_000_000);
        assert!(p.output.abs() < 1e-9);
    }

    #[test]
    fn relay_tuning_measures_the_loop_and_sets_gains() {
        let mut pid = AtPid::default();
        let mut t = Tunables {
            tune_cycles: 4,
            ..Tunables::default()
        };
        let mut p = LoopPins {
            enable: true,
            tune_mode: true,
            ..Default::default()
        };
        pid.step(&mut p, &mut t, 1_000_000);
        assert_eq!(pid.state(), State::TuneIdle);
        p.tune_start = true;
        pid.step(&mut p, &mut t, 1_000_000);
        pid.step(&mut p, &mut t, 1_000_000);
        assert_eq!(p.output, 0.5, "relay on");
        // A plant that follows the output as a position with a lag: the
        // feedback oscillates around the command.
        let mut x = 0.0;
        let mut calls = 0;
        while pid.state() != State::TuneIdle {
            x += p.output * 0.001;
            p.feedback = x;
            pid.step(&mut p, &mut t, 1_000_000);
            calls += 1;
            assert!(calls < 10_000);
        }
        assert!(!p.tune_start, "cleared at the end");
        assert_eq!(p.output, 0.0);
        assert!(pid.internals.ultimate_gain > 0.0 && pid.internals.ultimate_period > 0.0);
        assert_eq!(t.pgain, 0.6 * pid.internals.ultimate_gain);
        assert_eq!(t.ff1, 0.0);
    }

    #[test]
    fn pins_debug_and_bad_params() {
        let h = TestHost::new("at-pid");
        for bad in [&["num_chan=17"][..], &["num_chan=2", "names=a"]] {
            h.check_load_fails(&MODULE, bad);
        }
        h.load(&MODULE, &["names=x", "debug=1"]).unwrap();
        let mut want = vec![
            "enable bit in 0".to_string(),
            "command float in 0".into(),
            "feedback float in 0".into(),
            "error float out 0".into(),
            "output float out 0".into(),
            "tune-mode bit in 0".into(),
            "tune-start bit io 0".into(),
            "tune-cycles u32 io 50".into(),
            "tune-type u32 io 0".into(),
        ];
        for (n, v) in FLOAT_TUNABLES.iter().zip(Tunables::default().floats()) {
            want.push(format!("{n} float io {v}"));
        }
        for n in [
            "errorI",
            "errorD",
            "commandD",
            "commandDD",
            "ultimate-gain",
            "ultimate-period",
        ] {
            want.push(format!("{n} float out 0"));
        }
        let want: Vec<&str> = want.iter().map(String::as_str).collect();
        h.check_pins("x", &want);
        assert_eq!(h.functs(), ["x.do-pid-calcs"]);
        let mut h = TestHost::new("at-pid-default");
        h.load(&MODULE, &[]).unwrap();
        assert_eq!(h.functs().len(), 3);
        assert!(
            h.items("pid.0.errorI").is_empty(),
            "internals only with debug"
        );
        h.thread(&["pid.0.do-pid-calcs"]);
        h.set("pid.0.enable", Bit(true));
        h.expect(&[("pid.0.command", Float(0.5))], "pid.0.output", Float(0.5));
    }
}
