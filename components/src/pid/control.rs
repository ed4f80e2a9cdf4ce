//! `pid`: LinuxCNC's PID controller, up to 16 loops, with deadband, error
//! and output limits, feed-forward of the command and its first three
//! derivatives, index-enable handling, saturation reporting and relay
//! auto-tuning.
//!
//! The per-call algorithm lives in [`Pid`], which works on a snapshot of
//! the loop's pins ([`PidIo`]) and knows nothing about HAL; the module's
//! function reads the pins, calls [`Pid::step`] and writes the pins back.

use hal_core::module::{ModuleArgs, ModuleDef, ParamDecl, ParamKind};
use hal_core::{Host, In, Io, Out, Pin, Result};

use crate::halcomp::channel_names;

/// Most loops one load creates.
pub const MAX_CHAN: usize = 16;
/// Loops created when neither `num_chan=` nor `names=` is given.
pub const DEFAULT_CHAN: usize = 3;
/// The value of pi the auto-tuner uses: LinuxCNC's truncated constant
/// (not `std::f64::consts::PI`, which would change the tuned gains).
#[allow(clippy::approx_constant)]
pub const PI_TRUNCATED: f64 = 3.141592653589;

/// The module parameters: `num_chan=`, `names=`, `debug=` (at_pid takes
/// the same).
pub const PARAMS: &[ParamDecl] = &[
    ParamDecl {
        name: "num_chan",
        kind: ParamKind::Int,
        help: "number of PID loops (1-16, default 3)",
    },
    ParamDecl {
        name: "names",
        kind: ParamKind::StrArray(MAX_CHAN),
        help: "names of the PID loops, comma separated",
    },
    ParamDecl {
        name: "debug",
        kind: ParamKind::Int,
        help: "if > 0, export the internal values as pins",
    },
];

/// The `pid` module.
pub static MODULE: ModuleDef = ModuleDef {
    name: "pid",
    params: PARAMS,
    help: "PID controller with feed-forward and auto-tuning",
    load,
};

/// The state of the auto-tuner; [`TuneState::Pid`] is normal control.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TuneState {
    /// Normal PID control.
    Pid,
    /// Tune mode on, waiting for `tune-start`.
    Idle,
    /// `tune-start` seen: the next call starts the relay.
    Start,
    /// Relay driving positive (the error was last >= 0).
    Pos,
    /// Relay driving negative (the error was last < 0).
    Neg,
    /// Leaving tuning: output goes to `bias`, `tune-start` is cleared.
    Abort,
}

/// The values of one loop's pins that a call reads or writes (everything
/// but `command-deriv`/`feedback-deriv`, which [`Pid::step`] reaches
/// through a callback, and the debug-only pins, which mirror [`Pid`]'s
/// state).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PidIo {
    /// `enable` (in).
    pub enable: bool,
    /// `command` (in).
    pub command: f64,
    /// `feedback` (in).
    pub feedback: f64,
    /// `index-enable` (in).
    pub index_enable: bool,
    /// `error-previous-target` (in).
    pub error_previous_target: bool,
    /// `Pgain` (in; written by the auto-tuner).
    pub pgain: f64,
    /// `Igain` (in; written by the auto-tuner).
    pub igain: f64,
    /// `Dgain` (in; written by the auto-tuner).
    pub dgain: f64,
    /// `FF0` (in; written by the auto-tuner).
    pub ff0: f64,
    /// `FF1` (in; written by the auto-tuner).
    pub ff1: f64,
    /// `FF2` (in; written by the auto-tuner).
    pub ff2: f64,
    /// `FF3` (in).
    pub ff3: f64,
    /// `deadband` (in).
    pub deadband: f64,
    /// `maxerror` (in; 0 means no limit, as for every `max*`).
    pub maxerror: f64,
    /// `maxerrorI` (in).
    pub maxerror_i: f64,
    /// `maxerrorD` (in).
    pub maxerror_d: f64,
    /// `maxcmdD` (in).
    pub maxcmd_d: f64,
    /// `maxcmdDD` (in).
    pub maxcmd_dd: f64,
    /// `maxcmdDDD` (in).
    pub maxcmd_ddd: f64,
    /// `bias` (in).
    pub bias: f64,
    /// `maxoutput` (in).
    pub maxoutput: f64,
    /// `tune-effort` (io).
    pub tune_effort: f64,
    /// `tune-cycles` (io): half cycles the tuner measures.
    pub tune_cycles: u32,
    /// `tune-type` (io): 0 sets P/I/D, anything else P/I/FF1.
    pub tune_type: u32,
    /// `tune-mode` (in).
    pub tune_mode: bool,
    /// `tune-start` (io; cleared by the tuner).
    pub tune_start: bool,
    /// `error` (out).
    pub error: f64,
    /// `output` (out).
    pub output: f64,
    /// `saturated` (out).
    pub saturated: bool,
    /// `saturated-s` (out, read back to accumulate).
    pub saturated_s: f64,
    /// `saturated-count` (out, read back to count).
    pub saturated_count: i32,
}

impl Default for PidIo {
    /// The pins' values right after `loadrt`.
    fn default() -> Self {
        PidIo {
            enable: false,
            command: 0.0,
            feedback: 0.0,
            index_enable: false,
            error_previous_target: true,
            pgain: 1.0,
            igain: 0.0,
            dgain: 0.0,
            ff0: 0.0,
            ff1: 0.0,
            ff2: 0.0,
            ff3: 0.0,
            deadband: 0.0,
            maxerror: 0.0,
            maxerror_i: 0.0,
            maxerror_d: 0.0,
            maxcmd_d: 0.0,
            maxcmd_dd: 0.0,
            maxcmd_ddd: 0.0,
            bias: 0.0,
            maxoutput: 0.0,
            tune_effort: 0.5,
            tune_cycles: 50,
            tune_type: 0,
            tune_mode: false,
            tune_start: false,
            error: 0.0,
            output: 0.0,
            saturated: false,
            saturated_s: 0.0,
            saturated_count: 0,
        }
    }
}

/// Limits `x` to `[-m, m]` unless `m` is 0, tested in LinuxCNC's order
/// (`x > m` first, then `x < -m`).
fn limit(x: f64, m: f64) -> f64 {
    if m != 0.0 {
        if x > m {
            return m;
        } else if x < -m {
            return -m;
        }
    }
    x
}

/// One PID loop's internal state.
#[derive(Clone, Debug, PartialEq)]
pub struct Pid {
    /// Command of the previous call (0 again after a tune-mode call).
    pub prev_cmd: f64,
    /// Feedback of the previous call.
    pub prev_fb: f64,
    /// Direction the output was saturated in last call: 1, -1 or 0.
    pub limit_state: f64,
    /// `index-enable` of the previous call.
    pub prev_ie: bool,
    /// Error integrator (`errorI`).
    pub error_i: f64,
    /// Error derivative (`errorD`).
    pub error_d: f64,
    /// Command derivative used by FF1 (`commandD`).
    pub command_d: f64,
    /// Second command derivative (`commandDD`).
    pub command_dd: f64,
    /// Third command derivative (`commandDDD`).
    pub command_ddd: f64,
    /// Auto-tuner state.
    pub tstate: TuneState,
    /// Half cycles completed while tuning.
    pub cycle_count: u32,
    /// Nanoseconds in the current half cycle (wraps like C's u32).
    pub cycle_period: u32,
    /// Largest |error| in the current half cycle.
    pub cycle_amplitude: f64,
    /// Seconds spent in completed half cycles.
    pub total_time: f64,
    /// Mean peak |error| over the half cycles, built up one term at a time.
    pub avg_amplitude: f64,
    /// Ultimate gain the tuner found (`ultimate-gain`).
    pub ultimate_gain: f64,
    /// Ultimate period the tuner found, in seconds (`ultimate-period`).
    pub ultimate_period: f64,
}

impl Default for Pid {
    fn default() -> Self {
        Pid::new()
    }
}

impl Pid {
    /// A loop as loaded: everything 0, normal PID control.
    pub fn new() -> Pid {
        Pid {
            prev_cmd: 0.0,
            prev_fb: 0.0,
            limit_state: 0.0,
            prev_ie: false,
            error_i: 0.0,
            error_d: 0.0,
            command_d: 0.0,
            command_dd: 0.0,
            command_ddd: 0.0,
            tstate: TuneState::Pid,
            cycle_count: 0,
            cycle_period: 0,
            cycle_amplitude: 0.0,
            total_time: 0.0,
            avg_amplitude: 0.0,
            ultimate_gain: 0.0,
            ultimate_period: 0.0,
        }
    }

    /// One call of `do-pid-calcs` with thread period `period` (ns).
    ///
    /// `derivs` stands for the `command-deriv` and `feedback-deriv` pins:
    /// given `Some((command estimate, feedback estimate))` it stores the
    /// numeric estimates as the values the pins read while unconnected;
    /// given `None` it leaves them; either way it returns what the two
    /// pins read now (a connected pin reads its signal instead).
    pub fn step(
        &mut self,
        io: &mut PidIo,
        period: i64,
        mut derivs: impl FnMut(Option<(f64, f64)>) -> (f64, f64),
    ) {
        if self.tstate != TuneState::Pid {
            self.autotune(io, period);
            return;
        }
        let t = period as f64 * 1e-9;
        let r = 1.0 / t;
        let en = io.enable;
        let cmd = io.command;
        let fb = io.feedback;
        // On the call where index-enable falls the encoder position has
        // just jumped: use the current command and keep the old estimates.
        let ie_fell = self.prev_ie && !io.index_enable;
        let mut e = if !ie_fell && io.error_previous_target {
            self.prev_cmd - fb
        } else {
            cmd - fb
        };
        io.error = e;
        if io.tune_mode {
            self.error_i = 0.0;
            self.error_d = 0.0;
            self.prev_cmd = 0.0;
            self.limit_state = 0.0;
            self.command_d = 0.0;
            self.command_dd = 0.0;
            io.output = 0.0;
            self.tstate = TuneState::Idle;
            return;
        }
        e = limit(e, io.maxerror);
        // Outside the deadband the deadband is subtracted, so the
        // transfer function has no step at its edge.
        e = if e > io.deadband {
            e - io.deadband
        } else if e < -io.deadband {
            e + io.deadband
        } else {
            0.0
        };
        if en {
            // Anti-windup: hold the integrator while the output is
            // saturated in the direction the error pushes.
            if e * self.limit_state <= 0.0 {
                self.error_i += e * t;
            }
            self.error_i = limit(self.error_i, io.maxerror_i);
        } else {
            self.error_i = 0.0;
        }
        let estimates = if ie_fell {
            None
        } else {
            Some(((cmd - self.prev_cmd) * r, (fb - self.prev_fb) * r))
        };
        let (cmd_deriv, fb_deriv) = derivs(estimates);
        self.error_d = limit(cmd_deriv - fb_deriv, io.maxerror_d);
        let old_cd = self.command_d;
        self.command_d = cmd_deriv;
        self.prev_ie = io.index_enable;
        self.prev_cmd = cmd;
        self.prev_fb = fb;
        self.command_d = limit(self.command_d, io.maxcmd_d);
        let old_cdd = self.command_dd;
        self.command_dd = limit((self.command_d - old_cd) * r, io.maxcmd_dd);
        self.command_ddd = limit((self.command_dd - old_cdd) * r, io.maxcmd_ddd);
        let out = if en {
            // The PID terms and the feed-forward terms are summed as two
            // separate left-to-right chains, then added (LinuxCNC's order).
            let mut out =
                io.bias + io.pgain * e + io.igain * self.error_i + io.dgain * self.error_d;
            let feed_forward = cmd * io.ff0
                + self.command_d * io.ff1
                + self.command_dd * io.ff2
                + self.command_ddd * io.ff3;
            out += feed_forward;
            if io.maxoutput != 0.0 {
                if out > io.maxoutput {
                    out = io.maxoutput;
                    self.limit_state = 1.0;
                } else if out < -io.maxoutput {
                    out = -io.maxoutput;
                    self.limit_state = -1.0;
                } else {
                    self.limit_state = 0.0;
                }
            }
            out
        } else {
            self.limit_state = 0.0;
            0.0
        };
        io.output = out;
        if self.limit_state != 0.0 {
            io.saturated = true;
            io.saturated_s += period as f64 * 1e-9;
            // Counts up to s32's maximum and stays there.
            io.saturated_count = io.saturated_count.saturating_add(1);
        } else {
            io.saturated = false;
            io.saturated_s = 0.0;
            io.saturated_count = 0;
        }
    }

    /// One call while tuning: a relay of amplitude `|tune-effort|` around
    /// `bias` makes the loop oscillate; after `tune-cycles` half cycles
    /// the ultimate gain and period give Ziegler-Nichols gains.
    fn autotune(&mut self, io: &mut PidIo, period: i64) {
        let e = io.command - io.feedback;
        io.error = e;
        if !io.enable || !io.tune_mode {
            self.tstate = TuneState::Abort;
        }
        match self.tstate {
            TuneState::Idle => {
                if io.tune_start {
                    self.tstate = TuneState::Start;
                }
                return;
            }
            TuneState::Start => {
                self.tstate = TuneState::Pos;
                self.cycle_count = 0;
                self.cycle_period = 0;
                self.cycle_amplitude = 0.0;
                self.total_time = 0.0;
                self.avg_amplitude = 0.0;
                self.ultimate_gain = 0.0;
                self.ultimate_period = 0.0;
                io.output = io.bias + io.tune_effort.abs();
                return;
            }
            TuneState::Pos | TuneState::Neg => {
                self.cycle_period = self.cycle_period.wrapping_add(period as u32);
                if e < 0.0 {
                    if -e > self.cycle_amplitude {
                        self.cycle_amplitude = -e;
                    }
                    if self.tstate == TuneState::Pos {
                        self.tstate = TuneState::Neg;
                        self.end_half_cycle(io.tune_cycles);
                    }
                    io.output = io.bias - io.tune_effort.abs();
                } else {
                    if e > self.cycle_amplitude {
                        self.cycle_amplitude = e;
                    }
                    if self.tstate == TuneState::Neg {
                        self.tstate = TuneState::Pos;
                        self.end_half_cycle(io.tune_cycles);
                    }
                    io.output = io.bias + io.tune_effort.abs();
                }
                if self.cycle_count < io.tune_cycles {
                    return;
                }
                let cycles = io.tune_cycles as f64;
                self.ultimate_gain =
                    (4.0 * io.tune_effort.abs()) / (PI_TRUNCATED * self.avg_amplitude);
                self.ultimate_period = 2.0 * self.total_time / cycles;
                let (ku, tu) = (self.ultimate_gain, self.ultimate_period);
                io.ff0 = 0.0;
                io.ff2 = 0.0;
                if io.tune_type == 0 {
                    io.pgain = 0.6 * ku;
                    io.igain = 1.2 * ku / tu;
                    io.dgain = (3.0 / 40.0) * ku * tu;
                    io.ff1 = 0.0;
                } else {
                    io.pgain = 0.45 * ku;
                    io.igain = 0.54 * ku / tu;
                    io.dgain = 0.0;
                    io.ff1 = 1.0;
                }
            }
            TuneState::Abort | TuneState::Pid => {}
        }
        io.output = io.bias;
        io.tune_start = false;
        self.tstate = if io.tune_mode {
            TuneState::Idle
        } else {
            TuneState::Pid
        };
    }

    /// Books the half cycle that just ended.
    fn end_half_cycle(&mut self, tune_cycles: u32) {
        self.cycle_count = self.cycle_count.wrapping_add(1);
        self.avg_amplitude += self.cycle_amplitude / tune_cycles as f64;
        self.cycle_amplitude = 0.0;
        self.total_time += self.cycle_period as f64 * 0.000000001;
        self.cycle_period = 0;
    }
}

/// The internal values `debug=1` exports as output pins.
struct DebugPins {
    error_i: Pin<f64, Out>,
    error_d: Pin<f64, Out>,
    command_d: Pin<f64, Out>,
    command_dd: Pin<f64, Out>,
    command_ddd: Pin<f64, Out>,
    ultimate_gain: Pin<f64, Out>,
    ultimate_period: Pin<f64, Out>,
}

/// The pins of one loop.
struct LoopPins {
    enable: Pin<bool, In>,
    command: Pin<f64, In>,
    command_deriv: Pin<f64, In>,
    feedback: Pin<f64, In>,
    feedback_deriv: Pin<f64, In>,
    error: Pin<f64, Out>,
    output: Pin<f64, Out>,
    saturated: Pin<bool, Out>,
    saturated_s: Pin<f64, Out>,
    saturated_count: Pin<i32, Out>,
    pgain: Pin<f64, In>,
    igain: Pin<f64, In>,
    dgain: Pin<f64, In>,
    ff0: Pin<f64, In>,
    ff1: Pin<f64, In>,
    ff2: Pin<f64, In>,
    ff3: Pin<f64, In>,
    deadband: Pin<f64, In>,
    maxerror: Pin<f64, In>,
    maxerror_i: Pin<f64, In>,
    maxerror_d: Pin<f64, In>,
    maxcmd_d: Pin<f64, In>,
    maxcmd_dd: Pin<f64, In>,
    maxcmd_ddd: Pin<f64, In>,
    bias: Pin<f64, In>,
    maxoutput: Pin<f64, In>,
    index_enable: Pin<bool, In>,
    error_previous_target: Pin<bool, In>,
    tune_effort: Pin<f64, Io>,
    tune_cycles: Pin<u32, Io>,
    tune_type: Pin<u32, Io>,
    tune_mode: Pin<bool, In>,
    tune_start: Pin<bool, Io>,
    debug: Option<DebugPins>,
}

impl LoopPins {
    /// Creates the pins `<prefix>.*` with LinuxCNC's defaults.
    fn new(c: &hal_core::Component, prefix: &str, debug: bool) -> Result<LoopPins> {
        let p = |item: &str| format!("{prefix}.{item}");
        let d = PidIo::default();
        let debug = if debug {
            Some(DebugPins {
                error_i: c.pin(&p("errorI"))?,
                error_d: c.pin(&p("errorD"))?,
                command_d: c.pin(&p("commandD"))?,
                command_dd: c.pin(&p("commandDD"))?,
                command_ddd: c.pin(&p("commandDDD"))?,
                ultimate_gain: c.pin(&p("ultimate-gain"))?,
                ultimate_period: c.pin(&p("ultimate-period"))?,
            })
        } else {
            None
        };
        Ok(LoopPins {
            enable: c.pin(&p("enable"))?,
            command: c.pin(&p("command"))?,
            command_deriv: c.pin(&p("command-deriv"))?,
            feedback: c.pin(&p("feedback"))?,
            feedback_deriv: c.pin(&p("feedback-deriv"))?,
            error: c.pin(&p("error"))?,
            output: c.pin(&p("output"))?,
            saturated: c.pin(&p("saturated"))?,
            saturated_s: c.pin(&p("saturated-s"))?,
            saturated_count: c.pin(&p("saturated-count"))?,
            pgain: c.pin_init(&p("Pgain"), d.pgain)?,
            igain: c.pin(&p("Igain"))?,
            dgain: c.pin(&p("Dgain"))?,
            ff0: c.pin(&p("FF0"))?,
            ff1: c.pin(&p("FF1"))?,
            ff2: c.pin(&p("FF2"))?,
            ff3: c.pin(&p("FF3"))?,
            deadband: c.pin(&p("deadband"))?,
            maxerror: c.pin(&p("maxerror"))?,
            maxerror_i: c.pin(&p("maxerrorI"))?,
            maxerror_d: c.pin(&p("maxerrorD"))?,
            maxcmd_d: c.pin(&p("maxcmdD"))?,
            maxcmd_dd: c.pin(&p("maxcmdDD"))?,
            maxcmd_ddd: c.pin(&p("maxcmdDDD"))?,
            bias: c.pin(&p("bias"))?,
            maxoutput: c.pin(&p("maxoutput"))?,
            index_enable: c.pin(&p("index-enable"))?,
            error_previous_target: c
                .pin_init(&p("error-previous-target"), d.error_previous_target)?,
            tune_effort: c.pin_init(&p("tune-effort"), d.tune_effort)?,
            tune_cycles: c.pin_init(&p("tune-cycles"), d.tune_cycles)?,
            tune_type: c.pin(&p("tune-type"))?,
            tune_mode: c.pin(&p("tune-mode"))?,
            tune_start: c.pin(&p("tune-start"))?,
            debug,
        })
    }

    /// Reads every pin of the snapshot.
    fn read(&self) -> PidIo {
        PidIo {
            enable: self.enable.get(),
            command: self.command.get(),
            feedback: self.feedback.get(),
            index_enable: self.index_enable.get(),
            error_previous_target: self.error_previous_target.get(),
            pgain: self.pgain.get(),
            igain: self.igain.get(),
            dgain: self.dgain.get(),
            ff0: self.ff0.get(),
            ff1: self.ff1.get(),
            ff2: self.ff2.get(),
            ff3: self.ff3.get(),
            deadband: self.deadband.get(),
            maxerror: self.maxerror.get(),
            maxerror_i: self.maxerror_i.get(),
            maxerror_d: self.maxerror_d.get(),
            maxcmd_d: self.maxcmd_d.get(),
            maxcmd_dd: self.maxcmd_dd.get(),
            maxcmd_ddd: self.maxcmd_ddd.get(),
            bias: self.bias.get(),
            maxoutput: self.maxoutput.get(),
            tune_effort: self.tune_effort.get(),
            tune_cycles: self.tune_cycles.get(),
            tune_type: self.tune_type.get(),
            tune_mode: self.tune_mode.get(),
            tune_start: self.tune_start.get(),
            error: self.error.get(),
            output: self.output.get(),
            saturated: self.saturated.get(),
            saturated_s: self.saturated_s.get(),
            saturated_count: self.saturated_count.get(),
        }
    }

    /// Writes the outputs, and the inputs the call changed (the tuner's
    /// gains and `tune-start`); untouched inputs are not rewritten, so a
    /// value another writer stores meanwhile is not lost.
    fn write(&self, before: &PidIo, io: &PidIo, pid: &Pid) {
        fn changed(a: f64, b: f64) -> bool {
            a.to_bits() != b.to_bits()
        }
        self.error.set(io.error);
        self.output.set(io.output);
        self.saturated.set(io.saturated);
        self.saturated_s.set(io.saturated_s);
        self.saturated_count.set(io.saturated_count);
        for (pin, old, new) in [
            (&self.pgain, before.pgain, io.pgain),
            (&self.igain, before.igain, io.igain),
            (&self.dgain, before.dgain, io.dgain),
            (&self.ff0, before.ff0, io.ff0),
            (&self.ff1, before.ff1, io.ff1),
            (&self.ff2, before.ff2, io.ff2),
        ] {
            if changed(old, new) {
                pin.overwrite(new);
            }
        }
        if before.tune_start != io.tune_start {
            self.tune_start.set(io.tune_start);
        }
        if let Some(d) = &self.debug {
            d.error_i.set(pid.error_i);
            d.error_d.set(pid.error_d);
            d.command_d.set(pid.command_d);
            d.command_dd.set(pid.command_dd);
            d.command_ddd.set(pid.command_ddd);
            d.ultimate_gain.set(pid.ultimate_gain);
            d.ultimate_period.set(pid.ultimate_period);
        }
    }

    /// One call of `do-pid-calcs`.
    fn run(&self, pid: &mut Pid, period: i64) {
        let before = self.read();
        let mut io = before;
        pid.step(&mut io, period, |estimates| {
            if let Some((cmd_d, fb_d)) = estimates {
                self.command_deriv.set_unlinked(cmd_d);
                self.feedback_deriv.set_unlinked(fb_d);
            }
            (self.command_deriv.get(), self.feedback_deriv.get())
        });
        self.write(&before, &io, pid);
    }
}

fn load(host: &Host, args: &ModuleArgs) -> Result<()> {
    // The same num_chan/names rules as encoder.
    let names = channel_names("pid", "pid", DEFAULT_CHAN, MAX_CHAN, args)?;
    let debug = args.int("debug").unwrap_or(0) > 0;
    let mut b = host.new_rt_component("pid")?;
    for prefix in &names {
        let pins = LoopPins::new(b.component(), prefix, debug)?;
        let mut pid = Pid::new();
        b.funct(&format!("{prefix}.do-pid-calcs"), true, move |ctx| {
            pins.run(&mut pid, ctx.period())
        })?;
    }
    b.ready()
}

#[cfg(test)]
mod tests;
